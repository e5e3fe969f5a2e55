// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Periodic boxes (Mesh/Periodic directions): simple shear of a neo-Hookean
// block to gamma = 1 (sigma_xy = G gamma exactly), a block translating
// through the periodic faces (rigid: no strain, u = v t), and the scenes
// that are refused.

#include <fmpm/particle_properties.h>

#include <cmath>
#include <string>

#include "scene_helpers.h"
#include <gtest/gtest.h>

namespace
{
  using namespace fmpm_tests;
  using Index = fmpm::PropertyIndex<2>;

  /** Volume average of sigma_xy, the largest |J - 1| and the number of
   * points that crossed the periodic face (their initial position moved
   * below x = 0 with them). */
  struct ShearResult
  {
    double       mean_shear_stress = 0;
    double       max_volume_change = 0;
    unsigned int n_crossed         = 0;
    double       lowest_x = 1e300, highest_x = -1e300;
  };

  ShearResult
  run_shear(const std::string &overrides)
  {
    ParameterHandler prm;
    auto             simulator =
      make_simulator<2>({parameter_dir + "simple_shear.prm"},
                        output_overrides("output-simple-shear") + overrides,
                        prm);
    simulator->run();
    const auto &points = fmpm_tests::inspect(*simulator).get_material_points();
    ShearResult result;
    double      volume = 0;
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const double V = points.column(Index::volume)[k];
        volume += V;
        // (2D: xx, yy, zz, xy at stored slots 0, 1, 2, 3.)
        result.mean_shear_stress += V * points.column(Index::stress + 3)[k];
        result.max_volume_change =
          std::max(result.max_volume_change,
                   std::abs(V / points.column(Index::initial_volume)[k] - 1));
        if (points.column(Index::initial_position)[k] < 0)
          ++result.n_crossed;
        result.lowest_x  = std::min(result.lowest_x, points.position[k][0]);
        result.highest_x = std::max(result.highest_x, points.position[k][0]);
      }
    result.mean_shear_stress /= volume;
    return result;
  }



  // parameters/simple_shear.prm: fixed bottom, top sliding along x to
  // gamma = 1, periodic in x. Neo-Hookean with J = 1: sigma_xy = G gamma =
  // 100 Pa. Dynamic (the wall drives the block) with FLIP, FMPM(5) and the
  // exact full-mass solve; kinematic: every node row y_j moves with
  // v_x = gamma' y_j (a region wall per row). The volume average is within
  // 1 % of G gamma (a block that misses the momentum or mass of the twin
  // face's nodes tears there; with free sides it reaches only 30 % of G
  // gamma); the points near the top travel a whole period and re-enter at
  // x = 0.
  TEST(Periodic, SimpleShearReachesGGamma)
  {
    const double      G = 100, gamma = 1;
    const std::string fmpm5 =
      "subsection Particle update\n set Model name = fmpm\nend\n"
      "subsection Mass matrix\n set Model name = fmpm\n subsection Fmpm\n"
      "  set Order = 5\n end\nend\n";
    const std::string full =
      "subsection Particle update\n set Model name = fmpm\nend\n"
      "subsection Mass matrix\n set Model name = full\nend\n";
    std::string kinematic =
      "set Number of moving walls = 8\nsubsection Boundary conditions\n";
    for (unsigned int j = 1; j < 8; ++j)
      kinematic +=
        " subsection Moving wall " + std::to_string(j) +
        "\n  set Boundary ids =\n  set Region = 0.03125 - abs(y - " +
        std::to_string(j / 8.) +
        ")\n  set Direction = 1, 0\n"
        "  set Velocity = (t < t0 ? V*(1 - cos(pi*t/t0))/2 : V)*" +
        std::to_string(j / 8.) +
        "\n  set Function constants = V=0.25, t0=1, pi=3.141592653589793\n"
        " end\n";
    kinematic += "end\n";
    for (const auto &[name, overrides] :
         std::vector<std::pair<std::string, std::string>>{{"FLIP", ""},
                                                          {"FMPM(5)", fmpm5},
                                                          {"full", full},
                                                          {"kinematic",
                                                           kinematic}})
      {
        const ShearResult result = run_shear(overrides);
        EXPECT_NEAR(result.mean_shear_stress, G * gamma, 0.01 * G * gamma)
          << name;
        EXPECT_LT(result.max_volume_change, 1e-3) << name;
        // The top two rows of points (16 points each) travel more than
        // 0.8 m: each of their points has crossed x = 1 once or not.
        EXPECT_GE(result.n_crossed, 8u) << name;
        EXPECT_GE(result.lowest_x, 0) << name;
        EXPECT_LT(result.highest_x, 1) << name;
      }
  }



  // A block that does not fill the box, free flight with v = (0.3, 0.2) in
  // a box periodic in x and y, for 4 s: it crosses both faces (and the
  // corner) and straddles them. Rigid translation: the strain energy stays
  // zero, momentum and kinetic energy keep their values, every point's
  // displacement x - X is v t (the initial position moves with the point at
  // each crossing), and every point is inside the box: a point that is not
  // brought back is lost (mass drops) or leaves the box. (The nodal sums
  // across a face are what the simple shear tests: a uniform velocity is
  // the same on both sides of the face, joined or not.)
  TEST(Periodic, BlockTranslatesThroughPeriodicFaces)
  {
    for (const std::string update : {"flip", "pic"})
      {
        ParameterHandler prm;
        auto             simulator = make_simulator<2>(
          {parameter_dir + "vibrating_bar.prm"},
          output_overrides("output-periodic-translation") +
            "subsection Reference solution\n set Enable = false\nend\n"
                        "subsection Mesh\n set Upper corner = 1, 1\n"
                        " set Subdivisions = 8, 8\n set Periodic directions = x, y\nend\n"
                        "subsection Boundary conditions\n set Roller boundary ids =\nend\n"
                        "subsection Time\n set End time = 4\n set Strain update = usf\n"
                        "end\n"
                        "subsection Particle update\n set Model name = " +
            update +
            "\nend\n"
                        "subsection Body 0\n set Initial velocity = 0.3, 0.2\n"
                        " set Center = 0.7, 0.6\n set Half lengths = 0.25, 0.25\nend\n",
          prm);
        simulator->run();
        const auto &history = fmpm_tests::inspect(*simulator).get_history();
        const auto &first   = history.front();
        for (const auto &row : history)
          {
            EXPECT_NEAR(row.momentum[0], 0.3 * first.mass, 1e-12) << update;
            EXPECT_NEAR(row.momentum[1], 0.2 * first.mass, 1e-12) << update;
            EXPECT_NEAR(row.kinetic_energy,
                        first.kinetic_energy,
                        1e-10 * first.kinetic_energy)
              << update;
            EXPECT_LT(row.strain_energy, 1e-9 * first.kinetic_energy) << update;
          }
        EXPECT_NEAR(history.back().time, 4, 1e-12);
        const auto &points =
          fmpm_tests::inspect(*simulator).get_material_points();
        unsigned int n_wrapped = 0;
        for (unsigned int k = 0; k < points.n_points(); ++k)
          for (unsigned int d = 0; d < 2; ++d)
            {
              const double x = points.position[k][d];
              const double X = points.column(Index::initial_position + d)[k];
              EXPECT_NEAR(x - X, (d == 0 ? 0.3 : 0.2) * 4, 1e-10) << update;
              EXPECT_GE(x, 0) << update;
              EXPECT_LT(x, 1) << update;
              if (X < 0)
                ++n_wrapped;
            }
        // (After 1.2 m along x and 0.8 m along y every point has crossed
        // x = 1, and those starting above y = 0.2 also y = 1.)
        EXPECT_GT(n_wrapped, points.n_points()) << update;
      }
  }



  // Scenes that periodicity does not support are refused with a message
  // naming the parameter.
  TEST(Periodic, UnsupportedScenesAreRefused)
  {
    const std::vector<std::pair<std::string, std::vector<std::string>>> cases =
      {{"subsection Mesh\n set Periodic directions = z\nend\n",
        {"Mesh/Periodic directions", "x, y."}},
       {"subsection Mesh\n set Type = ball\nend\n",
        {"Mesh/Periodic directions", "Mesh/Type = box", "ball"}},
       {"subsection Shape function\n set Type = ugimp\nend\n",
        {"Mesh/Periodic directions", "classic", "ugimp"}},
       {"subsection Boundary conditions\n set Fixed boundary ids = 1, 2\n"
        "end\n",
        {"Fixed boundary ids", "boundary id 1", "periodic direction x"}},
       {"subsection Boundary conditions\n subsection Moving wall 0\n"
        "  set Boundary ids = 0\n end\nend\n",
        {"Moving wall 0/Boundary ids", "boundary id 0"}}};
    for (const auto &[setting, words] : cases)
      {
        ParameterHandler prm;
        try
          {
            make_simulator<2>({parameter_dir + "simple_shear.prm"},
                              output_overrides("output-periodic-bad") + setting,
                              prm);
            ADD_FAILURE() << "accepted: " << setting;
          }
        catch (const std::exception &e)
          {
            for (const auto &word : words)
              EXPECT_NE(std::string(e.what()).find(word), std::string::npos)
                << e.what();
          }
      }
  }
} // namespace
