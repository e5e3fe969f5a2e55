// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/grid_transfer.h>

#include <cmath>

namespace fmpm
{
  template <int dim>
  void
  GridTransfer<dim>::reinit(const DoFHandler<dim>             &dof_handler,
                            const AffineConstraints<double>   &constraints,
                            const Utilities::MPI::Partitioner &partitioner)
  {
    AssertThrow(dof_handler.get_fe().dofs_per_cell == n_nodes,
                ExcMessage("GridTransfer needs an FE_Q(1) DoFHandler."));
    cells.clear();
    cells.resize(dof_handler.get_triangulation().n_active_cells());
    has_data.assign(cells.size(), false);
    std::vector<types::global_dof_index> dofs(n_nodes);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          CellData &data = cells[cell->active_cell_index()];
          has_data[cell->active_cell_index()] = true;
          cell->get_dof_indices(dofs);
          data.has_constraints = false;
          for (unsigned int i = 0; i < n_nodes; ++i)
            {
              data.dof_index[i]   = dofs[i];
              data.local_index[i] = partitioner.global_to_local(dofs[i]);
              data.vertex[i]      = cell->vertex(i);
              if (constraints.is_constrained(dofs[i]))
                data.has_constraints = true;
            }

          // The multilinear map is affine if every vertex is where the
          // affine map through vertices 0, 1, 2 (and 4) puts it.
          Tensor<2, dim> J;
          for (unsigned int d = 0; d < dim; ++d)
            {
              const Tensor<1, dim> edge = data.vertex[1u << d] - data.vertex[0];
              for (unsigned int c = 0; c < dim; ++c)
                J[c][d] = edge[c];
            }
          const double scale = std::pow(std::abs(determinant(J)), 1.0 / dim);
          data.is_affine     = true;
          for (unsigned int i = 0; i < n_nodes; ++i)
            {
              Point<dim> affine = data.vertex[0];
              for (unsigned int d = 0; d < dim; ++d)
                if ((i >> d) & 1)
                  affine += data.vertex[1u << d] - data.vertex[0];
              if ((affine - data.vertex[i]).norm() > 1e-12 * scale)
                data.is_affine = false;
            }
          data.inverse_jacobian_transpose = transpose(invert(J));
        }
  }

  template class GridTransfer<2>;
  template class GridTransfer<3>;
} // namespace fmpm
