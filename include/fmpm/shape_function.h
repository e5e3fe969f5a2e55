// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_shape_function_h
#define fmpm_shape_function_h

#include <fmpm/grid_transfer.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <algorithm>
#include <array>
#include <string>
#include <utility>
#include <vector>

namespace fmpm
{
  /**
   * @brief Effective shape functions S̄_gp and gradients Ḡ_gp of seed 001
   * ("Shape functions for MPM, GIMP, and CPDI") on any FE_Q(1) mesh.
   *
   * - classic: S_g(x_p), ∇S_g(x_p) (Eq. linear_shape); the transfer loops
   *   keep their per-cell fast path for it and never call this code.
   * - ugimp: S̄ = 1/V ∫_Ω S_g, Ḡ = 1/V ∫_Ω ∇S_g (Eqs. effectiveS, G_gimp)
   *   over the axis-aligned box Ω of the initial half-lengths l⁰.
   * - cpgimp: the same over the box circumscribing the deformed particle
   *   F·diag(l⁰) (l_d = Σ_j |F_dj| l⁰_j; seed 001 §UGIMP and cpGIMP).
   * - cpdi: S̄ = mean_α S_g(x_α), Ḡ = 2^-dim s⁻ᵀ Σ_α r_α S_g(x_α) over the
   *   corners x_α = x_p + s r_α of the parallelogram/parallelepiped
   *   s = F·diag(l⁰) (Eq. cpdi and the matrix form after it; the seed writes
   *   s⁻ᵀ Rᵀ Sᵀ, the dimensions need s⁻ᵀ R Sᵀ).
   *
   * GIMP on a uniform patch of axis-aligned cells (and l ≤ h/2) uses the
   * closed forms (Eqs. gimp_shape, gimpGrad) per direction. Otherwise the
   * integral is a quadrature over the box split at the faces of the cells
   * it crosses (exact on axis-aligned cells, hanging nodes included);
   * across non-axis-aligned cells the box is bisected a few times and the
   * pieces that still cross faces use Gauss points located one by one.
   *
   * The support of a point lives in the patch of its cell (the cells
   * sharing a vertex with it, all owned or ghost on any MPI rank); a domain
   * that reaches further is reported.
   */
  namespace ShapeFunction
  {
    using namespace dealii;

    enum class Type
    {
      classic,
      ugimp,
      cpgimp,
      cpdi,
      /** Quadratic B-splines on a uniform box lattice (BSpline). */
      b2spline,
      /** Cubic B-splines. */
      b3spline,
      /** uGIMP over the quadratic B-splines. */
      b2gimp,
      /** CPDI corners over the quadratic B-splines. */
      b2cpdi
    };

    /** The names of Type in the parameter file. */
    inline const char *
    pattern()
    {
      return "classic|ugimp|cpgimp|cpdi|b2spline|b3spline|b2gimp|b2cpdi";
    }

    /** Whether @p type is one of the B-spline shape functions. */
    inline bool
    is_bspline(const Type type)
    {
      return type == Type::b2spline || type == Type::b3spline ||
             type == Type::b2gimp || type == Type::b2cpdi;
    }

    /** Type from its parameter name (throws for unknown names). */
    Type
    parse(const std::string &name);

    /** The parameter name of @p type (parse() reads it back). */
    std::string
    parameter_name(const Type type);

    /** One node of a point's support: S̄_gp and Ḡ_gp. */
    template <int dim>
    struct Node
    {
      /** Index into the ghosted grid vectors. */
      unsigned int local_index;
      /** Global DoF (for constraints and the full mass matrix). */
      types::global_dof_index dof;
      bool                    constrained;
      double                  S;
      Tensor<1, dim>          G;
    };

    enum class Status
    {
      ok,
      /** The domain reaches beyond the cells around the point's cell. */
      beyond_neighbors,
      /** The domain reaches outside the mesh by more than half a cell. */
      outside_mesh,
      /** B-splines with padding: the point or its domain is in the padding
       * layer. */
      in_padding_layer,
      /** B-splines: a vertex of the support is on no cell this rank holds
       * (owned or ghost). */
      vertex_not_on_rank,
      /** B-spline GIMP/CPDI: the domain is wider than a support holds (GIMP:
       * a half-length above half a cell; CPDI: corners more than a cell
       * from the point). */
      domain_too_wide
    };

    /**
     * @brief The support of one point: every node with its S̄ and Ḡ.
     *
     * @param cell active cell index of the point's (locally owned) cell
     * @param x the point's position
     * @param F the deformation gradient (dim x dim block)
     * @param l0 the initial half-lengths
     * @param allow_closed_form use GIMP's closed forms where they hold
     *        (false: always the quadrature, for tests)
     * @param cpdi_critical_radius CPDI only: if positive, each half-diagonal
     *        s r of the domain longer than this many times the smallest
     *        extent of the point's cell is shortened to it and s rebuilt
     *        from the diagonals (limit_cpdi_domain()); 0: the domain as F
     *        gives it
     */
    template <int dim>
    Status
    compute_support(const Type               type,
                    const GridTransfer<dim> &transfer,
                    const unsigned int       cell,
                    const Point<dim>        &x,
                    const Tensor<2, dim>    &F,
                    const Tensor<1, dim>    &l0,
                    std::vector<Node<dim>>  &support,
                    const bool               allow_closed_form    = true,
                    const double             cpdi_critical_radius = 0);

    /**
     * @brief Shortens the half-diagonals of a CPDI domain s = F diag(l⁰)
     * to at most @p r_max and rebuilds s from them.
     *
     * The 2^(dim-1) half-diagonals d_k = s r_k (r_k ∈ {±1}^dim with last
     * entry +1) longer than @p r_max are scaled to length r_max; column j of
     * s becomes 2^(1-dim) Σ_k r_k[j] d_k, the least-squares fit (exact in 2D;
     * in 3D s is then scaled as a whole if a diagonal is still longer than
     * r_max; s is unchanged when no diagonal is too long). A long, thin domain
     * keeps its short directions and its corners stay within r_max of the
     * point, so a limit of one cell keeps them in the neighbour cells.
     *
     * @return whether s was changed
     */
    template <int dim>
    bool
    limit_cpdi_domain(Tensor<2, dim> &s, const double r_max);

    /**
     * @brief Seed 001 Eqs. gimp_shape and gimpGrad: the 1D GIMP weight
     * @p S and its derivative @p G for r = x_p − x_g, cell size h,
     * half-length l ≤ h/2.
     */
    inline void
    gimp_1d(const double r,
            const double h,
            const double l,
            double      &S,
            double      &G)
    {
      if (r <= -h - l)
        S = G = 0;
      else if (r <= -h + l)
        {
          S = (h + l + r) * (h + l + r) / (4 * h * l);
          G = (h + l + r) / (2 * h * l);
        }
      else if (r <= -l)
        {
          S = 1 + r / h;
          G = 1 / h;
        }
      else if (r <= l)
        {
          S = 1 - (r * r + l * l) / (2 * h * l);
          G = -r / (h * l);
        }
      else if (r <= h - l)
        {
          S = 1 - r / h;
          G = -1 / h;
        }
      else if (r <= h + l)
        {
          S = (h + l - r) * (h + l - r) / (4 * h * l);
          G = -(h + l - r) / (2 * h * l);
        }
      else
        S = G = 0;
    }

    /** The same as a pair (S, G). */
    inline std::pair<double, double>
    gimp_1d(const double r, const double h, const double l)
    {
      std::pair<double, double> w;
      gimp_1d(r, h, l, w.first, w.second);
      return w;
    }

    /**
     * @brief The planes and nodes of the patch of one locally owned cell
     * whose patch is uniform (GridTransfer's CellData::uniform_patch): four
     * planes per direction (own lower − h, lower, upper, upper + h), the
     * patch's cells by column and its nodes by plane. Shared by the closed
     * forms on uniform patches (plane and axisymmetric GIMP).
     */
    template <int dim>
    struct UniformPatchPlanes
    {
      /** @brief The planes and nodes of the patch of @p cell_index. */
      void
      reinit(const GridTransfer<dim> &transfer, const unsigned int cell_index);

      static constexpr unsigned int n_slots = 1u << (2 * dim); // 4^dim
      /** Whether the patch has the cell in columns (c_0, c_1[, c_2]), at
       * Σ c_d 3^d. */
      std::array<bool, dim == 2 ? 9 : 27> has_cell;
      /** Plane coordinates per direction, and the cell size h. */
      double plane[dim][4];
      double h[dim];
      /** Node on planes (p_0, p_1[, p_2]), slot Σ p_d 4^d. */
      std::array<unsigned int, n_slots>            local_index;
      std::array<types::global_dof_index, n_slots> dof;
    };

    /**
     * @brief GIMP's closed forms (seed 001 Eqs. gimp_shape, gimpGrad) around
     * one locally owned cell whose patch is uniform (GridTransfer's
     * CellData::uniform_patch): the patch's nodes lie on four planes per
     * direction (own lower − h, lower, upper, upper + h), so a point's
     * support is the tensor product of 1D weights, evaluated once per plane.
     * At the mesh boundary the patch lacks cells; the closed forms hold for
     * boxes that overlap only cells it has.
     * Built once per cell, read by each of its points.
     */
    template <int dim>
    class UniformGimpPatch : private UniformPatchPlanes<dim>
    {
    public:
      using UniformPatchPlanes<dim>::reinit;

      /** @brief The patch's planes and nodes (read by the axisymmetric
       * closed forms of the same cell). */
      const UniformPatchPlanes<dim> &
      planes() const
      {
        return *this;
      }

      /**
       * @brief Whether the closed forms hold for a point at @p x with
       * half-lengths @p l: x in the cell, l ≤ h/2, and the box x ± l
       * overlaps only cells of the patch.
       */
      bool
      applies(const Point<dim> &x, const Tensor<1, dim> &l) const;

      /**
       * @brief Call @p sink(local index, DoF, S̄, Ḡ) for every node of the
       * patch cells the box x ± l overlaps (each once, lexicographic in the
       * planes), except those where both S̄ and Ḡ vanish. Inline, so that
       * the caller's sink writes the values where they go (a Node built on
       * the stack and copied cost a store-forwarding stall per node).
       */
      template <typename Sink>
      void
      for_each_node(const Point<dim>     &x,
                    const Tensor<1, dim> &l,
                    Sink                &&sink) const
      {
        unsigned int first_plane[dim], last_plane[dim];
        for (unsigned int d = 0; d < dim; ++d)
          overlapped_columns(x, l, d, first_plane[d], last_plane[d]);
        sink_nodes(x, l, first_plane, last_plane, sink);
      }

      /**
       * @brief for_each_node() if applies(), in one pass; returns
       * applies().
       */
      template <typename Sink>
      DEAL_II_ALWAYS_INLINE bool
      for_each_node_if_applies(const Point<dim>     &x,
                               const Tensor<1, dim> &l,
                               Sink                &&sink) const
      {
        unsigned int first_plane[dim], last_plane[dim];
        if (!columns_if_applies(x, l, first_plane, last_plane))
          return false;
        sink_nodes(x, l, first_plane, last_plane, sink);
        return true;
      }

    private:
      /** The columns c (cells between planes c and c + 1) the box x ± l
       * overlaps in direction d: [first, last). */
      void
      overlapped_columns(const Point<dim>     &x,
                         const Tensor<1, dim> &l,
                         const unsigned int    d,
                         unsigned int         &first,
                         unsigned int         &last) const
      {
        first = 3;
        last  = 0;
        for (unsigned int c = 0; c < 3; ++c)
          if (plane[d][c] < x[d] + l[d] && plane[d][c + 1] > x[d] - l[d])
            {
              first = std::min(first, c);
              last  = c + 1;
            }
      }

      /** The overlapped columns of each direction, and whether the closed
       * forms apply (see applies()). */
      bool
      columns_if_applies(const Point<dim>     &x,
                         const Tensor<1, dim> &l,
                         unsigned int (&first)[dim],
                         unsigned int (&last)[dim]) const
      {
        for (unsigned int d = 0; d < dim; ++d)
          {
            if (l[d] > 0.5 * h[d] || x[d] < plane[d][1] || x[d] > plane[d][2])
              return false;
            overlapped_columns(x, l, d, first[d], last[d]);
          }
        // Every overlapped cell is in the patch (at the mesh boundary it
        // may not be: the general path reports the box).
        for (unsigned int c0 = first[0]; c0 < last[0]; ++c0)
          for (unsigned int c1 = first[1]; c1 < last[1]; ++c1)
            if constexpr (dim == 2)
              {
                if (!has_cell[c0 + 3 * c1])
                  return false;
              }
            else
              for (unsigned int c2 = first[2]; c2 < last[2]; ++c2)
                if (!has_cell[c0 + 3 * c1 + 9 * c2])
                  return false;
        return true;
      }

      /** The nodes of the planes [first_plane, last_plane] (inclusive) of
       * each direction: their 1D weights, then their products. */
      template <typename Sink>
      void
      sink_nodes(const Point<dim>     &x,
                 const Tensor<1, dim> &l,
                 const unsigned int (&first_plane)[dim],
                 const unsigned int (&last_plane)[dim],
                 Sink &sink) const
      {
        double w[dim][4], dw[dim][4];
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int p = first_plane[d]; p <= last_plane[d]; ++p)
            gimp_1d(x[d] - plane[d][p], h[d], l[d], w[d][p], dw[d][p]);
        // The nodes in slot order (p_0 fastest).
        auto sink_node = [&](const unsigned int(&p)[dim]) {
          double         value = 1;
          Tensor<1, dim> gradient;
          for (unsigned int d = 0; d < dim; ++d)
            {
              value *= w[d][p[d]];
              double g = dw[d][p[d]];
              for (unsigned int e = 0; e < dim; ++e)
                if (e != d)
                  g *= w[e][p[e]];
              gradient[d] = g;
            }
          if (value != 0 || gradient.norm_square() != 0)
            {
              unsigned int slot = 0;
              for (unsigned int d = 0; d < dim; ++d)
                slot += p[d] << (2 * d);
              sink(local_index[slot], dof[slot], value, gradient);
            }
        };
        unsigned int p[dim];
        if constexpr (dim == 2)
          for (p[1] = first_plane[1]; p[1] <= last_plane[1]; ++p[1])
            for (p[0] = first_plane[0]; p[0] <= last_plane[0]; ++p[0])
              sink_node(p);
        else
          for (p[2] = first_plane[2]; p[2] <= last_plane[2]; ++p[2])
            for (p[1] = first_plane[1]; p[1] <= last_plane[1]; ++p[1])
              for (p[0] = first_plane[0]; p[0] <= last_plane[0]; ++p[0])
                sink_node(p);
      }

      using UniformPatchPlanes<dim>::has_cell;
      using UniformPatchPlanes<dim>::plane;
      using UniformPatchPlanes<dim>::h;
      using UniformPatchPlanes<dim>::local_index;
      using UniformPatchPlanes<dim>::dof;
    };

    /**
     * @brief CPDI supports (seed 001 Eq. cpdi) around one locally owned cell
     * whose patch is uniform (GridTransfer's CellData::uniform_patch) and
     * exactly axis-aligned: the cell of a corner x_α is found by
     * floor((x_α − x₀)/h) and its ξ by the cell's diagonal affine map, with
     * no point location; the corners' nodes are merged by their planes (four
     * per direction, as in UniformGimpPatch).
     *
     * The operations, and the order of the corners and of the nodes, are
     * those of compute_support()'s general path, which locates each corner
     * with GridTransfer::locate(): the same bits. As there, a corner takes
     * the previous corner's cell when that cell holds it within 1e-10 of
     * its size; a corner within 1e-9 of a face of another cell, or outside
     * the patch's cells (beyond the mesh boundary), is located by
     * GridTransfer::locate().
     * Built once per cell, read by each of its points.
     */
    template <int dim>
    class UniformCpdiPatch
    {
    public:
      static constexpr unsigned int n_nodes = GridTransfer<dim>::n_nodes;
      /** The most nodes a support can have: 2^dim corners of 2^dim nodes
       * each, within the 4^dim nodes of the patch. */
      static constexpr unsigned int max_support_size = n_nodes * n_nodes;

      /**
       * @brief The planes and cells of the patch of @p cell_index (which
       * must have a uniform patch).
       */
      void
      reinit(const GridTransfer<dim> &transfer, const unsigned int cell_index);

      /**
       * @brief Whether the patch's cells are exact axis-aligned boxes (no
       * off-diagonal entry in their inverse Jacobians), so that support()
       * repeats the general path's operations.
       */
      bool
      applies() const
      {
        return exact;
      }

      /**
       * @brief S̄_gp and Ḡ_gp of the point at @p x (in the patch's cell)
       * with the domain s = F diag(l⁰), limited as compute_support() does
       * for a positive @p cpdi_critical_radius: S̄ = 2^-dim Σ_α S_g(x_α),
       * Ḡ = 2^-dim Σ_α S_g(x_α) s⁻ᵀ r_α (seed 001 Eq. cpdi and the matrix
       * form after it).
       *
       * Writes the entries to @p node, @p S and @p G (room for
       * max_support_size each) and returns their number, or 0 when a
       * corner is in no cell of the patch (compute_support() reports it).
       */
      DEAL_II_ALWAYS_INLINE unsigned int
      support(const GridTransfer<dim> &transfer,
              const Point<dim>        &x,
              const Tensor<2, dim>    &F,
              const Tensor<1, dim>    &l0,
              const double             cpdi_critical_radius,
              unsigned int            *node,
              double                  *S,
              Tensor<1, dim>          *G) const
      {
        Tensor<2, dim> s;
        for (unsigned int c = 0; c < dim; ++c)
          for (unsigned int j = 0; j < dim; ++j)
            s[c][j] = F[c][j] * l0[j];
        if (cpdi_critical_radius > 0)
          limit_cpdi_domain(s, cpdi_critical_radius * smallest_extent);
        const Tensor<2, dim> s_inverse_transpose = transpose(invert(s));
        const double         weight              = 1.0 / n_nodes; // 2^-dim
        Tensor<1, dim>       w;
        return merge_corners(
          transfer,
          x,
          s,
          node,
          [&](const unsigned int, const Tensor<1, dim> &r)
            DEAL_II_ALWAYS_INLINE { w = weight * (s_inverse_transpose * r); },
          [&](const double S_corner, const unsigned int entry, const bool first)
            DEAL_II_ALWAYS_INLINE {
              if (first)
                {
                  S[entry] = weight * S_corner;
                  G[entry] = S_corner * w;
                }
              else
                {
                  S[entry] += weight * S_corner;
                  G[entry] += S_corner * w;
                }
            });
      }

      /**
       * @brief The corners x_α = x + s r_α (r_α ∈ {±1}^dim, α = Σ_j bit_j
       * 2^j with bit 0 for −1) located in the patch's cells and their nodes
       * merged by plane slot, in the order of compute_support(): for each α
       * @p corner(α, r_α), then @p entry(N_i(x_α), e, first) for each of the
       * cell's nodes i, with e the node's entry in @p node (written on its
       * first appearance, when first is true). The caller's weights then
       * give S̄, Ḡ (support()) or the axisymmetric S, G, T.
       *
       * @return the number of entries, or 0 when a corner is in no cell of
       * the patch
       */
      template <typename Corner, typename Entry>
      DEAL_II_ALWAYS_INLINE unsigned int
      merge_corners(const GridTransfer<dim> &transfer,
                    const Point<dim>        &x,
                    const Tensor<2, dim>    &s,
                    unsigned int            *node,
                    const Corner            &corner_,
                    const Entry             &entry_) const
      {
        // Entry of each plane slot in this support (none: 0xff).
        unsigned char entry_of_slot[max_support_size];
        std::fill(entry_of_slot, entry_of_slot + max_support_size, 0xff);
        unsigned int count = 0;
        unsigned int hint  = own_column;
        for (unsigned int alpha = 0; alpha < n_nodes; ++alpha)
          {
            Tensor<1, dim> r;
            for (unsigned int j = 0; j < dim; ++j)
              r[j] = ((alpha >> j) & 1) ? 1. : -1.;
            const Point<dim> corner = x + s * r;
            unsigned int     column;
            Point<dim>       xi;
            if (!locate(transfer, corner, hint, column, xi))
              return 0;
            hint = column;
            std::array<double, n_nodes> S_corner;
            GridTransfer<dim>::values(xi, S_corner);
            corner_(alpha, r);
            const ColumnCell &cell_ = cell[column];
            for (unsigned int i = 0; i < n_nodes; ++i)
              {
                const unsigned char slot  = cell_.slot[i];
                const unsigned char entry = entry_of_slot[slot];
                if (entry == 0xff)
                  {
                    entry_of_slot[slot] = count;
                    node[count]         = cell_.local_index[i];
                    entry_(S_corner[i], count, true);
                    ++count;
                  }
                else
                  entry_(S_corner[i], entry, false);
              }
          }
        return count;
      }

    private:
      /** A cell of the patch: what the corners in it read. */
      struct ColumnCell
      {
        /** The diagonal of its inverse Jacobian (1/h_d). */
        double inverse_extent[dim];
        /** Its nodes in vertex order, and their plane slots Σ p_d 4^d. */
        unsigned int  local_index[n_nodes];
        unsigned char slot[n_nodes];
      };

      /**
       * The cell (column Σ c_d 3^d) and reference point of @p corner as
       * GridTransfer::locate() finds them from the cell @p hint: the hint
       * if it holds the corner within 1e-10, else the cell of floor((x −
       * x₀)/h) if it holds it 1e-9 away from its faces, else locate()'s
       * answer. False if the corner is in no cell of the patch.
       */
      DEAL_II_ALWAYS_INLINE bool
      locate(const GridTransfer<dim> &transfer,
             const Point<dim>        &corner,
             const unsigned int       hint,
             unsigned int            &column,
             Point<dim>              &xi) const
      {
        if (has_cell[hint] && reference_point(hint, corner, xi, 1e-10))
          {
            column = hint;
            return true;
          }
        column              = 0;
        unsigned int stride = 1;
        for (unsigned int d = 0; d < dim; ++d, stride *= 3)
          {
            const double t = (corner[d] - plane[d][0]) * inverse_spacing[d];
            if (!(t >= 0 && t < 3)) // (NaN too)
              return locate_in_general(transfer, corner, hint, column, xi);
            column += stride * static_cast<unsigned int>(t);
          }
        if (column != hint && has_cell[column] &&
            reference_point(column, corner, xi, -1e-9))
          return true;
        return locate_in_general(transfer, corner, hint, column, xi);
      }

      /** ξ of @p x in the cell of @p column (GridTransfer::reference_point()'s
       * operations on an axis-aligned box), and whether it lies in [−margin,
       * 1 + margin]^dim. */
      DEAL_II_ALWAYS_INLINE bool
      reference_point(const unsigned int column,
                      const Point<dim>  &x,
                      Point<dim>        &xi,
                      const double       margin) const
      {
        bool         inside = true;
        unsigned int c      = column;
        for (unsigned int d = 0; d < dim; ++d, c /= 3)
          {
            // (0 + ...: the sum from 0 that reference_point() forms, with
            // the exact zeros of the off-diagonal terms.)
            xi[d] =
              0. + cell[column].inverse_extent[d] * (x[d] - plane[d][c % 3]);
            inside = inside && xi[d] >= -margin && xi[d] <= 1 + margin;
          }
        return inside;
      }

      /** GridTransfer::locate() from the hint's cell. */
      bool
      locate_in_general(const GridTransfer<dim> &transfer,
                        const Point<dim>        &corner,
                        const unsigned int       hint,
                        unsigned int            &column,
                        Point<dim>              &xi) const;

      static constexpr unsigned int n_columns = dim == 2 ? 9 : 27;
      /** The patch's cells, at column Σ c_d 3^d (c_d: 0 below the own cell,
       * 1 the own cell's, 2 above). */
      std::array<ColumnCell, n_columns>   cell;
      std::array<bool, n_columns>         has_cell;
      std::array<unsigned int, n_columns> cell_index;
      static constexpr unsigned int       own_column = dim == 2 ? 4 : 13;
      /** Plane coordinates per direction, and 1/h of the own cell. */
      double plane[dim][4];
      double inverse_spacing[dim];
      /** The smallest extent of the own cell (for the critical radius). */
      double smallest_extent = 0;
      bool   exact           = false;
    };

    /** The half-lengths of the GIMP box of a point (uGIMP or cpGIMP). */
    template <int dim>
    Tensor<1, dim>
    gimp_half_lengths(const Type            type,
                      const Tensor<2, dim> &F,
                      const Tensor<1, dim> &l0);
  } // namespace ShapeFunction
} // namespace fmpm

#endif
