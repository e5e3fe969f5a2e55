// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks the axisymmetric B-spline shape functions
// (fmpm::ShapeFunction::Axisymmetric::bspline_support(), GIMP_Theory
// Eqs. 5.5, 5.8, 5.9 over the B-spline basis) on a lattice that starts on
// the axis r = 0 with open knots: for b2spline, b3spline, b2gimp and b2cpdi
// at random points, near-axis and cut domains included, Σ S = 1,
// Σ S x_i = the r-weighted centroid of the domain, Σ G = 0,
// Σ G ⊗ x_i = I, Σ T r_i = 1 and Σ T = ∫dA/∫r dA, no vertex at r < 0; the
// b2gimp radial factors against a fine quadrature of their defining
// integrals; and the open-knot basis on the axis (the axis vertex's
// function alone is not zero there).

#include <fmpm/axisymmetric_bspline.h>
#include <fmpm/bspline.h>

#include <deal.II/base/tensor.h>

#include <cmath>
#include <map>
#include <random>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using fmpm::ShapeFunction::Type;
  namespace Axisymmetric = fmpm::ShapeFunction::Axisymmetric;
  namespace BSpline      = fmpm::BSpline;

  /** The lattice [0, 8h] x [0, 8h] of degree @p degree, open knots. */
  BSpline::Lattice<2>
  rz_lattice(const unsigned int degree, const double h)
  {
    return BSpline::Lattice<2>(Point<2>(0, 0),
                               Point<2>(8 * h, 8 * h),
                               {{8, 8}},
                               degree,
                               BSpline::Boundary::open_knots);
  }

  unsigned int
  degree_of(const Type type)
  {
    return type == Type::b3spline ? 3 : 2;
  }



  TEST(AxisymmetricBSpline, IdentitiesForEveryType)
  {
    const double                           h = 0.125;
    std::mt19937                           generator(5);
    std::uniform_real_distribution<double> unit(0, 1), amount(-0.2, 0.2);
    unsigned int                           n_checked = 0;
    for (const Type type :
         {Type::b2spline, Type::b3spline, Type::b2gimp, Type::b2cpdi})
      {
        const BSpline::Lattice<2> lattice = rz_lattice(degree_of(type), h);
        for (unsigned int p = 0; p < 60; ++p)
          {
            // A quarter of the points within a cell of the axis.
            const Point<2> x(p % 4 == 0 ? h * (0.02 + 0.98 * unit(generator)) :
                                          h * (1 + 6 * unit(generator)),
                             h * (1 + 6 * unit(generator)));
            const Tensor<1, 2> l0({0.25 * h, 0.2 * h});
            Tensor<2, 2>       F;
            for (unsigned int i = 0; i < 2; ++i)
              for (unsigned int j = 0; j < 2; ++j)
                F[i][j] = (i == j ? 1 : 0) + amount(generator);
            double       sum_S = 0, sum_T = 0, sum_T_r = 0;
            Tensor<1, 2> sum_G, sum_S_x;
            Tensor<2, 2> sum_G_x;
            bool         below_axis = false;
            const auto   status =
              Axisymmetric::bspline_support(type,
                                            lattice,
                                            x,
                                            F,
                                            l0,
                                            0.,
                                            [&](const std::array<int, 2> &index,
                                                const double              S,
                                                const Tensor<1, 2>       &G,
                                                const double              T) {
                                              const Point<2> x_i =
                                                lattice.vertex(index);
                                              below_axis = below_axis ||
                                                           index[0] < 0 ||
                                                           x_i[0] < 0;
                                              sum_S += S;
                                              sum_S_x += S * x_i;
                                              sum_G += G;
                                              sum_G_x += outer_product(G, x_i);
                                              sum_T += T;
                                              sum_T_r += T * x_i[0];
                                            });
            ASSERT_EQ(status, fmpm::ShapeFunction::Status::ok);
            EXPECT_FALSE(below_axis);
            // The r-weighted centroid and ∫dA/∫r dA of the domain.
            Point<2> centroid = x;
            double   area_over_r_area;
            if (type == Type::b2gimp)
              {
                const double a = std::max(x[0] - l0[0], 0.), b = x[0] + l0[0];
                centroid[0] =
                  2. / 3 * (b * b * b - a * a * a) / (b * b - a * a);
                area_over_r_area = 2 / (a + b);
              }
            else if (type == Type::b2cpdi)
              {
                Tensor<2, 2> s;
                for (unsigned int c = 0; c < 2; ++c)
                  for (unsigned int j = 0; j < 2; ++j)
                    s[c][j] = F[c][j] * l0[j];
                Axisymmetric::keep_cpdi_domain_off_axis(x[0], s);
                // ∫ ξ (s ξ)_r dξ / ∫ dξ = (s_00, s_01)/3 over [-1, 1]².
                const Tensor<1, 2> first_row({s[0][0], s[0][1]});
                centroid += s * first_row / (3 * x[0]);
                area_over_r_area = 1 / x[0];
              }
            else
              area_over_r_area = 1 / x[0];
            const std::string where =
              fmpm::ShapeFunction::parameter_name(type) + " at " +
              std::to_string(x[0]) + ", " + std::to_string(x[1]);
            EXPECT_NEAR(sum_S, 1, 1e-13) << where;
            EXPECT_NEAR((sum_S_x - centroid).norm(), 0, 1e-13) << where;
            EXPECT_NEAR(sum_G.norm() * h, 0, 1e-13) << where;
            EXPECT_NEAR((sum_G_x - unit_symmetric_tensor<2>()).norm(), 0, 1e-12)
              << where;
            EXPECT_NEAR(sum_T_r, 1, 1e-13) << where;
            EXPECT_NEAR(sum_T / area_over_r_area, 1, 1e-13) << where;
            ++n_checked;
          }
      }
    EXPECT_EQ(n_checked, 4u * 60);
  }



  // The b2gimp radial factors S_i = ∫N_i r/∫r, dS_i = ∫N_i' r/∫r,
  // T_i = ∫N_i/∫r against a composite midpoint rule with 20000 pieces of
  // the point values, for boxes cut at the axis and boxes across knots.
  TEST(AxisymmetricBSpline, RadialAveragesEqualFineQuadrature)
  {
    const double     h = 0.5;
    BSpline::Basis1D basis(2, 0., h, 8, BSpline::Boundary::open_knots);
    std::mt19937     generator(7);
    std::uniform_real_distribution<double> unit(0, 1);
    for (unsigned int p = 0; p < 20; ++p)
      {
        const double r_p = (p % 2 == 0 ? 0.6 : 6) * h * unit(generator) + 0.01;
        const double l   = 0.5 * h * (0.2 + 0.8 * unit(generator));
        const double a = std::max(r_p - l, 0.), b = r_p + l;
        int          first;
        unsigned int count;
        double S[BSpline::Basis1D::max_nodes], dS[BSpline::Basis1D::max_nodes],
          T[BSpline::Basis1D::max_nodes];
        ASSERT_TRUE(Axisymmetric::bspline_radial_averages(
          basis, a, b, first, count, S, dS, T));
        std::map<int, std::array<double, 3>> expected;
        const unsigned int                   n_pieces = 20000;
        const double                         r_area   = 0.5 * (b * b - a * a);
        for (unsigned int q = 0; q < n_pieces; ++q)
          {
            const double r = a + (q + 0.5) * (b - a) / n_pieces;
            const double w = (b - a) / n_pieces / r_area;
            int          first_q;
            unsigned int count_q;
            double       N[BSpline::Basis1D::max_nodes],
              dN[BSpline::Basis1D::max_nodes];
            ASSERT_TRUE(basis.values(r, first_q, count_q, N, dN));
            for (unsigned int k = 0; k < count_q; ++k)
              {
                auto &e = expected[first_q + static_cast<int>(k)];
                e[0] += w * N[k] * r;
                e[1] += w * dN[k] * r;
                e[2] += w * N[k];
              }
          }
        for (const auto &[i, e] : expected)
          {
            const int    k = i - first;
            const double S_i =
              (k >= 0 && k < static_cast<int>(count)) ? S[k] : 0;
            const double dS_i =
              (k >= 0 && k < static_cast<int>(count)) ? dS[k] : 0;
            const double T_i =
              (k >= 0 && k < static_cast<int>(count)) ? T[k] : 0;
            EXPECT_NEAR(S_i, e[0], 1e-8) << "vertex " << i << ", r_p " << r_p;
            EXPECT_NEAR(dS_i * h, e[1] * h, 1e-8) << "vertex " << i;
            EXPECT_NEAR(T_i * h, e[2] * h, 1e-8) << "vertex " << i;
          }
      }
  }



  // Open knots at r = 0: the axis vertex's function is 1 on the axis and
  // the only one that is not zero there (so v_r = 0 on that vertex holds
  // on the whole axis), for the quadratic and the cubic basis.
  TEST(AxisymmetricBSpline, OpenKnotBasisOnTheAxis)
  {
    for (const unsigned int degree : {2u, 3u})
      {
        BSpline::Basis1D basis(
          degree, 0., 0.25, 8, BSpline::Boundary::open_knots);
        int          first;
        unsigned int count;
        double N[BSpline::Basis1D::max_nodes], dN[BSpline::Basis1D::max_nodes];
        ASSERT_TRUE(basis.values(0., first, count, N, dN));
        EXPECT_GE(first, 0);
        for (unsigned int k = 0; k < count; ++k)
          EXPECT_NEAR(N[k], first + static_cast<int>(k) == 0 ? 1. : 0., 1e-15)
            << "degree " << degree << ", vertex " << first + k;
      }
  }
} // namespace
