// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// summary.json's energy_error (E - E0 - W) / scale with the potential
// energy measured from the initial configuration and the scale the largest
// of KE0 + SE0 and the energy moved between kinetic, strain and potential:
// small when a run keeps the energy, the lost share when it dissipates, and
// independent of the origin and of the empty mesh. Also the exact output
// times of Output/Interval.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "scene_helpers.h"
#include <gtest/gtest.h>

using namespace fmpm_tests;

namespace
{
  /** A value of summary.json in @p directory. */
  double
  summary_number(const std::string &directory, const std::string &key)
  {
    std::ifstream     file(directory + "/summary.json");
    std::stringstream text;
    text << file.rdbuf();
    const std::string json = text.str();
    const auto        at   = json.find("\"" + key + "\": ");
    if (at == std::string::npos)
      return std::nan("");
    return std::stod(json.substr(at + key.size() + 4));
  }

  /**
   * An elastic block (0.5 m x 0.5 m, E = 1 MPa, rho = 1000) released
   * stress-free on a roller floor under gravity: it sags and vibrates about
   * its static state. The mesh of cells h = 1/16 starts at @p origin and
   * has @p rows_above empty rows of cells above the block's 8 rows.
   */
  std::string
  sagging_block(const std::string &directory,
                const std::string &update,
                const Point<2>    &origin,
                const unsigned int rows_above)
  {
    const unsigned int rows = 8 + rows_above;
    std::ostringstream scene;
    scene << std::setprecision(17);
    scene << "set Dimension = 2\n"
          << "subsection Mesh\n set Lower corner = " << origin[0] << ", "
          << origin[1] << "\n set Upper corner = " << origin[0] + 1 << ", "
          << origin[1] + rows / 16. << "\n set Subdivisions = 16, " << rows
          << "\nend\n"
          << "subsection Boundary conditions\n set Roller boundary ids = 2\n"
          << "end\n"
          << "subsection Body force\n set Gravity = 0, -10\nend\n"
          << "subsection Material 0\n set Density = 1000\n"
          << " subsection Linear elastic\n  set Young's modulus = 1e6\n"
          << "  set Poisson's ratio = 0.3\n end\nend\n"
          << "subsection Body 0\n set Center = " << origin[0] + 0.5 << ", "
          << origin[1] + 0.25 << "\n set Half lengths = 0.25, 0.25\nend\n"
          << "subsection Particle update\n set Model name = " << update
          << "\nend\n"
          << "subsection Time\n set End time = 0.2\n set Courant number = 0.4\n"
          << "end\n"
          << "subsection Output\n set Interval = 0.005\nend\n"
          << output_overrides(directory);
    return scene.str();
  }

  double
  sagging_block_energy_error(const std::string &update,
                             const Point<2>    &origin,
                             const unsigned int rows_above)
  {
    const std::string directory = "output-energy-balance";
    ParameterHandler  prm;
    auto              simulator =
      make_simulator<2>({},
                        sagging_block(directory, update, origin, rows_above),
                        prm);
    simulator->run();
    const double error = summary_number(directory, "energy_error");
    std::cout << update << ", origin (" << origin << "), " << rows_above
              << " empty rows: energy_error " << error << ", scale "
              << summary_number(directory, "energy_error_scale") << std::endl;
    return error;
  }
} // namespace



// FLIP keeps the energy of the sagging block; PIC damps the vibration and
// loses a large share of the energy gravity moved into it (at rest in its
// static state it would have lost half of the potential energy released,
// a quarter of the largest excursion).
TEST(EnergyBalance, ConservingAndDissipatingRuns)
{
  const double flip = sagging_block_energy_error("flip", Point<2>(), 4);
  const double pic  = sagging_block_energy_error("pic", Point<2>(), 4);
  EXPECT_LT(std::abs(flip), 0.04); // -0.016 measured
  EXPECT_LT(pic, -0.15);           // -0.28 measured
}



// energy_error is the share of the exchanged energy the run lost, as one
// computes it from history.csv: (E_end − E_0) over the largest of KE_0 +
// SE_0 and the largest change of the kinetic, strain and potential energy
// at the outputs. (The cantilever's FMPM(32) run, doc/studies/cantilever.md,
// loses 8,642 J of the 76,392 J gravity moved into it and reports −0.113.)
TEST(EnergyBalance, ReportsTheShareOfTheExchangedEnergyLost)
{
  const std::string directory = "output-energy-balance-share";
  ParameterHandler  prm;
  auto              simulator =
    make_simulator<2>({}, sagging_block(directory, "pic", Point<2>(), 4), prm);
  simulator->run();
  const auto &history = fmpm_tests::inspect(*simulator).get_history();
  ASSERT_GT(history.size(), 10u);
  const auto &first     = history.front();
  double      exchanged = first.kinetic_energy + first.strain_energy;
  for (const auto &row : history)
    exchanged =
      std::max({exchanged,
                std::abs(row.kinetic_energy - first.kinetic_energy),
                std::abs(row.strain_energy - first.strain_energy),
                std::abs(row.potential_energy - first.potential_energy)});
  const double lost_share =
    (history.back().total_energy - first.total_energy) / exchanged;
  const double energy_error = summary_number(directory, "energy_error");
  std::cout << "lost share " << lost_share << ", energy_error " << energy_error
            << std::endl;
  EXPECT_LT(lost_share, -0.15);
  EXPECT_NEAR(energy_error, lost_share, 2e-3);
}



// The energy balance does not depend on where the origin lies (the
// potential energy is measured from the initial configuration) nor on how
// much empty mesh surrounds the body (the scale is the energy the run
// moves, not the work gravity could do across the mesh).
TEST(EnergyBalance, IndependentOfOriginAndEmptyMesh)
{
  const double reference = sagging_block_energy_error("pic", Point<2>(), 4);
  const double shifted = sagging_block_energy_error("pic", Point<2>(3, -7), 4);
  const double larger_mesh = sagging_block_energy_error("pic", Point<2>(), 40);
  EXPECT_NEAR(shifted, reference, 1e-6 * std::abs(reference));
  EXPECT_NEAR(larger_mesh, reference, 1e-6 * std::abs(reference));
}



// Output/Interval with Exact output times = true: the history rows
// lie at the multiples of the interval although the automatic time step
// does not divide it; without, at the first step past each multiple.
TEST(EnergyBalance, ExactOutputTimes)
{
  for (const bool exact : {true, false})
    {
      ParameterHandler  prm;
      const std::string overrides =
        sagging_block("output-exact-times", "flip", Point<2>(), 4) +
        "subsection Output\n set Interval = 0.0123\n set Exact output times = " +
        (exact ? "true" : "false") + "\nend\n";
      auto simulator = make_simulator<2>({}, overrides, prm);
      simulator->run();
      const auto  &rows  = fmpm_tests::inspect(*simulator).get_history();
      unsigned int n_off = 0;
      for (unsigned int r = 0; r + 1 < rows.size(); ++r)
        {
          const double multiple = std::round(rows[r].time / 0.0123) * 0.0123;
          EXPECT_NEAR(rows[r].time, r * 0.0123, exact ? 1e-12 : 1e-2);
          n_off += std::abs(rows[r].time - multiple) > 1e-9;
        }
      // Rows at 0, 0.0123, ..., 0.1968, then the end time 0.2.
      EXPECT_EQ(rows.size(), 18u);
      EXPECT_NEAR(rows.back().time, 0.2, 1e-14);
      if (exact)
        EXPECT_EQ(n_off, 0u);
      else
        EXPECT_GT(n_off, 10u);
    }
}
