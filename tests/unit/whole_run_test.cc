// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Whole runs in-process, compared with analytical solutions and
// conservation laws: the axially vibrating bar (centre-of-mass velocity
// (2 v0/pi) cos(omega t)), a freely translating body (momentum, energy and
// positions exact), the colliding disks (energy bounded, momentum zero).

#include <fmpm/constitutive_model/elastic_constants.h>
#include <fmpm/parameters.h>
#include <fmpm/simulator.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <map>

#include "scene_helpers.h"
#include <gtest/gtest.h>

namespace
{
  using namespace dealii;

  /** Run a scene: parameter files from parameters/ plus overrides. */
  template <int dim>
  std::vector<fmpm::HistoryRow<dim>>
  run_scene(const std::vector<std::string> &files, const std::string &overrides)
  {
    auto sources = fmpm::load_scene_sources(files);
    sources.emplace_back("overrides", overrides);
    ParameterHandler prm;
    fmpm::Parameters parameters;
    fmpm::read_scene(sources, prm, parameters);
    fmpm::Simulator<dim> simulator(parameters, prm, MPI_COMM_WORLD);
    simulator.run();
    return fmpm_tests::inspect(simulator).get_history();
  }

  const std::string parameter_dir = FMPM_SOURCE_DIR "/parameters/";

  std::string
  output_overrides(const std::string &directory)
  {
    return "subsection Output\n set Directory = " + directory +
           "\n set Write vtu = false\nend\nsubsection Timer\n set Type = "
           "none\nend\n";
  }
} // namespace



// The bar of parameters/vibrating_bar.prm: v_cm(t) = (2 v0/pi) cos(omega t).
// FLIP with lumped mass must follow it within 3% of the amplitude for two
// periods (a factor 2 in the stiffness or mass or a sign error is off by
// 40% or more within the first period), and conserve energy within 2%.
TEST(WholeRun, VibratingBarFollowsAnalyticalSolution)
{
  for (const std::string update : {"usl", "usf"})
    {
      const auto history =
        run_scene<2>({parameter_dir + "vibrating_bar.prm"},
                     output_overrides("output-bar-" + update) +
                       "subsection Time\n set Strain update = " + update +
                       "\nend\n");
      const double v0 = 0.1, omega = M_PI / 2 * 10;
      const double amplitude = 2 * v0 / M_PI;
      ASSERT_GT(history.size(), 70u);
      double max_error = 0;
      for (const auto &row : history)
        {
          const double v_cm     = row.momentum[0] / row.mass;
          const double expected = amplitude * std::cos(omega * row.time);
          max_error = std::max(max_error, std::abs(v_cm - expected));
          EXPECT_NEAR(row.total_energy,
                      history.front().total_energy,
                      0.02 * history.front().total_energy);
        }
      EXPECT_LT(max_error, 0.03 * amplitude) << "strain update " << update;
      EXPECT_NEAR(history.back().time, 0.8, 1e-12);
    }
}



// A body in free flight (no walls, no gravity) translates rigidly: grad v = 0,
// no stress, momentum and kinetic energy exact, for FLIP and PIC, USF and USL.
TEST(WholeRun, FreeTranslationConservesMomentumAndEnergy)
{
  for (const std::string update : {"flip", "pic"})
    for (const std::string strain : {"usf", "usl"})
      {
        const auto history = run_scene<2>(
          {parameter_dir + "vibrating_bar.prm"},
          output_overrides("output-free-" + update + strain) +
            "subsection Reference solution\n set Enable = false\nend\n"
            "subsection Mesh\n set Upper corner = 1.5, 1.5\n"
            " set Subdivisions = 12, 12\nend\n"
            "subsection Boundary conditions\n set Roller boundary ids =\nend\n"
            "subsection Time\n set End time = 1\n set Strain update = " +
            strain +
            "\nend\n"
            "subsection Particle update\n set Model name = " +
            update +
            "\nend\n"
            "subsection Body 0\n set Initial velocity = 0.3, 0.2\n"
            " set Center = 0.4, 0.4\n set Half lengths = 0.2, 0.3\nend\n");
        const auto &first = history.front();
        for (const auto &row : history)
          {
            EXPECT_NEAR(row.momentum[0], first.momentum[0], 1e-12 * first.mass);
            EXPECT_NEAR(row.momentum[1], first.momentum[1], 1e-12 * first.mass);
            EXPECT_NEAR(row.kinetic_energy,
                        first.kinetic_energy,
                        1e-10 * first.kinetic_energy);
            EXPECT_LT(row.strain_energy, 1e-9 * first.kinetic_energy);
          }
        EXPECT_NEAR(first.momentum[0], 0.3 * first.mass, 1e-12 * first.mass);
      }
}



// The colliding disks: total energy stays within 10% of its initial value
// over the whole collision with FLIP, the total momentum stays zero, and the
// disks really interact (strain energy rises, kinetic energy drops).
TEST(WholeRun, CollidingDisksEnergyBounded)
{
  const auto history =
    run_scene<2>({parameter_dir + "colliding_disks.prm"},
                 output_overrides("output-disks") +
                   "subsection Time\n set End time = 2.5\nend\n");
  const double E0         = history.front().total_energy;
  double       max_strain = 0, min_kinetic = E0;
  for (const auto &row : history)
    {
      EXPECT_LT(row.total_energy, 1.10 * E0) << "t = " << row.time;
      EXPECT_GT(row.total_energy, 0.90 * E0) << "t = " << row.time;
      EXPECT_NEAR(row.momentum[0], 0, 1e-10 * row.mass);
      EXPECT_NEAR(row.momentum[1], 0, 1e-10 * row.mass);
      max_strain  = std::max(max_strain, row.strain_energy);
      min_kinetic = std::min(min_kinetic, row.kinetic_energy);
    }
  EXPECT_GT(max_strain, 0.3 * E0);
  EXPECT_LT(min_kinetic, 0.7 * E0);
}



namespace
{
  /** summary.json value of @p key (a number) in @p directory. */
  double
  summary_value(const std::string &directory, const std::string &key)
  {
    std::ifstream     in(directory + "/summary.json");
    const std::string text((std::istreambuf_iterator<char>(in)),
                           std::istreambuf_iterator<char>());
    const auto        at = text.find("\"" + key + "\": ");
    if (at == std::string::npos)
      return std::numeric_limits<double>::quiet_NaN();
    return std::stod(text.substr(at + key.size() + 4));
  }

  std::string
  method_overrides(const std::string &update,
                   const std::string &mass_matrix,
                   const unsigned int order = 3)
  {
    return "subsection Particle update\n set Model name = " + update +
           "\nend\nsubsection Mass matrix\n set Model name = " + mass_matrix +
           "\n subsection Fmpm\n  set Order = " + std::to_string(order) +
           "\n end\nend\n";
  }
} // namespace



// A spinning, translating disk in free flight: every particle update with the
// lumped, FMPM(3) and exact full mass matrices conserves total momentum to
// round-off (Σ_p M_p (S m̃ₖ⁻¹ q)_p = 1ᵀ m̃ m̃ₖ⁻¹ q = 1ᵀ q since the row sums of
// m̃ are m; the CG solve restores this identity after convergence). The
// consistent FE mass matrix does not (1ᵀ m̃ K⁻¹ q ≠ 1ᵀ q), nor do damped
// updates, by design. FLIP-type updates with the exact full mass matrix are
// left out: they blow up on this scene (see below).
TEST(WholeRun, EveryUpdateConservesMomentumInFreeFlight)
{
  for (const std::string mass : {"lumped", "fmpm", "full"})
    for (const std::string update : {"flip",
                                     "pic",
                                     "fmpm",
                                     "xpic",
                                     "fmpm0",
                                     "flip midpoint",
                                     "flip end velocity",
                                     "pic midpoint",
                                     "flip pic blend"})
      {
        // FLIP-type updates (a = S m̃⁻¹ f) with the exact full mass matrix
        // are unstable on this free-surface scene within a few steps (as is
        // FMPM(20)); the stability studies show it. Momentum is checked for
        // them with FMPM(3).
        const bool uses_acceleration = update == "flip" || update == "fmpm0" ||
                                       update == "flip midpoint" ||
                                       update == "flip end velocity";
        if (mass == "full" && uses_acceleration)
          continue;
        const auto history = run_scene<2>(
          {parameter_dir + "vibrating_bar.prm"},
          output_overrides("output-momentum") + method_overrides(update, mass) +
            "subsection Reference solution\n set Enable = false\nend\n"
            "subsection Mesh\n set Upper corner = 1, 1\n"
            " set Subdivisions = 10, 10\nend\n"
            "subsection Boundary conditions\n set Roller boundary ids =\nend\n"
            "subsection Time\n set End time = 0.1\n set Courant number = 0.3\n"
            " set Strain update = usf\n set Strain update mass matrix = lumped\n"
            "end\n"
            "subsection Material 0\n set Model name = neo hookean\n"
            " subsection Neo hookean\n  set Bulk modulus = 100\n"
            "  set Shear modulus = 40\n end\nend\n"
            "subsection Body 0\n set Shape = sphere\n set Center = 0.45, 0.5\n"
            " set Half lengths = 0.25, 0.25\n"
            " set Initial velocity = 0.5 - 2*(y-0.5), 0.2 + 2*(x-0.45)\n"
            "end\n");
        const auto &first = history.front();
        double      scale =
          std::abs(first.momentum[0]) + std::abs(first.momentum[1]);
        for (const auto &row : history)
          for (unsigned int d = 0; d < 2; ++d)
            EXPECT_NEAR(row.momentum[d], first.momentum[d], 1e-11 * scale)
              << update << " with " << mass << " at t = " << row.time;
        EXPECT_GT(history.back().strain_energy, 0) << update; // it deforms
      }
}



// The vibrating bar with every method: the full-mass-matrix methods keep the
// energy, PIC loses a fifth of it in two periods (seed 000 §2.3). Errors are
// printed per method for the record.
TEST(WholeRun, VibratingBarEnergyByMethod)
{
  struct Case
  {
    std::string  update, mass;
    unsigned int order;
  };
  const std::vector<Case>       cases = {{"flip", "lumped", 1},
                                         {"pic", "lumped", 1},
                                         {"xpic", "fmpm", 3},
                                         {"fmpm", "lumped", 1},
                                         {"fmpm", "fmpm", 2},
                                         {"fmpm", "fmpm", 5},
                                         {"fmpm", "full", 1}};
  std::map<std::string, double> energy_error, velocity_error;
  for (const auto &c : cases)
    {
      const std::string name =
        c.update + " " + c.mass +
        (c.mass == "fmpm" ? std::to_string(c.order) : "");
      const std::string dir = "output-bar-methods";
      run_scene<2>({parameter_dir + "vibrating_bar.prm"},
                   output_overrides(dir) +
                     method_overrides(c.update, c.mass, c.order) +
                     "subsection Time\n set Courant number = 0.3\nend\n");
      energy_error[name]   = summary_value(dir, "energy_error");
      velocity_error[name] = summary_value(dir, "error_velocity_l2");
      std::cout << "vibrating bar, " << name << ": velocity error "
                << velocity_error[name] << ", energy error "
                << energy_error[name] << std::endl;
    }
  EXPECT_LT(energy_error["pic lumped"], -0.1);
  EXPECT_LT(energy_error["fmpm lumped"], -0.1); // FMPM(1) is a PIC method
  for (const std::string name :
       {"fmpm fmpm2", "fmpm fmpm5", "fmpm full", "xpic fmpm3"})
    EXPECT_LT(std::abs(energy_error[name]),
              0.1 * std::abs(energy_error["pic lumped"]))
      << name;
  EXPECT_LT(std::abs(energy_error["fmpm fmpm5"]),
            std::abs(energy_error["fmpm fmpm2"]));
  EXPECT_LT(velocity_error["fmpm full"], 0.02);
  EXPECT_LT(velocity_error["flip lumped"], 0.02);
  EXPECT_GT(velocity_error["pic lumped"], 0.03);
}



namespace
{
  /** Reads the Simulator's lumped nodal masses through SimulatorAccess. */
  template <int dim>
  class NodalMassProbe : public fmpm::SimulatorAccess<dim>
  {
  public:
    double
    total_nodal_mass() const
    {
      return this->get_lumped_mass().l1_norm();
    }
  };
} // namespace



// The particle-to-grid extrapolation m = SᵀM conserves the total mass to
// round-off (after a few steps of the colliding disks, on a mesh with cells
// of three different sizes the points have crossed).
TEST(WholeRun, MassExtrapolationConservesMass)
{
  auto sources =
    fmpm::load_scene_sources({parameter_dir + "colliding_disks.prm"});
  sources.emplace_back(
    "overrides",
    output_overrides("output-mass") +
      "subsection Time\n set Maximum number of steps = 7\nend\n");
  ParameterHandler prm;
  fmpm::Parameters parameters;
  fmpm::read_scene(sources, prm, parameters);
  fmpm::Simulator<2> simulator(parameters, prm, MPI_COMM_WORLD);
  simulator.run();
  NodalMassProbe<2> probe;
  probe.initialize_simulator(simulator);
  const double total_point_mass =
    fmpm_tests::inspect(simulator).get_history().back().mass;
  EXPECT_NEAR(probe.total_nodal_mass(),
              total_point_mass,
              1e-12 * total_point_mass);
  EXPECT_GT(total_point_mass, 0);
}



// Manufactured solution with a linear velocity field (parameters/
// manufactured_linear.prm; seed 000 §2.3.4 says PIC from FMPM(1) is more
// stable there than PIC from XPIC(1)). Measured at Courant 0.9 over 3 s
// (5 periods), 10 s and Courant 1.0: both stay stable and accurate, with
// equal velocity errors (time-integrated 0.78 %, largest away from zero
// crossings 1.56 %) and XPIC(1) slightly better positions (0.62 % against
// 0.68 %): the claimed difference does not show here. The test pins that
// both track the solution (FLIP's noise, 2.8 % integrated, or a wrong wall
// velocity exceed these bounds).
TEST(WholeRun, LinearVelocityManufacturedSolutionFmpm1AndXpic1)
{
  std::map<std::string, std::pair<double, double>> errors;
  for (const std::string update : {"fmpm", "xpic"})
    {
      const auto history = run_scene<2>(
        {parameter_dir + "manufactured_linear.prm"},
        output_overrides("output-linear-mms-" + update) +
          "subsection Particle update\n set Model name = " + update +
          "\nend\nsubsection Time\n set End time = 3\n set Courant number "
          "= 0.9\nend\n");
      ASSERT_NEAR(history.back().time, 3, 1e-12);
      double max_velocity_error = 0, max_displacement_error = 0;
      // Relative errors, where the reference is not near a zero crossing.
      const double omega = 10;
      for (const auto &row : history)
        {
          if (std::abs(std::cos(omega * row.time)) > 0.5)
            max_velocity_error =
              std::max(max_velocity_error, row.error_velocity_l2);
          if (std::abs(std::sin(omega * row.time)) > 0.5)
            max_displacement_error =
              std::max(max_displacement_error, row.error_displacement_l2);
        }
      errors[update] = {max_velocity_error, max_displacement_error};
    }
  for (const auto &entry : errors)
    {
      std::cout << entry.first << ": max relative L2 velocity error "
                << entry.second.first << ", displacement error "
                << entry.second.second << std::endl;
      EXPECT_LT(entry.second.first, 0.03) << entry.first;
      EXPECT_LT(entry.second.second, 0.02) << entry.first;
    }
  EXPECT_NEAR(errors["fmpm"].first / errors["xpic"].first, 1, 0.1);
}



// Shape functions on the large-deformation manufactured bar (parameters/
// manufactured_bar.prm, points crossing up to 1.6 cells): CPDI and cpGIMP
// converge (measured velocity orders 1.17 and 1.05 over 16-128 cells, to
// t = 0.4 s) while classic shape functions diverge (order -0.55, errors
// 0.56 -> 1.85 from cell-crossing noise). The test halves the mesh size once
// (32 -> 64 cells, to t = 0.2 s): CPDI's error must drop by a factor > 1.6
// and stay 10 times below classic's.
TEST(WholeRun, ShapeFunctionsConvergeWithCellCrossing)
{
  std::map<std::string, std::map<unsigned int, double>> error;
  for (const std::string type : {"classic", "cpdi"})
    for (const unsigned int n : {32u, 64u})
      {
        const double h       = 1.0 / n;
        const auto   history = run_scene<2>(
          {parameter_dir + "manufactured_bar.prm"},
          output_overrides("output-bar-mms") +
            "subsection Shape function\n set Type = " + type +
            "\nend\nsubsection Mesh\n set Subdivisions = " + std::to_string(n) +
            ", 2\n set Upper corner = 1, " + std::to_string(2 * h) +
            "\nend\nsubsection Body 0\n set Center = 0.5, " +
            std::to_string(h) + "\n set Half lengths = 0.5, " +
            std::to_string(h) +
            "\nend\nsubsection Time\n set End time = 0.2\n set Time step = " +
            std::to_string(0.008 * h) + "\nend\n");
        ASSERT_NEAR(history.back().time, 0.2, 1e-9);
        // Root mean square over the outputs of the relative L2 error.
        double sum = 0;
        for (const auto &row : history)
          sum += row.error_velocity_l2 * row.error_velocity_l2;
        error[type][n] = std::sqrt(sum / history.size());
        std::cout << type << " n = " << n << ": velocity error "
                  << error[type][n] << std::endl;
      }
  EXPECT_GT(error["cpdi"][32] / error["cpdi"][64], 1.6);
  EXPECT_LT(10 * error["cpdi"][64], error["classic"][64]);
}



namespace
{
  /** A spinning, stretching disk in free flight (large strains). */
  std::string
  free_disk_scene(const std::string &material)
  {
    return "subsection Reference solution\n set Enable = false\nend\n"
           "subsection Mesh\n set Upper corner = 1, 1\n"
           " set Subdivisions = 10, 10\nend\n"
           "subsection Boundary conditions\n set Roller boundary ids =\nend\n"
           "subsection Time\n set End time = 0.3\n set Courant number = 0.2\n"
           " set Strain update = usf\n set Strain update mass matrix = lumped\n"
           "end\n"
           "subsection Material 0\n set Model name = neo hookean\n"
           " subsection Neo hookean\n" +
           material +
           " end\nend\n"
           "subsection Body 0\n set Shape = sphere\n set Center = 0.45, 0.5\n"
           " set Half lengths = 0.25, 0.25\n"
           " set Initial velocity = 0.5 + 1.5*(x-0.45), 0.2 - 1.5*(y-0.5)\n"
           "end\n";
  }
} // namespace



// 'Young's modulus' and 'Poisson's ratio' give the run of the bulk and shear
// moduli K = E/(3(1 - 2 nu)), G = E/(2(1 + nu)), to the bit.
TEST(WholeRun, YoungsModulusAndPoissonsRatioGiveTheSameRun)
{
  const double E = 130, nu = 0.35;
  const double K =
    fmpm::ConstitutiveModel::ElasticConstants::bulk_modulus_of(E, nu);
  const double G =
    fmpm::ConstitutiveModel::ElasticConstants::shear_modulus_of(E, nu);
  EXPECT_NEAR(K, E / (3 * (1 - 2 * nu)), 1e-14 * K);
  EXPECT_NEAR(G, E / (2 * (1 + nu)), 1e-14 * G);
  for (const std::string form : {"J^2", "ln J"})
    {
      const std::string form_line = "  set Energy form = " + form + "\n";
      const auto        by_E_nu =
        run_scene<2>({parameter_dir + "vibrating_bar.prm"},
                     output_overrides("output-elastic-e-nu") +
                       free_disk_scene(form_line +
                                       "  set Young's modulus = 130\n"
                                       "  set Poisson's ratio = 0.35\n"));
      const auto by_K_G = run_scene<2>(
        {parameter_dir + "vibrating_bar.prm"},
        output_overrides("output-elastic-k-g") +
          free_disk_scene(
            form_line + "  set Bulk modulus = " + fmpm::format_number(K) +
            "\n  set Shear modulus = " + fmpm::format_number(G) + "\n"));
      ASSERT_EQ(by_E_nu.size(), by_K_G.size());
      ASSERT_GT(by_E_nu.size(), 5u);
      EXPECT_GT(by_E_nu.back().strain_energy,
                0.05 * by_E_nu.back().kinetic_energy);
      for (unsigned int r = 0; r < by_E_nu.size(); ++r)
        {
          EXPECT_EQ(by_E_nu[r].time, by_K_G[r].time) << form;
          EXPECT_EQ(by_E_nu[r].kinetic_energy, by_K_G[r].kinetic_energy)
            << form;
          EXPECT_EQ(by_E_nu[r].strain_energy, by_K_G[r].strain_energy) << form;
          EXPECT_EQ(by_E_nu[r].momentum, by_K_G[r].momentum) << form;
        }
    }
}



// The 'ln J' neo-Hookean form conserves energy in a whole run as well as
// the 'J^2' form: the disk above on a 20 x 20 mesh with FLIP, the lumped
// mass matrix and the USAVG+ strain update ends with an energy error
// (E - E0)/E0 of 2-3e-5 with either form, while it stores a seventh of its
// energy as strain energy. A strain energy that is not the integral of the
// stress power (a wrong coefficient of (ln J)^2 or of ln J) breaks the
// balance by a good part of that.
TEST(WholeRun, LogJNeoHookeanConservesEnergy)
{
  for (const std::string form : {"J^2", "ln J"})
    {
      const std::string dir = "output-log-j-energy";
      const auto        history =
        run_scene<2>({parameter_dir + "vibrating_bar.prm"},
                     output_overrides(dir) +
                       free_disk_scene("  set Energy form = " + form +
                                       "\n  set Bulk modulus = 100\n"
                                       "  set Shear modulus = 40\n") +
                       "subsection Mesh\n set Subdivisions = 20, 20\nend\n"
                       "subsection Time\n set Strain update = usavg+\nend\n");
      double max_strain = 0;
      for (const auto &row : history)
        max_strain = std::max(max_strain, row.strain_energy);
      const double energy_error = summary_value(dir, "energy_error");
      std::cout << "free disk, energy form " << form << ": energy error "
                << energy_error << ", largest strain energy / initial "
                << "total " << max_strain / history.front().total_energy
                << std::endl;
      EXPECT_GT(max_strain, 0.1 * history.front().total_energy) << form;
      EXPECT_LT(std::abs(energy_error), 2e-4) << form;
    }
}
