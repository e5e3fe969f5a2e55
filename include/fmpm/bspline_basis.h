// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_bspline_basis_h
#define fmpm_bspline_basis_h

#include <deal.II/base/config.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace fmpm
{
  // The B-spline basis of one direction (fmpm::BSpline, bspline.h).
  namespace BSpline
  {
    using namespace dealii;

    enum class Boundary
    {
      /** Uniform functions; no point in the outer layer of cells. */
      padding,
      /** Open (clamped) knot vectors at the mesh boundary. */
      open_knots
    };

    /** The names of Boundary in a parameter file. */
    inline const char *
    boundary_pattern()
    {
      return "padding|open knots";
    }

    /** Boundary from its name (throws for unknown names). */
    Boundary
    parse_boundary(const std::string &name);

    /**
     * @brief The B-spline basis of degree p of one direction of the lattice:
     * n cells of size h from @p lower, vertices i = 0 ... n.
     *
     * Evaluations return a window of consecutive vertices [first, first +
     * count) with their weights and derivatives (entries may be zero). All
     * loops are bounded by constants: no allocation, no virtual call.
     */
    class Basis1D
    {
    public:
      static constexpr unsigned int max_degree = 3;
      /** The most vertices of one evaluation (p + 2 at an open end, an
       * average of the cubic basis over a domain up to a cell long). */
      static constexpr unsigned int max_nodes = 6;

      Basis1D() = default;

      /** The fewest cells of a basis: 2 p for open knots (the two ends'
       * modified functions apart), 3 for padding (a cell between the
       * padding layers), 1 for the linear basis. */
      static unsigned int
      fewest_cells(const unsigned int degree, const Boundary boundary)
      {
        if (degree == 1)
          return 1;
        return boundary == Boundary::open_knots ? 2 * degree : 3;
      }

      /**
       * @param degree 1, 2 or 3
       * @param lower the coordinate of vertex 0
       * @param h the cell size (> 0)
       * @param n_cells the number of cells (at least fewest_cells())
       */
      Basis1D(const unsigned int degree,
              const double       lower,
              const double       h,
              const unsigned int n_cells,
              const Boundary     boundary);

      unsigned int
      degree() const
      {
        return p;
      }
      unsigned int
      n_cells() const
      {
        return n;
      }
      double
      cell_size() const
      {
        return h;
      }
      Boundary
      boundary() const
      {
        return boundary_treatment;
      }
      /** The coordinate of vertex @p i. */
      double
      vertex(const int i) const
      {
        return lower + i * h;
      }

      /** Knot m in cells from vertex 0 (clamped to [0, n] for open knots).
       */
      double
      knot(const int m) const
      {
        const double u = m - shift;
        if (boundary_treatment == Boundary::padding)
          return u;
        return std::min(std::max(u, 0.), static_cast<double>(n));
      }

      /**
       * @brief S_i(x) and dS_i/dx for the vertices [first, first + count).
       *
       * @return false if a vertex outside [0, n] would carry a weight
       * (padding only: on_lattice()).
       */
      DEAL_II_ALWAYS_INLINE bool
      values(const double  x,
             int          &first,
             unsigned int &count,
             double       *S,
             double       *dS) const
      {
        const double t = (x - lower) * inverse_h;
        if (!on_lattice(t, t))
          return false;
        const int j = span(t);
        if (uniform_span(j))
          uniform_values(j, t, first, count, S, dS);
        else
          span_values(j, t, first, count, S, dS);
        return true;
      }

      /**
       * @brief S̄_i = 1/(2l) ∫_{x−l}^{x+l} S_i and its derivative Ḡ_i =
       * 1/(2l) ∫ dS_i/dx over the segment (GIMP over the B-spline basis,
       * seed 001 Eqs. effectiveS, G_gimp in 1D), for 0 < l ≤ h/2.
       *
       * Quadratic basis on uniform pieces: the closed form S̄_i = (Φ(r +
       * λ) − Φ(r − λ))/(2λ), Ḡ_i = (N(r + λ) − N(r − λ))/(2λh) with Φ the
       * antiderivative of N, r = (x − x_i)/h, λ = l/h. Otherwise (near an
       * open end, or p ≠ 2): Gauss quadrature exact for degree 3 on each
       * polynomial piece of the segment.
       *
       * @return false if [x − l, x + l] reaches vertices beyond the lattice
       * (padding: on_lattice())
       */
      DEAL_II_ALWAYS_INLINE bool
      averages(const double  x,
               const double  l,
               int          &first,
               unsigned int &count,
               double       *S,
               double       *dS) const
      {
        const double t      = (x - lower) * inverse_h;
        const double lambda = l * inverse_h;
        if (!on_lattice(t - lambda, t + lambda))
          return false;
        const int j_low  = span(t - lambda);
        const int j_high = span(t + lambda);
        if (p == 2 && uniform_span(j_low) && uniform_span(j_high))
          quadratic_averages(t, lambda, first, count, S, dS);
        else
          averages_by_polynomials(
            t, lambda, j_low, j_high, first, count, S, dS);
        return true;
      }

      /**
       * @brief S_i and dS_i/dx (in cells, dS per unit t) of the B-splines of
       * knot span @p j at @p t (cells from vertex 0), by the Cox-de Boor
       * recursion (Cottrell et al. Eqs. 2.1, 2.2, 2.12) and the Greville
       * split to the vertices; @p t may lie outside the span (the span's
       * polynomial extended). Public for the tests; values() uses it near
       * open ends.
       *
       * @p knots gives knot m (in cells); the basis's own knots by default.
       */
      template <typename Knots>
      void
      span_values_with_knots(const int     j,
                             const double  t,
                             const Knots  &knots,
                             int          &first,
                             unsigned int &count,
                             double       *S,
                             double       *dS) const
      {
        const int degree = static_cast<int>(p);
        // N[r]: B-spline m = j − q + r of degree q (r = 0 ... q); previous:
        // degree q − 1.
        double N[max_degree + 1], previous[max_degree + 1];
        double derivative[max_degree + 1];
        N[0] = 1;
        for (int q = 1; q <= degree; ++q)
          {
            for (int r = 0; r < q; ++r)
              previous[r] = N[r];
            for (int r = 0; r <= q; ++r)
              {
                const int m     = j - q + r;
                double    value = 0;
                if (r >= 1)
                  value += (t - knots(m)) / (knots(m + q) - knots(m)) *
                           previous[r - 1];
                if (r + 1 <= q)
                  value += (knots(m + q + 1) - t) /
                           (knots(m + q + 1) - knots(m + 1)) * previous[r];
                N[r] = value;
              }
          }
        // dN_{m,p}/dt = p (N_{m,p−1}/(u_{m+p} − u_m) − N_{m+1,p−1}/(u_{m+p+1}
        // − u_{m+1})) (Cottrell et al. Eq. 2.12).
        for (int r = 0; r <= degree; ++r)
          {
            const int m = j - degree + r;
            double    d = 0;
            if (r >= 1)
              d += previous[r - 1] / (knots(m + degree) - knots(m));
            if (r + 1 <= degree)
              d -= previous[r] / (knots(m + degree + 1) - knots(m + 1));
            derivative[r] = degree * d;
          }
        // The Greville split: B-spline m to the vertices around g_m.
        int    vertex[max_degree + 1];
        double fraction[max_degree + 1];
        first    = std::numeric_limits<int>::max();
        int last = std::numeric_limits<int>::min();
        for (int r = 0; r <= degree; ++r)
          {
            const int m = j - degree + r;
            double    g = 0;
            for (int k = 1; k <= degree; ++k)
              g += knots(m + k);
            g /= degree;
            vertex[r]   = static_cast<int>(std::floor(g));
            fraction[r] = g - vertex[r];
            first       = std::min(first, vertex[r]);
            last = std::max(last, vertex[r] + (fraction[r] != 0 ? 1 : 0));
          }
        count = static_cast<unsigned int>(last - first + 1);
        std::fill(S, S + count, 0.);
        std::fill(dS, dS + count, 0.);
        for (int r = 0; r <= degree; ++r)
          {
            const int k = vertex[r] - first;
            S[k] += (1 - fraction[r]) * N[r];
            dS[k] += (1 - fraction[r]) * derivative[r];
            if (fraction[r] != 0)
              {
                S[k + 1] += fraction[r] * N[r];
                dS[k + 1] += fraction[r] * derivative[r];
              }
          }
      }

      /**
       * @brief The knot span of @p t (in cells): t ∈ [u_j, u_{j+1}), limited
       * to the spans whose functions all have their vertex in the lattice
       * (beyond them the first or last of those is extended).
       */
      int
      span(const double t) const
      {
        const int j = floor_to_int(t + shift);
        return std::min(std::max(j, first_span), last_span);
      }

      /**
       * @brief ⌊u⌋ as an int, for |u| < 2^31: the same integer as
       * static_cast<int>(std::floor(u)), without the call (std::floor is
       * not one instruction on plain x86-64) that dominated a point's 1D
       * basis evaluation.
       */
      static int
      floor_to_int(const double u)
      {
        const int j = static_cast<int>(u); // rounds towards zero
        return j - (u < j ? 1 : 0);
      }

      /**
       * @brief Whether [t_low, t_high] (in cells) lies where every function
       * that is not zero has its vertex in the lattice, up to round-off:
       * always for open knots; for padding, from the end of the padding
       * layer for the cubic (the first cell for the quadratic, everywhere
       * for the linear basis).
       */
      bool
      on_lattice(const double t_low, const double t_high) const
      {
        constexpr double round_off = 1e-10;
        return boundary_treatment == Boundary::open_knots ||
               (t_low >= knot(first_span) - round_off &&
                t_high <= knot(last_span + 1) + round_off);
      }

    private:
      /**
       * Whether the functions of span j are the uniform ones: with padding
       * everywhere; with open knots beyond the end's first non-empty span
       * (there the Greville split turns the end functions into the
       * uniform ones, e.g. 3/4 N_{0} = (3/2 − t)²/2 on [1/2, 3/2] for p =
       * 2), i.e. where u_{j−p+2} ... u_{j+p−1} are unclamped.
       */
      bool
      uniform_span(const int j) const
      {
        return boundary_treatment == Boundary::padding ||
               (j - static_cast<int>(p) + 2 - shift >= 0 &&
                j + static_cast<int>(p) - 1 - shift <= n);
      }

      /** The basis's own knots. */
      struct OwnKnots
      {
        const Basis1D *basis;
        double
        operator()(const int m) const
        {
          return basis->knot(m);
        }
      };

      // (Not inlined: the spans near open ends are rare, and their local
      // arrays would put a stack check into every values() call.)
      __attribute__((noinline)) void
      span_values(const int     j,
                  const double  t,
                  int          &first,
                  unsigned int &count,
                  double       *S,
                  double       *dS) const
      {
        span_values_with_knots(j, t, OwnKnots{this}, first, count, S, dS);
        for (unsigned int k = 0; k < count; ++k)
          dS[k] *= inverse_h;
      }

      /** The closed forms of the uniform B-spline on span j (vertices j − p
       * ... j). */
      DEAL_II_ALWAYS_INLINE void
      uniform_values(const int     j,
                     const double  t,
                     int          &first,
                     unsigned int &count,
                     double       *S,
                     double       *dS) const
      {
        first = j - static_cast<int>(p);
        count = p + 1;
        switch (p)
          {
            case 1:
              {
                const double xi = t - (j - 1); // in [0, 1)
                S[0]            = 1 - xi;
                S[1]            = xi;
                dS[0]           = -inverse_h;
                dS[1]           = inverse_h;
                return;
              }
            case 2:
              {
                // ξ from the middle vertex j − 1, in [−1/2, 1/2).
                const double xi    = t - (j - 1);
                const double below = 0.5 - xi, above = 0.5 + xi;
                S[0]  = 0.5 * below * below;
                S[1]  = 0.75 - xi * xi;
                S[2]  = 0.5 * above * above;
                dS[0] = -below * inverse_h;
                dS[1] = -2 * xi * inverse_h;
                dS[2] = above * inverse_h;
                return;
              }
            default:
              {
                // ξ from vertex j − 2, in [0, 1).
                const double     xi = t - (j - 2), xi2 = xi * xi, eta = 1 - xi;
                constexpr double sixth = 1. / 6;
                S[0]                   = sixth * eta * eta * eta;
                S[1]                   = sixth * (3 * xi2 * xi - 6 * xi2 + 4);
                S[2]  = sixth * (-3 * xi2 * xi + 3 * xi2 + 3 * xi + 1);
                S[3]  = sixth * xi2 * xi;
                dS[0] = -0.5 * eta * eta * inverse_h;
                dS[1] = (1.5 * xi2 - 2 * xi) * inverse_h;
                dS[2] = (-1.5 * xi2 + xi + 0.5) * inverse_h;
                dS[3] = 0.5 * xi2 * inverse_h;
                return;
              }
          }
      }

      /** averages() on uniform quadratic pieces: S̄_i = (Φ_i(b) −
       * Φ_i(a))/(2λ), Ḡ_i = (N_i(b) − N_i(a))/(2λh) with a, b = t ∓ λ, N_i
       * the uniform quadratic B-spline of vertex i and Φ_i = ∫ N_i. */
      DEAL_II_ALWAYS_INLINE void
      quadratic_averages(const double  t,
                         const double  lambda,
                         int          &first,
                         unsigned int &count,
                         double       *S,
                         double       *dS) const
      {
        // Vertices i with (i − 3/2, i + 3/2) ∩ (t − λ, t + λ) ≠ ∅.
        // (Within round-off of the padding layer a vertex beyond carries a
        // weight of (round-off)³: left out.)
        // (⌈u⌉ = −⌊−u⌋.)
        const double a = t - lambda, b = t + lambda;
        const int    first_unclamped = floor_to_int(a - 1.5) + 1;
        first                        = std::max(first_unclamped, 0);
        const int last =
          std::min(-floor_to_int(-(b + 1.5)) - 1, static_cast<int>(n));
        count = last - first + 1;
        // Φ_i and N_i at an end e of the segment from the three functions
        // not zero there, those of the vertices m − 1, m, m + 1 with
        // m = ⌊e + 1/2⌋, u = e − m ∈ [−1/2, 1/2): Φ = 1 − (1/2 − u)³/6,
        // 1/2 + 3u/4 − u³/3, (1/2 + u)³/6 and N = (1/2 − u)²/2, 3/4 − u²,
        // (1/2 + u)²/2; vertices left of them have Φ = 1, right of them
        // Φ = 0 (no branch on the pieces).
        const int m_a = floor_to_int(a + 0.5);
        const int m_b = floor_to_int(b + 0.5);
        const int d   = m_b - m_a; // 0 or 1 for λ ≤ 1/2
        if (d < 0 || d > 1 || first_unclamped != m_a - 1 ||
            last - first_unclamped > 2 + d)
          {
            averages_by_quadrature(
              t, lambda, span(a), span(b), first, count, S, dS);
            return;
          }
        const double u = a - m_a, v = b - m_b;
        const double ua = 0.5 - u, ub = 0.5 + u, va = 0.5 - v, vb = 0.5 + v;
        // Slot 0: vertex m_a − 1. The b-arrays start one vertex lower
        // (m_b − 2, Φ = 1) so that a vertex's b-slot is its a-slot + 1 − d.
        const double Phi_a[5] = {1 - ua * ua * ua / 6,
                                 0.5 + 0.75 * u - u * u * u / 3,
                                 ub * ub * ub / 6,
                                 0,
                                 0};
        const double Phi_b[6] = {1,
                                 1 - va * va * va / 6,
                                 0.5 + 0.75 * v - v * v * v / 3,
                                 vb * vb * vb / 6,
                                 0,
                                 0};
        const double N_a[5]   = {
            0.5 * ua * ua, 0.75 - u * u, 0.5 * ub * ub, 0, 0};
        const double N_b[6] = {
          0, 0.5 * va * va, 0.75 - v * v, 0.5 * vb * vb, 0, 0};
        const double scale = 0.5 / lambda, gradient_scale = scale * inverse_h;
        const int    offset = first - first_unclamped;
        for (unsigned int k = 0; k < count; ++k)
          {
            const int k_a = static_cast<int>(k) + offset, k_b = k_a + 1 - d;
            S[k]  = scale * (Phi_b[k_b] - Phi_a[k_a]);
            dS[k] = gradient_scale * (N_b[k_b] - N_a[k_a]);
          }
      }

      /** Two-point Gauss on each polynomial piece of [t − λ, t + λ]: exact
       * for the piecewise cubic S_i (p ≤ 3). Not inlined, as span_values().
       */
      __attribute__((noinline)) void
      averages_by_quadrature(const double  t,
                             const double  lambda,
                             const int     j_low,
                             const int     j_high,
                             int          &first,
                             unsigned int &count,
                             double       *S,
                             double       *dS) const
      {
        constexpr double offset = 0.28867513459481287; // 1/(2√3)
        double           S_q[max_nodes], dS_q[max_nodes];
        double           S_sum[2 * max_nodes] = {}, dS_sum[2 * max_nodes] = {};
        int              first_q;
        unsigned int     count_q;
        first                  = std::numeric_limits<int>::max();
        int          last      = std::numeric_limits<int>::min();
        const int    sum_first = node_of_span_start(j_low);
        const double a = t - lambda, b = t + lambda;
        for (int j = j_low; j <= j_high; ++j)
          {
            // The piece of [a, b] in span j (the end spans extended).
            const double lo     = (j == j_low) ? a : knot(j);
            const double hi     = (j == j_high) ? b : knot(j + 1);
            const double weight = 0.5 * (hi - lo) / (2 * lambda);
            if (!(hi > lo))
              continue;
            for (const double g : {-offset, offset})
              {
                const double s = 0.5 * (lo + hi) + g * (hi - lo);
                if (uniform_span(j))
                  uniform_values(j, s, first_q, count_q, S_q, dS_q);
                else
                  span_values(j, s, first_q, count_q, S_q, dS_q);
                for (unsigned int k = 0; k < count_q; ++k)
                  {
                    const int e = first_q + static_cast<int>(k) - sum_first;
                    S_sum[e] += weight * S_q[k];
                    dS_sum[e] += weight * dS_q[k];
                  }
                first = std::min(first, first_q);
                last  = std::max(last, first_q + static_cast<int>(count_q) - 1);
              }
          }
        count = last - first + 1;
        for (unsigned int k = 0; k < count; ++k)
          {
            S[k]  = S_sum[first - sum_first + static_cast<int>(k)];
            dS[k] = dS_sum[first - sum_first + static_cast<int>(k)];
          }
      }

      /** averages() from each span's stored polynomials (open knots, where
       * the uniform closed form does not hold): on each piece [lo, hi] of
       * [t − λ, t + λ] in span j, S̄_i += ∫ P_ij / (2λ) and Ḡ_i += (P_ij(hi)
       * − P_ij(lo)) / (2λh), exact. Without stored polynomials (padding),
       * the quadrature. Not inlined, as span_values(). */
      __attribute__((noinline)) void
      averages_by_polynomials(const double  t,
                              const double  lambda,
                              const int     j_low,
                              const int     j_high,
                              int          &first,
                              unsigned int &count,
                              double       *S,
                              double       *dS) const
      {
        if (span_polynomials.empty())
          {
            averages_by_quadrature(
              t, lambda, j_low, j_high, first, count, S, dS);
            return;
          }
        double S_sum[2 * max_nodes] = {}, dS_sum[2 * max_nodes] = {};
        first                  = std::numeric_limits<int>::max();
        int          last      = std::numeric_limits<int>::min();
        const int    sum_first = node_of_span_start(j_low);
        const double a = t - lambda, b = t + lambda;
        const double inverse_length = 0.5 / lambda;
        for (int j = j_low; j <= j_high; ++j)
          {
            // The piece of [a, b] in span j (the end spans extended).
            const double lo = (j == j_low) ? a : knot(j);
            const double hi = (j == j_high) ? b : knot(j + 1);
            if (!(hi > lo))
              continue;
            const SpanPolynomials &span = span_polynomials[j - first_span];
            // Powers of the local coordinate u = t − u_j at the ends.
            double u_lo[max_degree + 2], u_hi[max_degree + 2];
            u_lo[0] = u_hi[0] = 1;
            for (unsigned int q = 0; q <= p; ++q)
              {
                u_lo[q + 1] = u_lo[q] * (lo - knot(j));
                u_hi[q + 1] = u_hi[q] * (hi - knot(j));
              }
            for (unsigned int k = 0; k < span.count; ++k)
              {
                double integral = 0, difference = 0;
                for (unsigned int q = 0; q <= p; ++q)
                  {
                    integral += span.coefficient[k][q] *
                                (u_hi[q + 1] - u_lo[q + 1]) / (q + 1);
                    difference += span.coefficient[k][q] * (u_hi[q] - u_lo[q]);
                  }
                const int e = span.first + static_cast<int>(k) - sum_first;
                S_sum[e] += inverse_length * integral;
                dS_sum[e] += inverse_length * inverse_h * difference;
              }
            first = std::min(first, span.first);
            last =
              std::max(last, span.first + static_cast<int>(span.count) - 1);
          }
        count = last - first + 1;
        for (unsigned int k = 0; k < count; ++k)
          {
            S[k]  = S_sum[first - sum_first + static_cast<int>(k)];
            dS[k] = dS_sum[first - sum_first + static_cast<int>(k)];
          }
      }

      /** The lowest vertex a span's functions reach (its Greville split
       * included). */
      int
      node_of_span_start(const int j) const
      {
        const int m = j - static_cast<int>(p);
        double    g = 0;
        for (unsigned int k = 1; k <= p; ++k)
          g += knot(m + k);
        return static_cast<int>(std::floor(g / p));
      }

      unsigned int p     = 2;
      double       lower = 0, h = 1, inverse_h = 1;
      unsigned int n                  = 1;
      Boundary     boundary_treatment = Boundary::open_knots;
      /** u_m = m − shift before clamping: (p + 1)/2. */
      double shift = 1.5;
      /** The first and last spans whose functions have their vertices in
       * the lattice: the first and last non-empty ones (open knots), p and n
       * (padding). */
      int first_span = 0, last_span = 0;

      /** The functions of one span as polynomials in u = t − u_j:
       * S_i = Σ_q coefficient[k][q] u^q for vertex i = first + k. */
      struct SpanPolynomials
      {
        int          first                                  = 0;
        unsigned int count                                  = 0;
        double       coefficient[max_nodes][max_degree + 1] = {};
      };
      /** Per span from first_span (open knots; empty for padding). */
      std::vector<SpanPolynomials> span_polynomials;
    };
  } // namespace BSpline
} // namespace fmpm

#endif
