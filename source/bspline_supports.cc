// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The B-spline shape functions on the mesh: the lattice and vertex map of
// a uniform box mesh, the vertices a cell's points can reach, the messages
// of a failed support (the per-point supports are inline in
// bspline_supports.h).

#include <fmpm/bspline_supports.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace fmpm
{
  namespace BSpline
  {
    template <int dim>
    void
    VertexMap<dim>::add(const Lattice<dim>              &lattice,
                        const std::vector<Point<dim>>   &positions,
                        const std::vector<unsigned int> &local_indices)
    {
      AssertDimension(positions.size(), local_indices.size());
      if (positions.empty())
        return;
      std::vector<std::array<int, dim>> indices(positions.size());
      int                               new_first[dim], new_last[dim];
      for (unsigned int d = 0; d < dim; ++d)
        {
          new_first[d] =
            count[d] > 0 ? first[d] : std::numeric_limits<int>::max();
          new_last[d] = count[d] > 0 ? first[d] + int(count[d]) - 1 :
                                       std::numeric_limits<int>::min();
        }
      for (unsigned int v = 0; v < positions.size(); ++v)
        for (unsigned int d = 0; d < dim; ++d)
          {
            const Basis1D &basis = lattice.basis(d);
            indices[v][d]        = static_cast<int>(std::round(
              (positions[v][d] - basis.vertex(0)) / basis.cell_size()));
            new_first[d]         = std::min(new_first[d], indices[v][d]);
            new_last[d]          = std::max(new_last[d], indices[v][d]);
          }
      // The dense box grows to hold them: copy the old entries over.
      unsigned int new_count[dim];
      std::size_t  size = 1;
      for (unsigned int d = 0; d < dim; ++d)
        {
          new_count[d] = new_last[d] - new_first[d] + 1;
          size *= new_count[d];
        }
      std::vector<unsigned int> new_local(size, numbers::invalid_unsigned_int);
      const auto                entry = [&](const std::array<int, dim> &index) {
        std::size_t e = 0, stride = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            e += stride * (index[d] - new_first[d]);
            stride *= new_count[d];
          }
        return e;
      };
      for (std::size_t e = 0; e < local.size(); ++e)
        {
          std::array<int, dim> index;
          std::size_t          rest = e;
          for (unsigned int d = 0; d < dim; ++d)
            {
              index[d] = first[d] + static_cast<int>(rest % count[d]);
              rest /= count[d];
            }
          new_local[entry(index)] = local[e];
        }
      for (unsigned int v = 0; v < positions.size(); ++v)
        new_local[entry(indices[v])] = local_indices[v];
      for (unsigned int d = 0; d < dim; ++d)
        {
          first[d] = new_first[d];
          count[d] = new_count[d];
        }
      local.swap(new_local);
    }



    template void
    VertexMap<2>::add(const Lattice<2> &,
                      const std::vector<Point<2>> &,
                      const std::vector<unsigned int> &);
    template void
    VertexMap<3>::add(const Lattice<3> &,
                      const std::vector<Point<3>> &,
                      const std::vector<unsigned int> &);
  } // namespace BSpline



  namespace ShapeFunction
  {
    template <int dim>
    void
    BSplineSupports<dim>::reinit(const Type               type,
                                 const BSpline::Boundary  boundary,
                                 const GridTransfer<dim> &transfer,
                                 const unsigned int       n_active_cells,
                                 const MPI_Comm           communicator)
    {
      kind = Kind::none;
      if (!is_bspline(type))
        return;
      std::string error;
      lattice = BSpline::Lattice<dim>::of_mesh(transfer,
                                               n_active_cells,
                                               type == Type::b3spline ? 3 : 2,
                                               boundary,
                                               communicator,
                                               error);
      AssertThrow(error.empty(),
                  ExcMessage("Shape function/Type = " + parameter_name(type) +
                             ": " + error +
                             ". Use a Mesh/Type = box without refinement, or "
                             "another shape function."));
      vertices.reinit(lattice, transfer, n_active_cells);
      smallest_cell = std::numeric_limits<double>::max();
      for (unsigned int d = 0; d < dim; ++d)
        {
          half_cell[d]  = 0.5 * lattice.basis(d).cell_size() * (1 + 1e-12);
          smallest_cell = std::min(smallest_cell, lattice.basis(d).cell_size());
        }
      kind = type == Type::b2gimp ? Kind::gimp :
             type == Type::b2cpdi ? Kind::cpdi :
                                    Kind::values;
    }



    template <int dim>
    void
    BSplineSupports<dim>::vertices_in_reach(
      const typename GridTransfer<dim>::CellData &cell,
      std::vector<unsigned int>                  &local_indices) const
    {
      local_indices.clear();
      const int            r = static_cast<int>(reach());
      std::array<int, dim> first, index;
      unsigned int         n = 1;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const BSpline::Basis1D &basis = lattice.basis(d);
          first[d] =
            static_cast<int>(std::round((cell.lower()[d] - basis.vertex(0)) /
                                        basis.cell_size())) -
            r;
          n *= 2 * r + 2;
        }
      for (unsigned int e = 0; e < n; ++e)
        {
          unsigned int rest = e;
          for (unsigned int d = 0; d < dim; ++d)
            {
              index[d] = first[d] + static_cast<int>(rest % (2 * r + 2));
              rest /= 2 * r + 2;
            }
          const unsigned int local = vertices.local_index(index);
          if (local != numbers::invalid_unsigned_int)
            local_indices.push_back(local);
        }
    }



    template <int dim>
    const char *
    BSplineSupports<dim>::explain(const Status status)
    {
      switch (status)
        {
          case Status::in_padding_layer:
            return "is in the padding layer of the B-spline lattice (the "
                   "outer layer of cells, which 'Shape function/B-spline "
                   "boundary = padding' keeps free of points): enlarge the "
                   "mesh by a cell on each side or use 'open knots'";
          case Status::vertex_not_on_rank:
            return "needs a lattice vertex on no cell this MPI rank holds "
                   "(one layer of ghost cells)";
          case Status::domain_too_wide:
            return "has a domain wider than B-spline GIMP/CPDI supports "
                   "hold (half-lengths above half a cell, or CPDI corners "
                   "more than a cell from the point): use more Points per "
                   "cell or a Shape function/CPDI critical radius of at most "
                   "1";
          default:
            return "has no B-spline support";
        }
    }



    template class BSplineSupports<2>;
    template class BSplineSupports<3>;
  } // namespace ShapeFunction
} // namespace fmpm
