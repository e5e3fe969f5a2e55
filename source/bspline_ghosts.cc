// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/bspline_ghosts.h>

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fmpm
{
  namespace BSpline
  {
    template <int dim>
    IndexSet
    VerticesBeyondGhostCells<dim>::index_set(
      const types::global_dof_index n_dofs) const
    {
      IndexSet set(n_dofs);
      set.add_indices(dofs.begin(), dofs.end());
      set.compress();
      return set;
    }



    template <int dim>
    VerticesBeyondGhostCells<dim>
    vertices_beyond_ghost_cells(const DoFHandler<dim> &dof_handler,
                                const IndexSet        &locally_relevant_dofs,
                                const unsigned int     reach,
                                const MPI_Comm         communicator)
    {
      // The box and cell size of the lattice, as Lattice::of_mesh() finds
      // them: lowest, highest (negated) and largest extent, combined.
      std::vector<double> combined(3 * dim, std::numeric_limits<double>::max());
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const BoundingBox<dim> box = cell->bounding_box();
            for (unsigned int d = 0; d < dim; ++d)
              {
                combined[d] = std::min(combined[d], box.lower_bound(d));
                combined[dim + d] =
                  std::min(combined[dim + d], -box.upper_bound(d));
                combined[2 * dim + d] =
                  std::min(combined[2 * dim + d],
                           box.lower_bound(d) - box.upper_bound(d));
              }
          }
      Utilities::MPI::min(combined, communicator, combined);
      Point<dim>                    lower;
      std::array<double, dim>       h;
      std::array<unsigned int, dim> n_vertices;
      std::size_t                   n_lattice = 1;
      for (unsigned int d = 0; d < dim; ++d)
        {
          lower[d]      = combined[d];
          h[d]          = -combined[2 * dim + d];
          n_vertices[d] = 1 + static_cast<unsigned int>(std::round(
                                (-combined[dim + d] - lower[d]) / h[d]));
          n_lattice *= n_vertices[d];
        }
      // Lattice index of a coordinate, limited to the lattice.
      const auto index_of = [&](const double x, const unsigned int d) {
        const long i = std::lround((x - lower[d]) / h[d]);
        return static_cast<int>(
          std::clamp<long>(i, 0, static_cast<long>(n_vertices[d]) - 1));
      };
      const auto number_of = [&](const std::array<int, dim> &index) {
        std::size_t number = 0, stride = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            number += stride * index[d];
            stride *= n_vertices[d];
          }
        return number;
      };

      // Lattice vertex -> DoF + 1 (0: none), from the owners, gathered.
      const IndexSet owned = dof_handler.locally_owned_dofs();
      std::vector<types::global_dof_index> dof_of_vertex(n_lattice, 0);
      std::array<int, dim>                 index;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const unsigned int v : cell->vertex_indices())
            {
              const types::global_dof_index dof = cell->vertex_dof_index(v, 0);
              if (!owned.is_element(dof))
                continue;
              for (unsigned int d = 0; d < dim; ++d)
                index[d] = index_of(cell->vertex(v)[d], d);
              dof_of_vertex[number_of(index)] = dof + 1;
            }
      Utilities::MPI::max(dof_of_vertex, communicator, dof_of_vertex);

      // The vertices in reach of the owned cells that no held cell has.
      std::vector<std::size_t> numbers;
      const int                r        = static_cast<int>(reach);
      const unsigned int       per_side = 2 * reach + 2;
      unsigned int             n_box    = 1;
      for (unsigned int d = 0; d < dim; ++d)
        n_box *= per_side;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const BoundingBox<dim> box = cell->bounding_box();
            for (unsigned int e = 0; e < n_box; ++e)
              {
                unsigned int rest   = e;
                bool         inside = true;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    const int i = index_of(box.lower_bound(d), d) - r +
                                  static_cast<int>(rest % per_side);
                    rest /= per_side;
                    inside =
                      inside && i >= 0 && i < static_cast<int>(n_vertices[d]);
                    index[d] = i;
                  }
                if (!inside)
                  continue;
                const std::size_t             number = number_of(index);
                const types::global_dof_index dof    = dof_of_vertex[number];
                if (dof > 0 && !locally_relevant_dofs.is_element(dof - 1))
                  numbers.push_back(number);
              }
          }
      std::sort(numbers.begin(), numbers.end());
      numbers.erase(std::unique(numbers.begin(), numbers.end()), numbers.end());

      VerticesBeyondGhostCells<dim>                               result;
      std::vector<std::pair<types::global_dof_index, Point<dim>>> found;
      found.reserve(numbers.size());
      for (const std::size_t number : numbers)
        {
          std::size_t rest = number;
          Point<dim>  x;
          for (unsigned int d = 0; d < dim; ++d)
            {
              x[d] =
                lower[d] + h[d] * static_cast<double>(rest % n_vertices[d]);
              rest /= n_vertices[d];
            }
          found.emplace_back(dof_of_vertex[number] - 1, x);
        }
      std::sort(found.begin(), found.end(), [](const auto &a, const auto &b) {
        return a.first < b.first;
      });
      for (const auto &[dof, x] : found)
        {
          result.dofs.push_back(dof);
          result.positions.push_back(x);
        }
      return result;
    }



    template struct VerticesBeyondGhostCells<2>;
    template struct VerticesBeyondGhostCells<3>;
    template VerticesBeyondGhostCells<2>
    vertices_beyond_ghost_cells(const DoFHandler<2> &,
                                const IndexSet &,
                                const unsigned int,
                                const MPI_Comm);
    template VerticesBeyondGhostCells<3>
    vertices_beyond_ghost_cells(const DoFHandler<3> &,
                                const IndexSet &,
                                const unsigned int,
                                const MPI_Comm);
  } // namespace BSpline
} // namespace fmpm
