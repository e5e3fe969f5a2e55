// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_axisymmetric_bspline_h
#define fmpm_axisymmetric_bspline_h

#include <fmpm/axisymmetric_shape_function.h>
#include <fmpm/bspline.h>
#include <fmpm/shape_function.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fmpm
{
  namespace ShapeFunction
  {
    namespace Axisymmetric
    {
      /**
       * @brief The r-weighted averages of the radial basis (direction 0)
       * over [a, b] (0 <= a < b), GIMP over the B-spline basis in its
       * axisymmetric form (GIMP_Theory Eqs. 5.5, 5.8, 5.9 in r):
       *
       *   S_i = ∫ N_i r dr / A,  dS_i = ∫ N_i' r dr / A,  T_i = ∫ N_i dr / A,
       *   A = ∫_a^b r dr = (b² − a²)/2,
       *
       * for the vertices [first, first + count). The integrands are
       * polynomials of degree ≤ 4 between the half-cell points (the knots of
       * the quadratic and cubic bases lie on them), so a 3-point Gauss rule
       * on each piece is exact. Σ_i S_i = 1, Σ_i S_i r_i = ∫ r² dr / A,
       * Σ_i T_i r_i = 1 (Σ_i N_i r_i = r).
       *
       * @return false if the basis is not defined at a or b (padding:
       * the padding layer)
       */
      inline bool
      bspline_radial_averages(const BSpline::Basis1D &basis,
                              const double            a,
                              const double            b,
                              int                    &first,
                              unsigned int           &count,
                              double                 *S,
                              double                 *dS,
                              double                 *T)
      {
        constexpr unsigned int n_sum = 2 * BSpline::Basis1D::max_nodes + 4;
        double N[BSpline::Basis1D::max_nodes], dN[BSpline::Basis1D::max_nodes];
        double S_sum[n_sum] = {}, dS_sum[n_sum] = {}, T_sum[n_sum] = {};
        int    first_q;
        unsigned int count_q;
        if (!basis.values(a, first_q, count_q, N, dN) ||
            !basis.values(b, first_q, count_q, N, dN))
          return false;
        const double half   = 0.5 * basis.cell_size();
        const double origin = basis.vertex(0);
        const int    sum_first =
          static_cast<int>(std::floor((a - origin) / basis.cell_size())) - 3;
        // Gauss-Legendre on [0, 1], 3 points.
        constexpr double point[3]  = {0.5 - 0.3872983346207417,
                                      0.5,
                                      0.5 + 0.3872983346207417};
        constexpr double weight[3] = {5. / 18, 8. / 18, 5. / 18};
        first                      = std::numeric_limits<int>::max();
        int    last                = std::numeric_limits<int>::min();
        double lo                  = a;
        while (lo < b)
          {
            // The next half-cell point above lo.
            const double next =
              origin + (std::floor((lo - origin) / half + 1e-12) + 1) * half;
            const double hi = std::min(next, b);
            if (hi > lo)
              for (unsigned int q = 0; q < 3; ++q)
                {
                  const double r = lo + point[q] * (hi - lo);
                  const double w = weight[q] * (hi - lo);
                  basis.values(r, first_q, count_q, N, dN);
                  for (unsigned int k = 0; k < count_q; ++k)
                    {
                      const int e = first_q + static_cast<int>(k) - sum_first;
                      Assert(e >= 0 && e < static_cast<int>(n_sum),
                             ExcInternalError());
                      S_sum[e] += w * r * N[k];
                      dS_sum[e] += w * r * dN[k];
                      T_sum[e] += w * N[k];
                    }
                  first = std::min(first, first_q);
                  last =
                    std::max(last, first_q + static_cast<int>(count_q) - 1);
                }
            lo = hi;
          }
        const double inverse_area = 2 / (b * b - a * a);
        count                     = last - first + 1;
        for (unsigned int k = 0; k < count; ++k)
          {
            const int e = first - sum_first + static_cast<int>(k);
            S[k]        = S_sum[e] * inverse_area;
            dS[k]       = dS_sum[e] * inverse_area;
            T[k]        = T_sum[e] * inverse_area;
          }
        return true;
      }



      /**
       * @brief S_ip, G_ip, T_ip of a point at @p x (r_p = x_0 > 0) for the
       * B-spline shape functions in their axisymmetric form (the namespace's
       * formulas over the B-spline basis of @p lattice):
       * - b2spline, b3spline: S = N_i(x_p), G = ∇N_i(x_p), T = N_i(x_p)/r_p;
       * - b2gimp: the box [max(r_p − l_r, 0), r_p + l_r] × [z_p ± l_z]
       *   (l = l⁰, at most half a cell): S, G, T products of the radial
       *   r-weighted averages (bspline_radial_averages()) and the plain
       *   averages in z;
       * - b2cpdi: the corners x_α = x_p + s r_α of s = F diag(l⁰) (limited
       *   as limit_cpdi_domain(), kept off the axis as
       *   keep_cpdi_domain_off_axis()), S_ip = Σ_α w_α N_i(x_α), G_ip =
       *   Σ_α g_α N_i(x_α), T_ip = t Σ_α N_i(x_α) with cpdi_corner_weights().
       *
       * Calls @p sink(lattice index, S, G, T) for every vertex of the
       * support.
       */
      template <typename Sink>
      ShapeFunction::Status
      bspline_support(const Type                 type,
                      const BSpline::Lattice<2> &lattice,
                      const Point<2>            &x,
                      const Tensor<2, 2>        &F,
                      const Tensor<1, 2>        &l0,
                      const double               cpdi_critical_radius,
                      Sink                     &&sink)
      {
        using ShapeFunction::Status;
        const double r_p = x[0];
        switch (type)
          {
            case Type::b2spline:
            case Type::b3spline:
              {
                BSpline::ProductSupport<2> product;
                if (lattice.point_support(x, product) != BSpline::Status::ok)
                  return Status::in_padding_layer;
                const double inverse_r = 1 / r_p;
                product.for_each_node([&](const std::array<int, 2> &index,
                                          const double              S,
                                          const Tensor<1, 2>       &G) {
                  sink(index, S, G, S * inverse_r);
                });
                return Status::ok;
              }
            case Type::b2gimp:
              {
                for (unsigned int d = 0; d < 2; ++d)
                  if (l0[d] > 0.5 * lattice.basis(d).cell_size() * (1 + 1e-12))
                    return Status::domain_too_wide;
                BSpline::ProductSupport<2> product;
                double                     T_r[BSpline::Basis1D::max_nodes];
                if (!bspline_radial_averages(lattice.basis(0),
                                             std::max(r_p - l0[0], 0.),
                                             r_p + l0[0],
                                             product.first[0],
                                             product.count[0],
                                             product.w[0],
                                             product.dw[0],
                                             T_r) ||
                    !lattice.basis(1).averages(x[1],
                                               l0[1],
                                               product.first[1],
                                               product.count[1],
                                               product.w[1],
                                               product.dw[1]))
                  return Status::in_padding_layer;
                for (unsigned int k = 0; k < product.count[1]; ++k)
                  for (unsigned int j = 0; j < product.count[0]; ++j)
                    {
                      const double S = product.w[0][j] * product.w[1][k];
                      Tensor<1, 2> G;
                      G[0]           = product.dw[0][j] * product.w[1][k];
                      G[1]           = product.w[0][j] * product.dw[1][k];
                      const double T = T_r[j] * product.w[1][k];
                      if (S != 0 || G.norm_square() != 0 || T != 0)
                        sink(std::array<int, 2>{{product.first[0] +
                                                   static_cast<int>(j),
                                                 product.first[1] +
                                                   static_cast<int>(k)}},
                             S,
                             G,
                             T);
                    }
                return Status::ok;
              }
            case Type::b2cpdi:
              {
                Tensor<2, 2> s;
                for (unsigned int a = 0; a < 2; ++a)
                  for (unsigned int b = 0; b < 2; ++b)
                    s[a][b] = F[a][b] * l0[b];
                const double smallest_cell =
                  std::min(lattice.basis(0).cell_size(),
                           lattice.basis(1).cell_size());
                if (cpdi_critical_radius > 0)
                  limit_cpdi_domain(s, cpdi_critical_radius * smallest_cell);
                keep_cpdi_domain_off_axis(r_p, s);
                for (unsigned int d = 0; d < 2; ++d)
                  if (!(std::abs(s[d][0]) + std::abs(s[d][1]) <=
                        lattice.basis(d).cell_size() * (1 + 1e-12)))
                    return Status::domain_too_wide;
                std::array<double, 4>       w;
                std::array<Tensor<1, 2>, 4> g;
                double                      t;
                cpdi_corner_weights(r_p, s, w, g, t);
                BSpline::ProductSupport<2> corner[4];
                int first[2] = {std::numeric_limits<int>::max(),
                                std::numeric_limits<int>::max()};
                int last[2]  = {std::numeric_limits<int>::min(),
                                std::numeric_limits<int>::min()};
                for (unsigned int alpha = 0; alpha < 4; ++alpha)
                  {
                    Tensor<1, 2> r;
                    r[0] = (alpha & 1) ? 1. : -1.;
                    r[1] = (alpha & 2) ? 1. : -1.;
                    if (lattice.point_support(x + s * r, corner[alpha]) !=
                        BSpline::Status::ok)
                      return Status::in_padding_layer;
                    for (unsigned int d = 0; d < 2; ++d)
                      {
                        first[d] = std::min(first[d], corner[alpha].first[d]);
                        last[d] =
                          std::max(last[d],
                                   corner[alpha].first[d] +
                                     static_cast<int>(corner[alpha].count[d]) -
                                     1);
                      }
                  }
                constexpr int width = BSpline::BoxSupport<2>::max_per_direction;
                if (last[0] - first[0] + 1 > width ||
                    last[1] - first[1] + 1 > width)
                  return Status::domain_too_wide;
                std::array<double, width * width>       S{}, T{};
                std::array<Tensor<1, 2>, width * width> G;
                for (unsigned int alpha = 0; alpha < 4; ++alpha)
                  corner[alpha].for_each_node(
                    [&](const std::array<int, 2> &index,
                        const double              N,
                        const Tensor<1, 2> &) {
                      const unsigned int e =
                        (index[0] - first[0]) + width * (index[1] - first[1]);
                      S[e] += w[alpha] * N;
                      G[e] += N * g[alpha];
                      T[e] += t * N;
                    });
                for (int k = first[1]; k <= last[1]; ++k)
                  for (int j = first[0]; j <= last[0]; ++j)
                    {
                      const unsigned int e =
                        (j - first[0]) + width * (k - first[1]);
                      if (S[e] != 0 || G[e].norm_square() != 0 || T[e] != 0)
                        sink(std::array<int, 2>{{j, k}}, S[e], G[e], T[e]);
                    }
                return Status::ok;
              }
            default:
              Assert(false, ExcInternalError());
          }
        return Status::ok;
      }
    } // namespace Axisymmetric
  }   // namespace ShapeFunction
} // namespace fmpm

#endif
