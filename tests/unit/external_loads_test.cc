// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks fmpm::ExternalLoads<2>: the rotating frame's acceleration
// b = g − ω × (ω × r) − 2 ω × V − ω̇ × r against its closed form for
// ω(t) = (0, 0, a + c t) (centrifugal, Coriolis and Euler terms), and with
// ω, ω̇ evaluated once per step the same bits as evaluating them for every
// point; b(X, t) at the initial position; a traction's force t(t) A_p on
// the points of its box only, its power F · V and the work
// W = W_walls + Σ F · V Δt of the step, which starts from zero power in the
// next step.

#include <fmpm/external_loads.h>
#include <fmpm/material_points.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_properties.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using Index = fmpm::PropertyIndex<2>;

  /** A store of points in one cell with the loads' slots. */
  struct LoadedPoints
  {
    Triangulation<2>            triangulation;
    fmpm::ParticleProperties<2> properties;
    fmpm::ExternalLoads<2>      loads;
    fmpm::MaterialPoints<2>     points;

    explicit LoadedPoints(const fmpm::Parameters &parameters)
    {
      GridGenerator::hyper_cube(triangulation, -4, 4);
      loads.initialize(parameters, properties);
      points.initialize(properties.n_properties());
      points.set_cell_order({triangulation.begin_active()},
                            triangulation.n_active_cells());
    }

    /** A point at @p x (initial position @p X) with velocity @p V, mass
     * @p M and initial half lengths (0.1, 0.2). */
    void
    add(const unsigned int  id,
        const Point<2>     &x,
        const Point<2>     &X,
        const Tensor<1, 2> &V,
        const double        M)
    {
      std::vector<double> record(properties.n_properties(), 0.);
      record[Index::mass] = M;
      for (unsigned int d = 0; d < 2; ++d)
        {
          record[Index::velocity + d]         = V[d];
          record[Index::initial_position + d] = X[d];
        }
      record[Index::initial_half_length]     = 0.1;
      record[Index::initial_half_length + 1] = 0.2;
      points.add(
        id, x, Point<2>(0.5, 0.5), triangulation.begin_active(), record.data());
      points.rebin();
    }
  };

  /** b of the rotating frame as it was evaluated for every point: ω at t
   * and ω̇ by the central difference over ±10⁻⁶ max(1, |t|). */
  Tensor<1, 2>
  rotating_frame_per_point(FunctionParser<1>  &omega_function,
                           const double        t,
                           const Point<2>     &x,
                           const Tensor<1, 2> &V,
                           const Tensor<1, 2> &g,
                           const Point<2>     &center)
  {
    Tensor<1, 3> omega, omega_dot, r, v;
    const double dt = 1e-6 * std::max(1.0, std::abs(t));
    omega_function.set_time(t);
    for (unsigned int d = 0; d < 3; ++d)
      omega[d] = omega_function.value(Point<1>(), d);
    omega_function.set_time(t + dt);
    for (unsigned int d = 0; d < 3; ++d)
      omega_dot[d] = omega_function.value(Point<1>(), d);
    omega_function.set_time(t - dt);
    for (unsigned int d = 0; d < 3; ++d)
      omega_dot[d] =
        (omega_dot[d] - omega_function.value(Point<1>(), d)) / (2 * dt);
    for (unsigned int d = 0; d < 2; ++d)
      {
        r[d] = x[d] - center[d];
        v[d] = V[d];
      }
    const Tensor<1, 3> a = cross_product_3d(omega, cross_product_3d(omega, r)) +
                           2 * cross_product_3d(omega, v) +
                           cross_product_3d(omega_dot, r);
    Tensor<1, 2> b = g;
    for (unsigned int d = 0; d < 2; ++d)
      b[d] -= a[d];
    return b;
  }
} // namespace



TEST(ExternalLoads, RotatingFrameTermsOncePerStep)
{
  fmpm::Parameters parameters;
  parameters.gravity                         = {0, -9.81, 0};
  parameters.rotating_frame.enable           = true;
  parameters.rotating_frame.angular_velocity = "0; 0; 2 + 3*t";
  parameters.rotating_frame.center           = {0.5, 0.25, 0};
  LoadedPoints loaded(parameters);
  EXPECT_TRUE(loaded.loads.has_point_body_force());
  // r = (1, 0), V = (0, 0.5); a point at rest at the centre.
  loaded.add(
    0, Point<2>(1.5, 0.25), Point<2>(1.5, 0.25), Tensor<1, 2>({0., 0.5}), 2.);
  loaded.add(
    1, Point<2>(0.5, 0.25), Point<2>(0.5, 0.25), Tensor<1, 2>({0., 0.}), 2.);

  for (const double t : {0.4, 1.7})
    {
      loaded.loads.begin_step(t);
      // Ω = 2 + 3 t, Ω̇ = 3: b = (Ω² + Ω, g_y − 3 r_x) at r = (1, 0) with
      // V = (0, 0.5): −ω×(ω×r) = (Ω², 0), −2ω×V = (Ω, 0), −ω̇×r = (0, −3).
      const double Omega = 2 + 3 * t;
      const auto   b     = loaded.loads.acceleration(loaded.points, 0);
      EXPECT_NEAR(b[0], Omega * Omega + Omega, 1e-7 * Omega * Omega);
      EXPECT_NEAR(b[1], -9.81 - 3., 1e-7);
      // At the frame's centre and at rest only gravity.
      const auto b_center = loaded.loads.acceleration(loaded.points, 1);
      EXPECT_EQ(b_center[0], 0.);
      EXPECT_EQ(b_center[1], -9.81);

      // ω depends on t only: the bits of evaluating it for every point.
      FunctionParser<1> omega_function(3);
      omega_function.initialize("x,t", {"0", "0", "2 + 3*t"}, {}, true);
      for (unsigned int k = 0; k < 2; ++k)
        {
          const unsigned int id = loaded.points.id[k];
          const Point<2>     x  = loaded.points.position[k];
          const Tensor<1, 2> V({loaded.points.column(Index::velocity)[k],
                                loaded.points.column(Index::velocity + 1)[k]});
          const auto         per_point =
            rotating_frame_per_point(omega_function,
                                     t,
                                     x,
                                     V,
                                     Tensor<1, 2>({0., -9.81}),
                                     Point<2>(0.5, 0.25));
          const auto once = loaded.loads.acceleration(loaded.points, k);
          EXPECT_EQ(once[0], per_point[0]) << "point " << id;
          EXPECT_EQ(once[1], per_point[1]) << "point " << id;
        }
    }
}



TEST(ExternalLoads, BodyAccelerationAtInitialPosition)
{
  fmpm::Parameters parameters;
  parameters.gravity           = {1, 0, 0};
  parameters.body_acceleration = "x*t; 2*y";
  for (const bool at_initial : {false, true})
    {
      parameters.body_acceleration_at_initial_position = at_initial;
      LoadedPoints loaded(parameters);
      loaded.add(
        0, Point<2>(1, 2), Point<2>(3, -1), Tensor<1, 2>({0., 0.}), 1.);
      loaded.loads.begin_step(0.5);
      const Point<2> where = at_initial ? Point<2>(3, -1) : Point<2>(1, 2);
      const auto     b     = loaded.loads.acceleration(loaded.points, 0);
      EXPECT_DOUBLE_EQ(b[0], 1. + where[0] * 0.5);
      EXPECT_DOUBLE_EQ(b[1], 2. * where[1]);
    }
}



TEST(ExternalLoads, TractionForcePowerAndWork)
{
  fmpm::Parameters parameters;
  parameters.gravity = {0, -2, 0};
  fmpm::TractionParameters traction;
  traction.box_lower                       = {0, 0, 0};
  traction.box_upper                       = {1, 1, 0};
  traction.traction                        = "2*t; -1";
  traction.normal_axis                     = 0;
  parameters.boundary_conditions.tractions = {traction};
  LoadedPoints loaded(parameters);
  EXPECT_TRUE(loaded.loads.has_tractions());
  // Point 0 starts in the box (area 2 l0_y = 0.4), point 1 outside.
  loaded.add(0, Point<2>(3, 3), Point<2>(0.5, 0.5), Tensor<1, 2>({3., 1.}), 2.);
  loaded.add(
    1, Point<2>(0.5, 0.5), Point<2>(2, 0.5), Tensor<1, 2>({1., 1.}), 2.);
  loaded.loads.mark_traction_points(loaded.points);

  loaded.loads.begin_step(0.5);
  // t = (1, −1), F = 0.4 t = (0.4, −0.4) on point 0 (by its initial
  // position), none on point 1.
  const auto F = loaded.loads.traction_force(loaded.points, 0);
  EXPECT_DOUBLE_EQ(F[0], 0.4);
  EXPECT_DOUBLE_EQ(F[1], -0.4);
  EXPECT_EQ(loaded.loads.traction_force(loaded.points, 1).norm(), 0.);
  const auto a0 = loaded.loads.acceleration(loaded.points, 0);
  EXPECT_DOUBLE_EQ(a0[0], 0.2);
  EXPECT_DOUBLE_EQ(a0[1], -2.2);
  const auto a1 = loaded.loads.acceleration(loaded.points, 1);
  EXPECT_EQ(a1[0], 0.);
  EXPECT_EQ(a1[1], -2.);

  // W = W_walls + F · V Δt = 0.25 + 0.8 × 0.1; the scale at least
  // |F| × the mesh diameter.
  loaded.loads.add_step_work(0.25, 0.1, 2., MPI_COMM_WORLD);
  EXPECT_DOUBLE_EQ(loaded.loads.work(), 0.25 + 0.08);
  EXPECT_DOUBLE_EQ(loaded.loads.work_scale(), 0.4 * std::sqrt(2.) * 2.);
  // The next step starts from zero power: only the walls' work.
  loaded.loads.begin_step(0.6);
  loaded.loads.add_step_work(-0.05, 0.1, 2., MPI_COMM_WORLD);
  EXPECT_DOUBLE_EQ(loaded.loads.work(), 0.25 + 0.08 - 0.05);
  EXPECT_DOUBLE_EQ(loaded.loads.work_scale(), 0.4 * std::sqrt(2.) * 2. + 0.05);
}
