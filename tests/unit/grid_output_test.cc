// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// What a run writes on request: the grid acceleration of seed 000 Eq. 4.1.

#include <fmpm/simulator.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "scene_helpers.h"
#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  // Output/Write grid acceleration (seed 000 Eq. 4.1): in the first step of a
  // block falling under gravity, a = g at every node with mass, for the lumped
  // mass and for FMPM(3) (m̃ 1 = m, so the series returns g exactly); on a
  // fixed bottom a_y = 0 at its nodes, and FMPM(3)'s constrained series keeps
  // g three node rows away from them.
  TEST(GridOutput, AccelerationOfEq41)
  {
    const double g = -9.81;
    for (const bool fixed_bottom : {false, true})
      for (const std::string mass_matrix : {"lumped", "fmpm"})
        {
          const std::string directory = "output-grid-acceleration-" +
                                        mass_matrix +
                                        (fixed_bottom ? "-fixed" : "-free");
          ParameterHandler prm;
          auto             simulator = fmpm_tests::make_simulator<2>(
            {fmpm_tests::parameter_dir + "vibrating_bar.prm"},
            fmpm_tests::output_overrides(directory) +
              "subsection Body force\n set Gravity = 0, " + std::to_string(g) +
              "\nend\nsubsection Reference solution\n set Enable = false\nend\n"
                          "subsection Mesh\n set Upper corner = 1, 1\n"
                          " set Subdivisions = 8, 8\nend\n"
                          "subsection Boundary conditions\n set Roller boundary ids =\n"
                          " set Fixed boundary ids = " +
              (fixed_bottom ? "2" : "") +
              "\nend\n"
                          "subsection Time\n set Maximum number of steps = 1\nend\n"
                          "subsection Mass matrix\n set Model name = " +
              mass_matrix +
              "\n subsection Fmpm\n  set Order = 3\n end\nend\n"
                          "subsection Particle update\n set Model name = " +
              (mass_matrix == "fmpm" ? "fmpm" : "flip") +
              "\nend\n"
                          "subsection Body 0\n set Initial velocity = 0, 0\n"
                          " set Center = 0.5, 0.375\n set Half lengths = 0.25, 0.375\nend\n"
                          "subsection Output\n set Write vtu = true\n"
                          " set Write grid acceleration = true\nend\n",
            prm);
          simulator->run();
          const auto &a = fmpm_tests::inspect(*simulator)
                            .get_grid_field(fmpm::ParticleUpdate::acceleration);
          const auto &dofs = fmpm_tests::inspect(*simulator).get_dof_handler();
          // Node heights from the DoF support points (Q1: the vertices).
          std::map<types::global_dof_index, double> height;
          for (const auto &cell : dofs.active_cell_iterators())
            {
              std::vector<types::global_dof_index> indices(
                dofs.get_fe().n_dofs_per_cell());
              cell->get_dof_indices(indices);
              for (unsigned int v = 0; v < 4; ++v)
                height[indices[v]] = cell->vertex(v)[1];
            }
          unsigned int n_gravity = 0;
          for (const auto &[dof, y] : height)
            {
              const double ax = a.block(0)[dof], ay = a.block(1)[dof];
              EXPECT_NEAR(ax, 0, 1e-12) << directory << " node " << dof;
              if (fixed_bottom && y < 1e-12)
                EXPECT_EQ(ay, 0.) << directory << " held node " << dof;
              else if (ay != 0 && // nodes without mass have none
                       (mass_matrix == "lumped" || !fixed_bottom || y > 0.3))
                {
                  EXPECT_NEAR(ay, g, 1e-10) << directory << " y = " << y;
                  ++n_gravity;
                }
            }
          EXPECT_GT(n_gravity, 15u) << directory;
        }
  }
} // namespace
