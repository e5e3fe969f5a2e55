// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks the mass matrices' stability_limit(), the measured critical Courant
// numbers that cap the automatic time step's: none for the lumped mass matrix
// with every update and strain update (so lumped-mass runs keep their time
// steps); FMPM(k)'s limit falls with k to the full matrix's and never rises;
// lumped strain velocities are at least as stable as full-mass ones; FLIP-type
// updates get at most the leapfrog limit; FLIP with the full matrix and the
// consistent matrix carry a warning naming the alternative; Time/Courant
// number limit is checked.

#include <fmpm/mass_matrix/interface.h>
#include <fmpm/parameters.h>
#include <fmpm/shape_function.h>
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

  /** A mass matrix (its order k for 'fmpm', periodic or not) and the rest
   * of the method. */
  struct Case
  {
    std::string           mass;
    unsigned int          order    = 1;
    bool                  periodic = false;
    fmpm::StabilityMethod method;
  };

  Case
  method(const std::string &mass,
         const unsigned int order,
         const bool         flip_type,
         const std::string &strain_update,
         const std::string &strain_mass = "same")
  {
    Case c;
    c.mass                 = mass;
    c.order                = order;
    c.method.flip_type     = flip_type;
    c.method.strain_update = fmpm::StrainUpdateScheme::of(strain_update);
    c.method.lumped_strain_velocities = strain_mass == "lumped";
    return c;
  }

  /** The limit the mass matrix plugin of @p c answers. */
  fmpm::StabilityLimit
  stability_limit(const Case &c)
  {
    using Registry = fmpm::MassMatrix::Registry<2>;
    dealii::ParameterHandler prm;
    Registry::instance().declare_parameters(prm);
    if (c.mass == "fmpm")
      {
        prm.enter_subsection("Fmpm");
        prm.set("Order", std::to_string(c.order));
        if (c.periodic)
          prm.set("Period", "5");
        prm.leave_subsection();
      }
    return Registry::instance().create(c.mass, prm)->stability_limit(c.method);
  }



  TEST(StabilityLimit, LumpedHasNone)
  {
    for (const auto &su : strain_updates)
      for (const bool flip : {false, true})
        {
          EXPECT_TRUE(std::isinf(
            stability_limit(method("lumped", 1, flip, su)).max_courant));
          EXPECT_TRUE(std::isinf(
            stability_limit(method("fmpm", 1, flip, su)).max_courant));
          EXPECT_TRUE(
            stability_limit(method("lumped", 1, flip, su)).warning.empty());
        }
  }



  TEST(StabilityLimit, FallsWithTheOrder)
  {
    for (const auto &su : strain_updates)
      for (const bool flip : {false, true})
        for (const std::string strain_mass : {"same", "lumped"})
          {
            double previous = 1, order_10 = 1;
            for (unsigned int k = 2; k <= 100; ++k)
              {
                const double c =
                  stability_limit(method("fmpm", k, flip, su, strain_mass))
                    .max_courant;
                EXPECT_LE(c, previous) << su << " k = " << k;
                EXPECT_GT(c, 0);
                previous = c;
                if (k == 10)
                  order_10 = c;
              }
            const double full =
              stability_limit(method("full", 1000000, flip, su, strain_mass))
                .max_courant;
            EXPECT_LE(full, order_10 + 1e-12) << su;
            // Lumped strain velocities: at least as stable.
            if (strain_mass == "lumped")
              {
                EXPECT_GE(full,
                          stability_limit(
                            method("full", 1000000, flip, su, "same"))
                            .max_courant);
              }
          }
    // The measured values (doc/studies/stability.md): the bar's critical
    // Courant numbers, and the rigid rotation's for the full matrix.
    EXPECT_DOUBLE_EQ(
      stability_limit(method("fmpm", 2, false, "usavg+")).max_courant, 0.9);
    EXPECT_DOUBLE_EQ(
      stability_limit(method("fmpm", 5, false, "usavg+")).max_courant, 0.6);
    EXPECT_DOUBLE_EQ(
      stability_limit(method("fmpm", 5, false, "usl")).max_courant, 0.5);
    EXPECT_DOUBLE_EQ(
      stability_limit(method("full", 1000000, false, "usavg+")).max_courant,
      0.12);
    // NairnMPM's bar runs FMPM(5) at Courant 0.5 (USAVG+): below the limit,
    // so at the requested time step.
    EXPECT_GT(stability_limit(method("fmpm", 5, false, "usavg+")).max_courant,
              0.5);
    // FLIP-type updates: the leapfrog limit 1/sqrt(1 + 3/4) for k = 2 of
    // the lumped limit (1 with USAVG+, 0.75 with USL-).
    EXPECT_NEAR(stability_limit(method("fmpm", 2, true, "usavg+")).max_courant,
                1 / std::sqrt(1.75),
                1e-12);
    EXPECT_NEAR(stability_limit(method("fmpm", 2, true, "usl")).max_courant,
                0.75 / std::sqrt(1.75),
                1e-12);
  }



  TEST(StabilityLimit, KnownFailuresAreWarned)
  {
    const auto flip_full =
      stability_limit(method("full", 1000000, true, "usavg+"));
    EXPECT_NE(flip_full.warning.find("Particle update/Model name = fmpm"),
              std::string::npos)
      << flip_full.warning;
    EXPECT_TRUE(stability_limit(method("full", 1000000, false, "usavg+"))
                  .warning.empty());
    const auto consistent =
      stability_limit(method("consistent", 1, false, "usl"));
    EXPECT_NE(consistent.warning.find("free surfaces"), std::string::npos);
    EXPECT_LT(consistent.max_courant, 1);
  }



  // High orders with full-mass strain velocities: the rigid rotation fails
  // at C = 0.1 for k = 32 (stable at 0.08) and at 3.2/k for k = 12-32, the
  // colliding disks at 0.1 for k = 64 (stable at 0.05), so the limit must
  // lie below those.
  TEST(StabilityLimit, HighOrdersFallAsOneOverK)
  {
    for (const auto &su : {"usavg+", "usl"})
      {
        EXPECT_LE(stability_limit(method("fmpm", 32, false, su)).max_courant,
                  0.08 + 1e-12);
        for (const unsigned int k : {12u, 16u, 24u, 32u})
          EXPECT_LT(stability_limit(method("fmpm", k, false, su)).max_courant,
                    3.2 / k);
        EXPECT_LE(stability_limit(method("fmpm", 64, false, su)).max_courant,
                  0.05 + 1e-12);
        EXPECT_GE(stability_limit(method("fmpm", 64, false, su)).max_courant,
                  0.035);
        EXPECT_LE(stability_limit(method("fmpm", 24, false, su)).max_courant,
                  0.133);
      }
  }



  // CPDI (any strain update) and GIMP with USAVG/USAVG+: the rigid rotation
  // is stable at 1.18/sqrt(k) for k = 12 to 64 and unstable at 0.3 for
  // k = 32 (0.4 for k = 16); the 2026 disk impact (CPDI, USL-) runs
  // FMPM(16) and FMPM(32) at NairnMPM's 0.2. GIMP with USL- keeps the
  // classic limit (the rotation fails FMPM(16) at 0.2, in NairnMPM too).
  TEST(StabilityLimit, SmoothShapeFunctionsFallAsOneOverSqrtK)
  {
    auto limit = [](const std::string &shape,
                    const unsigned int k,
                    const std::string &su) {
      Case m                  = method("fmpm", k, false, su);
      m.method.shape_function = fmpm::ShapeFunction::parse(shape);
      return stability_limit(m).max_courant;
    };
    for (const auto &[shape, su] :
         std::vector<std::pair<std::string, std::string>>{{"cpdi", "usl"},
                                                          {"cpdi", "usf"},
                                                          {"cpdi", "usl+"},
                                                          {"cpdi", "usavg+"},
                                                          {"ugimp", "usavg+"},
                                                          {"cpgimp", "usavg"}})
      {
        for (const unsigned int k : {16u, 32u})
          EXPECT_GE(limit(shape, k, su), 0.2) << shape << su << k;
        EXPECT_LE(limit(shape, 16, su), 0.3 + 1e-12) << shape << su;
        EXPECT_LE(limit(shape, 32, su), 0.212 + 1e-12) << shape << su;
        EXPECT_LE(limit(shape, 64, su), 0.15 + 1e-12) << shape << su;
        EXPECT_LE(limit(shape, 12, su), 0.35 + 1e-12) << shape << su;
        // Below k = 10 the bar's table: the same as classic's for CPDI and
        // with re-extrapolation, lower for GIMP with USAVG-
        // (ShapeFunctionsWithoutReextrapolation).
        if (shape == "cpdi" || su == "usavg+")
          EXPECT_EQ(limit(shape, 5, su), limit("classic", 5, su))
            << shape << su;
        else
          EXPECT_LT(limit(shape, 5, su), limit("classic", 5, su))
            << shape << su;
      }
    for (const std::string shape : {"classic", "ugimp", "cpgimp"})
      for (const unsigned int k : {16u, 32u})
        EXPECT_LT(limit(shape, k, "usl"), 0.2) << shape << k;
    EXPECT_LT(limit("classic", 16, "usavg+"), 0.2);
  }



  // USL- and USAVG- update the stresses with the series' grid velocities:
  // the vibrating bar (20 periods, 32 cells) fails below the classic table
  // with uGIMP/cpGIMP (FMPM(5), USL-: stable at 0.299, unstable at 0.311)
  // and b2spline (0.463 / 0.475, with a padding layer FMPM(2) too), so the
  // limit must lie below those; with re-extrapolation (USF, USL+, USAVG+)
  // every shape function is at least as stable as classic.
  TEST(StabilityLimit, ShapeFunctionsWithoutReextrapolation)
  {
    auto limit = [](const std::string &shape,
                    const unsigned int k,
                    const std::string &su,
                    const bool         padding = false) {
      Case m                   = method("fmpm", k, false, su);
      m.method.shape_function  = fmpm::ShapeFunction::parse(shape);
      m.method.bspline_padding = padding;
      return stability_limit(m).max_courant;
    };
    EXPECT_LE(limit("ugimp", 5, "usl"), 0.299 + 0.005);
    EXPECT_LE(limit("cpgimp", 2, "usl"), 0.4398 + 0.005);
    EXPECT_LE(limit("ugimp", 10, "usavg"), 0.2875 + 0.005);
    EXPECT_LE(limit("b2spline", 5, "usl"), 0.4633 + 0.005);
    EXPECT_LE(limit("b2spline", 10, "usl"), 0.346 + 0.005);
    EXPECT_LE(limit("b2spline", 2, "usl", true), 0.4633 + 0.005);
    EXPECT_LE(limit("b2gimp", 10, "usl"), 0.4163 + 0.005);
    EXPECT_LE(limit("classic", 2, "usavg"), 0.7562 + 0.005);
    // No lower than the measured stable Courant numbers.
    EXPECT_GE(limit("ugimp", 5, "usl"), 0.29);
    EXPECT_GE(limit("b2spline", 5, "usl"), 0.45);
    // Classic's table where it held (USL-, USAVG+), and with
    // re-extrapolation the classic table for every shape function.
    EXPECT_DOUBLE_EQ(limit("classic", 2, "usl"), 0.6);
    EXPECT_DOUBLE_EQ(limit("classic", 10, "usl"), 0.5);
    for (const std::string shape : {"classic",
                                    "ugimp",
                                    "cpgimp",
                                    "cpdi",
                                    "b2spline",
                                    "b2gimp",
                                    "b2cpdi",
                                    "b3spline"})
      {
        for (const std::string su : {"usf", "usl+", "usavg+"})
          for (const unsigned int k : {2u, 3u, 5u, 10u})
            EXPECT_EQ(limit(shape, k, su), limit("classic", k, su))
              << shape << su << k;
        // Falls with the order.
        for (const std::string &su : strain_updates)
          for (const bool padding : {false, true})
            {
              double previous = 1;
              for (unsigned int k = 2; k <= 40; ++k)
                {
                  const double c = limit(shape, k, su, padding);
                  EXPECT_LE(c, previous) << shape << su << k;
                  previous = c;
                }
            }
      }
  }



  // Periodic FMPM(k): the vibrating bar with period 5 fails at C = 0.4 and
  // with periods 3-10 at 0.5, stable at 0.35: the limit lies below those
  // and below the method's own.
  TEST(StabilityLimit, PeriodicFmpmIsCapped)
  {
    for (const auto &su : strain_updates)
      for (const unsigned int k : {2u, 5u, 10u})
        {
          Case         m          = method("fmpm", k, false, su);
          const double every_step = stability_limit(m).max_courant;
          m.periodic              = true;
          const double periodic   = stability_limit(m).max_courant;
          EXPECT_LE(periodic, every_step) << su << k;
          EXPECT_LE(periodic, 0.35 + 1e-12) << su << k;
          EXPECT_GT(periodic, 0) << su << k;
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
      Case m                       = method(mass, order, flip_type, "usavg+");
      m.method.position_update_psi = psi;
      return stability_limit(m).note;
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
    const auto read = [](const std::string &value) {
      dealii::ParameterHandler prm;
      fmpm::Parameters         parameters;
      fmpm::read_scene({{"default scene", fmpm::default_scene()},
                        {"limit.prm",
                         "subsection Time\n set Courant number limit = " +
                           value + "\nend\n"}},
                       prm,
                       parameters);
      return parameters.time.courant_limit;
    };
    for (const std::string value : {"0", "-1", "fast", "0.5x", "inf"})
      {
        try
          {
            read(value);
            ADD_FAILURE() << value << " was accepted";
          }
        catch (const std::exception &e)
          {
            EXPECT_NE(fmpm::error_message(e).find(
                        "Time/Courant number limit = <" + value + ">"),
                      std::string::npos)
              << fmpm::error_message(e);
          }
      }
    EXPECT_EQ(read("0.5"), 0.5);
    EXPECT_EQ(read("auto"), 0);
    EXPECT_TRUE(std::isinf(read("none")));
  }
} // namespace
