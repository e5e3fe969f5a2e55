// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Multimaterial contact (seed 004): the contact laws at one node against
// their definitions (Eqs. 7-10) and the kinetic energy they remove; whole
// runs: perfect interfaces reproduce the single-material run to round-off
// (§3.2), a block slides down an inclined plane with the exact Coulomb
// acceleration g(sin θ − μ cos θ), frictionless disks rebound conserving
// momentum; bad Contact input is refused with the parameter's name.

#include <fmpm/contact.h>
#include <fmpm/particle_properties.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "scene_helpers.h"
#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using fmpm::Contact::correct;
  using fmpm::Contact::Law;
  using fmpm::Contact::NodePair;
  using fmpm_tests::make_simulator;
  using fmpm_tests::output_overrides;
  using fmpm_tests::parameter_dir;

  /** α moving right and down onto β (n̂ = +y from α to β is "up"). */
  NodePair<2>
  approaching_pair(const double tangential_speed)
  {
    NodePair<2> node;
    node.mass_alpha        = 2.0;
    node.mass_beta         = 3.0;
    node.momentum_alpha[0] = 2.0 * tangential_speed;
    node.momentum_alpha[1] = 2.0 * 0.5; // α moves up, toward β
    node.momentum_beta[0]  = 0;
    node.momentum_beta[1]  = 3.0 * -0.25; // β moves down, toward α
    node.normal[1]         = 1;
    return node;
  }

  double
  kinetic_energy(const NodePair<2> &node, const Tensor<1, 2> &dp)
  {
    const Tensor<1, 2> pa = node.momentum_alpha + dp;
    const Tensor<1, 2> pb = node.momentum_beta - dp;
    return 0.5 * pa * pa / node.mass_alpha + 0.5 * pb * pb / node.mass_beta;
  }

  TEST(ContactLaw, PerfectMovesBothWithTheCentreOfMass)
  {
    const NodePair<2>  node = approaching_pair(1.0);
    const auto         c    = correct(Law{"perfect", {}}, node);
    const Tensor<1, 2> v_a =
      (node.momentum_alpha + c.delta_momentum) / node.mass_alpha;
    const Tensor<1, 2> v_b =
      (node.momentum_beta - c.delta_momentum) / node.mass_beta;
    const Tensor<1, 2> v_cm = (node.momentum_alpha + node.momentum_beta) / 5.0;
    EXPECT_NEAR((v_a - v_cm).norm(), 0, 1e-15);
    EXPECT_NEAR((v_b - v_cm).norm(), 0, 1e-15);
    // Perfect interfaces hold also when separating.
    NodePair<2> separating = node;
    separating.normal *= -1;
    EXPECT_NEAR((correct(Law{"perfect", {}}, separating).delta_momentum -
                 c.delta_momentum)
                  .norm(),
                0,
                1e-15);
  }

  TEST(ContactLaw, FrictionlessRemovesTheNormalApproachOnly)
  {
    const NodePair<2> node = approaching_pair(1.0);
    const auto        c    = correct(Law{"frictionless", {}}, node);
    ASSERT_TRUE(c.in_contact);
    const Tensor<1, 2> v_a =
      (node.momentum_alpha + c.delta_momentum) / node.mass_alpha;
    const Tensor<1, 2> v_b =
      (node.momentum_beta - c.delta_momentum) / node.mass_beta;
    EXPECT_NEAR((v_b - v_a)[1], 0, 1e-15);    // no approach left
    EXPECT_NEAR((v_b - v_a)[0], -1.0, 1e-15); // slip unchanged
    EXPECT_EQ(c.friction_work, 0.);
    // Separating, or not touching: no correction.
    NodePair<2> apart = node;
    apart.normal *= -1;
    EXPECT_FALSE(correct(Law{"frictionless", {}}, apart).in_contact);
    NodePair<2> not_touching = node;
    not_touching.touching    = false;
    EXPECT_EQ(
      correct(Law{"coulomb", {0.3}}, not_touching).delta_momentum.norm(), 0.);
  }

  TEST(ContactLaw, CoulombSticksOrSlipsAtMuTimesTheNormalImpulse)
  {
    // Δp^α(0)·n̂ = m_red (v^β − v^α)·n̂ = 1.2 × (−0.75) = −0.9.
    const double m_red = 2.0 * 3.0 / 5.0, dp0_n = m_red * -0.75;
    for (const double slip : {0.1, 2.0})
      {
        const NodePair<2> node = approaching_pair(slip);
        const Law         law{"coulomb", {0.4}};
        const auto        c = correct(law, node);
        ASSERT_TRUE(c.in_contact);
        const double dp0_t = m_red * slip; // tangential Δp^α(0)
        // The normal part as frictionless; the tangential part is Δp^α(0)·t̂
        // (stick) or μ|Δp^α(0)·n̂| (slip), whichever is smaller.
        EXPECT_NEAR(c.delta_momentum[1], dp0_n, 1e-15);
        const double expected_t =
          -std::min(dp0_t, -law.coefficients[0] * dp0_n);
        EXPECT_NEAR(c.delta_momentum[0], expected_t, 1e-15) << slip;
        // Kinetic energy removed = normal inelastic loss + friction work.
        const double removed = kinetic_energy(node, Tensor<1, 2>()) -
                               kinetic_energy(node, c.delta_momentum);
        EXPECT_NEAR(removed, 0.5 * m_red * 0.75 * 0.75 + c.friction_work, 1e-14)
          << slip;
        EXPECT_GT(c.friction_work, 0);
      }
  }



  /** The colliding disks with two materials of the same properties. */
  std::string
  two_material_disks(const std::string &contact, const std::string &update)
  {
    return "set Number of materials = 2\n"
           "subsection Material 1\n set Model name = linear elastic\n"
           " set Density = 1000\n subsection Linear elastic\n"
           "  set Young's modulus = 1000\n  set Poisson's ratio = 0.3\n"
           " end\nend\n"
           "subsection Body 1\n set Material = 1\nend\n"
           "subsection Particle update\n set Model name = " +
           update +
           "\nend\n"
           "subsection Time\n set End time = 1.8\nend\n"
           "subsection Contact\n" +
           contact + "end\n";
  }

  // Logistic regression (seed 004 Eqs. 19-21, appendix): two point clouds
  // separated by a line at 30° with a gap; the fit finds its normal.
  TEST(ContactNormals, LogisticRegressionFindsTheSeparatingLine)
  {
    const double              theta = M_PI / 6;
    const Tensor<1, 2>        n({std::cos(theta), std::sin(theta)});
    std::vector<Tensor<1, 2>> x;
    std::vector<double>       c;
    for (int i = -4; i < 4; ++i)
      for (int j = -4; j < 4; ++j)
        {
          const Tensor<1, 2> p({0.25 * i + 0.125, 0.25 * j + 0.125});
          const double       s = p * n;
          if (std::abs(s) < 0.1) // the gap
            continue;
          x.push_back(p + Tensor<1, 2>({3., -1.})); // any origin
          c.push_back(s < 0 ? -1. : 1.);
        }
    const auto fit = fmpm::Contact::logistic_regression_normal<2>(x.data(),
                                                                  c.data(),
                                                                  x.size(),
                                                                  0.5);
    ASSERT_TRUE(fit.valid);
    EXPECT_TRUE(fit.converged);
    EXPECT_GT(fit.iterations, 0u);
    EXPECT_LT(std::acos(std::min(1., fit.normal * n)), 0.02);

    // Seed 004 Fig. 3C: a corner of α below a full edge of β. The average
    // of the volume gradients tilts the normal by about 18°; LR finds the
    // horizontal plane (normal +y).
    x.clear();
    c.clear();
    for (int i = -4; i < 4; ++i)
      for (int j = -4; j < 4; ++j)
        {
          const Tensor<1, 2> p({0.25 * i + 0.125, 0.25 * j + 0.125});
          if (p[1] > 0)
            {
              x.push_back(p);
              c.push_back(1.);
            }
          else if (p[0] < 0)
            {
              x.push_back(p);
              c.push_back(-1.);
            }
        }
    const auto corner = fmpm::Contact::logistic_regression_normal<2>(x.data(),
                                                                     c.data(),
                                                                     x.size(),
                                                                     0.5);
    ASSERT_TRUE(corner.valid);
    EXPECT_LT(std::abs(corner.normal[0]), 0.05) << corner.normal;
    EXPECT_GT(corner.normal[1], 0.99);

    // 3D: a plane with normal (1, 2, 2)/3.
    const Tensor<1, 3>        n3({1. / 3, 2. / 3, 2. / 3});
    std::vector<Tensor<1, 3>> x3;
    c.clear();
    for (int i = -2; i < 2; ++i)
      for (int j = -2; j < 2; ++j)
        for (int k = -2; k < 2; ++k)
          {
            const Tensor<1, 3> p({i + 0.5, j + 0.5, k + 0.5});
            if (std::abs(p * n3) < 0.2)
              continue;
            x3.push_back(p);
            c.push_back(p * n3 < 0 ? -1. : 1.);
          }
    const auto fit3 = fmpm::Contact::logistic_regression_normal<3>(x3.data(),
                                                                   c.data(),
                                                                   x3.size(),
                                                                   1.);
    ASSERT_TRUE(fit3.valid);
    EXPECT_LT(std::acos(std::min(1., fit3.normal * n3)), 0.05);
  }

  // R_p of Eq. 25: an undeformed square point has R_0 along the axes; a
  // stretch by 2 along x doubles it along x; a rotation carries it along.
  TEST(ContactNormals, DeformedRadius)
  {
    const Tensor<1, 2> R0({0.25, 0.25}), ex({1., 0.}), ey({0., 1.});
    Tensor<2, 2>       F_inverse = unit_symmetric_tensor<2>();
    EXPECT_NEAR(fmpm::Contact::deformed_radius(F_inverse, R0, ex), 0.25, 1e-15);
    F_inverse[0][0] = 0.5; // F = diag(2, 1)
    EXPECT_NEAR(fmpm::Contact::deformed_radius(F_inverse, R0, ex), 0.5, 1e-15);
    EXPECT_NEAR(fmpm::Contact::deformed_radius(F_inverse, R0, ey), 0.25, 1e-15);
    // 45°: the inscribed circle stretched to an ellipse with semi-axes
    // 0.5, 0.25: r = 1/sqrt(cos²/a² + sin²/b²).
    const Tensor<1, 2> diagonal({std::sqrt(0.5), std::sqrt(0.5)});
    EXPECT_NEAR(fmpm::Contact::deformed_radius(F_inverse, R0, diagonal),
                1. / std::sqrt(0.5 / 0.25 + 0.5 / 0.0625),
                1e-15);
  }

  // d(x) of seed 004 Fig. 1 against hand values for 2 points per cell
  // (l_p = 1/4 cell): one point in the support, x = e − l_p, so d = x + l_p;
  // the edge on the node (e = 0): points at −1/4 and −3/4 with S = 3/4 and
  // 1/4 (classic and uGIMP alike) put x at −3/8; β mirrors α.
  TEST(ContactNormals, EdgeDistanceFit)
  {
    using fmpm::ShapeFunction::Type;
    for (const Type type : {Type::classic, Type::ugimp})
      {
        const fmpm::Contact::EdgeDistance d(type, 0.25);
        EXPECT_NEAR(d.alpha(-0.375), 0, 2e-3);
        EXPECT_NEAR(d.beta(0.375), 0, 2e-3);
        EXPECT_NEAR(d.alpha(-0.4),
                    d.alpha(-0.375) - (0.4 - 0.375) / 0.75 * 1,
                    0.02); // the local slope: dx/de = 0.75 ... 1
        for (double x = -1.2; x < 0.3; x += 0.01)
          EXPECT_LT(d.alpha(x), d.alpha(x + 0.01));
      }
    const fmpm::Contact::EdgeDistance classic(Type::classic, 0.25);
    EXPECT_NEAR(classic.alpha(-0.95), -0.7, 2e-3);
    // CPDI's corner average differs from uGIMP's convolution.
    const fmpm::Contact::EdgeDistance cpdi(Type::cpdi, 0.25),
      gimp(Type::ugimp, 0.25);
    EXPECT_GT(std::abs(cpdi.alpha(-0.6) - gimp.alpha(-0.6)), 1e-3);
  }



  // Seed 004 §3.2-3.3: with every interface perfect, FLIP, PIC, XPIC(1) (Eq.
  // 38) and FMPM(1) with the lumped mass matrix give the single-material run to
  // round-off (two corrections per step, the contact force from Δp^α+ only).
  TEST(ContactRun, PerfectInterfacesEqualOneMaterial)
  {
    for (const std::string update : {"flip", "pic", "xpic", "fmpm"})
      {
        ParameterHandler prm_one, prm_two;
        auto             one = make_simulator<2>(
          {parameter_dir + "colliding_disks.prm"},
          output_overrides("output-contact-one") +
            "subsection Particle update\n set Model name = " + update +
            "\nend\nsubsection Time\n set End time = 1.8\nend\n",
          prm_one);
        auto two = make_simulator<2>(
          {parameter_dir + "colliding_disks.prm"},
          output_overrides("output-contact-two") +
            two_material_disks(" set Model name = multimaterial\n"
                               " set Law = perfect\n"
                               " set Normals = average gradient\n",
                               update),
          prm_two);
        one->run();
        two->run();
        const auto &h1 = fmpm_tests::inspect(*one).get_history();
        const auto &h2 = fmpm_tests::inspect(*two).get_history();
        ASSERT_EQ(h1.size(), h2.size());
        ASSERT_GT(h1.size(), 10u);
        const double E0 = h1.front().total_energy;
        for (unsigned int r = 0; r < h1.size(); ++r)
          {
            EXPECT_NEAR(h2[r].kinetic_energy, h1[r].kinetic_energy, 1e-10 * E0)
              << update << " t = " << h1[r].time;
            EXPECT_NEAR(h2[r].strain_energy, h1[r].strain_energy, 1e-10 * E0)
              << update << " t = " << h1[r].time;
          }
        // The strain energy at the end shows the disks did collide.
        EXPECT_GT(h1.back().strain_energy, 0.01 * E0) << update;
      }
  }



  // Multimaterial XPIC(k)/FMPM(k) (seed 004 Eq. 37, seed 000 Eqs. 3.18,
  // 3.22) with perfect interfaces. Net incremental contact (the default:
  // the laws also correct every increment of the series) moves the
  // increments of the materials at shared nodes with their centre of mass,
  // so the series is the single-material one: equal to round-off. Once
  // per step, the runs differ by the projection of V − Sv (Eq. 47),
  // nonzero but small; without the Δv^α term ("uncorrected", Eq. 48) the
  // first correction's momentum exchange is lost every step and the disks
  // pass through each other. Measured on the colliding disks, largest
  // kinetic-energy difference in E0: net incremental 5e-16 to 2e-15; once
  // per step XPIC(2) 1.3 %, XPIC(5) 1.9 %, FMPM(2) 0.9 %, FMPM(5) 4.0 %;
  // uncorrected 99 %.
  TEST(ContactRun, MultimaterialXpicAndFmpmAgainstOneMaterial)
  {
    auto run = [](const std::string &settings, const std::string &directory) {
      ParameterHandler prm;
      auto             simulator =
        make_simulator<2>({parameter_dir + "colliding_disks.prm"},
                          output_overrides(directory) + settings,
                          prm);
      simulator->run();
      return fmpm_tests::inspect(*simulator).get_history();
    };
    for (const std::string update : {"xpic", "fmpm"})
      for (const unsigned int k : {2u, 5u})
        {
          // The time steps of the former stability factors 0.9 (k = 2)
          // and 0.6 (k = 5) x 0.4.
          const std::string method =
            "subsection Mass matrix\n set Model name = fmpm\n"
            " subsection Fmpm\n  set Order = " +
            std::to_string(k) +
            "\n end\nend\nsubsection Time\n set Courant number = " +
            (k == 2 ? "0.36" : "0.24") + "\nend\n";
          const auto        one     = run(method +
                                 "subsection Particle update\n set Model "
                                            "name = " +
                                 update +
                                 "\nend\nsubsection Time\n set End time = "
                                            "1.8\nend\n",
                               "output-mxpic-one");
          const std::string contact = " set Model name = multimaterial\n"
                                      " set Law = perfect\n"
                                      " set Normals = specified\n";
          const std::string once =
            " set Contact in mass-matrix iterations = once per step\n";
          auto difference = [&](const std::string &settings) {
            const auto two =
              run(method + two_material_disks(contact + settings, update),
                  "output-mxpic-two");
            EXPECT_EQ(one.size(), two.size());
            const double E0     = one.front().total_energy;
            double       result = 0;
            for (unsigned int r = 0; r < std::min(one.size(), two.size()); ++r)
              result = std::max(
                result,
                std::abs(two[r].kinetic_energy - one[r].kinetic_energy) / E0);
            return result;
          };
          const double net_incremental = difference("");
          const double once_per_step   = difference(once);
          const double uncorrected =
            difference(once + " set XPIC contact term = uncorrected\n");
          // The corrected momenta through the series: with the increments
          // made equal the one field again.
          const double series = difference(" set XPIC contact term = series\n");
          EXPECT_LT(series, 1e-12) << update << k;
          std::cout << update << "(" << k << "), perfect interfaces: largest "
                    << "kinetic energy difference to one material "
                    << net_incremental << " (net incremental), "
                    << once_per_step << " (once per step), " << uncorrected
                    << " (uncorrected)" << std::endl;
          EXPECT_LT(net_incremental, 1e-12) << update << k;
          EXPECT_GT(once_per_step, 1e-4) << update << k; // Eq. 47 ≠ 0
          EXPECT_LT(once_per_step, 0.06) << update << k;
          EXPECT_GT(uncorrected, 10 * once_per_step) << update << k;
        }
  }



  // The exact solve with per-material fields (Mass matrix = full): the
  // k → ∞ limit of net incremental contact, each material's m̃^α coupled
  // at the pairs in contact. With perfect interfaces every shared node is
  // in contact and the increments are those of one field: the run equals
  // the single-material exact solve to the CG tolerance (weak nodes are
  // decided on the sums over the materials in contact). With
  // frictionless contact the disks rebound and momentum stays zero (each
  // m̃^α conserves its material's momentum, the contact forces are equal
  // and opposite).
  TEST(ContactRun, ExactSolveWithContactIsTheLimitOfNetIncremental)
  {
    const std::string full =
      "subsection Mass matrix\n set Model name = full\n"
      " subsection Full\n  set Tolerance = 1e-12\n end\nend\n"
      // The time step of the former stability factor 0.75 x 0.4.
      "subsection Time\n set Strain update mass matrix = lumped\n"
      " set Courant number = 0.3\nend\n";
    auto run = [&](const std::string &settings, const std::string &directory) {
      ParameterHandler prm;
      auto             simulator =
        make_simulator<2>({parameter_dir + "colliding_disks.prm"},
                          output_overrides(directory) + full + settings,
                          prm);
      simulator->run();
      return fmpm_tests::inspect(*simulator).get_history();
    };
    const auto one =
      run("subsection Particle update\n set Model name = fmpm\nend\n"
          "subsection Time\n set End time = 1.8\nend\n",
          "output-exact-one");
    const auto two = run(two_material_disks(" set Model name = multimaterial\n"
                                            " set Law = perfect\n"
                                            " set Normals = specified\n",
                                            "fmpm"),
                         "output-exact-two");
    ASSERT_EQ(one.size(), two.size());
    const double E0         = one.front().total_energy;
    double       difference = 0;
    for (unsigned int r = 0; r < one.size(); ++r)
      difference =
        std::max(difference,
                 std::abs(two[r].kinetic_energy - one[r].kinetic_energy) / E0);
    std::cout << "exact solve, perfect interfaces: largest kinetic energy "
              << "difference to one material " << difference << std::endl;
    EXPECT_LT(difference, 1e-9);
    EXPECT_GT(one.back().strain_energy, 0.01 * E0); // the disks collided

    const auto rebound =
      run(two_material_disks(" set Model name = multimaterial\n"
                             " set Law = frictionless\n"
                             " set Normals = contact position\n",
                             "fmpm") +
            "subsection Time\n set End time = 2.2\nend\n",
          "output-exact-rebound");
    double max_contact_nodes = 0;
    for (const auto &row : rebound)
      {
        EXPECT_LT(row.momentum.norm(), 1e-8); // CG: |r| < 1e-10 |p|
        max_contact_nodes = std::max(max_contact_nodes, row.extra.back());
      }
    EXPECT_GT(max_contact_nodes, 0);
    EXPECT_LT(rebound.back().extra[1], -0.05); // body 0 moves back
    EXPECT_GT(rebound.back().extra[8 + 1], 0.05);
  }



  // Seed 004 Eq. 47, computed: with a perfect interface and contact once per
  // step, one XPIC(2) step of two materials differs from the single-material
  // step by S(S^{+α} − S⁺)(V − Sv) at every point (V the point velocities,
  // v = S⁺V). The test computes that term with its own bilinear S on the
  // 20 x 20 grid and compares point by point; the same for the
  // "uncorrected" series (no Δv^α, Eq. 48), S(2v^{α0} − S^{+α}Sv^{α0}) −
  // S(2v − S⁺Sv) with v^{α0} = S^{+α}V. Two touching blocks, one smooth
  // velocity field plus a small ripple; USL and zero initial stress, so the
  // first step has no forces and the velocities are the projections alone.
  // Measured: both match to 1e-15 m/s; the ripple 10x smaller makes the
  // Eq. 47 term 7.6x smaller; the smooth field 10x larger makes it 3.5x
  // larger and the uncorrected term 10.3x (12.7x the Eq. 47 term).
  struct Eq47Point
  {
    Point<2>     x;
    Tensor<1, 2> V;
    double       M;
    unsigned int material;
  };

  std::map<types::particle_index, Tensor<1, 2>>
  one_xpic2_step(
    const std::string                          &velocity,
    const std::string                          &contact,
    const std::string                          &directory,
    std::map<types::particle_index, Eq47Point> *initial_points = nullptr)
  {
    const std::string scene =
      "set Dimension = 2\nset Number of bodies = 2\n"
      "set Number of materials = 2\n"
      "subsection Mesh\n set Upper corner = 1, 1\n"
      " set Subdivisions = 20, 20\nend\n"
      "subsection Time\n set Strain update = usl\n"
      " set Maximum number of steps = 1\n set End time = 1\nend\n"
      "subsection Material 0\n set Density = 1000\nend\n"
      "subsection Material 1\n set Density = 1000\nend\n"
      "subsection Body 0\n set Center = 0.4, 0.5\n"
      " set Half lengths = 0.1, 0.2\n set Initial velocity = " +
      velocity +
      "\nend\n"
      "subsection Body 1\n set Center = 0.6, 0.5\n"
      " set Half lengths = 0.1, 0.2\n set Material = 1\n"
      " set Initial velocity = " +
      velocity +
      "\nend\n"
      "subsection Particle update\n set Model name = xpic\nend\n"
      "subsection Mass matrix\n set Model name = fmpm\n"
      " subsection Fmpm\n  set Order = 2\n end\nend\n"
      "subsection Contact\n" +
      contact + "end\n";
    ParameterHandler prm;
    auto             simulator =
      make_simulator<2>({}, scene + output_overrides(directory), prm);
    simulator->run();
    std::map<types::particle_index, Tensor<1, 2>> result;
    const auto &points = fmpm_tests::inspect(*simulator).get_material_points();
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const auto p = points.record(k);
        result[points.id[k]] =
          fmpm::get_vector<2>(p, fmpm::PropertyIndex<2>::velocity);
        if (initial_points)
          {
            Eq47Point point;
            point.x = Point<2>(
              fmpm::get_vector<2>(p, fmpm::PropertyIndex<2>::initial_position));
            point.M = p[fmpm::PropertyIndex<2>::mass];
            point.material =
              static_cast<unsigned int>(p[fmpm::PropertyIndex<2>::material_id]);
            (*initial_points)[points.id[k]] = point;
          }
      }
    return result;
  }

  TEST(ContactRun, MultimaterialXpicDiffersByTheTermOfEq47)
  {
    const double       h = 0.05; // 20 x 20 cells on the unit square
    const unsigned int n = 21;
    // S_ip of classic bilinear shape functions
    auto support = [&](const Point<2>              &x,
                       std::array<unsigned int, 4> &node,
                       std::array<double, 4>       &S) {
      const unsigned int ix = static_cast<unsigned int>(x[0] / h);
      const unsigned int iy = static_cast<unsigned int>(x[1] / h);
      const double       fx = x[0] / h - ix, fy = x[1] / h - iy;
      for (unsigned int c = 0; c < 4; ++c)
        {
          const unsigned int a = c % 2, b = c / 2;
          node[c] = (iy + b) * n + ix + a;
          S[c]    = (a ? fx : 1 - fx) * (b ? fy : 1 - fy);
        }
    };
    auto field_value = [](const Point<2> &x,
                          const double    A,
                          const double    ripple) {
      // the scene's 'Initial velocity' below
      return Tensor<1, 2>({A * std::sin(3 * x[0] + 2 * x[1]) +
                             ripple * std::sin(97 * x[0]) * std::cos(89 * x[1]),
                           A * std::cos(2 * x[0] - 3 * x[1]) +
                             ripple * std::cos(83 * x[0] + 71 * x[1])});
    };
    const std::string perfect_once =
      " set Model name = multimaterial\n set Law = perfect\n"
      " set Normals = specified\n set Specified normal = 1, 0\n"
      " set Contact in mass-matrix iterations = once per step\n";

    // (smooth amplitude A, ripple): the ripple down 10x, then A up 10x
    const std::array<std::array<double, 2>, 3> cases = {
      {{{0.1, 0.01}}, {{0.1, 0.001}}, {{1.0, 0.001}}}};
    std::array<double, 3> corrected_norm{}, uncorrected_norm{};
    unsigned int          case_index = 0;
    for (const auto &[A, ripple] : cases)
      {
        std::ostringstream velocity;
        velocity << A << "*sin(3*x+2*y) + " << ripple
                 << "*sin(97*x)*cos(89*y); " << A << "*cos(2*x-3*y) + "
                 << ripple << "*cos(83*x+71*y)";
        std::map<types::particle_index, Eq47Point> initial;
        const auto             single = one_xpic2_step(velocity.str(),
                                           " set Model name = none\n",
                                           "output-eq47-single",
                                           &initial);
        std::vector<Eq47Point> points; // in the order of the ids
        for (const auto &entry : initial)
          points.push_back(entry.second);
        const auto corrected =
          one_xpic2_step(velocity.str(), perfect_once, "output-eq47-multi");
        const auto uncorrected =
          one_xpic2_step(velocity.str(),
                         perfect_once +
                           " set XPIC contact term = uncorrected\n",
                         "output-eq47-uncorrected");
        const auto series =
          one_xpic2_step(velocity.str(),
                         perfect_once + " set XPIC contact term = series\n",
                         "output-eq47-series");
        ASSERT_EQ(points.size(), single.size());
        ASSERT_EQ(corrected.size(), single.size());
        ASSERT_EQ(series.size(), single.size());
        for (auto &point : points)
          point.V = field_value(point.x, A, ripple);

        // Grid quantities of the single field and of each material: m, S⁺.
        std::vector<double>         m(n * n), m_a(2 * n * n);
        std::vector<Tensor<1, 2>>   v(n * n), v_a0(2 * n * n);
        std::array<unsigned int, 4> node;
        std::array<double, 4>       S;
        for (const auto &point : points)
          {
            support(point.x, node, S);
            for (unsigned int c = 0; c < 4; ++c)
              {
                m[node[c]] += point.M * S[c];
                v[node[c]] += point.M * S[c] * point.V;
                m_a[point.material * n * n + node[c]] += point.M * S[c];
                v_a0[point.material * n * n + node[c]] +=
                  point.M * S[c] * point.V;
              }
          }
        for (unsigned int i = 0; i < n * n; ++i)
          {
            if (m[i] > 0)
              v[i] /= m[i];
            for (unsigned int a = 0; a < 2; ++a)
              if (m_a[a * n * n + i] > 0)
                v_a0[a * n * n + i] /= m_a[a * n * n + i];
          }
        // S applied to a grid field at a point; S⁺ (single or of material α)
        // applied to values at the points.
        auto interpolate = [&](const std::vector<Tensor<1, 2>> &field,
                               const unsigned int               offset,
                               const Point<2>                  &x) {
          std::array<unsigned int, 4> nd;
          std::array<double, 4>       w;
          support(x, nd, w);
          Tensor<1, 2> value;
          for (unsigned int c = 0; c < 4; ++c)
            value += w[c] * field[offset + nd[c]];
          return value;
        };
        auto project = [&](const std::vector<Tensor<1, 2>> &values,
                           const bool                       per_material) {
          std::vector<Tensor<1, 2>> result(2 * n * n);
          for (unsigned int q = 0; q < points.size(); ++q)
            {
              support(points[q].x, node, S);
              const unsigned int offset =
                per_material ? points[q].material * n * n : 0;
              for (unsigned int c = 0; c < 4; ++c)
                result[offset + node[c]] += points[q].M * S[c] * values[q];
            }
          for (unsigned int i = 0; i < 2 * n * n; ++i)
            {
              const double mass =
                per_material ? m_a[i] : (i < n * n ? m[i] : 0);
              if (mass > 0)
                result[i] /= mass;
            }
          return result;
        };
        // Eq. 47: W = V − Sv, term = S(S^{+α} − S⁺)W.
        std::vector<Tensor<1, 2>> W(points.size()), Sv_a0(points.size());
        std::vector<Tensor<1, 2>> Sv(points.size());
        for (unsigned int q = 0; q < points.size(); ++q)
          {
            Sv[q] = interpolate(v, 0, points[q].x);
            W[q]  = points[q].V - Sv[q];
            Sv_a0[q] =
              interpolate(v_a0, points[q].material * n * n, points[q].x);
          }
        const auto W_single   = project(W, false);
        const auto W_material = project(W, true);
        const auto SpSv       = project(Sv, false);   // S⁺Sv
        const auto SaSva0     = project(Sv_a0, true); // S^{+α}Sv^{α0}
        const auto SaSv       = project(Sv, true);    // S^{+α}Sv

        double       max_corrected_error = 0, max_uncorrected_error = 0;
        double       max_series_error = 0, max_series_term = 0;
        double       max_term = 0, max_term48 = 0;
        unsigned int q = 0;
        for (const auto &[id, V_single] : single)
          {
            (void)id;
            const auto        &point = points[q++];
            const unsigned int a     = point.material * n * n;
            const Tensor<1, 2> term  = interpolate(W_material, a, point.x) -
                                      interpolate(W_single, 0, point.x);
            // S(2v^{α0} − S^{+α}Sv^{α0}) − S(2v − S⁺Sv)
            const Tensor<1, 2> term48 = 2 * interpolate(v_a0, a, point.x) -
                                        interpolate(SaSva0, a, point.x) -
                                        2 * interpolate(v, 0, point.x) +
                                        interpolate(SpSv, 0, point.x);
            // 'series': the corrected lumped velocity of α is v at every
            // node of α (perfect interface), so XPIC(2) gives S(2v −
            // S^{+α}Sv): the term S(S⁺ − S^{+α})Sv.
            const Tensor<1, 2> series_term =
              interpolate(SpSv, 0, point.x) - interpolate(SaSv, a, point.x);
            max_series_term = std::max(max_series_term, series_term.norm());
            max_series_error =
              std::max(max_series_error,
                       (series.at(id) - V_single - series_term).norm());
            max_term   = std::max(max_term, term.norm());
            max_term48 = std::max(max_term48, term48.norm());
            max_corrected_error =
              std::max(max_corrected_error,
                       (corrected.at(id) - V_single - term).norm());
            max_uncorrected_error =
              std::max(max_uncorrected_error,
                       (uncorrected.at(id) - V_single - term48).norm());
          }
        std::cout << "A " << A << ", ripple " << ripple
                  << ": Eq. 47 term up to " << max_term
                  << " m/s, run difference matches it to "
                  << max_corrected_error << "; uncorrected term up to "
                  << max_term48 << ", matched to " << max_uncorrected_error
                  << std::endl;
        EXPECT_GT(max_term, 1e-2 * ripple); // the term is not zero
        EXPECT_LT(max_corrected_error, 1e-12);
        EXPECT_LT(max_uncorrected_error, 1e-12);
        std::cout << "series term up to " << max_series_term << ", matched to "
                  << max_series_error << std::endl;
        EXPECT_GT(max_series_term, 1e-2 * ripple);
        EXPECT_LT(max_series_error, 1e-12);
        corrected_norm[case_index]   = max_term;
        uncorrected_norm[case_index] = max_term48;
        ++case_index;
      }
    // Eq. 47 follows the ripple V − Sv and hardly the smooth field; the
    // uncorrected term follows the velocity field itself (Eq. 48).
    EXPECT_LT(corrected_norm[1] / corrected_norm[0], 0.2);
    EXPECT_LT(corrected_norm[2] / corrected_norm[1], 5);     // measured 3.5
    EXPECT_GT(uncorrected_norm[2] / uncorrected_norm[1], 8); // 10.3
    EXPECT_GT(uncorrected_norm[2], 10 * corrected_norm[2]);
  }



  // Adaptive (hanging-node) meshes: the disks with frictionless LR contact
  // on a 10 x 10 mesh refined once around the points (Mesh refinement/
  // Strategy = material points) against the uniform 20 x 20 mesh of the
  // same cell size there: the cell sizes at the contact nodes, the clouds
  // and the normals are the same, so are the energies, to round-off.
  TEST(ContactRun, AdaptiveMeshEqualsUniformMesh)
  {
    // FLIP with the lumped mass, and the exact solve with contact (its CG
    // on the condensed m̃^α of the adapted mesh).
    for (const std::string method :
         {"", "subsection Mass matrix\n set Model name = full\nend\n"})
      {
        const std::string update = method.empty() ? "flip" : "fmpm";
        auto run = [&](const std::string &mesh, const std::string &directory) {
          ParameterHandler prm;
          auto             simulator = make_simulator<2>(
            {parameter_dir + "colliding_disks.prm"},
            output_overrides(directory) +
              two_material_disks(" set Model name = multimaterial\n"
                                             " set Law = frictionless\n"
                                             " set Normals = logistic regression\n",
                                 update) +
              method + mesh,
            prm);
          simulator->run();
          return fmpm_tests::inspect(*simulator).get_history();
        };
        const auto uniform = run("", "output-contact-uniform");
        const auto adaptive =
          run("subsection Mesh\n set Subdivisions = 10, 10\nend\n"
              "subsection Mesh refinement\n set Strategy = material points\n"
              " set Maximum level = 1\n set Buffer layers = 2\n"
              " set Interval = 10\nend\n",
              "output-contact-adaptive");
        ASSERT_EQ(uniform.size(), adaptive.size()) << update;
        const double E0            = uniform.front().total_energy;
        double       contact_nodes = 0;
        for (unsigned int r = 0; r < uniform.size(); ++r)
          {
            EXPECT_NEAR(adaptive[r].kinetic_energy,
                        uniform[r].kinetic_energy,
                        1e-9 * E0)
              << update << " t = " << uniform[r].time;
            EXPECT_NEAR(adaptive[r].strain_energy,
                        uniform[r].strain_energy,
                        1e-9 * E0)
              << update << " t = " << uniform[r].time;
            contact_nodes = std::max(contact_nodes, adaptive[r].extra.back());
          }
        EXPECT_GT(contact_nodes, 0) << update;
      }
  }



  /** Block on an elastic base under gravity tilted by 30°. */
  std::string
  inclined_plane(const std::string &contact)
  {
    return "set Dimension = 2\nset Number of bodies = 2\n"
           "set Number of materials = 2\n"
           "subsection Mesh\n set Lower corner = 0, 0\n"
           " set Upper corner = 2, 0.5\n set Subdivisions = 40, 10\nend\n"
           "subsection Boundary conditions\n set Fixed boundary ids = 2\nend\n"
           // g = 9.81 tilted by 30°
           "subsection Body force\n set Gravity = 4.905, -8.495704797\nend\n"
           "subsection Time\n set End time = 0.4\n set Courant number = 0.4\n"
           " set Strain update = usavg+\nend\n"
           "subsection Material 0\n set Model name = linear elastic\n"
           " set Density = 2000\n subsection Linear elastic\n"
           "  set Young's modulus = 2e7\n end\nend\n"
           "subsection Material 1\n set Model name = linear elastic\n"
           " set Density = 1000\n subsection Linear elastic\n"
           "  set Young's modulus = 1e7\n end\nend\n"
           "subsection Body 0\n set Center = 1, 0.075\n"
           " set Half lengths = 1, 0.075\n set Material = 0\nend\n"
           "subsection Body 1\n set Center = 0.3, 0.225\n"
           " set Half lengths = 0.2, 0.075\n set Material = 1\nend\n"
           "subsection Output\n set Interval = 0.02\nend\n"
           "subsection Contact\n set Model name = multimaterial\n"
           " set Normals = specified\n set Specified normal = 0, 1\n" +
           contact + "end\n";
  }

  /** History columns of material 1 (the block) and the contact sums. */
  struct BlockHistory
  {
    std::vector<double> time, velocity_x, friction_work;
  };

  BlockHistory
  run_block(const std::string &contact, const std::string &directory)
  {
    ParameterHandler prm;
    auto             simulator =
      make_simulator<2>({},
                        inclined_plane(contact) + output_overrides(directory),
                        prm);
    simulator->run();
    // extra: per material mass, v_x, v_y, σxx, σyy, σxy, K, U; then
    // friction_work, contact_nodes.
    BlockHistory h;
    for (const auto &row : fmpm_tests::inspect(*simulator).get_history())
      {
        EXPECT_EQ(row.extra.size(), 2 * 8 + 2u);
        h.time.push_back(row.time);
        h.velocity_x.push_back(row.extra[8 + 1]);
        h.friction_work.push_back(row.extra[16]);
      }
    return h;
  }

  /** The slope of v(t) over the second half (after the block settled). */
  double
  late_acceleration(const BlockHistory &h)
  {
    const unsigned int n = h.time.size(), half = n / 2;
    return (h.velocity_x[n - 1] - h.velocity_x[half]) /
           (h.time[n - 1] - h.time[half]);
  }

  TEST(ContactRun, BlockSlidesDownAnInclinedPlaneWithCoulombFriction)
  {
    const double g = 9.81, theta = M_PI / 6;
    for (const double mu : {0.0, 0.3})
      {
        const BlockHistory h =
          run_block(" set Law = coulomb\n set Friction coefficient = " +
                      std::to_string(mu) + "\n",
                    "output-inclined");
        const double exact = g * (std::sin(theta) - mu * std::cos(theta));
        EXPECT_NEAR(late_acceleration(h), exact, 0.02 * exact) << "mu " << mu;
        EXPECT_NEAR(h.velocity_x.back() / h.time.back(), exact, 0.02 * exact)
          << "mu " << mu;
        if (mu > 0)
          {
            // Friction work = μ N × slip, slip = ∫ v dt (the base is still).
            double slip = 0;
            for (unsigned int r = 1; r < h.time.size(); ++r)
              slip += 0.5 * (h.velocity_x[r] + h.velocity_x[r - 1]) *
                      (h.time[r] - h.time[r - 1]);
            const double N = 1000 * 0.4 * 0.15 * g * std::cos(theta);
            EXPECT_NEAR(h.friction_work.back(),
                        mu * N * slip,
                        0.05 * mu * N * slip);
          }
        else
          EXPECT_EQ(h.friction_work.back(), 0.);
      }
    // A perfect interface holds the block on the base.
    const BlockHistory stuck =
      run_block(" set Law = perfect\n", "output-stuck");
    EXPECT_LT(std::abs(stuck.velocity_x.back()), 0.01);
  }



  // The block on the inclined plane with each normal method found from
  // the grid or the points (seed 004 §4.1; NairnMPM reaches 0.981 of exact
  // with LR): LR within 1 % of g(sin θ − μ cos θ) and closer than the grid
  // methods (measured: DF 0.94, CP = 0.8 0.87 of exact: their normals tilt
  // at the block's corners and its grid-line edge).
  TEST(ContactRun, InclinedPlaneWithEachNormalMethod)
  {
    const double g = 9.81, theta = M_PI / 6, mu = 0.3;
    const double exact = g * (std::sin(theta) - mu * std::cos(theta));
    std::map<std::string, double> error;
    for (const std::string method :
         {"logistic regression", "d fit", "contact position"})
      {
        const BlockHistory h =
          run_block(" set Law = coulomb\n set Friction coefficient = 0.3\n"
                    " set Normals = " +
                      method + "\n",
                    "output-inclined-normals");
        const double ratio = h.velocity_x.back() / h.time.back() / exact;
        std::cout << "inclined plane, " << method << ": " << ratio
                  << " of exact" << std::endl;
        error[method] = std::abs(ratio - 1);
        EXPECT_LT(error[method], 0.2) << method;
        EXPECT_GT(h.friction_work.back(), 0) << method;
      }
    EXPECT_LT(error["logistic regression"], 0.01);
    EXPECT_LT(error["logistic regression"], error["d fit"]);
    EXPECT_LT(error["logistic regression"], error["contact position"]);
  }



  // Seed 004 Fig. 2 (parameters/two_blocks_gap.prm, the small version of
  // parameters/studies/contact_gap.study): the top block closes a 1.5-cell
  // gap at t_c = 7.796 ms. The bottom block carries no stress before t_c;
  // with LR it is loaded (σ_yy below half the impact stress ρcv) within
  // 1 % after t_c, with the contact plane on a grid line and in mid cell.
  // The velocity criterion alone detects contact far too early.
  double
  gap_contact_time(const std::string &settings, const std::string &directory)
  {
    ParameterHandler prm;
    auto             simulator =
      make_simulator<2>({parameter_dir + "two_blocks_gap.prm"},
                        output_overrides(directory) +
                          "subsection Time\n set End time = 0.00795\nend\n"
                          "subsection Output\n set Interval = 2e-5\nend\n" +
                          settings,
                        prm);
    simulator->run();
    const double threshold = 0.5 * 1000 * 1924 * 0.962;
    double       t0 = 0, s0 = 0;
    for (const auto &row : fmpm_tests::inspect(*simulator).get_history())
      {
        const double s = row.extra[4]; // σ_yy of material 0
        if (s < -threshold)
          return t0 + (row.time - t0) * (-threshold - s0) / (s - s0);
        t0 = row.time;
        s0 = s;
      }
    return std::numeric_limits<double>::infinity();
  }

  TEST(ContactRun, TwoBlocksCloseTheGapOnTime)
  {
    const double t_c       = 0.0075 / 0.962;
    const double grid_line = gap_contact_time("", "output-gap-grid-line");
    EXPECT_NEAR(grid_line, t_c, 0.01 * t_c);
    const double mid_cell = gap_contact_time(
      "subsection Body 0\n set Center = 0.02, 0.02625\n"
      " set Half lengths = 0.02, 0.02625\nend\n"
      "subsection Body 1\n set Center = 0.02, 0.08375\nend\n"
      "subsection Boundary conditions\n subsection Moving wall 0\n"
      "  set Function constants = v=0.962, top=0.1075\n end\nend\n",
      "output-gap-mid-cell");
    EXPECT_NEAR(mid_cell, t_c, 0.01 * t_c);
    const double velocity_only =
      gap_contact_time("subsection Contact\n set Normals = velocity only\nend\n"
                       "subsection Time\n set End time = 0.004\nend\n",
                       "output-gap-velocity-only");
    EXPECT_LT(velocity_only, 0.8 * t_c);
  }



  // Seed 004 Fig. 5, shortened: two identical blocks that start in contact
  // (their point domains tile, d_LR = 0 up to round-off), compressed past
  // the moment the wall reaches the next node row (5.2 ms, a small wave
  // through the interface). The average axial stress of the multimaterial
  // run must follow the single-material run of the same update; before the
  // touching tolerance a gap of 1e-7 cells switched contact off at nodes
  // carrying the whole load and LR-XPIC(2) left the bonded run by 80 %
  // (now within 0.13 %).
  std::vector<double>
  compression_axial_stress(const std::string &settings,
                           const std::string &directory)
  {
    ParameterHandler prm;
    auto             simulator = make_simulator<2>(
      {parameter_dir + "two_blocks_compression.prm"},
      output_overrides(directory) +
        "subsection Time\n set End time = 0.007\nend\n"
                    "subsection Particle update\n set Model name = xpic\nend\n"
                    "subsection Mass matrix\n set Model name = fmpm\n"
                    " subsection Fmpm\n  set Order = 2\n end\nend\n" +
        settings,
      prm);
    simulator->run();
    std::vector<double> stress;
    for (const auto &row : fmpm_tests::inspect(*simulator).get_history())
      {
        // mass-weighted σ_yy of the two materials (8 columns each in 2D)
        const double m0 = row.extra[0], m1 = row.extra[8];
        stress.push_back((m0 * row.extra[4] + m1 * row.extra[8 + 4]) /
                         (m0 + m1));
      }
    return stress;
  }

  TEST(ContactRun, BlocksStartingInContactStayBondedInCompression)
  {
    const auto single = compression_axial_stress(
      "subsection Contact\n set Model name = none\nend\n",
      "output-compression-single");
    const auto multi =
      compression_axial_stress("", "output-compression-multimaterial");
    ASSERT_EQ(single.size(), multi.size());
    ASSERT_GT(single.size(), 15u);
    // 7 ms = 6.7 % strain: σ_yy ≈ −2.2e8 Pa at the end.
    EXPECT_LT(single.back(), -2e8);
    for (unsigned int i = 1; i < single.size(); ++i)
      EXPECT_NEAR(multi[i], single[i], 3e-3 * std::abs(single[i]))
        << "output " << i;
  }



  // FLIP's first-order position update (psi = 0), which these contact
  // runs were measured with. The errors grow with psi, nearly linearly:
  // the sandwich's axial stress is off by 0.0001 %, 0.007 %, 0.12 % at
  // psi = 0, 0.5, 1 (bound 0.01 %), the spring bar's energy changes by
  // 0.60 %, 1.12 %, 1.77 % (bound 1 %), and NairnMPM's two disks end at
  // E/E0 = 1.00025 (psi = 0) and 1.0026 (psi = 1). Why: the spring's force
  // and the LR contact test depend on the point positions, and FLIP's
  // velocity takes the force at the start of the step. For such a
  // position-driven oscillator of frequency ω, V⁺ = V + aΔt with X⁺ = X +
  // (V − psi aΔt/2 + aΔt)Δt advances (X, V) by a matrix of determinant
  // 1 + psi ω²Δt²/2: energy grows each step (the bar: ωΔt = 3.6e-3, 1,168
  // steps, +0.74 %); psi = 0 is symplectic Euler (determinant 1). The
  // bulk's stress comes from F, which USAVG+ updates with the averaged
  // velocity that psi = 1 moves the points with (doc/choosing_a_method.md,
  // known failures).
  const std::string flip_first_order_position_update =
    "subsection Particle update\n subsection Flip\n"
    "  set Position update psi = 0\n end\nend\n";

  // Seed 004 Fig. 4C: a thin material (half a cell, one row of points)
  // between two others, all identical, LR with the scene's Coulomb law
  // (mu = 0.2), compressed to 5 %
  // like the blocks above: every node of the thin layer's lower face sees
  // three materials. The layer touches both blocks while the blocks are
  // half a cell apart: the explicit method corrects the two pairs in
  // contact together; the lumped method sees the layer against the sum of
  // two blocks on either side of it, which no line separates.
  std::vector<double>
  sandwich_axial_stress(const std::string &settings,
                        const std::string &directory,
                        double            *layer_gap = nullptr)
  {
    ParameterHandler prm;
    auto             simulator = make_simulator<2>(
      {parameter_dir + "two_blocks_compression.prm"},
      output_overrides(directory) + flip_first_order_position_update +
        "set Number of bodies = 3\nset Number of materials = 3\n"
                    "subsection Time\n set End time = 0.0052\nend\n"
                    "subsection Body 1\n set Center = 0.02, 0.05125\n"
                    " set Half lengths = 0.02, 0.00125\nend\n"
                    "subsection Body 2\n set Shape = box\n"
                    " set Center = 0.02, 0.07625\n set Half lengths = 0.02, 0.02375\n"
                    " set Material = 2\n set Initial velocity = 0; -v*y/H\n"
                    " set Function constants = v=0.962, H=0.1\nend\n"
                    "subsection Material 2\n set Model name = neo hookean\n"
                    " set Density = 1000\n subsection Neo hookean\n"
                    "  set Bulk modulus = 2.45e9\n  set Shear modulus = 9.4e8\n"
                    " end\nend\n" +
        settings,
      prm);
    simulator->run();
    std::vector<double> stress;
    for (const auto &row : fmpm_tests::inspect(*simulator).get_history())
      {
        // mass-weighted σ_yy of the materials (8 columns each in 2D)
        double mass = 0, sum = 0;
        for (unsigned int a = 0; 8 * a + 4 < row.extra.size(); ++a)
          {
            mass += row.extra[8 * a];
            sum += row.extra[8 * a] * row.extra[8 * a + 4];
          }
        stress.push_back(sum / mass);
      }
    if (layer_gap)
      {
        // The smallest distance between the layer's row of points and the
        // nearest row of either block.
        const auto &points =
          fmpm_tests::inspect(*simulator).get_material_points();
        double below = -1, above = 1, layer_low = 1, layer_high = -1;
        for (unsigned int k = 0; k < points.n_points(); ++k)
          {
            const unsigned int body = static_cast<unsigned int>(
              points.record(k)[fmpm::PropertyIndex<2>::body_id]);
            const double y = points.position[k][1];
            if (body == 0)
              below = std::max(below, y);
            else if (body == 2)
              above = std::min(above, y);
            else
              {
                layer_low  = std::min(layer_low, y);
                layer_high = std::max(layer_high, y);
              }
          }
        *layer_gap = std::min(layer_low - below, above - layer_high);
      }
    return stress;
  }

  TEST(ContactRun, ThinLayerBetweenTwoBlocksWithExplicitThreeMaterialNodes)
  {
    const auto single =
      sandwich_axial_stress("subsection Contact\n set Model name = none\nend\n",
                            "output-sandwich-single");
    ASSERT_GT(single.size(), 10u);
    EXPECT_LT(single.back(), -1.5e8); // 5 % strain
    double     gap   = 0;
    const auto multi = sandwich_axial_stress(
      "subsection Contact\n set Three or more materials = explicit\nend\n",
      "output-sandwich-explicit",
      &gap);
    ASSERT_EQ(single.size(), multi.size());
    double max_error = 0;
    for (unsigned int i = 1; i < single.size(); ++i)
      max_error =
        std::max(max_error,
                 std::abs(multi[i] - single[i]) / std::abs(single.back()));
    std::cout << "max axial stress error " << 100 * max_error
              << " %, smallest gap between point rows " << gap << " m\n";
    // (Lumped and pairwise 3+ nodes stop this run by energy growth at 0.2
    // and 0.4 ms.)
    EXPECT_LT(max_error, 1e-4);
    // The layer's row stays between the blocks' rows, 2.5 mm apart at the
    // start, about 5 % less when compressed uniformly.
    EXPECT_GT(gap, 0.9 * 0.0025);
    EXPECT_LT(gap, 0.0025);
  }



  // Imperfect interfaces ([Nairn2013]): a stiffness the time step cannot
  // resolve is the perfect interface, with FLIP and with FMPM(2)'s net
  // incremental contact (the colliding disks stick).
  TEST(ContactRun, StiffImperfectInterfaceIsPerfect)
  {
    for (const std::string update : {"flip", "fmpm"})
      {
        const std::string fmpm_order =
          update == "fmpm" ? "subsection Mass matrix\n set Model name = fmpm\n"
                             " subsection Fmpm\n  set Order = 2\n end\nend\n" :
                             "";
        auto run = [&](const std::string &law, const std::string &directory) {
          ParameterHandler prm;
          auto             simulator = make_simulator<2>(
            {parameter_dir + "colliding_disks.prm"},
            output_overrides(directory) + fmpm_order +
              two_material_disks(" set Model name = multimaterial\n"
                                             " set Normals = average gradient\n" +
                                   law,
                                 update),
            prm);
          simulator->run();
          return fmpm_tests::inspect(*simulator).get_history();
        };
        const auto perfect = run(" set Law = perfect\n", "output-perfect");
        const auto stiff   = run(" set Law = imperfect\n"
                                 " set Interface normal stiffness = 1e30\n"
                                 " set Interface tangential stiffness = 1e30\n",
                               "output-stiff-imperfect");
        ASSERT_EQ(perfect.size(), stiff.size());
        const double E0 = perfect.front().total_energy;
        for (unsigned int r = 0; r < perfect.size(); ++r)
          {
            EXPECT_NEAR(stiff[r].kinetic_energy,
                        perfect[r].kinetic_energy,
                        1e-12 * E0)
              << update << " t = " << perfect[r].time;
            EXPECT_NEAR(stiff[r].strain_energy,
                        perfect[r].strain_energy,
                        1e-12 * E0)
              << update << " t = " << perfect[r].time;
          }
        EXPECT_GT(perfect.back().strain_energy, 0.01 * E0) << update;
      }
  }

  // D = 0 transmits nothing: two blocks that start bonded and move apart
  // separate as with frictionless contact (which corrects nothing between
  // separating materials).
  TEST(ContactRun, ImperfectInterfaceWithoutStiffnessSeparatesFreely)
  {
    auto run = [](const std::string &law, const std::string &directory) {
      ParameterHandler prm;
      auto             simulator = make_simulator<2>(
        {parameter_dir + "two_blocks_compression.prm"},
        output_overrides(directory) +
          "subsection Boundary conditions\n set Fixed boundary ids =\n"
                      " subsection Moving wall 0\n"
                      "  set Function constants = v=0, top=1\n end\nend\n"
                      "subsection Time\n set End time = 0.001\nend\n"
                      "subsection Output\n set Interval = 0.0001\nend\n"
                      "subsection Body 0\n set Initial velocity = 0; -1\nend\n"
                      "subsection Body 1\n set Initial velocity = 0; 1\nend\n"
                      "subsection Contact\n" +
          law + "end\n",
        prm);
      simulator->run();
      return fmpm_tests::inspect(*simulator).get_history();
    };
    const auto frictionless =
      run(" set Law = frictionless\n", "output-separate-frictionless");
    const auto debonded = run(" set Law = imperfect\n"
                              " set Interface normal stiffness = 0\n"
                              " set Interface tangential stiffness = 0\n",
                              "output-separate-debonded");
    ASSERT_EQ(frictionless.size(), debonded.size());
    ASSERT_GT(frictionless.size(), 4u);
    for (unsigned int r = 0; r < frictionless.size(); ++r)
      for (unsigned int c = 0; c < 16; ++c) // the two materials' columns
        EXPECT_NEAR(debonded[r].extra[c],
                    frictionless[r].extra[c],
                    1e-12 * (std::abs(frictionless[r].extra[c]) + 1e-3))
          << "row " << r << " column " << c;
    // They moved apart: each keeps its velocity.
    EXPECT_NEAR(debonded.back().extra[2], -1, 1e-2);
    EXPECT_NEAR(debonded.back().extra[8 + 2], 1, 1e-2);
  }

  // A fixed-free bar (length L, E, rho, nu = 0) of two materials joined at
  // x = L/2 by an interface spring of stiffness D (traction D [u]): its
  // modes u = A sin(kx) (x < a), B cos(k(L - x)) (x > a) with
  // E u' = D [u] at x = a give (E k / D) cos(ka) sin(k(L - a)) = cos(kL);
  // D L / E = 1, a = L/2: tan(kL) = 2/(kL), kL = 1.07687 (the bonded bar:
  // pi/2). Started in that mode, material 0's mean velocity is
  // proportional to cos(omega t), omega = k sqrt(E/rho).
  TEST(ContactRun, BarWithAnInterfaceSpringVibratesAtItsFrequency)
  {
    const double L = 0.4, E = 1e9, rho = 1000, D = E / L, a = L / 2;
    // x tan x = 2 by Newton's method
    double x = 1;
    for (unsigned int i = 0; i < 50; ++i)
      x -=
        (x * std::tan(x) - 2) / (std::tan(x) + x / (std::cos(x) * std::cos(x)));
    const double       k = x / L, omega = k * std::sqrt(E / rho);
    const double       T = 2 * M_PI / omega;
    std::ostringstream scene;
    scene.precision(17);
    scene
      << "set Dimension = 2\nset Number of bodies = 2\n"
      << "set Number of materials = 2\n"
      << flip_first_order_position_update
      << "subsection Mesh\n set Lower corner = 0, 0\n set Upper corner = " << L
      << ", 0.02\n set Subdivisions = 80, 4\nend\n"
      << "subsection Boundary conditions\n set Roller boundary ids = 0\nend\n"
      << "subsection Time\n set End time = " << 1.25 * T
      << "\n set Courant number = 0.5\nend\n";
    for (unsigned int m = 0; m < 2; ++m)
      scene << "subsection Material " << m
            << "\n set Model name = linear elastic\n set Density = " << rho
            << "\n subsection Linear elastic\n  set Young's modulus = " << E
            << "\n  set Poisson's ratio = 0\n end\nend\n";
    scene << "subsection Body 0\n set Shape = box\n set Center = " << a / 2
          << ", 0.01\n set Half lengths = " << a / 2 << ", 0.01\n"
          << " set Initial velocity = v0*sin(k*x); 0\n"
          << " set Function constants = v0=0.1, k=" << k << "\nend\n"
          << "subsection Body 1\n set Shape = box\n set Material = 1\n"
          << " set Center = " << (a + L) / 2
          << ", 0.01\n set Half lengths = " << (L - a) / 2 << ", 0.01\n"
          << " set Initial velocity = v0*C*cos(k*(L-x)); 0\n"
          << " set Function constants = v0=0.1, k=" << k << ", L=" << L
          << ", C=" << std::cos(k * a) / std::sin(k * (L - a)) << "\nend\n"
          << "subsection Contact\n set Model name = multimaterial\n"
          << " set Normals = average gradient\n set Law = imperfect\n"
          << " set Interface normal stiffness = " << D
          << "\n set Interface tangential stiffness = " << D << "\nend\n"
          << "subsection Output\n set Interval = " << T / 200 << "\nend\n";
    ParameterHandler prm;
    auto             simulator =
      make_simulator<2>({},
                        scene.str() + output_overrides("output-interface-bar"),
                        prm);
    simulator->run();
    // The zero crossings of material 0's mean velocity: T/4, 3T/4 (and
    // 5T/4 at the end).
    const auto         &history = fmpm_tests::inspect(*simulator).get_history();
    std::vector<double> crossings;
    for (unsigned int r = 1; r < history.size(); ++r)
      {
        const double v0 = history[r - 1].extra[1], v1 = history[r].extra[1];
        if ((v0 > 0) != (v1 > 0))
          crossings.push_back(history[r - 1].time +
                              (history[r].time - history[r - 1].time) * v0 /
                                (v0 - v1));
      }
    ASSERT_GE(crossings.size(), 2u);
    const double measured_period =
      2 * (crossings.back() - crossings.front()) / (crossings.size() - 1);
    std::cout << std::setprecision(6) << "period " << measured_period
              << " s, analytical " << T
              << " s (bonded: " << 4 * L / std::sqrt(E / rho) << " s)\n";
    EXPECT_NEAR(measured_period / T, 1, 0.005);
    // The energy history counts the spring's energy ½ A_c D [u]²: the
    // total stays (the bar's energy is half in the spring at T/2).
    double max_energy_change = 0;
    for (const auto &row : history)
      max_energy_change =
        std::max(max_energy_change,
                 std::abs(row.total_energy / history.front().total_energy - 1));
    std::cout << "largest energy change " << max_energy_change << "\n";
    EXPECT_LT(max_energy_change, 0.01);
  }



  // NairnMPM's two-disk example (parameters/two_disks.prm: its material,
  // 'Strain measure = kirchhoff', and its contact detection, 'Gap closing =
  // false'), on 1 mm cells: frictionless LR contact keeps the energy. At
  // 16 ms (after the rebound) E/E0 = 1.00025; with one velocity field
  // 0.99988; with fmpm's gap closing 0.99392. On the scene's 0.5 mm cells
  // (doc/studies/two_disks_contact_energy.md) 1.00008, NairnMPM 0.99999.
  TEST(ContactRun, TwoDisksKeepTheirEnergyLikeNairnMPM)
  {
    ParameterHandler prm;
    auto             simulator = make_simulator<2>(
      {parameter_dir + "two_disks.prm"},
      output_overrides("output-two-disks-energy") +
        flip_first_order_position_update +
        "subsection Mesh\n set Subdivisions = 105, 49\nend\n"
                    "subsection Time\n set Time step = 1.59090230663411e-05\nend\n",
      prm);
    simulator->run();
    const auto &history = fmpm_tests::inspect(*simulator).get_history();
    ASSERT_NEAR(history.back().time, 0.016, 1e-12);
    const double E0                = history.front().total_energy;
    double       max_contact_nodes = 0;
    for (const auto &row : history)
      max_contact_nodes = std::max(max_contact_nodes, row.extra.back());
    EXPECT_GT(max_contact_nodes, 10);
    // Rebound: each disk's x velocity reversed (+2.5 and -2.5 m/s at the
    // start), and the disks are apart again.
    EXPECT_LT(history.back().extra[1], -1.5);
    EXPECT_GT(history.back().extra[8 + 1], 1.5);
    EXPECT_EQ(history.back().extra.back(), 0.);
    EXPECT_NEAR(history.back().total_energy / E0, 1, 5e-4);
  }



  // Frictionless disks: they bounce off each other (each material's
  // velocity reverses), the total momentum stays zero, and contact was
  // detected at nodes only around the impact.
  TEST(ContactRun, FrictionlessDisksRebound)
  {
    ParameterHandler prm;
    auto             simulator = make_simulator<2>(
      {parameter_dir + "colliding_disks.prm"},
      output_overrides("output-contact-disks") +
        two_material_disks(" set Model name = multimaterial\n"
                                       " set Law = frictionless\n"
                                       " set Normals = contact position\n",
                           "flip") +
        "subsection Time\n set End time = 2.2\nend\n",
      prm);
    simulator->run();
    const auto &history = fmpm_tests::inspect(*simulator).get_history();
    double      max_contact_nodes = 0;
    for (const auto &row : history)
      {
        EXPECT_LT(row.momentum.norm(), 1e-12);
        max_contact_nodes = std::max(max_contact_nodes, row.extra.back());
      }
    EXPECT_GT(max_contact_nodes, 0);
    EXPECT_EQ(history.front().extra.back(), 0.);
    // Body 0 (material 0) started at +0.1 in x, body 1 at -0.1.
    EXPECT_NEAR(history.front().extra[1], 0.1, 1e-12);
    EXPECT_LT(history.back().extra[1], -0.05);
    EXPECT_GT(history.back().extra[8 + 1], 0.05);
  }



  /** Three blocks meeting at a T (seed 004 Fig. 4A): the node where they
   * meet sees three materials. */
  std::string
  three_blocks(const std::string &materials_and_contact)
  {
    std::string scene =
      "set Dimension = 2\nset Number of bodies = 3\n"
      "subsection Mesh\n set Lower corner = 0, 0\n set Upper corner = 1, 1\n"
      " set Subdivisions = 10, 10\nend\n"
      "subsection Time\n set End time = 0.6\nend\n"
      "subsection Body 0\n set Center = 0.3, 0.5\n set Half lengths = 0.1, 0.2\n"
      " set Initial velocity = 0.1, 0\nend\n"
      "subsection Body 1\n set Center = 0.5, 0.6\n set Half lengths = 0.1, 0.1\n"
      " set Initial velocity = -0.05, -0.05\nend\n"
      "subsection Body 2\n set Center = 0.5, 0.4\n set Half lengths = 0.1, 0.1\n"
      " set Initial velocity = -0.05, 0.05\nend\n";
    for (unsigned int m = 0; m < 3; ++m)
      scene += "subsection Material " + std::to_string(m) +
               "\n set Model name = linear elastic\n set Density = 1000\n"
               " subsection Linear elastic\n  set Young's modulus = 1000\n"
               " end\nend\n";
    return scene + materials_and_contact;
  }

  // Nodes with three materials (seed 004 §3.4): with perfect laws the
  // lumped method (each material against the sum of the others, Eq. 50)
  // reproduces the single-material run; the pairwise method conserves
  // momentum exactly.
  TEST(ContactRun, ThreeMaterialNodes)
  {
    ParameterHandler prm_one;
    auto             one = make_simulator<2>({},
                                 three_blocks("set Number of materials = 3\n") +
                                   output_overrides("output-blocks-one"),
                                 prm_one);
    one->run();
    const std::string materials = "set Number of materials = 3\n"
                                  "subsection Body 1\n set Material = 1\nend\n"
                                  "subsection Body 2\n set Material = 2\nend\n";
    for (const std::string method : {"lumped", "pairwise"})
      {
        ParameterHandler prm;
        auto             three = make_simulator<2>(
          {},
          three_blocks(
            materials +
            "subsection Contact\n set Model name = multimaterial\n"
                        " set Normals = average gradient\n set Law = " +
            std::string(method == "lumped" ? "perfect" : "frictionless") +
            "\n set Three or more materials = " + method + "\nend\n") +
            output_overrides("output-blocks-" + method),
          prm);
        three->run();
        const auto &h1 = fmpm_tests::inspect(*one).get_history();
        const auto &h3 = fmpm_tests::inspect(*three).get_history();
        ASSERT_EQ(h1.size(), h3.size());
        const double E0                = h1.front().total_energy;
        const double p_norm            = h1.front().momentum.norm();
        double       max_contact_nodes = 0;
        for (unsigned int r = 0; r < h1.size(); ++r)
          {
            EXPECT_NEAR((h3[r].momentum - h1.front().momentum).norm(),
                        0,
                        1e-12 * p_norm)
              << method;
            if (method == "lumped")
              {
                EXPECT_NEAR(h3[r].total_energy, h1[r].total_energy, 1e-10 * E0);
              }
            max_contact_nodes = std::max(max_contact_nodes, h3[r].extra.back());
          }
        // contact_nodes (last extra column): the blocks collide.
        EXPECT_GT(max_contact_nodes, 0) << method;
      }
  }



  /** Indices of the points with at least 6 of their 8 nearest other
   * points in one single other body (contrib/studies/ellipse_compaction.py's
   * "inside another body"). */
  std::vector<unsigned int>
  points_inside_another_body(const std::vector<Point<2>>     &x,
                             const std::vector<unsigned int> &body)
  {
    std::vector<unsigned int>                    inside;
    std::vector<std::pair<double, unsigned int>> distance(x.size());
    for (unsigned int i = 0; i < x.size(); ++i)
      {
        for (unsigned int j = 0; j < x.size(); ++j)
          distance[j] = {j == i ? std::numeric_limits<double>::max() :
                                  x[i].distance_square(x[j]),
                         j};
        std::partial_sort(distance.begin(),
                          distance.begin() + 8,
                          distance.end());
        std::map<unsigned int, unsigned int> votes;
        for (unsigned int k = 0; k < 8; ++k)
          if (body[distance[k].second] != body[i])
            ++votes[body[distance[k].second]];
        for (const auto &[other, count] : votes)
          if (count >= 6)
            {
              inside.push_back(i);
              break;
            }
      }
    return inside;
  }

  // The neighbour test counts a point placed among another body's points
  // and none on a clean interface.
  TEST(ContactCompaction, InsideAnotherBodyTest)
  {
    std::vector<Point<2>>     x;
    std::vector<unsigned int> body;
    for (unsigned int i = 0; i < 10; ++i)
      for (unsigned int j = 0; j < 10; ++j)
        {
          x.emplace_back(i, j);
          body.push_back(i < 5 ? 0 : 1);
        }
    EXPECT_TRUE(points_inside_another_body(x, body).empty());
    body[7 * 10 + 4]  = 0; // a point of body 0 deep in body 1
    const auto inside = points_inside_another_body(x, body);
    ASSERT_EQ(inside.size(), 1u);
    EXPECT_EQ(inside[0], 74u);
  }

  // A small seed 004 Fig. 6: the four lowest ellipses of
  // parameters/ellipse_compaction.prm in a 1 x 0.8 mm box (same cells,
  // points, materials, CPDI with a critical radius of 1, multimaterial
  // XPIC(5), frictionless LR, lumped 3+ nodes, the piston driving the node
  // below its face), compressed by 65 % at 100 m/s to about 45 GPa. LR keeps
  // every point out of the other bodies (DF: 22 points inside, 2026-11-26);
  // no point piles up on the piston face (a box wall that pushes points
  // back onto its face: 158); the points' volumes fit in the box.
  TEST(ContactCompaction, LogisticRegressionKeepsCompactedEllipsesApart)
  {
    const double top = 0.0008, speed = 100, end_time = 0.65 * top / speed;
    std::string  scene =
      "set Dimension = 2\nset Number of bodies = 4\n"
      "set Number of materials = 4\nset Number of moving walls = 1\n"
      "subsection Mesh\n set Upper corner = 0.001, 0.0008\n"
      " set Subdivisions = 35, 28\nend\n"
      "subsection Shape function\n set Type = cpdi\n"
      " set CPDI critical radius = 1\nend\n"
      "subsection Boundary conditions\n set Fixed boundary ids = 2\n"
      " set Roller boundary ids = 0, 1\n subsection Moving wall 0\n"
      "  set Region = y - (top - v*t) + h - 1e-7\n  set Direction = 0, 1\n"
      "  set Velocity = -v\n"
      "  set Function constants = v=100, top=0.0008, h=2.857142857e-5\n"
      " end\nend\n"
      "subsection Time\n set End time = 5.2e-6"
      // The time step of the former stability factor 0.6 x 0.4.
      "\n set Courant number = 0.24\n set Strain update = usavg+\nend\n"
      "subsection Particle update\n set Model name = xpic\n"
      " subsection Xpic\n  set Position update psi = 0\n end\nend\n"
      "subsection Mass matrix\n set Model name = fmpm\n"
      " subsection Fmpm\n  set Order = 5\n end\nend\n"
      "subsection Contact\n set Model name = multimaterial\n"
      " set Normals = logistic regression\n set Law = frictionless\n"
      " set Three or more materials = lumped\nend\n";
    const std::array<std::array<double, 4>, 4> ellipses = {
      {{{0.2424, 0.1395, 0.2110, 0.1074}},
       {{0.7264, 0.1454, 0.2420, 0.1134}},
       {{0.4711, 0.3858, 0.2557, 0.1260}},
       {{0.8609, 0.4962, 0.1055, 0.2197}}}};
    for (unsigned int b = 0; b < 4; ++b)
      {
        const auto        &e = ellipses[b];
        std::ostringstream body;
        body << "subsection Body " << b << "\n set Shape = ellipsoid\n"
             << " set Center = " << 1e-3 * e[0] << ", " << 1e-3 * e[1]
             << "\n set Half lengths = " << 1e-3 * e[2] << ", " << 1e-3 * e[3]
             << "\n set Material = " << b << "\nend\n"
             << "subsection Material " << b
             << "\n set Model name = neo hookean\n set Density = 2780\n"
             << " subsection Neo hookean\n  set Bulk modulus = 7.809e10\n"
             << "  set Shear modulus = 2.76e10\n end\nend\n";
        scene += body.str();
      }
    ParameterHandler prm;
    auto             simulator = make_simulator<2>(
      {}, scene + output_overrides("output-ellipse-compaction-small"), prm);
    simulator->run();
    ASSERT_NEAR(fmpm_tests::inspect(*simulator).get_history().back().time,
                end_time,
                1e-12);

    std::vector<Point<2>>     x;
    std::vector<unsigned int> body;
    double                    volume = 0;
    const auto &points = fmpm_tests::inspect(*simulator).get_material_points();
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const auto p = points.record(k);
        x.push_back(points.position[k]);
        body.push_back(
          static_cast<unsigned int>(p[fmpm::PropertyIndex<2>::body_id]));
        volume += p[fmpm::PropertyIndex<2>::volume];
      }
    ASSERT_GT(x.size(), 1500u);
    const auto inside = points_inside_another_body(x, body);
    EXPECT_TRUE(inside.empty()) << inside.size() << " points, the first at "
                                << (inside.empty() ? Point<2>() : x[inside[0]]);
    const double face    = top - speed * end_time;
    const double spacing = 0.001 / 70; // 2 x 2 points per cell
    unsigned int on_face = 0;
    for (const auto &point : x)
      on_face += point[1] > face - 0.1 * spacing;
    EXPECT_EQ(on_face, 0u);
    EXPECT_LT(volume / (0.001 * face), 1.0);
    // Compacted: the piston (the last reaction, after the boundary ids 2, 0
    // and 1) presses with about 40 GPa over the box width.
    const auto &reactions =
      fmpm_tests::inspect(*simulator).get_history().back().reactions;
    ASSERT_EQ(reactions.size(), 4u);
    EXPECT_GT(-reactions.back()[1] / 0.001, 30e9);
  }



  TEST(ContactParameters, BadInputNamesTheParameter)
  {
    const std::string scene = two_material_disks(
      " set Model name = multimaterial\n set Normals = specified\n", "flip");
    const std::vector<std::pair<std::string, std::vector<std::string>>> cases =
      {{" set Pair laws = 0 2: perfect\n", {"Contact/Pair laws", "material 2"}},
       {" set Pair laws = 0 1: sticky\n", {"Contact/Pair laws", "sticky"}},
       {" set Pair laws = 0 1 perfect\n", {"Contact/Pair laws", "a b: law"}},
       {" set Pair laws = 0 1: frictionless 0.3\n",
        {"Contact/Pair laws", "takes no number", "coulomb"}},
       {" set Normals = nearest node\n", {"Normals", "logistic", "specified"}}};
    for (const auto &[setting, words] : cases)
      {
        ParameterHandler prm;
        try
          {
            make_simulator<2>({parameter_dir + "colliding_disks.prm"},
                              output_overrides("output-contact-bad") + scene +
                                "subsection Contact\n" + setting + "end\n",
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
    // The exact full mass matrix with contact once per step: the limit has
    // no contact left; refused, naming both settings.
    ParameterHandler prm;
    try
      {
        make_simulator<2>(
          {parameter_dir + "colliding_disks.prm"},
          output_overrides("output-contact-bad") +
            two_material_disks(" set Model name = multimaterial\n"
                               " set Normals = specified\n"
                               " set Contact in mass-matrix iterations = once "
                               "per step\n",
                               "fmpm") +
            "subsection Mass matrix\n set Model name = "
            "full\nend\n",
          prm);
        ADD_FAILURE() << "the full mass matrix with contact once per step "
                         "accepted";
      }
    catch (const std::exception &e)
      {
        EXPECT_NE(std::string(e.what()).find("once per step"),
                  std::string::npos)
          << e.what();
        EXPECT_NE(std::string(e.what()).find("Model name = full"),
                  std::string::npos)
          << e.what();
      }
  }
} // namespace
