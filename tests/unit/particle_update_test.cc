// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Each particle update against its column of seed 000 Table 2.1 and its
// equation: FMPM(1) is Eq. 2.40, XPIC(1) Eq. 2.38, FMPM(k) with the lumped
// mass gives PIC's velocity (but not PIC's position), FMPM(0) is FLIP with
// psi = 1, and the known-bad variants are what seeds 000 and 003 write.

#include <fmpm/particle_update/interface.h>

#include <deal.II/base/parameter_handler.h>

#include <random>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using namespace fmpm::ParticleUpdate;

  /** A batch with random fields; grid fields consistent for lumped mass. */
  Batch<2>
  random_batch(const unsigned int n)
  {
    std::mt19937                           rng(7);
    std::uniform_real_distribution<double> r(-1, 1);
    Batch<2>                               batch;
    batch.resize(n);
    batch.time_step = 0.01;
    for (unsigned int q = 0; q < n; ++q)
      {
        for (unsigned int d = 0; d < 2; ++d)
          {
            batch.velocity[q][d]                  = r(rng);
            batch.position[q][d]                  = r(rng);
            batch.grid[lumped_velocity][q][d]     = r(rng);      // S m⁻¹ p
            batch.grid[lumped_acceleration][q][d] = 10 * r(rng); // S m⁻¹ f
          }
        // Lumped mass: m̃ₖ⁻¹ = m⁻¹, so the scene's fields equal the lumped ones.
        batch.grid[velocity][q]     = batch.grid[lumped_velocity][q];
        batch.grid[acceleration][q] = batch.grid[lumped_acceleration][q];
        batch.grid[lumped_updated_velocity][q] =
          batch.grid[lumped_velocity][q] +
          batch.time_step * batch.grid[lumped_acceleration][q]; // S m⁻¹ p⁺
        batch.grid[updated_velocity][q] =
          batch.grid[lumped_updated_velocity][q];
      }
    return batch;
  }

  Batch<2>
  run(const std::string &name,
      const Batch<2>    &input,
      const std::string &settings = "")
  {
    ParameterHandler prm;
    Registry<2>::instance().declare_parameters(prm);
    prm.parse_input_from_string(settings);
    const auto update = Registry<2>::instance().create(name, prm);
    Batch<2>   batch  = input;
    update->update(batch);
    return batch;
  }
} // namespace



TEST(ParticleUpdate, FmpmOneIsEquation240)
{
  const Batch<2> in  = random_batch(20);
  const Batch<2> out = run("fmpm", in);
  const double   dt  = in.time_step;
  for (unsigned int q = 0; q < 20; ++q)
    {
      const Tensor<1, 2> Sm_p_plus = in.grid[lumped_updated_velocity][q];
      EXPECT_LT((out.velocity[q] - Sm_p_plus).norm(), 1e-15);
      const Point<2> X =
        in.position[q] + 0.5 * (Sm_p_plus + in.velocity[q]) * dt;
      EXPECT_LT((out.position[q] - X).norm(), 1e-15);
    }
}



TEST(ParticleUpdate, XpicOneIsEquation238)
{
  const Batch<2> in  = random_batch(20);
  const Batch<2> out = run("xpic", in);
  const double   dt  = in.time_step;
  for (unsigned int q = 0; q < 20; ++q)
    {
      const Tensor<1, 2> Sm_p_plus = in.grid[lumped_updated_velocity][q];
      const Tensor<1, 2> Sm_p      = in.grid[lumped_velocity][q];
      EXPECT_LT((out.velocity[q] - Sm_p_plus).norm(), 1e-14);
      const Point<2> X =
        in.position[q] + (Sm_p + 0.5 * (Sm_p_plus - in.velocity[q])) * dt;
      EXPECT_LT((out.position[q] - X).norm(), 1e-15);
    }
}



TEST(ParticleUpdate, PsiZeroMovesPointsWithTheGridVelocity)
{
  // Eq. 2.28 with psi = 0: FMPM(k) moves the points with v_p = S m~_k^-1 p+
  // and XPIC(k) with S m^-1 p+ (FLIP's), the velocities that update F;
  // the new particle velocities are those of psi = 1.
  Batch<2> in = random_batch(20);
  for (unsigned int q = 0; q < 20; ++q)
    in.grid[velocity][q] *= 0.5; // S m~_k^-1 p differs from S m^-1 p
  const double   dt = in.time_step;
  const Batch<2> fmpm =
    run("fmpm", in, "subsection Fmpm\nset Position update psi = 0\nend\n");
  const Batch<2> fmpm1 = run("fmpm", in);
  const Batch<2> xpic =
    run("xpic", in, "subsection Xpic\nset Position update psi = 0\nend\n");
  const Batch<2> xpic1 = run("xpic", in);
  for (unsigned int q = 0; q < 20; ++q)
    {
      const Tensor<1, 2> v_p = in.grid[updated_velocity][q];
      const Tensor<1, 2> Sm_p_plus =
        in.grid[lumped_velocity][q] + dt * in.grid[lumped_acceleration][q];
      EXPECT_LT((fmpm.position[q] - (in.position[q] + v_p * dt)).norm(), 1e-15);
      EXPECT_LT((xpic.position[q] - (in.position[q] + Sm_p_plus * dt)).norm(),
                1e-15);
      EXPECT_EQ(fmpm.velocity[q], fmpm1.velocity[q]);
      EXPECT_EQ(xpic.velocity[q], xpic1.velocity[q]);
      // and psi = 1 does not move them so
      EXPECT_GT((fmpm1.position[q] - fmpm.position[q]).norm(), 1e-6);
      EXPECT_GT((xpic1.position[q] - xpic.position[q]).norm(), 1e-6);
    }
}



TEST(ParticleUpdate, FmpmLumpedGivesPicVelocityNotPicPosition)
{
  const Batch<2> in                  = random_batch(20);
  const Batch<2> fmpm                = run("fmpm", in);
  const Batch<2> pic                 = run("pic", in);
  double         position_difference = 0;
  for (unsigned int q = 0; q < 20; ++q)
    {
      EXPECT_EQ(fmpm.velocity[q], pic.velocity[q]);
      position_difference += (fmpm.position[q] - pic.position[q]).norm();
    }
  EXPECT_GT(position_difference, 1e-6);
}



TEST(ParticleUpdate, FlipColumnsOfTable21)
{
  const Batch<2> in = random_batch(20);
  const double   dt = in.time_step;
  const Batch<2> flip =
    run("flip", in, "subsection Flip\nset Position update psi = 0\nend\n");
  const Batch<2> flip1 =
    run("flip", in, "subsection Flip\nset Position update psi = 1\nend\n");
  // The default is psi = 1.
  const Batch<2> flip_default = run("flip", in);
  const Batch<2> fmpm0        = run("fmpm0", in);
  const Batch<2> mid          = run("flip midpoint", in);
  const Batch<2> end          = run("flip end velocity", in);
  const Batch<2> blend =
    run("flip pic blend",
        in,
        "subsection Flip pic blend\nset FLIP fraction = 0.7\nend\n");
  for (unsigned int q = 0; q < 20; ++q)
    {
      const Tensor<1, 2> a   = in.grid[acceleration][q];
      const Tensor<1, 2> v_p = in.grid[updated_velocity][q];
      const Tensor<1, 2> V   = in.velocity[q];
      const Point<2>     X   = in.position[q];
      // FLIP(Std) with ψ = 0: V += a dt, X += v_p dt.
      EXPECT_LT((flip.velocity[q] - (V + a * dt)).norm(), 1e-15);
      EXPECT_LT((flip.position[q] - (X + v_p * dt)).norm(), 1e-15);
      // ψ = 1 and FMPM(0): X += (v_p − ½ a dt) dt (Eq. 2.28, Table 2.1).
      EXPECT_LT((flip1.position[q] - (X + (v_p - 0.5 * dt * a) * dt)).norm(),
                1e-15);
      EXPECT_EQ(fmpm0.position[q], flip1.position[q]);
      EXPECT_EQ(flip_default.position[q], flip1.position[q]);
      // Eq. 2.33: X += (V + ½ a dt) dt.
      EXPECT_LT((mid.position[q] - (X + (V + 0.5 * dt * a) * dt)).norm(),
                1e-15);
      // Seed 003 Eq. 1.64: X += V^(n+1) dt.
      EXPECT_LT((end.position[q] - (X + (V + a * dt) * dt)).norm(), 1e-15);
      // Seed 000 §2.3.4: V = αV + S m⁻¹(p⁺ − αp), X += V^(n+1) dt.
      const Tensor<1, 2> V_blend = 0.7 * V + v_p - 0.7 * in.grid[velocity][q];
      EXPECT_LT((blend.velocity[q] - V_blend).norm(), 1e-15);
      EXPECT_LT((blend.position[q] - (X + V_blend * dt)).norm(), 1e-15);
    }
}
