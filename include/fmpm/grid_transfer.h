// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_grid_transfer_h
#define fmpm_grid_transfer_h

#include <fmpm/vertex_cells.h>

#include <deal.II/base/geometry_info.h>
#include <deal.II/base/partitioner.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>

#include <array>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The transfer operators of seed 000 for classic (FE_Q(1)) shape
   * functions: S_pi (grid to point values, Eq. 1.1) and G_pi (grid to point
   * gradients, Eq. 2.8) at a point given by its reference coordinates in its
   * cell.
   *
   * Per locally owned and ghost cell it caches the vertices (an axis-aligned
   * box without patches: vertex 0 and the last), the DoFs as global
   * and as local (ghosted vector) indices, whether a hanging-node constraint
   * touches the cell, and for parallelogram/parallelepiped cells the constant
   * inverse Jacobian. The shape functions equal those of FE_Q<dim>(1) with a
   * MappingQ of degree 1 (DoF i sits on vertex i).
   *
   * @tparam dim space dimension
   */
  template <int dim>
  class GridTransfer
  {
  public:
    static constexpr unsigned int n_nodes =
      GeometryInfo<dim>::vertices_per_cell;

    /** The vertex list of a cell that keeps it, and its bounding box
     * (widened by 1e-10 of its size). */
    struct FullVertices
    {
      std::array<Point<dim>, n_nodes> vertex;
      Point<dim>                      box_lower, box_upper;
    };

    /**
     * @brief A cell's vertices: vertex 0 and vertex n_nodes - 1 always,
     * the others only for cells with their full list (not an axis-aligned
     * box, or a run with patches).
     */
    struct Vertices
    {
      Point<dim> first, last;
      /** The full list, or nullptr. */
      const FullVertices *full = nullptr;

      const Point<dim> &
      operator[](const unsigned int i) const
      {
        Assert(i == 0 || i == n_nodes - 1 || full != nullptr,
               ExcMessage("Only vertices 0 and n_nodes - 1 of this cell are "
                          "kept."));
        return i == 0 ? first : (full != nullptr ? full->vertex[i] : last);
      }
    };

    struct CellData
    {
      std::array<unsigned int, n_nodes> local_index;
      Vertices                          vertex;
      Tensor<2, dim>                    inverse_jacobian_transpose;
      bool                              is_affine       = true;
      bool                              has_constraints = false;
      /** Edges parallel to the axes (a box): then lower/upper bound it. */
      bool is_axis_aligned = false;
      /**
       * Locally owned cell whose neighbours (the cells sharing a vertex;
       * fewer than 3^dim at the mesh boundary) are all axis-aligned boxes
       * of its own size without hanging nodes: GIMP's closed forms (seed
       * 001 Eq. gimp_shape) hold around it for boxes inside those cells.
       */
      bool uniform_patch = false;
      /** Bit i set if DoF i is constrained (a hanging node). */
      unsigned char constrained_nodes = 0;
      /** Bit f set if face f (xi_{f/2} = f%2) lies on the mesh boundary
       * (not a periodic face). */
      unsigned char boundary_faces = 0;

      /** Vertex 0 and vertex n_nodes - 1: an axis-aligned box's corners. */
      const Point<dim> &
      lower() const
      {
        return vertex.first;
      }
      const Point<dim> &
      upper() const
      {
        return vertex.last;
      }
    };

    /**
     * @brief Cache the data of every locally owned and ghost cell, and for
     * each locally owned cell its patch (the cell, then the owned or ghost
     * cells sharing a vertex with it, hanging vertices included) unless
     * @p with_patches is false (classic shape functions need none). The
     * patches come from @p vertex_cells when given (the map of the mesh of
     * @p dof_handler), else from a map built here.
     */
    void
    reinit(const DoFHandler<dim>             &dof_handler,
           const AffineConstraints<double>   &constraints,
           const Utilities::MPI::Partitioner &partitioner,
           const bool                         with_patches = true,
           const VertexCells<dim>            *vertex_cells = nullptr);

    /** @brief The global DoF index of node @p i of @p cell. */
    types::global_dof_index
    dof_index(const CellData &cell, const unsigned int i) const
    {
      return partitioner->local_to_global(cell.local_index[i]);
    }

    /** @brief The patch of a locally owned cell (active cell indices). */
    const std::vector<unsigned int> &
    patch(const unsigned int active_cell_index) const
    {
      static const std::vector<unsigned int> none;
      return active_cell_index < patches.size() ? patches[active_cell_index] :
                                                  none;
    }

    /** @brief Where a point was found: its cell and reference point. */
    struct Location
    {
      unsigned int cell = 0;
      Point<dim>   xi;
    };

    enum class LocateStatus
    {
      found,
      /** Beyond the patch of the home cell (and inside the mesh). */
      beyond_patch,
      /** Outside the mesh by more than half a boundary cell. */
      outside_mesh
    };

    /**
     * @brief Find the cell of the patch of @p home_cell that holds @p x,
     * trying @p hint first. A point slightly outside the mesh (up to half
     * a cell across a boundary face) belongs to the boundary cell whose
     * multilinear basis is extended (extrapolated) to it: partition of
     * unity and linear completeness still hold there.
     */
    LocateStatus
    locate(const unsigned int home_cell,
           const Point<dim>  &x,
           const unsigned int hint,
           Location          &location) const;

    /** @brief Whether the cell's map takes @p xi to @p x (non-affine cells:
     * Newton converged). */
    static bool
    maps_to(const CellData &cell, const Point<dim> &xi, const Point<dim> &x);

    /**
     * @brief Whether @p xi lies in the reference cell, up to @p tolerance,
     * or beyond one of the cell's boundary faces by at most @p extension.
     */
    static bool
    contains(const CellData   &cell,
             const Point<dim> &xi,
             const double      tolerance,
             const double      extension)
    {
      for (unsigned int d = 0; d < dim; ++d)
        {
          if (xi[d] < -tolerance &&
              (!(cell.boundary_faces & (1u << (2 * d))) || xi[d] < -extension))
            return false;
          if (xi[d] > 1 + tolerance &&
              (!(cell.boundary_faces & (1u << (2 * d + 1))) ||
               xi[d] > 1 + extension))
            return false;
        }
      return true;
    }

    const CellData &
    cell_data(const unsigned int active_cell_index) const
    {
      return cells[active_cell_index];
    }

    /** @brief S_pi: the nodal shape function values at @p xi. */
    static void
    values(const Point<dim> &xi, std::array<double, n_nodes> &S)
    {
      for (unsigned int i = 0; i < n_nodes; ++i)
        {
          double s = 1;
          for (unsigned int d = 0; d < dim; ++d)
            s *= ((i >> d) & 1) ? xi[d] : 1 - xi[d];
          S[i] = s;
        }
    }

    /** @brief Gradients with respect to the reference coordinates. */
    static void
    reference_gradients(const Point<dim>                    &xi,
                        std::array<Tensor<1, dim>, n_nodes> &dS)
    {
      for (unsigned int i = 0; i < n_nodes; ++i)
        for (unsigned int c = 0; c < dim; ++c)
          {
            double g = 1;
            for (unsigned int d = 0; d < dim; ++d)
              {
                const bool upper = (i >> d) & 1;
                if (d == c)
                  g *= upper ? 1.0 : -1.0;
                else
                  g *= upper ? xi[d] : 1 - xi[d];
              }
            dS[i][c] = g;
          }
    }

    /**
     * @brief S_pi and G_pi at reference point @p xi of a cell.
     */
    static void
    values_and_gradients(const CellData                      &cell,
                         const Point<dim>                    &xi,
                         std::array<double, n_nodes>         &S,
                         std::array<Tensor<1, dim>, n_nodes> &G)
    {
      values(xi, S);
      reference_gradients(xi, G);
      Tensor<2, dim> inverse_jacobian_transpose;
      if (cell.is_affine)
        inverse_jacobian_transpose = cell.inverse_jacobian_transpose;
      else
        {
          // J = Σ_i x_i ⊗ ∇̂N_i of the multilinear map at xi.
          Tensor<2, dim> J;
          for (unsigned int i = 0; i < n_nodes; ++i)
            J += outer_product(cell.vertex[i], G[i]);
          inverse_jacobian_transpose = transpose(invert(J));
        }
      for (unsigned int i = 0; i < n_nodes; ++i)
        G[i] = inverse_jacobian_transpose * G[i];
    }

    /**
     * @brief Reference coordinates of the real point @p x in a cell, from a
     * starting guess @p xi (the point's old reference coordinates): exact
     * for parallelograms/parallelepipeds, Newton iterations of the
     * multilinear map otherwise.
     */
    static DEAL_II_ALWAYS_INLINE Point<dim>
                                 reference_point(const CellData   &cell,
                                                 const Point<dim> &x,
                                                 const Point<dim> &xi)
    {
      // Affine cells: x = x₀ + J ξ inverts in one product (inlined: the
      // particle update calls it for every point).
      if (cell.is_affine)
        {
          Point<dim> xi_affine;
          for (unsigned int c = 0; c < dim; ++c)
            for (unsigned int d = 0; d < dim; ++d)
              xi_affine[c] += cell.inverse_jacobian_transpose[d][c] *
                              (x[d] - cell.vertex[0][d]);
          return xi_affine;
        }
      return reference_point_by_newton(cell, x, xi);
    }

    /** @brief reference_point() on a cell that is not affine: Newton
     * iterations of the multilinear map from @p xi. */
    static Point<dim>
    reference_point_by_newton(const CellData   &cell,
                              const Point<dim> &x,
                              Point<dim>        xi)
    {
      std::array<double, n_nodes>         S;
      std::array<Tensor<1, dim>, n_nodes> dS;
      for (unsigned int iteration = 0; iteration < 8; ++iteration)
        {
          values(xi, S);
          Point<dim> x_xi;
          for (unsigned int i = 0; i < n_nodes; ++i)
            x_xi += S[i] * cell.vertex[i];
          reference_gradients(xi, dS);
          Tensor<2, dim> J;
          for (unsigned int i = 0; i < n_nodes; ++i)
            J += outer_product(cell.vertex[i], dS[i]);
          const Tensor<1, dim> step = invert(J) * (x - x_xi);
          xi += step;
          if (step.norm() < 1e-13)
            break;
        }
      return xi;
    }

    /** @brief Whether @p xi lies in the reference cell. */
    static bool
    is_inside(const Point<dim> &xi)
    {
      for (unsigned int d = 0; d < dim; ++d)
        if (xi[d] < -1e-12 || xi[d] > 1 + 1e-12)
          return false;
      return true;
    }

    /** @brief Whether the data of a cell is cached (owned or ghost cell). */
    bool
    has_cell_data(const unsigned int active_cell_index) const
    {
      return active_cell_index < has_data.size() && has_data[active_cell_index];
    }

    GridTransfer() = default;
    /** Not copyable: the cells point into full_vertices (moves keep it). */
    GridTransfer(const GridTransfer &) = delete;
    GridTransfer &
    operator=(const GridTransfer &) = delete;

  private:
    /** Whether @p x lies in the cell's bounding box (an axis-aligned
     * cell's from lower() and upper(), widened). */
    bool
    in_box(const unsigned int cell, const Point<dim> &x) const;

    std::vector<CellData> cells;
    /** The ghosted vectors' partitioner (local_index <-> DoF index). */
    const Utilities::MPI::Partitioner     *partitioner = nullptr;
    std::vector<bool>                      has_data;
    std::vector<FullVertices>              full_vertices;
    std::vector<std::vector<unsigned int>> patches;
  };
} // namespace fmpm

#endif
