// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks the constitutive models (dim = 2 in plane strain, and dim = 3):
// NeoHookean (seed 004 Eq. 18) against a hand computation for a uniaxial
// stretch, its Kirchhoff stress against finite differences of its energy
// (tau = dW/dF F^T) for general F, zero stress/energy at F = I and its wave
// speed at J = 1; LinearElastic against sigma = lambda tr(eps) I + 2 mu eps,
// W = 1/2 sigma:eps and sqrt((lambda + 2 mu)/rho); and that check_parameters
// rejects non-physical parameters with a message naming the parameter. The
// 'ln J' neo-Hookean form against hand computations, energy derivatives and
// a rotation; E and nu as the alternative to K and G.

#include <fmpm/constitutive_model/elastic_constants.h>
#include <fmpm/constitutive_model/linear_elastic.h>
#include <fmpm/constitutive_model/mie_gruneisen.h>
#include <fmpm/constitutive_model/neo_hookean.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_properties.h>

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using fmpm::ConstitutiveModel::StressUpdateInputs;
  using fmpm::ConstitutiveModel::StressUpdateOutputs;

  template <typename T>
  class ConstitutiveModelTest : public ::testing::Test
  {};

  template <int d>
  using Dim        = std::integral_constant<int, d>;
  using Dimensions = ::testing::Types<Dim<2>, Dim<3>>;
  TYPED_TEST_SUITE(ConstitutiveModelTest, Dimensions);

  /**
   * A random deformation gradient with det F > 0 (close to, but clearly
   * away from, I). In 2D plane strain: only the upper 2x2 block differs from
   * I.
   */
  template <int dim>
  Tensor<2, 3>
  random_deformation_gradient(std::mt19937 &generator, const double amplitude)
  {
    std::uniform_real_distribution<double> uniform(-amplitude, amplitude);
    Tensor<2, 3>                           F = unit_symmetric_tensor<3>();
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = 0; j < dim; ++j)
        F[i][j] += uniform(generator);
    return F;
  }

  /** Relative difference |a - b| / |b| of two tensors. */
  template <typename A, typename B>
  double
  relative_error(const A &a, const B &b)
  {
    return (Tensor<2, 3>(a) - Tensor<2, 3>(b)).norm() / Tensor<2, 3>(b).norm();
  }

  /** Run update_stress of @p model on a batch of deformation gradients. */
  template <typename Model>
  StressUpdateOutputs
  update(const Model &model, const std::vector<Tensor<2, 3>> &F)
  {
    StressUpdateInputs inputs;
    inputs.resize(F.size());
    for (unsigned int q = 0; q < F.size(); ++q)
      {
        inputs.set_deformation_gradient(q, F[q]);
        inputs.set_velocity_gradient(q, Tensor<2, 3>());
      }
    inputs.time_step = 1e-3;
    StressUpdateOutputs outputs;
    model.update_stress(inputs, outputs);
    return outputs;
  }

  /** Expect @p check to throw, with a message containing every @p words. */
  void
  expect_error(const std::function<void()>    &check,
               const std::vector<std::string> &words)
  {
    try
      {
        check();
        ADD_FAILURE() << "no exception thrown; expected one naming <"
                      << words.front() << ">";
      }
    catch (const std::exception &e)
      {
        const std::string message = fmpm::error_message(e);
        for (const auto &word : words)
          EXPECT_NE(message.find(word), std::string::npos)
            << "message does not contain <" << word << ">:\n"
            << message;
      }
  }



  // F = diag(lambda, 1, 1): J = lambda, b = diag(lambda^2, 1, 1),
  // bbar = lambda^{-2/3} b, I1bar = lambda^{-2/3} (lambda^2 + 2), so
  //   tau_11 = 2G/3 lambda^{-2/3} (lambda^2 - 1) + K/2 (lambda^2 - 1),
  //   tau_22 = tau_33 = -G/3 lambda^{-2/3} (lambda^2 - 1) + K/2 (lambda^2-1),
  //   sigma = tau / lambda, off-diagonals 0,
  //   W = G/2 (lambda^{-2/3}(lambda^2 + 2) - 3)
  //       + K/2 (1/2 (lambda^2 - 1) - ln lambda).
  TYPED_TEST(ConstitutiveModelTest, NeoHookeanUniaxialStretch)
  {
    constexpr int                            dim = TypeParam::value;
    fmpm::ConstitutiveModel::NeoHookean<dim> model;
    model.bulk_modulus  = 2.5e6;
    model.shear_modulus = 1.2e6;
    const double K = model.bulk_modulus, G = model.shear_modulus;

    for (const double lambda : {1.3, 0.8})
      {
        Tensor<2, 3> F = unit_symmetric_tensor<3>();
        F[0][0]        = lambda;

        const double l2     = lambda * lambda;
        const double l_m23  = std::pow(lambda, -2.0 / 3.0);
        const double tau_11 = 2 * G / 3 * l_m23 * (l2 - 1) + K / 2 * (l2 - 1);
        const double tau_22 = -G / 3 * l_m23 * (l2 - 1) + K / 2 * (l2 - 1);
        const double W      = G / 2 * (l_m23 * (l2 + 2) - 3) +
                         K / 2 * (0.5 * (l2 - 1) - std::log(lambda));
        SymmetricTensor<2, 3> expected_sigma;
        expected_sigma[0][0] = tau_11 / lambda;
        expected_sigma[1][1] = tau_22 / lambda;
        expected_sigma[2][2] = tau_22 / lambda;

        const StressUpdateOutputs out   = update(model, {F});
        const double              scale = expected_sigma.norm();
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            EXPECT_NEAR(out.stress_tensor(0)[i][j],
                        expected_sigma[i][j],
                        1e-12 * scale)
              << "lambda = " << lambda << ", sigma_" << i << j;
        EXPECT_NEAR(out.strain_energy_density[0], W, 1e-12 * std::abs(W));

        SymmetricTensor<2, 3> tau;
        double                energy = 0;
        model.stress_and_energy(F, tau, energy);
        EXPECT_NEAR(tau[0][0], tau_11, 1e-12 * std::abs(tau_11));
        EXPECT_NEAR(tau[1][1], tau_22, 1e-12 * std::abs(tau_11));
        EXPECT_NEAR(energy, W, 1e-12 * std::abs(W));
      }
  }



  // tau = dW/dF F^T by central differences of W, and sigma = tau / J from
  // update_stress, for several random F in one batch.
  TYPED_TEST(ConstitutiveModelTest, NeoHookeanStressIsEnergyDerivative)
  {
    constexpr int                            dim = TypeParam::value;
    fmpm::ConstitutiveModel::NeoHookean<dim> model;
    model.bulk_modulus  = 3.0;
    model.shear_modulus = 0.7;

    std::mt19937              generator(11 + dim);
    std::vector<Tensor<2, 3>> batch;
    for (unsigned int q = 0; q < 4; ++q)
      {
        const Tensor<2, 3> F = random_deformation_gradient<dim>(generator, 0.3);
        ASSERT_GT(determinant(F), 0.2);
        batch.push_back(F);
      }
    const StressUpdateOutputs out = update(model, batch);

    const double h = 1e-5;
    for (unsigned int q = 0; q < batch.size(); ++q)
      {
        const Tensor<2, 3> &F = batch[q];
        Tensor<2, 3>        P; // dW/dF
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            {
              SymmetricTensor<2, 3> tau;
              double                W_plus = 0, W_minus = 0;
              Tensor<2, 3>          F_h = F;
              F_h[i][j] += h;
              model.stress_and_energy(F_h, tau, W_plus);
              F_h[i][j] -= 2 * h;
              model.stress_and_energy(F_h, tau, W_minus);
              P[i][j] = (W_plus - W_minus) / (2 * h);
            }
        const Tensor<2, 3> tau_fd = P * transpose(F);
        const double       J      = determinant(F);

        SymmetricTensor<2, 3> tau;
        double                W = 0;
        model.stress_and_energy(F, tau, W);
        EXPECT_LT(relative_error(tau, tau_fd), 1e-6)
          << "F = " << F << "\ntau = " << tau << "\nFD: " << tau_fd;
        EXPECT_LT(relative_error(out.stress_tensor(q), tau_fd / J), 1e-6)
          << "point " << q << ": sigma = " << out.stress_tensor(q)
          << "\nFD tau/J: " << tau_fd / J;
        EXPECT_NEAR(out.strain_energy_density[q], W, 1e-14 * std::abs(W));
        EXPECT_GT(W, 0);
        if (dim == 3)
          {
            // The batch update is stress_and_energy() entry by entry: the
            // same values to the bit (σ = τ/J as deal.II divides).
            const Tensor<2, 3> sigma      = out.stress_tensor(q);
            const Tensor<2, 3> tau_over_J = tau / J;
            EXPECT_EQ(sigma, tau_over_J) << "point " << q;
            EXPECT_EQ(out.strain_energy_density[q], W) << "point " << q;
          }
        if (dim == 2)
          {
            // Plane strain: no in-plane/out-of-plane shear.
            EXPECT_EQ(out.stress_tensor(q)[0][2], 0.0);
            EXPECT_EQ(out.stress_tensor(q)[1][2], 0.0);
          }
      }
  }



  TYPED_TEST(ConstitutiveModelTest, NeoHookeanUndeformedAndWaveSpeed)
  {
    constexpr int                            dim = TypeParam::value;
    fmpm::ConstitutiveModel::NeoHookean<dim> model;
    model.bulk_modulus  = 4.0e6;
    model.shear_modulus = 1.5e6;

    const StressUpdateOutputs out = update(model, {unit_symmetric_tensor<3>()});
    EXPECT_LT(out.stress_tensor(0).norm(), 1e-12 * model.bulk_modulus);
    EXPECT_NEAR(out.strain_energy_density[0], 0.0, 1e-12 * model.bulk_modulus);

    const double density = 1200;
    EXPECT_NEAR(model.wave_speed(density, 1.0),
                std::sqrt(
                  (model.bulk_modulus + 4.0 / 3.0 * model.shear_modulus) /
                  density),
                1e-12 * std::sqrt(model.bulk_modulus / density));
  }



  TYPED_TEST(ConstitutiveModelTest, LinearElastic)
  {
    constexpr int                               dim = TypeParam::value;
    fmpm::ConstitutiveModel::LinearElastic<dim> model;
    model.strain_measure =
      fmpm::ConstitutiveModel::LinearElastic<dim>::StrainMeasure::total;
    model.youngs_modulus = 7.0e4;
    model.poissons_ratio = 0.27;
    const double E = model.youngs_modulus, nu = model.poissons_ratio;
    const double mu     = E / (2 * (1 + nu));
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));

    // Small random symmetric strain eps (plane strain in 2D) plus a small
    // rotation-like skew part that the model must ignore: F = I + eps + w.
    std::mt19937                           generator(5 + dim);
    std::uniform_real_distribution<double> uniform(-1e-3, 1e-3);
    Tensor<2, 3>                           eps, w;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = i; j < dim; ++j)
        {
          eps[i][j] = eps[j][i] = uniform(generator);
          if (j > i)
            {
              w[i][j] = uniform(generator);
              w[j][i] = -w[i][j];
            }
        }
    const Tensor<2, 3> F = Tensor<2, 3>(unit_symmetric_tensor<3>()) + eps + w;

    double trace_eps = 0;
    for (unsigned int i = 0; i < 3; ++i)
      trace_eps += eps[i][i];
    Tensor<2, 3> sigma;
    double       W = 0;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        {
          sigma[i][j] = 2 * mu * eps[i][j] + (i == j ? lambda * trace_eps : 0);
          W += 0.5 * sigma[i][j] * eps[i][j];
        }

    const StressUpdateOutputs out = update(model, {F});
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        EXPECT_NEAR(out.stress_tensor(0)[i][j],
                    sigma[i][j],
                    1e-12 * sigma.norm())
          << "sigma_" << i << j;
    EXPECT_NEAR(out.strain_energy_density[0], W, 1e-12 * W);
    if (dim == 2)
      {
        // Plane strain: eps_33 = 0 but sigma_33 = lambda tr(eps).
        EXPECT_NEAR(out.stress_tensor(0)[2][2],
                    lambda * trace_eps,
                    1e-12 * sigma.norm());
      }

    const StressUpdateOutputs zero =
      update(model, {unit_symmetric_tensor<3>()});
    EXPECT_EQ(zero.stress_tensor(0).norm(), 0.0);
    EXPECT_EQ(zero.strain_energy_density[0], 0.0);

    const double density = 2700;
    for (const double J : {1.0, 0.9})
      EXPECT_NEAR(model.wave_speed(density, J),
                  std::sqrt((lambda + 2 * mu) / density),
                  1e-12 * std::sqrt(E / density));
  }



  TYPED_TEST(ConstitutiveModelTest, CheckParameters)
  {
    constexpr int     dim   = TypeParam::value;
    const std::string where = "Material 3/Linear elastic";
    {
      fmpm::ConstitutiveModel::LinearElastic<dim> model;
      EXPECT_NO_THROW(model.check_parameters(where));
      model.poissons_ratio = 0.49;
      EXPECT_NO_THROW(model.check_parameters(where));
      for (const double E : {0.0, -2.0e5})
        {
          fmpm::ConstitutiveModel::LinearElastic<dim> bad;
          bad.youngs_modulus = E;
          expect_error([&]() { bad.check_parameters(where); },
                       {"Young's modulus", where});
        }
      for (const double nu : {0.5, 0.6})
        {
          fmpm::ConstitutiveModel::LinearElastic<dim> bad;
          bad.poissons_ratio = nu;
          expect_error([&]() { bad.check_parameters(where); },
                       {"Poisson's ratio", where});
        }
    }
    {
      const std::string nh_where = "Material 0/Neo hookean";
      fmpm::ConstitutiveModel::NeoHookean<dim> model;
      EXPECT_NO_THROW(model.check_parameters(nh_where));
      for (const double K : {0.0, -1.0e6})
        {
          fmpm::ConstitutiveModel::NeoHookean<dim> bad;
          bad.bulk_modulus = K;
          expect_error([&]() { bad.check_parameters(nh_where); },
                       {"Bulk modulus", nh_where});
        }
      for (const double G : {0.0, -1.0e6})
        {
          fmpm::ConstitutiveModel::NeoHookean<dim> bad;
          bad.shear_modulus = G;
          expect_error([&]() { bad.check_parameters(nh_where); },
                       {"Shear modulus", nh_where});
        }
    }
  }
} // namespace



namespace
{
  // The incremental linear elastic form: sigma += dt C : sym(L) from the
  // stored stress; a rigid rotation rate (skew L) adds no stress; the stored
  // energy grows by J (sigma_old + sigma_new)/2 : D dt.
  template <int dim>
  void
  check_incremental_linear_elastic()
  {
    using Index = fmpm::PropertyIndex<dim>;
    fmpm::ConstitutiveModel::LinearElastic<dim> model; // incremental
    model.youngs_modulus = 200;
    model.poissons_ratio = 0.25;
    const double mu      = 200 / (2 * 1.25);
    const double lambda  = 200 * 0.25 / (1.25 * 0.5);

    fmpm::ConstitutiveModel::StressUpdateInputs  inputs;
    fmpm::ConstitutiveModel::StressUpdateOutputs outputs;
    inputs.resize(2);
    inputs.time_step = 0.01;
    std::vector<std::vector<double>> storage(
      2, std::vector<double>(Index::n_core_properties, 0.));
    SymmetricTensor<2, 3> sigma_old;
    sigma_old[0][0] = 1.5;
    sigma_old[0][1] = -0.5;
    std::vector<fmpm::RecordColumns> records;
    for (unsigned int q = 0; q < 2; ++q)
      records.emplace_back(make_array_view(storage[q]));
    for (unsigned int q = 0; q < 2; ++q)
      {
        inputs.properties[q] = records[q].record();
        fmpm::set_symmetric_tensor3(inputs.properties[q],
                                    Index::stress,
                                    sigma_old);
        inputs.properties[q][Index::strain_energy_density] = 0.1;
        inputs.set_old_stress(q, sigma_old);
        inputs.old_strain_energy_density[q] = 0.1;
        inputs.set_deformation_gradient(q, unit_symmetric_tensor<3>());
      }
    Tensor<2, 3> L;
    L[0][0] = 0.3;
    L[0][1] = 0.2;
    L[1][0] = 0.1; // sym part 0.15, skew part 0.05
    inputs.set_velocity_gradient(0, L);
    Tensor<2, 3> spin; // pure rotation rate
    spin[0][1] = 1.0;
    spin[1][0] = -1.0;
    inputs.set_velocity_gradient(1, spin);
    model.update_stress(inputs, outputs);

    SymmetricTensor<2, 3> D;
    D[0][0] = 0.3;
    D[0][1] = 0.15;
    const SymmetricTensor<2, 3> expected =
      sigma_old +
      0.01 * (lambda * trace(D) * unit_symmetric_tensor<3>() + 2 * mu * D);
    EXPECT_LT((outputs.stress_tensor(0) - expected).norm(),
              1e-12 * expected.norm());
    EXPECT_NEAR(outputs.strain_energy_density[0],
                0.1 + 0.5 * ((sigma_old + expected) * D) * 0.01,
                1e-14);
    EXPECT_LT((outputs.stress_tensor(1) - sigma_old).norm(), 1e-14);
    EXPECT_NEAR(outputs.strain_energy_density[1], 0.1, 1e-14);
  }
} // namespace

TEST(LinearElasticIncremental, TwoD)
{
  check_incremental_linear_elastic<2>();
}

TEST(LinearElasticIncremental, ThreeD)
{
  check_incremental_linear_elastic<3>();
}



namespace
{
  // 'Strain measure = jaumann': under a pure spin Ω (L = Ω, D = 0) the
  // stress turns with the material, dσ/dt = Ωσ − σΩ, so σ(t) = R σ₀ Rᵀ
  // with R the rotation by ωt (forward Euler: first order in Δt), and
  // the stored energy does not change.
  template <int dim>
  void
  check_jaumann_rotation()
  {
    using Index = fmpm::PropertyIndex<dim>;
    fmpm::ConstitutiveModel::LinearElastic<dim> model;
    model.youngs_modulus = 200;
    model.poissons_ratio = 0.25;
    model.strain_measure =
      fmpm::ConstitutiveModel::LinearElastic<dim>::StrainMeasure::jaumann;
    const double       omega = 2, angle = M_PI / 3;
    const unsigned int n_steps = 20000;
    const double       dt      = angle / omega / n_steps;

    fmpm::ConstitutiveModel::StressUpdateInputs  inputs;
    fmpm::ConstitutiveModel::StressUpdateOutputs outputs;
    inputs.resize(1);
    inputs.time_step = dt;
    std::vector<double>       storage(Index::n_core_properties, 0.);
    const fmpm::RecordColumns record(make_array_view(storage));
    inputs.properties[0] = record.record();
    inputs.set_deformation_gradient(0, unit_symmetric_tensor<3>());
    Tensor<2, 3> spin; // v = ω e_z × x: L_xy = −ω, L_yx = ω
    spin[0][1] = -omega;
    spin[1][0] = omega;
    inputs.set_velocity_gradient(0, spin);
    SymmetricTensor<2, 3> sigma;
    sigma[0][0]                         = 3;
    sigma[2][2]                         = 1;
    const SymmetricTensor<2, 3> sigma_0 = sigma;
    inputs.old_strain_energy_density[0] = 0.5;
    for (unsigned int step = 0; step < n_steps; ++step)
      {
        inputs.set_old_stress(0, sigma);
        model.update_stress(inputs, outputs);
        sigma                               = outputs.stress_tensor(0);
        inputs.old_strain_energy_density[0] = outputs.strain_energy_density[0];
      }
    Tensor<2, 3> R;
    R[0][0] = R[1][1]           = std::cos(angle);
    R[1][0]                     = std::sin(angle);
    R[0][1]                     = -std::sin(angle);
    R[2][2]                     = 1;
    const Tensor<2, 3> expected = R * Tensor<2, 3>(sigma_0) * transpose(R);
    EXPECT_LT((Tensor<2, 3>(sigma) - expected).norm(), 1e-3 * sigma_0.norm())
      << sigma << " against " << expected;
    EXPECT_EQ(outputs.strain_energy_density[0], 0.5);
    // The non-objective update keeps σ₀ (checked above): a real change.
    EXPECT_GT((Tensor<2, 3>(sigma_0) - expected).norm(), 1);
  }
} // namespace

TEST(LinearElasticJaumann, StressTurnsWithTheSpin2D)
{
  check_jaumann_rotation<2>();
}

TEST(LinearElasticJaumann, StressTurnsWithTheSpin3D)
{
  check_jaumann_rotation<3>();
}



// 'Strain measure = kirchhoff': τ = Jσ follows τ += Δt (C : D + Ωτ − τΩ).
// A uniaxial stretch at rate d over one step from J^n = 1.1: τ_xx grows by
// Δt (λ + 2μ) d from J^n σ^n_xx, σ = τ/J^{n+1}, and W grows by
// τ_mid : D Δt (per reference volume, no J).
TEST(LinearElasticKirchhoff, UpdatesTheKirchhoffStress)
{
  using Index = fmpm::PropertyIndex<2>;
  fmpm::ConstitutiveModel::LinearElastic<2> model;
  model.youngs_modulus = 200;
  model.poissons_ratio = 0.25;
  model.strain_measure =
    fmpm::ConstitutiveModel::LinearElastic<2>::StrainMeasure::kirchhoff;
  const double mu = 200 / (2 * 1.25), lambda = 200 * 0.25 / (1.25 * 0.5);
  fmpm::ConstitutiveModel::StressUpdateInputs  inputs;
  fmpm::ConstitutiveModel::StressUpdateOutputs outputs;
  inputs.resize(1);
  const double dt = 0.01, d = 0.5, J_old = 1.1, J_new = 1.1 * (1 + d * dt);
  inputs.time_step = dt;
  std::vector<double>       storage(Index::n_core_properties, 0.);
  const fmpm::RecordColumns record(make_array_view(storage));
  inputs.properties[0] = record.record();
  Tensor<2, 3> F       = unit_symmetric_tensor<3>();
  F[0][0]              = J_new;
  inputs.set_deformation_gradient(0, F);
  Tensor<2, 3> L;
  L[0][0] = d;
  inputs.set_velocity_gradient(0, L);
  SymmetricTensor<2, 3> sigma;
  sigma[0][0] = 2;
  sigma[1][1] = 1;
  inputs.set_old_stress(0, sigma);
  inputs.old_volume_ratio[0]          = J_old;
  inputs.old_strain_energy_density[0] = 0.3;
  model.update_stress(inputs, outputs);
  const double tau_xx = J_old * 2 + dt * (lambda + 2 * mu) * d;
  const double tau_yy = J_old * 1 + dt * lambda * d;
  EXPECT_NEAR(outputs.stress_tensor(0)[0][0], tau_xx / J_new, 1e-13);
  EXPECT_NEAR(outputs.stress_tensor(0)[1][1], tau_yy / J_new, 1e-13);
  EXPECT_NEAR(outputs.stress_tensor(0)[2][2], dt * lambda * d / J_new, 1e-13);
  EXPECT_NEAR(outputs.strain_energy_density[0],
              0.3 + 0.5 * (J_old * 2 + tau_xx) * d * dt,
              1e-14);
}



// The 'ln J' neo-Hookean form, sigma = lambda ln J / J I + mu/J (b - I),
// W = mu/2 (tr b - 3) - mu ln J + lambda/2 (ln J)^2 with mu = G,
// lambda = K - 2G/3 (plane strain in 2D: b_zz = 1).
namespace
{
  using fmpm::ConstitutiveModel::NeoHookean;

  template <int dim>
  NeoHookean<dim>
  log_neo_hookean(const double K, const double G)
  {
    NeoHookean<dim> model;
    model.bulk_modulus  = K;
    model.shear_modulus = G;
    model.energy_form   = NeoHookean<dim>::EnergyForm::log_j;
    return model;
  }

  // Uniaxial stretch F = diag(s, 1, 1) and hydrostatic stretch (F = s I in
  // 3D, diag(s, s, 1) in plane strain): b = F F^T, J = det F, and the
  // stress and energy written out by hand.
  template <int dim>
  void
  check_log_neo_hookean_stretches()
  {
    const double          K = 2.5e6, G = 1.2e6;
    const double          mu = G, lambda = K - 2. / 3. * G;
    const NeoHookean<dim> model = log_neo_hookean<dim>(K, G);
    for (const double s : {1.3, 0.8})
      for (const bool hydrostatic : {false, true})
        {
          Tensor<2, 3> F = unit_symmetric_tensor<3>();
          F[0][0]        = s;
          if (hydrostatic)
            for (unsigned int d = 1; d < dim; ++d)
              F[d][d] = s;
          const unsigned int n_stretched = hydrostatic ? dim : 1;
          const double       J           = std::pow(s, n_stretched);
          const double       log_J       = n_stretched * std::log(s);
          // b_ii - 1 is s² - 1 on the stretched axes, 0 on the others.
          SymmetricTensor<2, 3> expected;
          for (unsigned int i = 0; i < 3; ++i)
            expected[i][i] =
              (mu * (i < n_stretched ? s * s - 1 : 0.) + lambda * log_J) / J;
          const double W = 0.5 * mu * n_stretched * (s * s - 1) - mu * log_J +
                           0.5 * lambda * log_J * log_J;

          const StressUpdateOutputs out   = update(model, {F});
          const double              scale = expected.norm();
          for (unsigned int i = 0; i < 3; ++i)
            for (unsigned int j = 0; j < 3; ++j)
              EXPECT_NEAR(out.stress_tensor(0)[i][j],
                          expected[i][j],
                          1e-12 * scale)
                << "s = " << s << (hydrostatic ? " hydrostatic" : " uniaxial")
                << ", sigma_" << i << j;
          EXPECT_NEAR(out.strain_energy_density[0], W, 1e-12 * std::abs(W));

          SymmetricTensor<2, 3> tau;
          double                energy = 0;
          model.stress_and_energy(F, tau, energy);
          EXPECT_LT(relative_error(tau / J, expected), 1e-13);
          EXPECT_NEAR(energy, W, 1e-12 * std::abs(W));
        }
  }

  // sigma = (dW/dF F^T)/J by central differences of W over every entry of
  // F, and dW/dt = J sigma : D along F(t) = F + t Fdot (D = sym(Fdot F^-1),
  // the stress power per reference volume), for random F in one batch.
  template <int dim>
  void
  check_log_neo_hookean_energy_derivative()
  {
    const NeoHookean<dim>     model = log_neo_hookean<dim>(3.0, 0.7);
    std::mt19937              generator(29 + dim);
    std::vector<Tensor<2, 3>> batch;
    for (unsigned int q = 0; q < 5; ++q)
      {
        const Tensor<2, 3> F = random_deformation_gradient<dim>(generator, 0.3);
        ASSERT_GT(determinant(F), 0.2);
        batch.push_back(F);
      }
    const StressUpdateOutputs out       = update(model, batch);
    const auto                energy_of = [&](const Tensor<2, 3> &F) {
      SymmetricTensor<2, 3> tau;
      double                W = 0;
      model.stress_and_energy(F, tau, W);
      return W;
    };

    const double h = 1e-5;
    for (unsigned int q = 0; q < batch.size(); ++q)
      {
        const Tensor<2, 3> &F = batch[q];
        const double        J = determinant(F);
        Tensor<2, 3>        P; // dW/dF
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            {
              Tensor<2, 3> F_h = F;
              F_h[i][j] += h;
              const double W_plus = energy_of(F_h);
              F_h[i][j] -= 2 * h;
              P[i][j] = (W_plus - energy_of(F_h)) / (2 * h);
            }
        const Tensor<2, 3> sigma = out.stress_tensor(q);
        EXPECT_LT(relative_error(sigma, P * transpose(F) / J), 1e-6)
          << "point " << q << ": sigma = " << sigma
          << "\nFD: " << P * transpose(F) / J;
        EXPECT_NEAR(out.strain_energy_density[q],
                    energy_of(F),
                    1e-14 * std::abs(energy_of(F)));

        // Stress power along a random rate (in plane in 2D).
        const Tensor<2, 3> F_dot =
          random_deformation_gradient<dim>(generator, 1.0) -
          Tensor<2, 3>(unit_symmetric_tensor<3>());
        const SymmetricTensor<2, 3> D = symmetrize(F_dot * invert(F));
        const double                dW_dt =
          (energy_of(F + h * F_dot) - energy_of(F - h * F_dot)) / (2 * h);
        const double power = J * scalar_product(out.stress_tensor(q), D);
        EXPECT_NEAR(dW_dt, power, 1e-7 * (std::abs(power) + 1))
          << "point " << q;
        if (dim == 2)
          {
            EXPECT_EQ(out.stress_tensor(q)[0][2], 0.0);
            EXPECT_EQ(out.stress_tensor(q)[1][2], 0.0);
          }
      }
  }
} // namespace

TEST(NeoHookeanLogJ, UniaxialAndHydrostaticStretch2D)
{
  check_log_neo_hookean_stretches<2>();
}

TEST(NeoHookeanLogJ, UniaxialAndHydrostaticStretch3D)
{
  check_log_neo_hookean_stretches<3>();
}

TEST(NeoHookeanLogJ, StressIsEnergyDerivative2D)
{
  check_log_neo_hookean_energy_derivative<2>();
}

TEST(NeoHookeanLogJ, StressIsEnergyDerivative3D)
{
  check_log_neo_hookean_energy_derivative<3>();
}

// A rigid rotation R of a deformed state turns the stress: sigma(R F) =
// R sigma(F) R^T (objective), with the same energy; a full batch of 64
// points (the vectorized path) gives the values of stress_and_energy().
TEST(NeoHookeanLogJ, ObjectiveAndFullBatch)
{
  const NeoHookean<3>       model = log_neo_hookean<3>(4.0, 1.1);
  std::mt19937              generator(5);
  std::vector<Tensor<2, 3>> batch, rotated;
  const double              angle = 0.7;
  Tensor<2, 3>              R;
  R[0][0] = R[1][1] = std::cos(angle);
  R[0][1]           = -std::sin(angle);
  R[1][0]           = std::sin(angle);
  R[2][2]           = 1;
  for (unsigned int q = 0; q < StressUpdateInputs::capacity; ++q)
    {
      batch.push_back(random_deformation_gradient<3>(generator, 0.25));
      rotated.push_back(R * batch.back());
    }
  const StressUpdateOutputs out         = update(model, batch);
  const StressUpdateOutputs out_rotated = update(model, rotated);
  for (unsigned int q = 0; q < batch.size(); ++q)
    {
      const Tensor<2, 3> sigma = out.stress_tensor(q);
      EXPECT_LT(relative_error(out_rotated.stress_tensor(q),
                               R * sigma * transpose(R)),
                1e-13)
        << "point " << q;
      EXPECT_NEAR(out_rotated.strain_energy_density[q],
                  out.strain_energy_density[q],
                  1e-13 * std::abs(out.strain_energy_density[q]));
      SymmetricTensor<2, 3> tau;
      double                W = 0;
      model.stress_and_energy(batch[q], tau, W);
      EXPECT_LT(relative_error(sigma, tau / determinant(batch[q])), 1e-14);
    }
}

// At J = 1 the wave speed is sqrt((K + 4G/3)/rho0) as for the 'J^2' form;
// it grows in compression (lambda > 0), and the batch maximum is the
// largest of the points'.
TEST(NeoHookeanLogJ, WaveSpeed)
{
  const double        K = 4.0e6, G = 1.5e6, density = 1200;
  const NeoHookean<2> model = log_neo_hookean<2>(K, G);
  EXPECT_NEAR(model.wave_speed(density, 1.0),
              std::sqrt((K + 4.0 / 3.0 * G) / density),
              1e-12 * std::sqrt(K / density));
  const double lambda = K - 2. / 3. * G;
  EXPECT_NEAR(model.wave_speed(density, 0.8),
              std::sqrt((lambda + 2 * G - 2 * lambda * std::log(0.8)) /
                        density),
              1e-12 * std::sqrt(K / density));
  const std::vector<double> J = {1.1, 0.8, 1.3, 0.95};
  EXPECT_EQ(model.max_wave_speed(density, make_array_view(J)),
            model.wave_speed(density, 0.8));
}



// Young's modulus and Poisson's ratio as the alternative to the bulk and
// shear moduli, through the parameter file: the same K = E/(3(1 - 2 nu)),
// G = E/(2(1 + nu)) (and E, nu from K, G for the linear elastic model); an
// error naming the subsection and the entries for both pairs, an incomplete
// pair or a Poisson's ratio outside (-1, 0.5).
namespace
{
  template <typename Model>
  std::unique_ptr<Model>
  parsed(const std::string &settings)
  {
    ParameterHandler prm;
    Model::declare_parameters(prm);
    prm.parse_input_from_string(settings);
    auto model = std::make_unique<Model>();
    model->parse_parameters(prm);
    return model;
  }
} // namespace

TEST(ElasticConstants, YoungsModulusAndPoissonsRatio)
{
  using fmpm::ConstitutiveModel::ElasticConstants;
  using fmpm::ConstitutiveModel::LinearElastic;
  using fmpm::ConstitutiveModel::MieGruneisen;
  const double      E = 2.1e11, nu = 0.29;
  const double      K = E / (3 * (1 - 2 * nu)), G = E / (2 * (1 + nu));
  const std::string E_nu =
    "set Young's modulus = 2.1e11\nset Poisson's ratio = 0.29\n";
  {
    const auto model = parsed<NeoHookean<2>>(E_nu);
    EXPECT_EQ(model->bulk_modulus, K);
    EXPECT_EQ(model->shear_modulus, G);
    EXPECT_NO_THROW(model->check_parameters("Material 0/Neo hookean"));
    // No constants: the defaults, as before.
    const auto defaults = parsed<NeoHookean<3>>("");
    EXPECT_EQ(defaults->bulk_modulus, 1e6);
    EXPECT_EQ(defaults->shear_modulus, 0.5e6);
    // The model's own pair, one entry: the other keeps its default.
    const auto bulk_only = parsed<NeoHookean<2>>("set Bulk modulus = 3e6\n");
    EXPECT_EQ(bulk_only->bulk_modulus, 3e6);
    EXPECT_EQ(bulk_only->shear_modulus, 0.5e6);
    EXPECT_NO_THROW(bulk_only->check_parameters("Material 0/Neo hookean"));
  }
  {
    const auto model = parsed<MieGruneisen<3>>(E_nu);
    EXPECT_EQ(model->bulk_modulus, K);
    EXPECT_EQ(model->shear_modulus, G);
  }
  {
    // Linear elastic computes with E, nu: K, G give them back.
    const auto model = parsed<LinearElastic<2>>(
      "set Bulk modulus = " + fmpm::format_number(K) +
      "\nset Shear modulus = " + fmpm::format_number(G) + "\n");
    EXPECT_NEAR(model->youngs_modulus, E, 1e-15 * E);
    EXPECT_NEAR(model->poissons_ratio, nu, 1e-15);
    EXPECT_NO_THROW(model->check_parameters("Material 0/Linear elastic"));
  }
  EXPECT_NEAR(ElasticConstants::youngs_modulus_of(K, G), E, 1e-15 * E);
  EXPECT_NEAR(ElasticConstants::poissons_ratio_of(K, G), nu, 1e-15);

  const std::string where = "Material 2/Neo hookean";
  expect_error(
    [&]() {
      parsed<NeoHookean<2>>(E_nu + "set Shear modulus = 1e9\n")
        ->check_parameters(where);
    },
    {where + "/Shear modulus = 1e9",
     where + "/Young's modulus = 2.1e11",
     "not both"});
  expect_error(
    [&]() {
      parsed<NeoHookean<3>>("set Poisson's ratio = 0.3\n")
        ->check_parameters(where);
    },
    {where + "/Poisson's ratio = 0.3", "without 'Young's modulus'"});
  for (const std::string nu_text : {"0.5", "-1", "0.7"})
    expect_error(
      [&]() {
        parsed<NeoHookean<2>>("set Young's modulus = 1e6\n"
                              "set Poisson's ratio = " +
                              nu_text + "\n")
          ->check_parameters(where);
      },
      {where + "/Poisson's ratio = " + nu_text, "(-1, 0.5)"});
  expect_error(
    [&]() {
      parsed<NeoHookean<2>>("set Young's modulus = -1e6\n"
                            "set Poisson's ratio = 0.3\n")
        ->check_parameters(where);
    },
    {where + "/Young's modulus = -1e6", "not positive"});
  const std::string le_where = "Material 1/Linear elastic";
  expect_error(
    [&]() {
      parsed<LinearElastic<3>>("set Shear modulus = 1e6\n")
        ->check_parameters(le_where);
    },
    {le_where + "/Shear modulus = 1e6", "without 'Bulk modulus'"});
  expect_error(
    [&]() {
      parsed<LinearElastic<3>>("set Young's modulus = 1e6\n"
                               "set Bulk modulus = 1e6\n"
                               "set Shear modulus = 1e6\n")
        ->check_parameters(le_where);
    },
    {le_where + "/Bulk modulus = 1e6", le_where + "/Young's modulus = 1e6"});
}
