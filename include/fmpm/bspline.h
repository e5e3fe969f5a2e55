// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_bspline_h
#define fmpm_bspline_h

#include <fmpm/bspline_basis.h>
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
      DEAL_II_ALWAYS_INLINE Status
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
      DEAL_II_ALWAYS_INLINE Status
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
        // Each corner's values S_i(x_α), the products of
        // ProductSupport::for_each_node() (its gradients are not needed).
        // Its entries whose value is zero add nothing: S and G never hold
        // −0, so adding ±0 leaves their bits as they are.
        for (unsigned int alpha = 0; alpha < n_corners; ++alpha)
          {
            const ProductSupport<dim> &c         = corner[alpha];
            unsigned int               k[dim]    = {};
            const unsigned int         n_entries = c.size();
            std::array<int, dim>       index;
            for (unsigned int e = 0; e < n_entries; ++e)
              {
                double value = 1;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    value *= c.w[d][k[d]];
                    index[d] = c.first[d] + static_cast<int>(k[d]);
                  }
                const unsigned int entry = support.entry(index);
                support.S[entry] += value / n_corners;
                support.G[entry] += value * weight_of_corner[alpha];
                for (unsigned int d = 0; d < dim; ++d)
                  if (++k[d] < c.count[d])
                    break;
                  else
                    k[d] = 0;
              }
          }
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

      /**
       * @brief The entries of @p product as ProductSupport::for_each_node()
       * gives them to a sink that stores the local index, S and G (same
       * order, same products, the entries whose S and G are zero left
       * out), with the local indices read along the rows of the dense map
       * instead of one local_index() a node: one bounds check a support.
       *
       * @return false if a node is not held by this rank (that node is left
       * out, as the sink leaves it out), or if the support is not inside the
       * map's box (then nothing is written; use for_each_node()).
       */
      DEAL_II_ALWAYS_INLINE bool
      write_product(const ProductSupport<dim> &product,
                    unsigned int              *node,
                    double                    *S,
                    Tensor<1, dim>            *G,
                    unsigned int              &n_written,
                    bool                      &all_on_rank) const
      {
        unsigned int base = 0, stride[dim];
        unsigned int row  = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const int k = product.first[d] - first[d];
            if (k < 0 || k + product.count[d] > count[d])
              return false;
            base += row * k;
            stride[d] = row;
            row *= count[d];
          }
        n_written     = 0;
        all_on_rank   = true;
        const auto &w = product.w, &dw = product.dw;
        const auto  emit = [&](const unsigned int    e,
                              const double          value,
                              const Tensor<1, dim> &g) {
          if (value == 0 && g.norm_square() == 0)
            return;
          const unsigned int local_index = local[e];
          if (local_index == numbers::invalid_unsigned_int)
            {
              all_on_rank = false;
              return;
            }
          node[n_written] = local_index;
          S[n_written]    = value;
          G[n_written]    = g;
          ++n_written;
        };
        // The products of ProductSupport::for_each_node(), factor by
        // factor in its order (bitwise the same S and G).
        if constexpr (dim == 2)
          for (unsigned int k1 = 0; k1 < product.count[1]; ++k1)
            for (unsigned int k0 = 0; k0 < product.count[0]; ++k0)
              {
                Tensor<1, dim> g;
                g[0] = dw[0][k0] * w[1][k1];
                g[1] = dw[1][k1] * w[0][k0];
                emit(base + k0 + stride[1] * k1, w[0][k0] * w[1][k1], g);
              }
        else if constexpr (dim == 3)
          for (unsigned int k2 = 0; k2 < product.count[2]; ++k2)
            for (unsigned int k1 = 0; k1 < product.count[1]; ++k1)
              for (unsigned int k0 = 0; k0 < product.count[0]; ++k0)
                {
                  Tensor<1, dim> g;
                  g[0] = dw[0][k0] * w[1][k1] * w[2][k2];
                  g[1] = dw[1][k1] * w[0][k0] * w[2][k2];
                  g[2] = dw[2][k2] * w[0][k0] * w[1][k1];
                  emit(base + k0 + stride[1] * k1 + stride[2] * k2,
                       w[0][k0] * w[1][k1] * w[2][k2],
                       g);
                }
        else
          return false;
        return true;
      }

      /**
       * @brief The entries of @p box as BoxSupport::for_each_node() gives
       * them to a sink that stores the local index, S and G, read along the
       * rows of the dense map as write_product() does.
       *
       * @return as write_product().
       */
      DEAL_II_ALWAYS_INLINE bool
      write_box(const BoxSupport<dim> &box,
                unsigned int          *node,
                double                *S,
                Tensor<1, dim>        *G,
                unsigned int          &n_written,
                bool                  &all_on_rank) const
      {
        unsigned int base = 0, stride[dim];
        unsigned int row  = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const int k = box.first[d] - first[d];
            if (k < 0 || k + box.count[d] > count[d])
              return false;
            base += row * k;
            stride[d] = row;
            row *= count[d];
          }
        n_written       = 0;
        all_on_rank     = true;
        const auto emit = [&](const unsigned int e, const unsigned int map) {
          if (box.S[e] == 0 && box.G[e].norm_square() == 0)
            return;
          const unsigned int local_index = local[map];
          if (local_index == numbers::invalid_unsigned_int)
            {
              all_on_rank = false;
              return;
            }
          node[n_written] = local_index;
          S[n_written]    = box.S[e];
          G[n_written]    = box.G[e];
          ++n_written;
        };
        unsigned int e = 0;
        if constexpr (dim == 2)
          for (unsigned int k1 = 0; k1 < box.count[1]; ++k1)
            for (unsigned int k0 = 0; k0 < box.count[0]; ++k0, ++e)
              emit(e, base + k0 + stride[1] * k1);
        else if constexpr (dim == 3)
          for (unsigned int k2 = 0; k2 < box.count[2]; ++k2)
            for (unsigned int k1 = 0; k1 < box.count[1]; ++k1)
              for (unsigned int k0 = 0; k0 < box.count[0]; ++k0, ++e)
                emit(e, base + k0 + stride[1] * k1 + stride[2] * k2);
        else
          return false;
        return true;
      }

    private:
      int                       first[dim] = {};
      unsigned int              count[dim] = {};
      std::vector<unsigned int> local;
    };
  } // namespace BSpline
} // namespace fmpm

#endif
