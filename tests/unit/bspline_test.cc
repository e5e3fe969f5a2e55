// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks fmpm::BSpline: the 1D bases of degree 1, 2, 3 with padding and
// open knots against an independent Cox-de Boor recursion on the explicit
// knot vector; partition of unity, linear completeness Σ S_i x_i = x,
// Σ dS_i = 0 and Σ dS_i x_i = 1 everywhere (the open ends and beyond them
// included); the open end's vertex function equal to 1 on the wall; that a
// wrong basis fails these checks (Uintah's merge of the extra end function,
// a perturbed knot); the B-spline GIMP averages in closed form against
// quadrature and against sampling; and in 2D and 3D, for b2spline,
// b3spline, b2gimp and b2cpdi with both boundaries, Σ S = 1, Σ S x_i = x,
// Σ G = 0, Σ G ⊗ x_i = I at random points, the lattice of a deal.II mesh
// and its vertex map, and the refusal of meshes that are not box
// lattices.

#include <fmpm/bspline.h>
#include <fmpm/bspline_supports.h>
#include <fmpm/grid_transfer.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/affine_constraints.h>

#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using fmpm::BSpline::Basis1D;
  using fmpm::BSpline::Boundary;

  // Sums of O(1) terms: round-off is a few 1e-16; a wrong basis is off by
  // 1e-3 or more.
  constexpr double tolerance = 1e-13;

  std::string
  name(const Boundary boundary)
  {
    return boundary == Boundary::padding ? "padding" : "open knots";
  }

  /** The knot vector (in cells) of the basis written out in full: open
   * (p + 1 repeated end knots) or uniform (p + 3 knots beyond each end). */
  std::vector<double>
  explicit_knots(const unsigned int p,
                 const unsigned int n,
                 const Boundary     boundary)
  {
    std::vector<double> knots;
    const double        shift = 0.5 * (p + 1);
    if (boundary == Boundary::open_knots)
      {
        knots.assign(p + 1, 0.);
        for (int m = 0; m <= static_cast<int>(n) + 2; ++m)
          if (m - shift > 0 && m - shift < n)
            knots.push_back(m - shift);
        knots.insert(knots.end(), p + 1, double(n));
      }
    else
      for (int m = -static_cast<int>(p) - 3; m <= static_cast<int>(n + p) + 3;
           ++m)
        knots.push_back(m - shift);
    return knots;
  }

  /** N_{m,q}(t) by the Cox-de Boor recursion (0/0 = 0); the last non-empty
   * span is closed at its right end. */
  double
  cox_de_boor(const std::vector<double> &U,
              const int                  m,
              const int                  q,
              const double               t)
  {
    if (q == 0)
      {
        const bool last_span =
          U[m + 1] == U.back() && U[m] < U[m + 1] && t == U.back();
        return (U[m] <= t && t < U[m + 1]) || last_span ? 1. : 0.;
      }
    double value = 0;
    if (U[m + q] > U[m])
      value += (t - U[m]) / (U[m + q] - U[m]) * cox_de_boor(U, m, q - 1, t);
    if (U[m + q + 1] > U[m + 1])
      value += (U[m + q + 1] - t) / (U[m + q + 1] - U[m + 1]) *
               cox_de_boor(U, m + 1, q - 1, t);
    return value;
  }

  double
  cox_de_boor_derivative(const std::vector<double> &U,
                         const int                  m,
                         const int                  q,
                         const double               t)
  {
    double value = 0;
    if (U[m + q] > U[m])
      value += q / (U[m + q] - U[m]) * cox_de_boor(U, m, q - 1, t);
    if (U[m + q + 1] > U[m + 1])
      value -= q / (U[m + q + 1] - U[m + 1]) * cox_de_boor(U, m + 1, q - 1, t);
    return value;
  }

  /** S_i(t), dS_i/dt of every vertex i = 0 ... n from the explicit knot
   * vector: each B-spline to the vertices around its Greville abscissa. */
  void
  reference_values(const std::vector<double> &U,
                   const unsigned int         p,
                   const unsigned int         n,
                   const double               t,
                   std::vector<double>       &S,
                   std::vector<double>       &dS)
  {
    S.assign(n + 1, 0.);
    dS.assign(n + 1, 0.);
    for (int m = 0; m + static_cast<int>(p) + 1 < static_cast<int>(U.size());
         ++m)
      {
        double g = 0;
        for (unsigned int k = 1; k <= p; ++k)
          g += U[m + k];
        g /= p;
        const double value      = cox_de_boor(U, m, p, t);
        const double derivative = cox_de_boor_derivative(U, m, p, t);
        const int    i          = static_cast<int>(std::floor(g + 1e-12));
        const double f          = std::max(0., g - i);
        for (const auto &[vertex, share] :
             {std::pair<int, double>{i, 1 - f}, {i + 1, f}})
          if (share != 0)
            {
              if (vertex < 0 || vertex > static_cast<int>(n))
                {
                  // (padding: functions of vertices beyond the lattice must
                  // vanish where the test evaluates)
                  EXPECT_EQ(value, 0.) << "vertex " << vertex << " at " << t;
                  continue;
                }
              S[vertex] += share * value;
              dS[vertex] += share * derivative;
            }
      }
  }

  /** The defects of Σ S = 1, Σ S x_i = x, Σ dS = 0, Σ dS x_i = 1 (scaled
   * by h) of one evaluation. */
  struct Defects
  {
    double unity = 0, linear = 0, gradient_sum = 0, gradient_linear = 0;
    double
    largest() const
    {
      return std::max(std::max(unity, linear),
                      std::max(gradient_sum, gradient_linear));
    }
  };

  Defects
  defects(const Basis1D &basis,
          const double   x,
          const int      first,
          const unsigned count,
          const double  *S,
          const double  *dS)
  {
    const double h = basis.cell_size();
    double       s = 0, sx = 0, g = 0, gx = 0;
    for (unsigned int k = 0; k < count; ++k)
      {
        const double xi = basis.vertex(first + k);
        s += S[k];
        sx += S[k] * xi;
        g += dS[k];
        gx += dS[k] * xi;
      }
    return Defects{std::abs(s - 1),
                   std::abs(sx - x) / h,
                   std::abs(g) * h,
                   std::abs(gx - 1)};
  }

  /** Sample points of a basis: the whole mesh and half a cell beyond (open
   * knots), or outside the padding layer; knots and vertices included. */
  std::vector<double>
  sample_points(const Basis1D &basis)
  {
    const double        n     = basis.n_cells();
    const bool          open  = basis.boundary() == Boundary::open_knots;
    const double        first = open ? -0.5 : 1, last = open ? n + 0.5 : n - 1;
    std::vector<double> t;
    for (double s = first; s <= last + 1e-12; s += 0.03125) // knots too
      t.push_back(s);
    std::mt19937                           generator(5);
    std::uniform_real_distribution<double> uniform(first, last);
    for (unsigned int k = 0; k < 400; ++k)
      t.push_back(uniform(generator));
    std::vector<double> x;
    for (const double s : t)
      x.push_back(basis.vertex(0) + s * basis.cell_size());
    return x;
  }

  const std::vector<Boundary> both_boundaries{Boundary::padding,
                                              Boundary::open_knots};



  TEST(BSpline1D, EqualsTheCoxDeBoorRecursionOnTheExplicitKnots)
  {
    const double lower = -1.3, h = 0.4;
    for (const Boundary boundary : both_boundaries)
      for (unsigned int p = 1; p <= 3; ++p)
        {
          const unsigned int  n = 9;
          const Basis1D       basis(p, lower, h, n, boundary);
          std::vector<double> U = explicit_knots(p, n, boundary);
          std::vector<double> S_ref, dS_ref;
          for (const double x : sample_points(basis))
            {
              const double t = (x - lower) / h;
              if (t < 0 || t > n)
                continue; // (the recursion knows no extension)
              double       S[Basis1D::max_nodes], dS[Basis1D::max_nodes];
              int          first;
              unsigned int count;
              ASSERT_TRUE(basis.values(x, first, count, S, dS));
              reference_values(U, p, n, t, S_ref, dS_ref);
              for (int i = 0; i <= static_cast<int>(n); ++i)
                {
                  const int    k  = i - first;
                  const bool   in = k >= 0 && k < static_cast<int>(count);
                  const double s = in ? S[k] : 0, ds = in ? dS[k] : 0;
                  ASSERT_NEAR(s, S_ref[i], 1e-14)
                    << "p = " << p << ", " << name(boundary) << ", vertex " << i
                    << ", t = " << t;
                  ASSERT_NEAR(ds * h, dS_ref[i], 1e-13)
                    << "p = " << p << ", " << name(boundary) << ", vertex " << i
                    << ", t = " << t;
                }
            }
        }
  }



  TEST(BSpline1D, KnownValuesAtVertices)
  {
    // Uniform B-splines at a vertex: quadratic 1/8, 3/4, 1/8; cubic 1/6,
    // 2/3, 1/6; the open end's vertex function is 1 on the wall.
    const Basis1D quadratic(2, 0, 1, 8, Boundary::open_knots),
      cubic(3, 0, 1, 8, Boundary::open_knots);
    double       S[Basis1D::max_nodes], dS[Basis1D::max_nodes];
    int          first;
    unsigned int count;
    quadratic.values(4, first, count, S, dS);
    ASSERT_EQ(first, 3);
    EXPECT_DOUBLE_EQ(S[0], 0.125);
    EXPECT_DOUBLE_EQ(S[1], 0.75);
    EXPECT_DOUBLE_EQ(S[2], 0.125);
    EXPECT_DOUBLE_EQ(dS[0], -0.5);
    EXPECT_DOUBLE_EQ(dS[1], 0);
    cubic.values(4, first, count, S, dS);
    ASSERT_EQ(count, 4u);
    int centre = 4 - first;
    EXPECT_NEAR(S[centre - 1], 1. / 6, 1e-15);
    EXPECT_NEAR(S[centre], 2. / 3, 1e-15);
    EXPECT_NEAR(S[centre + 1], 1. / 6, 1e-15);
    for (const Basis1D *basis : {&quadratic, &cubic})
      for (const double wall : {0., 8.})
        {
          basis->values(wall, first, count, S, dS);
          const int boundary_vertex = static_cast<int>(wall);
          for (unsigned int k = 0; k < count; ++k)
            EXPECT_NEAR(S[k],
                        first + static_cast<int>(k) == boundary_vertex ? 1. :
                                                                         0.,
                        1e-15)
              << "p = " << basis->degree() << " at " << wall;
        }
  }



  TEST(BSpline1D, PartitionOfUnityAndLinearCompletenessEverywhere)
  {
    for (const Boundary boundary : both_boundaries)
      for (unsigned int p = 1; p <= 3; ++p)
        for (const unsigned int n : {2 * p + 1, 7u, 16u})
          {
            const Basis1D basis(p, 3.7, 0.15, std::max(n, 3u), boundary);
            for (const double x : sample_points(basis))
              {
                double       S[Basis1D::max_nodes], dS[Basis1D::max_nodes];
                int          first;
                unsigned int count;
                ASSERT_TRUE(basis.values(x, first, count, S, dS))
                  << "p = " << p << ", " << name(boundary) << " at " << x;
                const Defects defect = defects(basis, x, first, count, S, dS);
                ASSERT_LT(defect.largest(), tolerance)
                  << "p = " << p << ", " << name(boundary) << ", n = " << n
                  << " at " << x << ": " << defect.unity << " " << defect.linear
                  << " " << defect.gradient_sum << " "
                  << defect.gradient_linear;
                // Nonnegative on the mesh (beyond, a piece is extended).
                const double t = (x - 3.7) / 0.15;
                if (t >= 0 && t <= basis.n_cells())
                  {
                    for (unsigned int k = 0; k < count; ++k)
                      ASSERT_GE(S[k], -1e-15) << p << " " << x;
                  }
              }
          }
  }



  TEST(BSpline1D, MirrorSymmetricAtBothEnds)
  {
    // S_i(x) = S_{n−i}(L − x), dS_i(x) = −dS_{n−i}(L − x).
    for (unsigned int p = 1; p <= 3; ++p)
      {
        const unsigned int n = 10;
        const Basis1D      basis(p, 0, 1, n, Boundary::open_knots);
        // (Off the knots: at a knot the span is the one on the right.)
        for (double x = -0.49; x <= n + 0.5; x += 0.0625)
          {
            double       S[6], dS[6], S_m[6], dS_m[6];
            int          first = 0, first_m = 0;
            unsigned int count = 0, count_m = 0;
            basis.values(x, first, count, S, dS);
            basis.values(n - x, first_m, count_m, S_m, dS_m);
            for (unsigned int k = 0; k < count; ++k)
              {
                const int    i = first + k, k_m = (n - i) - first_m;
                const double s_m =
                  (k_m >= 0 && k_m < int(count_m)) ? S_m[k_m] : 0;
                const double ds_m =
                  (k_m >= 0 && k_m < int(count_m)) ? dS_m[k_m] : 0;
                ASSERT_NEAR(S[k], s_m, 1e-14) << p << " " << x << " " << i;
                ASSERT_NEAR(dS[k], -ds_m, 1e-13) << p << " " << x << " " << i;
              }
          }
      }
  }



  // The checks fail for a wrong basis: (a) Uintah's BSplineInterpolator
  // adds the end's extra B-spline wholly to the boundary vertex (partition
  // of unity holds, linear completeness does not); (b) one interior knot
  // moved by 5 % of a cell: the values differ from the recursion on the
  // right knots, and with each B-spline kept on its vertex Σ S_i x_i ≠ x.
  TEST(BSpline1D, WrongBasesFailTheChecks)
  {
    for (unsigned int p = 2; p <= 3; ++p)
      {
        const unsigned int        n = 8;
        const Basis1D             basis(p, 0, 1, n, Boundary::open_knots);
        const std::vector<double> U =
          explicit_knots(p, n, Boundary::open_knots);
        const double gamma  = p == 2 ? 0.25 : 1. / 3; // its Greville abscissa
        double       merged = 0, right = 0;
        for (double t = 0.01; t < 2.5; t += 0.01)
          {
            double       S[6], dS[6];
            int          first = 0;
            unsigned int count = 0;
            basis.values(t, first, count, S, dS);
            right =
              std::max(right, defects(basis, t, first, count, S, dS).largest());
            // (a) the extra B-spline (explicit index 1) all on vertex 0.
            const double extra      = cox_de_boor(U, 1, p, t);
            const double extra_grad = cox_de_boor_derivative(U, 1, p, t);
            if (first == 0 && count > 1)
              {
                S[1] -= gamma * extra;
                S[0] += gamma * extra;
                dS[1] -= gamma * extra_grad;
                dS[0] += gamma * extra_grad;
              }
            merged =
              std::max(merged, defects(basis, t, first, count, S, dS).linear);
          }
        EXPECT_LT(right, tolerance) << "p = " << p;
        EXPECT_GT(merged, 1e-2) << "p = " << p;

        // (b) knot u_5 moved by 0.05 (an interior knot for p = 2, 3).
        auto moved = [&](const int m) {
          return basis.knot(m) + (m == 5 ? 0.05 : 0.);
        };
        std::vector<double> U_moved; // u_m at index m + 10
        for (int m = -10; m <= static_cast<int>(n) + 10; ++m)
          U_moved.push_back(m - 0.5 * (p + 1) + (m == 5 ? 0.05 : 0.));
        double value_error = 0, vertex_defect = 0;
        for (double t = 2.55; t < 5.5; t += 0.01)
          {
            const int    j = basis.span(t);
            double       S[6], dS[6], S_right[6], dS_right[6];
            int          first, first_right;
            unsigned int count, count_right;
            basis.span_values_with_knots(j, t, moved, first, count, S, dS);
            basis.values(t, first_right, count_right, S_right, dS_right);
            ASSERT_EQ(first, first_right);
            for (unsigned int k = 0; k < std::min(count, count_right); ++k)
              value_error = std::max(value_error, std::abs(S[k] - S_right[k]));
            double sum_x = 0;
            for (int m = 0;
                 m + static_cast<int>(p) + 1 < static_cast<int>(U_moved.size());
                 ++m)
              sum_x += cox_de_boor(U_moved, m, p, t) * (m - 10);
            vertex_defect = std::max(vertex_defect, std::abs(sum_x - t));
          }
        EXPECT_GT(value_error, 1e-3) << "p = " << p;
        EXPECT_GT(vertex_defect, 1e-3) << "p = " << p;
      }
  }



  TEST(BSpline1D, GimpAveragesEqualQuadratureAndSampling)
  {
    std::mt19937                           generator(11);
    std::uniform_real_distribution<double> unit(0, 1);
    for (const Boundary boundary : both_boundaries)
      for (unsigned int p = 1; p <= 3; ++p)
        {
          const unsigned int n = 12;
          const double       h = 0.25;
          const Basis1D      basis(p, 1.0, h, n, boundary);
          for (unsigned int sample = 0; sample < 300; ++sample)
            {
              const double l = h * (0.05 + 0.45 * unit(generator));
              // Open knots: anywhere on the mesh; padding: points outside
              // the padding layer whose domain stays on the lattice's
              // complete part.
              const double low = boundary == Boundary::open_knots ? 0 : 1.5;
              const double t   = low + (n - 2 * low) * unit(generator);
              const double x   = 1.0 + t * h;
              double       S[6], dS[6];
              int          first;
              unsigned int count;
              ASSERT_TRUE(basis.averages(x, l, first, count, S, dS))
                << p << " " << name(boundary) << " " << x;
              const Defects defect = defects(basis, x, first, count, S, dS);
              ASSERT_LT(defect.largest(), tolerance / (l / h))
                << "p = " << p << ", " << name(boundary) << " at " << x
                << ", l = " << l;
              // Sampling: the mean of S_i over 4000 midpoints (error ~ 1e-8
              // for the kinks), dS̄ = (S(x + l) − S(x − l))/(2l).
              const unsigned int  m = 4000;
              std::vector<double> mean(count, 0.);
              for (unsigned int q = 0; q < m; ++q)
                {
                  const double y = x - l + (q + 0.5) * (2 * l / m);
                  double       S_y[6], dS_y[6];
                  int          first_y;
                  unsigned int count_y;
                  ASSERT_TRUE(basis.values(y, first_y, count_y, S_y, dS_y));
                  for (unsigned int k = 0; k < count_y; ++k)
                    {
                      const int e = first_y + int(k) - first;
                      if (e >= 0 && e < int(count))
                        mean[e] += S_y[k] / m;
                      else
                        ASSERT_EQ(S_y[k], 0.) << "vertex outside the average";
                    }
                }
              for (unsigned int k = 0; k < count; ++k)
                ASSERT_NEAR(S[k], mean[k], 2e-7)
                  << "p = " << p << ", " << name(boundary) << " at " << x;
              // The derivative of the average.
              const double eps = 1e-6 * h;
              double       S_plus[6], S_minus[6], d_[6];
              int          f_plus, f_minus;
              unsigned int c_plus, c_minus;
              basis.averages(x + eps, l, f_plus, c_plus, S_plus, d_);
              basis.averages(x - eps, l, f_minus, c_minus, S_minus, d_);
              for (unsigned int k = 0; k < count; ++k)
                {
                  const int    i = first + k;
                  const double a =
                    (i - f_plus >= 0 && i - f_plus < int(c_plus)) ?
                      S_plus[i - f_plus] :
                      0;
                  const double b =
                    (i - f_minus >= 0 && i - f_minus < int(c_minus)) ?
                      S_minus[i - f_minus] :
                      0;
                  ASSERT_NEAR(dS[k], (a - b) / (2 * eps), 1e-6 / h)
                    << "p = " << p << " at " << x;
                }
            }
        }
  }



  TEST(BSpline1D, QuadraticClosedFormEqualsQuadrature)
  {
    // Padding: the closed form everywhere; open knots with the same
    // interior: quadrature across the whole lattice. They agree inside.
    const unsigned int n = 10;
    const Basis1D      closed(2, 0, 1, n, Boundary::padding);
    std::mt19937       generator(3);
    std::uniform_real_distribution<double> unit(0, 1);
    for (unsigned int sample = 0; sample < 2000; ++sample)
      {
        const double l = 0.02 + 0.48 * unit(generator);
        const double x = 2.5 + (n - 5) * unit(generator);
        double       S[6], dS[6], S_q[6], dS_q[6];
        int          first, first_q;
        unsigned int count, count_q;
        ASSERT_TRUE(closed.averages(x, l, first, count, S, dS));
        // The quadrature path: a basis whose knots are the same, forced
        // through span_values by the test's own Gauss sum.
        double       sum[12] = {}, dsum[12] = {};
        const int    base = first - 2;
        const double a = x - l, b = x + l;
        for (int j = closed.span(a); j <= closed.span(b); ++j)
          {
            const double lo = std::max(a, closed.knot(j)),
                         hi = std::min(b, closed.knot(j + 1));
            if (!(hi > lo))
              continue;
            for (const double g : {-0.28867513459481287, 0.28867513459481287})
              {
                const double s = 0.5 * (lo + hi) + g * (hi - lo);
                closed.span_values_with_knots(
                  j,
                  s,
                  [&](const int m) { return closed.knot(m); },
                  first_q,
                  count_q,
                  S_q,
                  dS_q);
                for (unsigned int k = 0; k < count_q; ++k)
                  {
                    sum[first_q + k - base] +=
                      0.5 * (hi - lo) / (2 * l) * S_q[k];
                    dsum[first_q + k - base] +=
                      0.5 * (hi - lo) / (2 * l) * dS_q[k];
                  }
              }
          }
        for (int e = 0; e < 12; ++e)
          {
            const int    k = base + e - first;
            const double s = (k >= 0 && k < int(count)) ? S[k] : 0;
            const double d = (k >= 0 && k < int(count)) ? dS[k] : 0;
            ASSERT_NEAR(s, sum[e], 1e-14 / l) << x << " " << l;
            ASSERT_NEAR(d, dsum[e], 1e-13 / l) << x << " " << l;
          }
      }
  }



  // Basis1D::floor_to_int() is the integer of std::floor() (which the span
  // of a point used before): at and next to integers of both signs, and at
  // random values. Rounding towards zero fails below 0, a test with <= at
  // the integers.
  TEST(BSpline1D, FloorToIntIsTheFloor)
  {
    std::vector<double> values;
    for (int i = -5; i <= 5; ++i)
      for (const double u : {double(i),
                             std::nextafter(double(i), -10.),
                             std::nextafter(double(i), 10.),
                             i + 0.5,
                             i - 1e-13})
        values.push_back(u);
    std::mt19937                           generator(3);
    std::uniform_real_distribution<double> wide(-1e6, 1e6);
    for (unsigned int k = 0; k < 1000; ++k)
      values.push_back(wide(generator));
    for (const double u : values)
      EXPECT_EQ(Basis1D::floor_to_int(u), static_cast<int>(std::floor(u))) << u;
  }

  TEST(BSpline1D, PaddingRefusesPointsThatNeedVerticesBeyond)
  {
    for (unsigned int p = 2; p <= 3; ++p)
      {
        const Basis1D basis(p, 0, 1, 8, Boundary::padding);
        double        S[6], dS[6];
        int           first;
        unsigned int  count;
        // Outside the padding layer: fine; in the layer, vertices beyond.
        EXPECT_TRUE(basis.values(1.0, first, count, S, dS));
        EXPECT_TRUE(basis.values(7.0, first, count, S, dS));
        EXPECT_FALSE(basis.values(0.4, first, count, S, dS));
        EXPECT_FALSE(basis.values(7.6, first, count, S, dS));
        // The same point with open knots is fine.
        const Basis1D open(p, 0, 1, 8, Boundary::open_knots);
        EXPECT_TRUE(open.values(0.4, first, count, S, dS));
      }
  }



  // ---- 2D and 3D ----------------------------------------------------------

  enum class Kind
  {
    b2spline,
    b3spline,
    b2gimp,
    b2cpdi
  };

  std::string
  name(const Kind kind)
  {
    switch (kind)
      {
        case Kind::b2spline:
          return "b2spline";
        case Kind::b3spline:
          return "b3spline";
        case Kind::b2gimp:
          return "b2gimp";
        default:
          return "b2cpdi";
      }
  }

  template <int dim>
  struct Entry
  {
    std::array<int, dim> index;
    double               S;
    Tensor<1, dim>       G;
  };

  template <int dim>
  fmpm::BSpline::Status
  support_of(const Kind                         kind,
             const fmpm::BSpline::Lattice<dim> &lattice,
             const Point<dim>                  &x,
             const Tensor<1, dim>              &l,
             const Tensor<2, dim>              &F,
             std::vector<Entry<dim>>           &entries)
  {
    entries.clear();
    auto sink = [&](const std::array<int, dim> &index,
                    const double                S,
                    const Tensor<1, dim>       &G) {
      entries.push_back(Entry<dim>{index, S, G});
    };
    fmpm::BSpline::Status status;
    if (kind == Kind::b2cpdi)
      {
        Tensor<2, dim> s;
        for (unsigned int a = 0; a < dim; ++a)
          for (unsigned int b = 0; b < dim; ++b)
            s[a][b] = F[a][b] * l[b];
        fmpm::BSpline::BoxSupport<dim> support;
        status = lattice.cpdi_support(x, s, support);
        if (status == fmpm::BSpline::Status::ok)
          support.for_each_node(sink);
      }
    else
      {
        fmpm::BSpline::ProductSupport<dim> support;
        status = kind == Kind::b2gimp ? lattice.gimp_support(x, l, support) :
                                        lattice.point_support(x, support);
        if (status == fmpm::BSpline::Status::ok)
          support.for_each_node(sink);
      }
    return status;
  }

  template <typename T>
  class BSplineLatticeTest : public ::testing::Test
  {};
  template <int d>
  using Dim        = std::integral_constant<int, d>;
  using Dimensions = ::testing::Types<Dim<2>, Dim<3>>;
  TYPED_TEST_SUITE(BSplineLatticeTest, Dimensions);

  // Σ S = 1, Σ S x_i = x, Σ G = 0, Σ G ⊗ x_i = I at random points of the
  // whole box (open knots) or outside the padding layer, for every type,
  // with an anisotropic lattice; every vertex of a support in the lattice.
  TYPED_TEST(BSplineLatticeTest, PartitionOfUnityAndLinearCompleteness)
  {
    constexpr int                 dim = TypeParam::value;
    Point<dim>                    lower, upper;
    std::array<unsigned int, dim> n_cells;
    for (unsigned int d = 0; d < dim; ++d)
      {
        lower[d]   = -0.5 + 0.1 * d;
        upper[d]   = 1.0 + 0.3 * d;
        n_cells[d] = 7 + 2 * d;
      }
    std::mt19937                           generator(7 + dim);
    std::uniform_real_distribution<double> unit(0, 1), symmetric(-1, 1);
    std::vector<Entry<dim>>                entries;
    for (const Boundary boundary : both_boundaries)
      for (const Kind kind :
           {Kind::b2spline, Kind::b3spline, Kind::b2gimp, Kind::b2cpdi})
        {
          const fmpm::BSpline::Lattice<dim> lattice(
            lower, upper, n_cells, kind == Kind::b3spline ? 3 : 2, boundary);
          unsigned int n_checked = 0;
          for (unsigned int sample = 0; sample < (dim == 2 ? 400 : 150);
               ++sample)
            {
              Point<dim>     x;
              Tensor<1, dim> l;
              Tensor<2, dim> F;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const double h = lattice.basis(d).cell_size();
                  // Open knots: the whole box and a quarter cell beyond;
                  // padding: between the padding layers, the domain inside
                  // the complete part (GIMP/CPDI: half a cell in).
                  const double margin =
                    boundary == Boundary::open_knots ?
                      -0.25 :
                      (kind == Kind::b2gimp || kind == Kind::b2cpdi ? 1.5 : 1);
                  x[d] = lower[d] + h * (margin + (n_cells[d] - 2 * margin) *
                                                    unit(generator));
                  l[d] = h * (0.1 + 0.15 * unit(generator));
                  for (unsigned int e = 0; e < dim; ++e)
                    F[d][e] = (d == e ? 1 : 0) + 0.3 * symmetric(generator);
                }
              bool inside = true;
              for (unsigned int d = 0; d < dim; ++d)
                inside = inside &&
                         x[d] > lower[d] + lattice.basis(d).cell_size() &&
                         x[d] < upper[d] - lattice.basis(d).cell_size();
              const auto status =
                support_of<dim>(kind, lattice, x, l, F, entries);
              ASSERT_EQ(status, fmpm::BSpline::Status::ok)
                << name(kind) << ", " << name(boundary) << " at " << x;
              double         s = 0;
              Point<dim>     sx;
              Tensor<1, dim> g;
              Tensor<2, dim> gx;
              for (const auto &entry : entries)
                {
                  for (unsigned int d = 0; d < dim; ++d)
                    {
                      ASSERT_GE(entry.index[d], 0);
                      ASSERT_LE(entry.index[d], int(n_cells[d]));
                    }
                  const Point<dim> xi = lattice.vertex(entry.index);
                  s += entry.S;
                  sx += entry.S * xi;
                  g += entry.G;
                  gx += outer_product(entry.G, xi);
                  // (Nonnegative where nothing is extended beyond the
                  // mesh.)
                  if (inside)
                    {
                      ASSERT_GE(entry.S, -1e-15);
                    }
                }
              const double h = lattice.basis(0).cell_size();
              ASSERT_NEAR(s, 1, tolerance) << name(kind) << " " << x;
              ASSERT_LT((sx - x).norm() / h, 10 * tolerance)
                << name(kind) << ", " << name(boundary) << " at " << x;
              ASSERT_LT(g.norm() * h, 10 * tolerance)
                << name(kind) << ", " << name(boundary) << " at " << x;
              ASSERT_LT((gx - unit_symmetric_tensor<dim>()).norm(),
                        10 * tolerance)
                << name(kind) << ", " << name(boundary) << " at " << x;
              ++n_checked;
            }
          EXPECT_GT(n_checked, 100u);
        }
  }

  // The limits: a vanishing GIMP box or CPDI domain gives the point
  // values; a support has (p+1)^dim vertices inside the lattice.
  TYPED_TEST(BSplineLatticeTest, SmallDomainsGiveThePointValues)
  {
    constexpr int                 dim = TypeParam::value;
    std::array<unsigned int, dim> n_cells;
    n_cells.fill(6);
    Point<dim> upper;
    for (unsigned int d = 0; d < dim; ++d)
      upper[d] = 1;
    const fmpm::BSpline::Lattice<dim> lattice(
      Point<dim>(), upper, n_cells, 2, Boundary::open_knots);
    std::mt19937                           generator(23);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<Entry<dim>>                point, gimp, cpdi;
    for (unsigned int sample = 0; sample < 50; ++sample)
      {
        Point<dim> x;
        for (unsigned int d = 0; d < dim; ++d)
          x[d] = unit(generator);
        Tensor<1, dim> l;
        for (unsigned int d = 0; d < dim; ++d)
          l[d] = 1e-4 / 6;
        const Tensor<2, dim> F = unit_symmetric_tensor<dim>();
        support_of<dim>(Kind::b2spline, lattice, x, l, F, point);
        support_of<dim>(Kind::b2gimp, lattice, x, l, F, gimp);
        support_of<dim>(Kind::b2cpdi, lattice, x, l, F, cpdi);
        std::map<std::array<int, dim>, std::pair<double, Tensor<1, dim>>>
          reference;
        for (const auto &e : point)
          reference[e.index] = {e.S, e.G};
        for (const auto *other : {&gimp, &cpdi})
          for (const auto &e : *other)
            {
              const auto   found = reference.find(e.index);
              const double S_ref =
                found == reference.end() ? 0 : found->second.first;
              const Tensor<1, dim> G_ref = found == reference.end() ?
                                             Tensor<1, dim>() :
                                             found->second.second;
              // O((l/h)^2) differences (kinks of S: O(l/h) at most).
              EXPECT_NEAR(e.S, S_ref, 1e-6) << x;
              EXPECT_LT((e.G - G_ref).norm(), 1e-3 * 6) << x;
            }
      }
  }



  /** A subdivided box on MPI_COMM_WORLD with GridTransfer. */
  template <int dim>
  struct MeshSetup
  {
    MeshSetup(const std::vector<unsigned int> &subdivisions,
              const Point<dim>                &lower,
              const Point<dim>                &upper,
              const bool                       refine_one = false,
              const bool                       distort    = false)
      : triangulation(MPI_COMM_WORLD)
      , fe(1)
      , dof_handler(triangulation)
    {
      GridGenerator::subdivided_hyper_rectangle(triangulation,
                                                subdivisions,
                                                lower,
                                                upper);
      if (refine_one)
        {
          triangulation.begin_active()->set_refine_flag();
          triangulation.execute_coarsening_and_refinement();
        }
      if (distort)
        GridTools::distort_random(0.2, triangulation, true, 99);
      dof_handler.distribute_dofs(fe);
      IndexSet relevant;
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      constraints.reinit(relevant);
      DoFTools::make_hanging_node_constraints(dof_handler, constraints);
      constraints.close();
      partitioner = std::make_shared<Utilities::MPI::Partitioner>(
        dof_handler.locally_owned_dofs(), relevant, MPI_COMM_WORLD);
      transfer.reinit(dof_handler, constraints, *partitioner);
      DoFTools::map_dofs_to_support_points(MappingQ<dim>(1),
                                           dof_handler,
                                           support_points);
    }

    parallel::distributed::Triangulation<dim>     triangulation;
    FE_Q<dim>                                     fe;
    DoFHandler<dim>                               dof_handler;
    AffineConstraints<double>                     constraints;
    std::shared_ptr<Utilities::MPI::Partitioner>  partitioner;
    fmpm::GridTransfer<dim>                       transfer;
    std::map<types::global_dof_index, Point<dim>> support_points;
  };

  // The lattice read from a subdivided box, and every vertex of the
  // rank's cells found by its lattice index at its DoF's support point.
  TYPED_TEST(BSplineLatticeTest, LatticeAndVertexMapOfAMesh)
  {
    constexpr int             dim = TypeParam::value;
    std::vector<unsigned int> subdivisions;
    Point<dim>                lower, upper;
    for (unsigned int d = 0; d < dim; ++d)
      {
        subdivisions.push_back(5 + d);
        lower[d] = -1 + 0.25 * d;
        upper[d] = lower[d] + 0.3 * subdivisions[d];
      }
    MeshSetup<dim> mesh(subdivisions, lower, upper);
    std::string    error;
    const auto     lattice =
      fmpm::BSpline::Lattice<dim>::of_mesh(mesh.transfer,
                                           mesh.triangulation.n_active_cells(),
                                           2,
                                           Boundary::open_knots,
                                           MPI_COMM_WORLD,
                                           error);
    ASSERT_TRUE(error.empty()) << error;
    for (unsigned int d = 0; d < dim; ++d)
      {
        EXPECT_EQ(lattice.n_vertices(d), subdivisions[d] + 1);
        EXPECT_NEAR(lattice.basis(d).cell_size(), 0.3, 1e-14);
        EXPECT_NEAR(lattice.basis(d).vertex(0), lower[d], 1e-14);
      }
    fmpm::BSpline::VertexMap<dim> map;
    map.reinit(lattice, mesh.transfer, mesh.triangulation.n_active_cells());
    unsigned int n_found = 0;
    for (const auto &[dof, position] : mesh.support_points)
      {
        std::array<int, dim> index;
        for (unsigned int d = 0; d < dim; ++d)
          index[d] =
            static_cast<int>(std::round((position[d] - lower[d]) / 0.3));
        const unsigned int local = map.local_index(index);
        ASSERT_NE(local, numbers::invalid_unsigned_int) << position;
        EXPECT_EQ(mesh.partitioner->local_to_global(local), dof);
        EXPECT_LT((lattice.vertex(index) - position).norm(), 1e-13);
        ++n_found;
      }
    EXPECT_EQ(n_found, mesh.dof_handler.n_dofs());
    std::array<int, dim> beyond;
    beyond.fill(-1);
    EXPECT_EQ(map.local_index(beyond), numbers::invalid_unsigned_int);
  }

  // VertexMap::write_product() gives the entries of a tensor-product
  // support with the same local indices, S and G (bitwise) and in the same
  // order as ProductSupport::for_each_node() with one local_index() per
  // node, for b2spline, b3spline and b2gimp supports all over the mesh
  // (open knots: the supports at the boundary are narrower); a window that
  // leaves the map's box is refused and nothing is written.
  TYPED_TEST(BSplineLatticeTest, VertexMapWritesProductsAsTheLookupDoes)
  {
    constexpr int             dim = TypeParam::value;
    std::vector<unsigned int> subdivisions;
    Point<dim>                lower, upper;
    for (unsigned int d = 0; d < dim; ++d)
      {
        subdivisions.push_back(5 + d);
        lower[d] = -1 + 0.25 * d;
        upper[d] = lower[d] + 0.3 * subdivisions[d];
      }
    MeshSetup<dim>                         mesh(subdivisions, lower, upper);
    std::mt19937                           generator(11 + dim);
    std::uniform_real_distribution<double> unit(0, 1);
    constexpr unsigned int max_size = fmpm::BSpline::BoxSupport<dim>::max_size;
    unsigned int           n_compared = 0;
    for (const unsigned int degree : {2u, 3u})
      {
        std::string error;
        const auto  lattice = fmpm::BSpline::Lattice<dim>::of_mesh(
          mesh.transfer,
          mesh.triangulation.n_active_cells(),
          degree,
          Boundary::open_knots,
          MPI_COMM_WORLD,
          error);
        ASSERT_TRUE(error.empty()) << error;
        fmpm::BSpline::VertexMap<dim> map;
        map.reinit(lattice, mesh.transfer, mesh.triangulation.n_active_cells());
        for (unsigned int sample = 0; sample < 200; ++sample)
          for (const bool gimp : {false, true})
            {
              if (gimp && degree != 2)
                continue;
              Point<dim>     x;
              Tensor<1, dim> l;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  x[d] = lower[d] + (upper[d] - lower[d]) * unit(generator);
                  l[d] = 0.15 * unit(generator);
                }
              fmpm::BSpline::ProductSupport<dim> product;
              ASSERT_EQ(gimp ? lattice.gimp_support(x, l, product) :
                               lattice.point_support(x, product),
                        fmpm::BSpline::Status::ok);
              std::vector<unsigned int>   node;
              std::vector<double>         S;
              std::vector<Tensor<1, dim>> G;
              product.for_each_node([&](const std::array<int, dim> &index,
                                        const double                value,
                                        const Tensor<1, dim>       &gradient) {
                node.push_back(map.local_index(index));
                S.push_back(value);
                G.push_back(gradient);
              });
              unsigned int   written_node[max_size];
              double         written_S[max_size];
              Tensor<1, dim> written_G[max_size];
              unsigned int   n_written   = 0;
              bool           all_on_rank = false;
              ASSERT_TRUE(map.write_product(product,
                                            written_node,
                                            written_S,
                                            written_G,
                                            n_written,
                                            all_on_rank));
              EXPECT_TRUE(all_on_rank);
              ASSERT_EQ(n_written, node.size()) << x;
              for (unsigned int j = 0; j < n_written; ++j)
                {
                  EXPECT_EQ(written_node[j], node[j]);
                  EXPECT_EQ(written_S[j], S[j]);
                  for (unsigned int d = 0; d < dim; ++d)
                    EXPECT_EQ(written_G[j][d], G[j][d]);
                }
              ++n_compared;

              // The window shifted one vertex below the lattice: refused.
              fmpm::BSpline::ProductSupport<dim> shifted = product;
              shifted.first[0]                           = -1;
              n_written                                  = 7;
              EXPECT_FALSE(map.write_product(shifted,
                                             written_node,
                                             written_S,
                                             written_G,
                                             n_written,
                                             all_on_rank));
              EXPECT_EQ(n_written, 7u);
            }
      }
    EXPECT_EQ(n_compared, 600u);
  }

  // The CPDI support (Lattice::cpdi_support()) is bitwise the sum over
  // the corners of their tensor products as ProductSupport::for_each_node()
  // gives them (S̄ += S_α/2^dim, Ḡ += S_α s⁻ᵀr_α/2^dim over the entries
  // that are not zero, corner by corner), and VertexMap::write_box() gives
  // the box's entries with the same local indices, S and G and in the same
  // order as BoxSupport::for_each_node() with one local_index() per node,
  // for deformed domains all over the mesh; a box that leaves the map's
  // box is refused and nothing is written.
  TYPED_TEST(BSplineLatticeTest, CpdiBoxesAsTheCornerSumAndTheLookup)
  {
    constexpr int             dim = TypeParam::value;
    std::vector<unsigned int> subdivisions;
    Point<dim>                lower, upper;
    for (unsigned int d = 0; d < dim; ++d)
      {
        subdivisions.push_back(6 + d);
        lower[d] = -1 + 0.25 * d;
        upper[d] = lower[d] + 0.3 * subdivisions[d];
      }
    MeshSetup<dim>                         mesh(subdivisions, lower, upper);
    std::mt19937                           generator(17 + dim);
    std::uniform_real_distribution<double> unit(0, 1);
    constexpr unsigned int max_size  = fmpm::BSpline::BoxSupport<dim>::max_size;
    constexpr unsigned int n_corners = 1u << dim;
    std::string            error;
    const auto             lattice =
      fmpm::BSpline::Lattice<dim>::of_mesh(mesh.transfer,
                                           mesh.triangulation.n_active_cells(),
                                           2,
                                           Boundary::open_knots,
                                           MPI_COMM_WORLD,
                                           error);
    ASSERT_TRUE(error.empty()) << error;
    fmpm::BSpline::VertexMap<dim> map;
    map.reinit(lattice, mesh.transfer, mesh.triangulation.n_active_cells());
    unsigned int n_compared = 0;
    for (unsigned int sample = 0; sample < 300; ++sample)
      {
        Point<dim>     x;
        Tensor<2, dim> s;
        for (unsigned int d = 0; d < dim; ++d)
          {
            x[d] = lower[d] + (upper[d] - lower[d]) * unit(generator);
            for (unsigned int e = 0; e < dim; ++e)
              s[d][e] = (d == e ? 0.075 : 0.02) * (2 * unit(generator) - 1) +
                        (d == e ? 0.04 : 0);
          }
        fmpm::BSpline::BoxSupport<dim> box;
        ASSERT_EQ(lattice.cpdi_support(x, s, box), fmpm::BSpline::Status::ok);

        // The corner sum entry by entry.
        std::map<std::array<int, dim>, std::pair<double, Tensor<1, dim>>> sum;
        const Tensor<2, dim> s_inverse_transpose = transpose(invert(s));
        for (unsigned int alpha = 0; alpha < n_corners; ++alpha)
          {
            Tensor<1, dim> r;
            for (unsigned int j = 0; j < dim; ++j)
              r[j] = ((alpha >> j) & 1) ? 1. : -1.;
            const Tensor<1, dim> weight = s_inverse_transpose * r / n_corners;
            fmpm::BSpline::ProductSupport<dim> corner;
            ASSERT_EQ(lattice.point_support(x + s * r, corner),
                      fmpm::BSpline::Status::ok);
            corner.for_each_node([&](const std::array<int, dim> &index,
                                     const double                S_alpha,
                                     const Tensor<1, dim> &) {
              auto &entry = sum[index];
              entry.first += S_alpha / n_corners;
              entry.second += S_alpha * weight;
            });
          }
        std::vector<unsigned int>   node;
        std::vector<double>         S;
        std::vector<Tensor<1, dim>> G;
        box.for_each_node([&](const std::array<int, dim> &index,
                              const double                value,
                              const Tensor<1, dim>       &gradient) {
          node.push_back(map.local_index(index));
          S.push_back(value);
          G.push_back(gradient);
          const auto entry = sum.find(index);
          ASSERT_NE(entry, sum.end());
          EXPECT_EQ(value, entry->second.first);
          for (unsigned int d = 0; d < dim; ++d)
            EXPECT_EQ(gradient[d], entry->second.second[d]);
        });
        // (No entry of the sum left out.)
        unsigned int n_not_zero = 0;
        for (const auto &entry : sum)
          if (entry.second.first != 0 || entry.second.second.norm_square() != 0)
            ++n_not_zero;
        EXPECT_EQ(n_not_zero, node.size());

        unsigned int   written_node[max_size];
        double         written_S[max_size];
        Tensor<1, dim> written_G[max_size];
        unsigned int   n_written   = 0;
        bool           all_on_rank = false;
        ASSERT_TRUE(map.write_box(
          box, written_node, written_S, written_G, n_written, all_on_rank));
        EXPECT_TRUE(all_on_rank);
        ASSERT_EQ(n_written, node.size()) << x;
        for (unsigned int j = 0; j < n_written; ++j)
          {
            EXPECT_EQ(written_node[j], node[j]);
            EXPECT_EQ(written_S[j], S[j]);
            for (unsigned int d = 0; d < dim; ++d)
              EXPECT_EQ(written_G[j][d], G[j][d]);
          }
        ++n_compared;

        // The box shifted one vertex below the lattice: refused.
        fmpm::BSpline::BoxSupport<dim> shifted = box;
        shifted.first[0]                       = -1;
        n_written                              = 7;
        EXPECT_FALSE(map.write_box(
          shifted, written_node, written_S, written_G, n_written, all_on_rank));
        EXPECT_EQ(n_written, 7u);
      }
    EXPECT_EQ(n_compared, 300u);
  }

  // Meshes that are not box lattices are refused with the reason.
  TYPED_TEST(BSplineLatticeTest, RefusesMeshesThatAreNotBoxLattices)
  {
    constexpr int             dim = TypeParam::value;
    std::vector<unsigned int> subdivisions(dim, 4);
    Point<dim>                lower, upper;
    for (unsigned int d = 0; d < dim; ++d)
      upper[d] = 1;
    for (const bool refine : {false, true})
      {
        MeshSetup<dim> mesh(subdivisions, lower, upper, refine, !refine);
        std::string    error;
        fmpm::BSpline::Lattice<dim>::of_mesh(
          mesh.transfer,
          mesh.triangulation.n_active_cells(),
          2,
          Boundary::padding,
          MPI_COMM_WORLD,
          error);
        EXPECT_NE(error.find("B-spline shape functions need a mesh of equal "
                             "axis-aligned boxes"),
                  std::string::npos)
          << error;
        EXPECT_NE(error.find(refine ? "hanging node" : "not an axis-aligned"),
                  std::string::npos)
          << error;
      }
  }

  // The shape functions b2spline, b3spline, b2gimp, b2cpdi as the
  // simulator computes them (ShapeFunction::BSplineSupports on a deal.II
  // mesh, entries addressed by local index): at random points of a
  // subdivided box, Σ S = 1, Σ S x_i = x, Σ G = 0, Σ G ⊗ x_i = I with x_i
  // the DoF support points, for both boundaries; a direction of one cell
  // (the linear basis there) included. (That the checks fail for a wrong
  // basis: WrongBasesFailTheChecks.)
  TYPED_TEST(BSplineLatticeTest, ShapeFunctionsOnTheMeshAreComplete)
  {
    using fmpm::ShapeFunction::Type;
    constexpr int dim = TypeParam::value;
    for (const bool thin : {false, true})
      {
        std::vector<unsigned int> subdivisions;
        Point<dim>                lower, upper;
        for (unsigned int d = 0; d < dim; ++d)
          {
            subdivisions.push_back(thin && d == 1 ? 1 : 8 + d);
            lower[d] = 0.3 - 0.2 * d;
            upper[d] = lower[d] + (0.25 + 0.05 * d) * subdivisions[d];
          }
        MeshSetup<dim>          mesh(subdivisions, lower, upper);
        std::vector<Point<dim>> node_position(
          mesh.partitioner->locally_owned_size() +
          mesh.partitioner->n_ghost_indices());
        for (const auto &[dof, position] : mesh.support_points)
          if (mesh.partitioner->in_local_range(dof) ||
              mesh.partitioner->is_ghost_entry(dof))
            node_position[mesh.partitioner->global_to_local(dof)] = position;
        std::mt19937                           generator(17);
        std::uniform_real_distribution<double> unit(0, 1);
        for (const Type type :
             {Type::b2spline, Type::b3spline, Type::b2gimp, Type::b2cpdi})
          for (const Boundary boundary : both_boundaries)
            {
              fmpm::ShapeFunction::BSplineSupports<dim> supports;
              supports.reinit(type,
                              boundary,
                              mesh.transfer,
                              mesh.triangulation.n_active_cells(),
                              MPI_COMM_WORLD);
              ASSERT_TRUE(supports.active());
              const auto  &lattice        = supports.get_lattice();
              unsigned int n_checked      = 0;
              double       largest_defect = 0;
              for (unsigned int q = 0; q < 200; ++q)
                {
                  // Points at least half a cell inside the padding layer's
                  // inner face (their domains too); anywhere with open
                  // knots.
                  Point<dim>     x;
                  Tensor<1, dim> l0;
                  Tensor<2, dim> F;
                  for (unsigned int d = 0; d < dim; ++d)
                    {
                      const double       h = lattice.basis(d).cell_size();
                      const unsigned int n = subdivisions[d];
                      // (one cell in a direction: the domains inside it)
                      const double margin = boundary == Boundary::open_knots ?
                                              0 :
                                            n > 1 ? 1.5 :
                                                    0.35;
                      x[d]                = lower[d] +
                             h * (margin + (n - 2 * margin) * unit(generator));
                      l0[d]   = 0.25 * h;
                      F[d][d] = 1 + 0.3 * (unit(generator) - 0.5);
                    }
                  F[0][dim - 1] = 0.2 * (unit(generator) - 0.5);
                  unsigned int   node[fmpm::ShapeFunction::BSplineSupports<
                    dim>::max_support_size];
                  double         S[fmpm::ShapeFunction::BSplineSupports<
                    dim>::max_support_size];
                  Tensor<1, dim> G[fmpm::ShapeFunction::BSplineSupports<
                    dim>::max_support_size];
                  unsigned int   count = 0;
                  const auto     status =
                    supports.support(x, F, l0, 0, node, S, G, count);
                  ASSERT_EQ(status, fmpm::ShapeFunction::Status::ok)
                    << fmpm::ShapeFunction::parameter_name(type) << ", "
                    << name(boundary) << " at " << x;
                  double         sum_S = 0;
                  Tensor<1, dim> sum_Sx, sum_G;
                  Tensor<2, dim> sum_Gx;
                  for (unsigned int e = 0; e < count; ++e)
                    {
                      const Point<dim> &xi = node_position[node[e]];
                      sum_S += S[e];
                      sum_Sx += S[e] * xi;
                      sum_G += G[e];
                      sum_Gx += outer_product(xi, G[e]);
                    }
                  const double defect =
                    std::abs(sum_S - 1) + (sum_Sx - x).norm() + sum_G.norm() +
                    (sum_Gx - unit_symmetric_tensor<dim>()).norm();
                  largest_defect = std::max(largest_defect, defect);
                  ++n_checked;
                }
              EXPECT_EQ(n_checked, 200u);
              EXPECT_LT(largest_defect, 1e-12)
                << fmpm::ShapeFunction::parameter_name(type) << ", "
                << name(boundary) << (thin ? ", one cell in y" : "");
            }
      }
  }

  // The shape-function layer refuses a mesh that is not a box lattice,
  // naming the parameter; with padding a point in the padding layer has no
  // support.
  TYPED_TEST(BSplineLatticeTest, ShapeFunctionsRefuseOtherMeshesAndPadding)
  {
    using fmpm::ShapeFunction::Type;
    constexpr int             dim = TypeParam::value;
    std::vector<unsigned int> subdivisions(dim, 6);
    Point<dim>                lower, upper;
    for (unsigned int d = 0; d < dim; ++d)
      upper[d] = 1.2;
    {
      MeshSetup<dim> distorted(subdivisions, lower, upper, false, true);
      fmpm::ShapeFunction::BSplineSupports<dim> supports;
      try
        {
          supports.reinit(Type::b2spline,
                          Boundary::open_knots,
                          distorted.transfer,
                          distorted.triangulation.n_active_cells(),
                          MPI_COMM_WORLD);
          ADD_FAILURE() << "a distorted mesh was accepted";
        }
      catch (const std::exception &error)
        {
          EXPECT_NE(
            std::string(error.what()).find("Shape function/Type = b2spline"),
            std::string::npos)
            << error.what();
        }
    }
    MeshSetup<dim>                            mesh(subdivisions, lower, upper);
    fmpm::ShapeFunction::BSplineSupports<dim> supports;
    supports.reinit(Type::b2spline,
                    Boundary::padding,
                    mesh.transfer,
                    mesh.triangulation.n_active_cells(),
                    MPI_COMM_WORLD);
    Point<dim> inside, in_layer;
    for (unsigned int d = 0; d < dim; ++d)
      {
        inside[d]   = 0.6;
        in_layer[d] = 0.6;
      }
    in_layer[0] = 0.05; // (cells are 0.2 wide)
    unsigned int         node[64], count;
    double               S[64];
    Tensor<1, dim>       G[64];
    const Tensor<2, dim> F = unit_symmetric_tensor<dim>();
    const Tensor<1, dim> l0;
    EXPECT_EQ(supports.support(inside, F, l0, 0, node, S, G, count),
              fmpm::ShapeFunction::Status::ok);
    EXPECT_EQ(count, dim == 2 ? 9u : 27u);
    EXPECT_EQ(supports.support(in_layer, F, l0, 0, node, S, G, count),
              fmpm::ShapeFunction::Status::in_padding_layer);
  }
} // namespace
