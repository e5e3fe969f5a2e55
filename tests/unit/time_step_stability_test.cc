// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks fmpm::stability_limit, the stability factors of the automatic time
// step: 1 for the lumped mass matrix with every update and strain update
// (so lumped-mass runs keep their time steps); FMPM(k)'s factor falls with
// k from 1 to the full matrix's and never rises; lumped strain velocities
// are at least as stable as full-mass ones; FLIP-type updates get at most
// the leapfrog limit; FLIP with the full matrix and the consistent matrix
// carry a warning naming the alternative; Time/Stability factor is checked.

#include <fmpm/parameters.h>
#include <fmpm/time_step_stability.h>

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  const std::vector<std::string> strain_updates = {"usf",
                                                   "usl",
                                                   "usl+",
                                                   "usavg",
                                                   "usavg+"};

  fmpm::StabilityMethod
  method(const std::string &mass,
         const unsigned int order,
         const bool         flip_type,
         const std::string &strain_update,
         const std::string &strain_mass = "same")
  {
    fmpm::StabilityMethod m;
    m.mass_matrix               = mass;
    m.order                     = order;
    m.flip_type                 = flip_type;
    m.strain_update             = strain_update;
    m.strain_update_mass_matrix = strain_mass;
    return m;
  }



  TEST(StabilityLimit, LumpedIsOne)
  {
    for (const auto &su : strain_updates)
      for (const bool flip : {false, true})
        {
          EXPECT_EQ(fmpm::stability_limit(method("lumped", 1, flip, su)).factor,
                    1.0);
          EXPECT_EQ(fmpm::stability_limit(method("fmpm", 1, flip, su)).factor,
                    1.0);
          EXPECT_TRUE(fmpm::stability_limit(method("lumped", 1, flip, su))
                        .warning.empty());
        }
  }



  TEST(StabilityLimit, FallsWithTheOrder)
  {
    for (const auto &su : strain_updates)
      for (const bool flip : {false, true})
        for (const std::string strain_mass : {"same", "lumped"})
          {
            double previous = 1, order_10 = 1;
            for (unsigned int k = 1; k <= 100; ++k)
              {
                const double f = fmpm::stability_limit(
                                   method("fmpm", k, flip, su, strain_mass))
                                   .factor;
                EXPECT_LE(f, previous) << su << " k = " << k;
                EXPECT_GT(f, 0);
                previous = f;
                if (k == 10)
                  order_10 = f;
              }
            const double full =
              fmpm::stability_limit(
                method("full", 1000000, flip, su, strain_mass))
                .factor;
            EXPECT_LE(full, order_10 + 1e-12) << su;
            // Lumped strain velocities: at least as stable.
            if (strain_mass == "lumped")
              {
                EXPECT_GE(full,
                          fmpm::stability_limit(
                            method("full", 1000000, flip, su, "same"))
                            .factor);
              }
          }
    // The measured values (doc/studies/stability.md).
    EXPECT_DOUBLE_EQ(
      fmpm::stability_limit(method("fmpm", 2, false, "usavg+")).factor, 0.9);
    EXPECT_DOUBLE_EQ(
      fmpm::stability_limit(method("fmpm", 5, false, "usavg+")).factor, 0.6);
    EXPECT_DOUBLE_EQ(
      fmpm::stability_limit(method("full", 1000000, false, "usavg+")).factor,
      1. / 3);
    // FLIP-type updates: the leapfrog limit 1/sqrt(1 + 3/4) for k = 2.
    EXPECT_NEAR(fmpm::stability_limit(method("fmpm", 2, true, "usavg+")).factor,
                1 / std::sqrt(1.75),
                1e-12);
  }



  TEST(StabilityLimit, KnownFailuresAreWarned)
  {
    const auto flip_full =
      fmpm::stability_limit(method("full", 1000000, true, "usavg+"));
    EXPECT_NE(flip_full.warning.find("Particle update/Model name = fmpm"),
              std::string::npos)
      << flip_full.warning;
    EXPECT_TRUE(fmpm::stability_limit(method("full", 1000000, false, "usavg+"))
                  .warning.empty());
    const auto consistent =
      fmpm::stability_limit(method("consistent", 1, false, "usl"));
    EXPECT_NE(consistent.warning.find("free surfaces"), std::string::npos);
    EXPECT_LT(consistent.factor, 1);
  }



  // High orders with full-mass strain velocities: the colliding disks fail
  // at C = 0.133 for k = 32 and at 0.1 for k = 64 (stable at 0.1 and 0.05),
  // so the factor must fall below those; k = 24 is stable at the full
  // matrix's 1/3 x 0.4.
  TEST(StabilityLimit, HighOrdersFallAsOneOverK)
  {
    for (const auto &su : {"usavg+", "usl"})
      {
        EXPECT_LE(0.4 *
                    fmpm::stability_limit(method("fmpm", 32, false, su)).factor,
                  0.1 + 1e-12);
        EXPECT_LE(0.4 *
                    fmpm::stability_limit(method("fmpm", 64, false, su)).factor,
                  0.05 + 1e-12);
        EXPECT_GE(fmpm::stability_limit(method("fmpm", 64, false, su)).factor,
                  0.04);
      }
  }



  // doc/studies/stability.md "Large compression": FMPM/XPIC of k >= 3 and
  // the exact solve with psi > 0 get a note naming psi = 0; k <= 2, psi = 0,
  // FLIP-type updates and the lumped matrix get none.
  TEST(StabilityLimit, LargeCompressionNoteNamesPsi)
  {
    auto note = [](const std::string &mass,
                   const unsigned int order,
                   const bool         flip_type,
                   const double       psi) {
      fmpm::StabilityMethod m = method(mass, order, flip_type, "usavg+");
      m.position_update_psi   = psi;
      return fmpm::stability_limit(m).note;
    };
    for (const unsigned int k : {3u, 5u, 10u, 20u})
      for (const double psi : {1., 0.25})
        EXPECT_NE(note("fmpm", k, false, psi).find("Position update psi = 0"),
                  std::string::npos)
          << k << ' ' << psi;
    EXPECT_NE(note("full", 1000000, false, 1).find("Large compression"),
              std::string::npos);
    EXPECT_TRUE(note("fmpm", 2, false, 1).empty());
    EXPECT_TRUE(note("fmpm", 5, false, 0).empty());
    EXPECT_TRUE(note("fmpm", 5, true, 1).empty());
    EXPECT_TRUE(note("lumped", 1, false, 1).empty());
  }



  TEST(StabilityLimit, ParameterIsChecked)
  {
    for (const std::string value : {"0", "1.5", "fast", "0.5x"})
      {
        dealii::ParameterHandler prm;
        fmpm::Parameters         parameters;
        try
          {
            fmpm::read_scene({{"default scene", fmpm::default_scene()},
                              {"factor.prm",
                               "subsection Time\n set Stability factor = " +
                                 value + "\nend\n"}},
                             prm,
                             parameters);
            ADD_FAILURE() << value << " was accepted";
          }
        catch (const std::exception &e)
          {
            EXPECT_NE(fmpm::error_message(e).find("Time/Stability factor = <" +
                                                  value + ">"),
                      std::string::npos)
              << fmpm::error_message(e);
          }
      }
    dealii::ParameterHandler prm;
    fmpm::Parameters         parameters;
    fmpm::read_scene({{"default scene", fmpm::default_scene()},
                      {"factor.prm",
                       "subsection Time\n set Stability factor = 0.5\nend\n"}},
                     prm,
                     parameters);
    EXPECT_EQ(parameters.time.stability_factor, 0.5);
  }
} // namespace
