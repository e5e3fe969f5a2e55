// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Body N/Initial stress: the points start pre-strained so that their model
// gives the stress; a column under gravity started in its geostatic stress
// stays at rest, the same column from zero stress oscillates.

#include <fmpm/parameters.h>
#include <fmpm/simulator.h>

#include <algorithm>
#include <cmath>

#include "scene_helpers.h"
#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using fmpm_tests::make_simulator;
  using Index = fmpm::PropertyIndex<2>;

  // A column 0.25 x 1 on rollers, fixed at its base, under g = 10 (ρ = 100,
  // E = 1e6, ν = 0.3), for 0.2 s (about 6 periods of its first mode).
  std::string
  column_scene(const std::string &initial_stress)
  {
    return R"(
set Dimension = 2
subsection Mesh
  set Lower corner = 0, 0
  set Upper corner = 0.25, 1
  set Subdivisions = 2, 8
end
subsection Boundary conditions
  set Fixed boundary ids  = 2
  set Roller boundary ids = 0, 1
end
subsection Body force
  set Gravity = 0, -10
end
subsection Time
  set End time = 0.2
  set Courant number = 0.5
  set Strain update = usl
end
subsection Material 0
  set Density = 100
  subsection Linear elastic
    set Young's modulus = 1e6
    set Poisson's ratio = 0.3
  end
end
subsection Body 0
  set Center = 0.125, 0.5
  set Half lengths = 0.125, 0.5
  set Function constants = rho=100, g=10, H=1, K0=0.428571428571
  set Initial stress = )" +
           initial_stress + R"(
end
)" + fmpm_tests::output_overrides("output-initial-stress-column");
  }

  struct ColumnRun
  {
    double max_kinetic_energy = 0;
    double max_speed          = 0;
    double max_stress_change  = 0;
  };

  ColumnRun
  run_column(const std::string &initial_stress)
  {
    ParameterHandler prm;
    auto simulator = make_simulator<2>({}, column_scene(initial_stress), prm);
    simulator->run();
    ColumnRun   result;
    const auto &points = fmpm_tests::inspect(*simulator).get_material_points();
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const auto   p     = points.record(k);
        const double depth = 1 - p[Index::initial_position + 1];
        // σ_yy = −ρ g depth, the value the scene gives.
        result.max_stress_change =
          std::max(result.max_stress_change,
                   std::abs(p[Index::stress + 1] + 100 * 10 * depth));
        result.max_speed =
          std::max(result.max_speed,
                   fmpm::get_vector<2>(p, Index::velocity).norm());
      }
    for (const auto &row : fmpm_tests::inspect(*simulator).get_history())
      result.max_kinetic_energy =
        std::max(result.max_kinetic_energy, row.kinetic_energy);
    return result;
  }
} // namespace



// Geostatic stress σ_yy = −ρ g (H − y), σ_xx = K0 σ_yy: the column stays at
// rest over the whole run and its stress does not move; from zero stress
// the same column falls onto its base and oscillates.
TEST(InitialStress, GeostaticColumnStaysAtRest)
{
  const double    rho = 100, g = 10, H = 1, W = 0.25, T = 0.2;
  const ColumnRun geostatic = run_column("K0*rho*g*(y - H); rho*g*(y - H); 0");
  const ColumnRun from_zero = run_column("");
  // Speed a point gains falling freely for 1% of the run.
  EXPECT_LT(geostatic.max_speed, 0.01 * g * T);
  // Within 1% of the base stress at every point.
  EXPECT_LT(geostatic.max_stress_change, 0.01 * rho * g * H);
  // The column from zero stress: its weight compresses it by
  // ρ g H²/(2M) (M = E(1−ν)/((1+ν)(1−2ν))); released suddenly it swings
  // with kinetic energies of the order of the weight times that
  // displacement, and its stress is far from the geostatic one.
  const double M               = 1e6 * 0.7 / (1.3 * 0.4);
  const double settlement_work = rho * W * H * g * (rho * g * H * H / (2 * M));
  EXPECT_GT(from_zero.max_kinetic_energy, 0.1 * settlement_work);
  EXPECT_LT(geostatic.max_kinetic_energy, 1e-3 * settlement_work);
  EXPECT_GT(from_zero.max_stress_change, 0.1 * rho * g * H);
}



// A uniform stress in a box held on all its sides stays; the stored
// deformation gradient is the stretch at which the model gives it: the
// neo-Hookean 'ln J' stress τ = μ(b − I) + λ ln J I of that F equals the
// given σ J, and the strain energy is W(F) ([BonetWood2008] Sec. 6.4.3).
TEST(InitialStress, NeoHookeanStartsAtTheGivenStress)
{
  const std::string scene = R"(
set Dimension = 2
subsection Mesh
  set Lower corner = 0, 0
  set Upper corner = 1, 1
  set Subdivisions = 4, 4
end
subsection Boundary conditions
  set Fixed boundary ids = 0, 1, 2, 3
end
subsection Time
  set End time = 0.01
  set Courant number = 0.5
end
subsection Material 0
  set Model name = neo hookean
  set Density = 1000
  subsection Neo hookean
    set Bulk modulus  = 1e6
    set Shear modulus = 4e5
    set Energy form = ln J
  end
end
subsection Body 0
  set Center = 0.5, 0.5
  set Half lengths = 0.5, 0.5
  set Initial stress = 3e5; -2e5; 1e5
end
)" + fmpm_tests::output_overrides("output-initial-stress-neo-hookean");
  ParameterHandler prm;
  auto             simulator = make_simulator<2>({}, scene, prm);
  simulator->run();
  const double mu = 4e5, lambda = 1e6 - 2. / 3 * 4e5;
  const auto  &points = fmpm_tests::inspect(*simulator).get_material_points();
  ASSERT_GT(points.n_points(), 0u);
  double strain_energy = 0;
  for (unsigned int k = 0; k < points.n_points(); ++k)
    {
      const auto   p = points.record(k);
      Tensor<2, 3> F;
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int c = 0; c < 3; ++c)
          F[a][c] = p[Index::deformation_gradient + 3 * a + c];
      F[2][2]                  = 1; // plane strain
      const double       J     = determinant(F);
      const Tensor<2, 3> b     = F * transpose(F);
      const Tensor<2, 3> I     = unit_symmetric_tensor<3>();
      const Tensor<2, 3> sigma = (mu * (b - I) + lambda * std::log(J) * I) / J;
      EXPECT_NEAR(sigma[0][0], 3e5, 1e-6 * 3e5);
      EXPECT_NEAR(sigma[1][1], -2e5, 1e-6 * 3e5);
      EXPECT_NEAR(sigma[0][1], 1e5, 1e-6 * 3e5);
      EXPECT_NEAR(p[Index::stress + 0], 3e5, 1e-6 * 3e5);
      EXPECT_NEAR(p[Index::stress + 1], -2e5, 1e-6 * 3e5);
      EXPECT_NEAR(p[Index::stress + 2], sigma[2][2], 1e-6 * 3e5);
      EXPECT_NEAR(p[Index::stress + 3], 1e5, 1e-6 * 3e5);
      // A real stretch: a few per cent of strain.
      EXPECT_GT(std::abs(F[0][0] - 1), 0.05);
      const double W = mu / 2 * (trace(b) - 3) - mu * std::log(J) +
                       lambda / 2 * std::log(J) * std::log(J);
      strain_energy += W * p[Index::initial_volume];
    }
  EXPECT_NEAR(
    fmpm_tests::inspect(*simulator).get_history().front().strain_energy,
    strain_energy,
    1e-6 * strain_energy);
}



// Linear elasticity (incremental): the stored energy of the pre-strain is
// ½ σ : C⁻¹ : σ, with σ_zz = ν (σ_xx + σ_yy) of plane strain. The stress
// varies in space but is in equilibrium (div σ = 0), so it stays.
TEST(InitialStress, LinearElasticStrainEnergy)
{
  const double E = 1e6, nu = 0.3;
  const std::string scene = R"(
set Dimension = 2
subsection Mesh
  set Lower corner = 0, 0
  set Upper corner = 1, 1
  set Subdivisions = 4, 4
end
subsection Boundary conditions
  set Fixed boundary ids = 0, 1, 2, 3
end
subsection Time
  set End time = 0.001
end
subsection Material 0
  set Density = 1000
  subsection Linear elastic
    set Young's modulus = 1e6
    set Poisson's ratio = 0.3
  end
end
subsection Body 0
  set Center = 0.5, 0.5
  set Half lengths = 0.5, 0.5
  set Initial stress = 2e2*y; -1e2*x; 50
end
)" + fmpm_tests::output_overrides("output-initial-stress-linear");
  ParameterHandler prm;
  auto             simulator = make_simulator<2>({}, scene, prm);
  simulator->run();
  double      expected = 0;
  const auto &points   = fmpm_tests::inspect(*simulator).get_material_points();
  for (unsigned int k = 0; k < points.n_points(); ++k)
    {
      const auto   p  = points.record(k);
      const double x  = p[Index::initial_position + 0];
      const double y  = p[Index::initial_position + 1];
      const double sx = 2e2 * y, sy = -1e2 * x, sxy = 50;
      const double sz = nu * (sx + sy);
      EXPECT_NEAR(p[Index::stress + 2], sz, 1e-6 * 2e2);
      const double ss = sx * sx + sy * sy + sz * sz + 2 * sxy * sxy;
      const double tr = sx + sy + sz;
      const double W  = ((1 + nu) * ss - nu * tr * tr) / (2 * E);
      expected += W * p[Index::initial_volume];
    }
  EXPECT_NEAR(
    fmpm_tests::inspect(*simulator).get_history().front().strain_energy,
    expected,
    1e-3 * expected);
}



// A model with history (Mie-Grueneisen with J2 plasticity, below its yield
// stress): each point starts at the given stress, held by a box fixed on
// all its sides.
TEST(InitialStress, MieGruneisenStartsAtTheGivenStress)
{
  const std::string scene = R"(
set Dimension = 2
subsection Mesh
  set Lower corner = 0, 0
  set Upper corner = 1, 1
  set Subdivisions = 4, 4
end
subsection Boundary conditions
  set Fixed boundary ids = 0, 1, 2, 3
end
subsection Time
  set Maximum number of steps = 3
  set End time = 1
end
subsection Material 0
  set Model name = mie gruneisen
  set Density    = 8930
  subsection Mie gruneisen
    set Bulk modulus  = 137e9
    set Shear modulus = 46e9
    set Yield stress  = 400e6
  end
end
subsection Body 0
  set Center = 0.5, 0.5
  set Half lengths = 0.5, 0.5
  set Initial stress = -1e8; -2e8; 5e7
end
)" + fmpm_tests::output_overrides("output-initial-stress-mie-gruneisen");
  ParameterHandler  prm;
  auto              simulator = make_simulator<2>({}, scene, prm);
  simulator->run();
  const auto &points = fmpm_tests::inspect(*simulator).get_material_points();
  ASSERT_GT(points.n_points(), 0u);
  for (unsigned int k = 0; k < points.n_points(); ++k)
    {
      const auto p = points.record(k);
      EXPECT_NEAR(p[Index::stress + 0], -1e8, 1e-6 * 2e8);
      EXPECT_NEAR(p[Index::stress + 1], -2e8, 1e-6 * 2e8);
      EXPECT_NEAR(p[Index::stress + 3], 5e7, 1e-6 * 2e8);
      // Compressed: J < 1.
      EXPECT_LT(p[Index::volume], p[Index::initial_volume]);
    }
  EXPECT_GT(fmpm_tests::inspect(*simulator).get_history().front().strain_energy,
            0);
}



// A model that cannot hold the stress is refused, naming the body.
TEST(InitialStress, RefusesWrongComponentCount)
{
  const std::string scene = R"(
set Dimension = 2
subsection Mesh
  set Subdivisions = 4, 4
end
subsection Body 0
  set Initial stress = 1; 2
end
)" + fmpm_tests::output_overrides("output-initial-stress-bad");
  ParameterHandler prm;
  try
    {
      auto simulator = make_simulator<2>({}, scene, prm);
      simulator->run();
      FAIL() << "a 2-component initial stress in 2D was accepted";
    }
  catch (const std::exception &e)
    {
      EXPECT_NE(std::string(e.what()).find("Body 0/Initial stress"),
                std::string::npos)
        << e.what();
    }
}
