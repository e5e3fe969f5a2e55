// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/grid_transfer.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fmpm
{
  template <int dim>
  void
  GridTransfer<dim>::reinit(const DoFHandler<dim>             &dof_handler,
                            const AffineConstraints<double>   &constraints,
                            const Utilities::MPI::Partitioner &partitioner,
                            const bool                         with_patches,
                            const VertexCells<dim>            *vertex_cells)
  {
    AssertThrow(dof_handler.get_fe().dofs_per_cell == n_nodes,
                ExcMessage("GridTransfer needs an FE_Q(1) DoFHandler."));
    this->partitioner = &partitioner;
    cells.clear();
    cells.resize(dof_handler.get_triangulation().n_active_cells());
    has_data.assign(cells.size(), false);
    full_vertices.clear();
    // Per cell its entry of full_vertices (pointers once the list is
    // complete).
    std::vector<unsigned int>            full_index(cells.size(),
                                         numbers::invalid_unsigned_int);
    std::vector<types::global_dof_index> dofs(n_nodes);
    std::array<Point<dim>, n_nodes>      vertex;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          CellData &data = cells[cell->active_cell_index()];
          has_data[cell->active_cell_index()] = true;
          cell->get_dof_indices(dofs);
          data.has_constraints   = false;
          data.constrained_nodes = 0;
          for (unsigned int i = 0; i < n_nodes; ++i)
            {
              data.local_index[i] = partitioner.global_to_local(dofs[i]);
              vertex[i]           = cell->vertex(i);
              if (constraints.is_constrained(dofs[i]))
                {
                  data.has_constraints = true;
                  data.constrained_nodes |= (1u << i);
                }
            }
          data.vertex.first = vertex[0];
          data.vertex.last  = vertex[n_nodes - 1];
          data.vertex.full  = nullptr;

          // The multilinear map is affine if every vertex is where the
          // affine map through vertices 0, 1, 2 (and 4) puts it.
          Tensor<2, dim> J;
          for (unsigned int d = 0; d < dim; ++d)
            {
              const Tensor<1, dim> edge = vertex[1u << d] - vertex[0];
              for (unsigned int c = 0; c < dim; ++c)
                J[c][d] = edge[c];
            }
          const double scale = std::pow(std::abs(determinant(J)), 1.0 / dim);
          data.is_affine     = true;
          for (unsigned int i = 0; i < n_nodes; ++i)
            {
              Point<dim> affine = vertex[0];
              for (unsigned int d = 0; d < dim; ++d)
                if ((i >> d) & 1)
                  affine += vertex[1u << d] - vertex[0];
              if ((affine - vertex[i]).norm() > 1e-12 * scale)
                data.is_affine = false;
            }
          data.inverse_jacobian_transpose = transpose(invert(J));

          data.is_axis_aligned = data.is_affine;
          for (unsigned int c = 0; c < dim; ++c)
            for (unsigned int d = 0; d < dim; ++d)
              if (c != d && std::abs(J[c][d]) > 1e-12 * scale)
                data.is_axis_aligned = false;
          // (A periodic face is no boundary: the mesh goes on across it.)
          data.boundary_faces = 0;
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary() && !cell->has_periodic_neighbor(f))
              data.boundary_faces |= (1u << f);

          // The full vertex list for the cells that need it: GIMP's
          // patches read every vertex, other cells their bounding box.
          if (with_patches || !data.is_axis_aligned)
            {
              full_index[cell->active_cell_index()] = full_vertices.size();
              full_vertices.emplace_back();
              FullVertices &full = full_vertices.back();
              full.vertex        = vertex;
              full.box_lower     = vertex[0];
              full.box_upper     = vertex[0];
              for (unsigned int i = 1; i < n_nodes; ++i)
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    full.box_lower[d] =
                      std::min(full.box_lower[d], vertex[i][d]);
                    full.box_upper[d] =
                      std::max(full.box_upper[d], vertex[i][d]);
                  }
              const double margin =
                1e-10 * (full.box_upper - full.box_lower).norm();
              for (unsigned int d = 0; d < dim; ++d)
                {
                  full.box_lower[d] -= margin;
                  full.box_upper[d] += margin;
                }
            }
        }
    full_vertices.shrink_to_fit();
    for (unsigned int c = 0; c < cells.size(); ++c)
      if (full_index[c] != numbers::invalid_unsigned_int)
        cells[c].vertex.full = &full_vertices[full_index[c]];

    // Patches: the cell first, then the other cells around its vertices
    // (deal.II's vertex-to-cell map includes the coarse cells next to
    // hanging vertices).
    patches.clear();
    if (!with_patches)
      return;
    patches.resize(cells.size());
    VertexCells<dim> own_vertex_cells;
    if (vertex_cells == nullptr)
      {
        own_vertex_cells.reinit(dof_handler.get_triangulation());
        vertex_cells = &own_vertex_cells;
      }
    for (const auto &cell :
         dof_handler.get_triangulation().active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int         index = cell->active_cell_index();
          std::vector<unsigned int> &patch = patches[index];
          patch.push_back(index);
          for (const unsigned int v : cell->vertex_indices())
            for (const auto &other : (*vertex_cells)[cell->vertex_index(v)])
              {
                const auto neighbor = vertex_cells->iterator(other);
                if (!neighbor->is_artificial() &&
                    std::find(patch.begin(),
                              patch.end(),
                              neighbor->active_cell_index()) == patch.end())
                  patch.push_back(neighbor->active_cell_index());
              }

          // Uniform patch: axis-aligned cells of this cell's size without
          // hanging nodes (3^dim of them, fewer at the mesh boundary).
          CellData &data    = cells[index];
          bool      uniform = data.is_axis_aligned && !data.has_constraints;
          for (const unsigned int other : patch)
            {
              const CellData &o = cells[other];
              if (!o.is_axis_aligned || o.has_constraints)
                uniform = false;
              for (unsigned int d = 0; d < dim; ++d)
                if (std::abs((o.upper()[d] - o.lower()[d]) -
                             (data.upper()[d] - data.lower()[d])) >
                    1e-12 * (data.upper()[d] - data.lower()[d]))
                  uniform = false;
            }
          data.uniform_patch = uniform;
        }
  }



  template <int dim>
  bool
  GridTransfer<dim>::maps_to(const CellData   &cell,
                             const Point<dim> &xi,
                             const Point<dim> &x)
  {
    // Newton's iterations of reference_point may stop early for points far
    // from a non-affine cell: check the multilinear map.
    if (cell.is_affine)
      return true;
    std::array<double, n_nodes> S;
    values(xi, S);
    Point<dim> x_xi;
    for (unsigned int i = 0; i < n_nodes; ++i)
      x_xi += S[i] * cell.vertex[i];
    return (x_xi - x).norm() <=
           1e-10 * (cell.vertex[n_nodes - 1] - cell.vertex[0]).norm();
  }



  template <int dim>
  typename GridTransfer<dim>::LocateStatus
  GridTransfer<dim>::locate(const unsigned int home_cell,
                            const Point<dim>  &x,
                            const unsigned int hint,
                            Location          &location) const
  {
    constexpr double tolerance = 1e-10;
    // Half a cell beyond a boundary face: further out is an error.
    constexpr double extension = 0.5;
    Point<dim>       center;
    for (unsigned int d = 0; d < dim; ++d)
      center[d] = 0.5;
    if (has_cell_data(hint) && in_box(hint, x))
      {
        const Point<dim> xi = reference_point(cells[hint], x, center);
        if (contains(cells[hint], xi, tolerance, 0) &&
            maps_to(cells[hint], xi, x))
          {
            location.cell = hint;
            location.xi   = xi;
            return LocateStatus::found;
          }
      }
    const std::vector<unsigned int> &candidates = patch(home_cell);
    // Cells that hold x, then boundary cells whose extended basis reaches x.
    for (const double reach : {0., extension})
      for (const unsigned int c : candidates)
        if ((c != hint || reach > 0) &&
            (reach > 0 ? cells[c].boundary_faces != 0 : in_box(c, x)))
          {
            const Point<dim> xi = reference_point(cells[c], x, center);
            if (contains(cells[c], xi, tolerance, reach) &&
                maps_to(cells[c], xi, x))
              {
                location.cell = c;
                location.xi   = xi;
                return LocateStatus::found;
              }
          }
    for (const unsigned int c : candidates)
      if (contains(cells[c],
                   reference_point(cells[c], x, center),
                   tolerance,
                   std::numeric_limits<double>::max()))
        return LocateStatus::outside_mesh;
    return LocateStatus::beyond_patch;
  }

  template <int dim>
  bool
  GridTransfer<dim>::in_box(const unsigned int cell, const Point<dim> &x) const
  {
    const CellData &data = cells[cell];
    if (data.vertex.full != nullptr)
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (x[d] < data.vertex.full->box_lower[d] ||
              x[d] > data.vertex.full->box_upper[d])
            return false;
        return true;
      }
    // An axis-aligned box: contains() decides within 1e-10 of its size, so
    // any wider margin gives the same cells.
    double margin = 0;
    for (unsigned int d = 0; d < dim; ++d)
      margin += data.upper()[d] - data.lower()[d];
    margin *= 1e-10;
    for (unsigned int d = 0; d < dim; ++d)
      if (x[d] < data.lower()[d] - margin || x[d] > data.upper()[d] + margin)
        return false;
    return true;
  }



  template class GridTransfer<2>;
  template class GridTransfer<3>;
} // namespace fmpm
