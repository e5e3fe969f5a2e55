// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_bspline_h
#define fmpm_bspline_h

#include <fmpm/grid_transfer.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace fmpm
{
  /**
   * @brief B-spline shape functions on a uniform box lattice of cells, one
   * function per vertex (the DoFs of the FE_Q(1) grid vectors).
   *
   * Degree p = 1 (the classic hat functions), 2 (quadratic, support ±1.5
   * cells, knots at the cell midpoints: NairnMPM's B2SPLINE) or 3 (cubic,
   * support ±2 cells, knots at the vertices). Vertex i of a direction
   * carries N_i(x) = N((x − x_i)/h) of the uniform B-spline N of degree p
   * centred at 0 (Cottrell, Hughes, Bazilevs, "Isogeometric Analysis"
   * (2009) Ch. 2; the node-centred quadratic is Steffen, Kirby, Berzins,
   * IJNME 76 (2008) 922, Eq. 16).
   *
   * Two boundary treatments (Boundary):
   * - padding: the uniform functions everywhere; the outer layer of cells
   *   holds no point (a padding layer, as NairnMPM's edge cells), so that
   *   every function that is not zero at a point has its vertex in the
   *   lattice.
   * - open_knots: the knot vector u_m = clamp(m − (p+1)/2, 0, n) (in cells)
   *   is open (repeated p+1 times) at both ends, so the basis is complete
   *   on the whole mesh [0, n] and the boundary vertex's function is 1 at
   *   the boundary and the only one that is not zero there (a velocity
   *   condition on it holds on the wall). The open basis has one function
   *   more than vertices at each end for p = 2, 3: B-spline m has its
   *   Greville abscissa g_m = (u_{m+1} + ... + u_{m+p})/p at a vertex
   *   (g_m = m away from the ends) except one per end (g = 1/4 for p = 2,
   *   1/3 for p = 3), which is split linearly between the two vertices
   *   around g. Then Σ_i S_i = 1 and Σ_i x_i S_i = x exactly (Σ_m N_m = 1,
   *   Σ_m g_m N_m = x; Cottrell et al. Eq. 2.21 and §2.1.4), as Uintah's
   *   BSplineInterpolator keeps the first but not the second.
   *   Outside the mesh the first/last polynomial piece is extended.
   *
   * Domain averages (GIMP over the B-spline basis, S̄ = 1/V ∫_Ω S, Ḡ =
   * 1/V ∫_Ω ∇S as seed 001 Eqs. effectiveS, G_gimp) and CPDI corners (seed
   * 001 Eq. cpdi with S_g the B-spline) are built from the same 1D
   * evaluations; every support is a tensor product (or, for CPDI, a sum of
   * tensor products) addressed by lattice indices.
   */
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
      bool
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
      bool
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
          averages_by_quadrature(t, lambda, j_low, j_high, first, count, S, dS);
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
        const int j = static_cast<int>(std::floor(t + shift));
        return std::min(std::max(j, first_span), last_span);
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

      void
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
      void
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

      /** The uniform quadratic B-spline N(s) centred at 0 and its
       * antiderivative Φ(s) = ∫_{−∞}^s N. */
      static double
      quadratic(const double s)
      {
        const double a = std::abs(s);
        if (a < 0.5)
          return 0.75 - s * s;
        if (a < 1.5)
          return 0.5 * (1.5 - a) * (1.5 - a);
        return 0;
      }
      static double
      quadratic_antiderivative(const double s)
      {
        if (s <= -1.5)
          return 0;
        if (s <= -0.5)
          return (s + 1.5) * (s + 1.5) * (s + 1.5) / 6;
        if (s <= 0.5)
          return 0.5 + 0.75 * s - s * s * s / 3;
        if (s < 1.5)
          return 1 - (1.5 - s) * (1.5 - s) * (1.5 - s) / 6;
        return 1;
      }

      void
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
        first = std::max(static_cast<int>(std::floor(t - lambda - 1.5)) + 1, 0);
        const int last =
          std::min(static_cast<int>(std::ceil(t + lambda + 1.5)) - 1,
                   static_cast<int>(n));
        count              = last - first + 1;
        const double scale = 0.5 / lambda;
        for (unsigned int k = 0; k < count; ++k)
          {
            const double r = t - (first + static_cast<int>(k));
            S[k]           = scale * (quadratic_antiderivative(r + lambda) -
                            quadratic_antiderivative(r - lambda));
            dS[k]          = scale * inverse_h *
                    (quadratic(r + lambda) - quadratic(r - lambda));
          }
      }

      /** Two-point Gauss on each polynomial piece of [t − λ, t + λ]: exact
       * for the piecewise cubic S_i (p ≤ 3). */
      void
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
    };



    enum class Status
    {
      ok,
      /** A vertex outside the lattice would carry a weight (padding: the
       * point or its domain lies in the padding layer or beyond). */
      outside_lattice,
      /** A CPDI domain spreads over more vertices than a support holds. */
      too_wide
    };

    /**
     * @brief A tensor-product support: per direction a window of vertices
     * and their 1D weights and derivatives; S_i = Π_d w_d, ∂S_i/∂x_d =
     * w'_d Π_{e≠d} w_e.
     */
    template <int dim>
    struct ProductSupport
    {
      static constexpr unsigned int max_per_direction = Basis1D::max_nodes;
      int                           first[dim];
      unsigned int                  count[dim];
      double                        w[dim][max_per_direction];
      double                        dw[dim][max_per_direction];

      /** The number of vertices of the window (zeros included). */
      unsigned int
      size() const
      {
        unsigned int s = 1;
        for (unsigned int d = 0; d < dim; ++d)
          s *= count[d];
        return s;
      }

      /**
       * @brief Call @p sink(index, S, G) for every vertex of the window whose
       * S or G is not zero (index: the lattice index, direction 0
       * fastest).
       */
      template <typename Sink>
      void
      for_each_node(Sink &&sink) const
      {
        std::array<int, dim> index;
        unsigned int         k[dim]    = {};
        const unsigned int   n_entries = size();
        for (unsigned int e = 0; e < n_entries; ++e)
          {
            double         value = 1;
            Tensor<1, dim> gradient;
            for (unsigned int d = 0; d < dim; ++d)
              {
                value *= w[d][k[d]];
                double g = dw[d][k[d]];
                for (unsigned int c = 0; c < dim; ++c)
                  if (c != d)
                    g *= w[c][k[c]];
                gradient[d] = g;
                index[d]    = first[d] + static_cast<int>(k[d]);
              }
            if (value != 0 || gradient.norm_square() != 0)
              sink(index, value, gradient);
            for (unsigned int d = 0; d < dim; ++d)
              if (++k[d] < count[d])
                break;
              else
                k[d] = 0;
          }
      }
    };

    /**
     * @brief A support on a box of vertices with S and G per vertex (CPDI:
     * a sum over the corners of tensor products).
     */
    template <int dim>
    struct BoxSupport
    {
      static constexpr unsigned int        max_per_direction = 6;
      static constexpr unsigned int        max_size = dim == 2 ? 36 : 216;
      int                                  first[dim];
      unsigned int                         count[dim];
      std::array<double, max_size>         S;
      std::array<Tensor<1, dim>, max_size> G;

      unsigned int
      size() const
      {
        unsigned int s = 1;
        for (unsigned int d = 0; d < dim; ++d)
          s *= count[d];
        return s;
      }

      /** The entry of lattice index @p index (inside the box). */
      unsigned int
      entry(const std::array<int, dim> &index) const
      {
        unsigned int e = 0, stride = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            e += stride * (index[d] - first[d]);
            stride *= count[d];
          }
        return e;
      }

      /** As ProductSupport::for_each_node(). */
      template <typename Sink>
      void
      for_each_node(Sink &&sink) const
      {
        std::array<int, dim> index;
        unsigned int         k[dim]    = {};
        const unsigned int   n_entries = size();
        for (unsigned int e = 0; e < n_entries; ++e)
          {
            for (unsigned int d = 0; d < dim; ++d)
              index[d] = first[d] + static_cast<int>(k[d]);
            if (S[e] != 0 || G[e].norm_square() != 0)
              sink(index, S[e], G[e]);
            for (unsigned int d = 0; d < dim; ++d)
              if (++k[d] < count[d])
                break;
              else
                k[d] = 0;
          }
      }
    };

    /**
     * @brief The B-spline basis of a uniform box lattice (tensor products of
     * Basis1D), and the supports of a point for b2spline/b3spline (values),
     * b2gimp (domain averages) and b2cpdi (corners).
     */
    template <int dim>
    class Lattice
    {
    public:
      Lattice() = default;

      /**
       * @param lower, upper the box of the mesh
       * @param n_cells cells per direction (uniform: (upper − lower)/n_cells)
       *
       * A direction with fewer than Basis1D::fewest_cells() cells carries
       * the linear basis.
       */
      Lattice(const Point<dim>                    &lower,
              const Point<dim>                    &upper,
              const std::array<unsigned int, dim> &n_cells,
              const unsigned int                   degree,
              const Boundary                       boundary);

      /**
       * @brief The lattice of a mesh of uniform axis-aligned boxes from the
       * cells GridTransfer caches (active cell indices below @p
       * n_active_cells), or an explanation in @p error why the mesh is not
       * one (a cell not a box, of another size or off the lattice, a
       * hanging node). The box is the bounding box of the cached cells
       * combined over @p communicator.
       */
      static Lattice
      of_mesh(const GridTransfer<dim> &transfer,
              const unsigned int       n_active_cells,
              const unsigned int       degree,
              const Boundary           boundary,
              const MPI_Comm           communicator,
              std::string             &error);

      const Basis1D &
      basis(const unsigned int d) const
      {
        return bases[d];
      }

      unsigned int
      degree() const
      {
        return bases[0].degree();
      }

      /** Vertices per direction (n_d + 1) and in all. */
      unsigned int
      n_vertices(const unsigned int d) const
      {
        return bases[d].n_cells() + 1;
      }
      unsigned int
      n_vertices() const
      {
        unsigned int n = 1;
        for (unsigned int d = 0; d < dim; ++d)
          n *= n_vertices(d);
        return n;
      }

      /** The number of a vertex: Σ_d i_d Π_{e<d} (n_e + 1). */
      unsigned int
      vertex_number(const std::array<int, dim> &index) const
      {
        unsigned int number = 0, stride = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            number += stride * index[d];
            stride *= n_vertices(d);
          }
        return number;
      }

      /** The position of the vertex of lattice index @p index. */
      Point<dim>
      vertex(const std::array<int, dim> &index) const
      {
        Point<dim> x;
        for (unsigned int d = 0; d < dim; ++d)
          x[d] = bases[d].vertex(index[d]);
        return x;
      }

      /** Whether @p x lies in the outer layer of cells (or outside). */
      bool
      in_padding_layer(const Point<dim> &x) const
      {
        for (unsigned int d = 0; d < dim; ++d)
          {
            const double t = (x[d] - bases[d].vertex(0)) / bases[d].cell_size();
            if (t < 1 || t > bases[d].n_cells() - 1)
              return true;
          }
        return false;
      }

      /** b2spline/b3spline: S_i(x_p) and ∇S_i(x_p). */
      Status
      point_support(const Point<dim> &x, ProductSupport<dim> &support) const
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (!bases[d].values(x[d],
                               support.first[d],
                               support.count[d],
                               support.w[d],
                               support.dw[d]))
            return Status::outside_lattice;
        return Status::ok;
      }

      /**
       * @brief b2gimp: the averages over the box x ± l (half-lengths l_d ≤
       * h_d/2), a product of 1D averages.
       */
      Status
      gimp_support(const Point<dim>     &x,
                   const Tensor<1, dim> &l,
                   ProductSupport<dim>  &support) const
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (!bases[d].averages(x[d],
                                 l[d],
                                 support.first[d],
                                 support.count[d],
                                 support.w[d],
                                 support.dw[d]))
            return Status::outside_lattice;
        return Status::ok;
      }

      /**
       * @brief b2cpdi: S̄_i = 2^-dim Σ_α S_i(x_α), Ḡ_i = 2^-dim Σ_α S_i(x_α)
       * s⁻ᵀ r_α over the corners x_α = x + s r_α, r_α ∈ {±1}^dim, of the
       * domain s = F diag(l⁰) (seed 001 Eq. cpdi and the matrix form after
       * it, with the B-spline S_i).
       */
      Status
      cpdi_support(const Point<dim>     &x,
                   const Tensor<2, dim> &s,
                   BoxSupport<dim>      &support) const
      {
        constexpr unsigned int n_corners = 1u << dim;
        ProductSupport<dim>    corner[n_corners];
        for (unsigned int d = 0; d < dim; ++d)
          {
            support.first[d] = std::numeric_limits<int>::max();
            support.count[d] = 0;
          }
        int last[dim];
        std::fill(last, last + dim, std::numeric_limits<int>::min());
        Tensor<1, dim>       weight_of_corner[n_corners];
        const Tensor<2, dim> s_inverse_transpose = transpose(invert(s));
        for (unsigned int alpha = 0; alpha < n_corners; ++alpha)
          {
            Tensor<1, dim> r;
            for (unsigned int j = 0; j < dim; ++j)
              r[j] = ((alpha >> j) & 1) ? 1. : -1.;
            const Point<dim> x_alpha = x + s * r;
            if (point_support(x_alpha, corner[alpha]) != Status::ok)
              return Status::outside_lattice;
            weight_of_corner[alpha] = s_inverse_transpose * r / n_corners;
            for (unsigned int d = 0; d < dim; ++d)
              {
                support.first[d] =
                  std::min(support.first[d], corner[alpha].first[d]);
                last[d] =
                  std::max(last[d],
                           corner[alpha].first[d] +
                             static_cast<int>(corner[alpha].count[d]) - 1);
              }
          }
        for (unsigned int d = 0; d < dim; ++d)
          {
            if (last[d] - support.first[d] + 1 >
                static_cast<int>(BoxSupport<dim>::max_per_direction))
              return Status::too_wide;
            support.count[d] = last[d] - support.first[d] + 1;
          }
        const unsigned int n_entries = support.size();
        std::fill(support.S.begin(), support.S.begin() + n_entries, 0.);
        std::fill(support.G.begin(),
                  support.G.begin() + n_entries,
                  Tensor<1, dim>());
        for (unsigned int alpha = 0; alpha < n_corners; ++alpha)
          corner[alpha].for_each_node([&](const std::array<int, dim> &index,
                                          const double                S_alpha,
                                          const Tensor<1, dim> &) {
            const unsigned int e = support.entry(index);
            support.S[e] += S_alpha / n_corners;
            support.G[e] += S_alpha * weight_of_corner[alpha];
          });
        return Status::ok;
      }

    private:
      std::array<Basis1D, dim> bases;
    };

    /**
     * @brief Lattice index -> local index in the ghosted grid vectors (and
     * global DoF) of the vertices of this rank's owned and ghost cells,
     * stored densely over the box of lattice indices they span.
     */
    template <int dim>
    class VertexMap
    {
    public:
      /** @brief The vertices of the cells GridTransfer caches (active cell
       * indices below @p n_active_cells). */
      void
      reinit(const Lattice<dim>      &lattice,
             const GridTransfer<dim> &transfer,
             const unsigned int       n_active_cells);

      /** @brief Adds the vertices at @p positions with local indices @p
       * local_indices (ghost entries beyond the cached cells). */
      void
      add(const Lattice<dim>              &lattice,
          const std::vector<Point<dim>>   &positions,
          const std::vector<unsigned int> &local_indices);

      /** The local index of a vertex, or numbers::invalid_unsigned_int if
       * no cached cell has it. */
      unsigned int
      local_index(const std::array<int, dim> &index) const
      {
        unsigned int e = 0, stride = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const int k = index[d] - first[d];
            if (k < 0 || k >= static_cast<int>(count[d]))
              return numbers::invalid_unsigned_int;
            e += stride * k;
            stride *= count[d];
          }
        return local[e];
      }

    private:
      int                       first[dim] = {};
      unsigned int              count[dim] = {};
      std::vector<unsigned int> local;
    };
  } // namespace BSpline
} // namespace fmpm

#endif
