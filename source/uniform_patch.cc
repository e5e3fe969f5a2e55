// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The closed forms of GIMP and CPDI on a uniform patch of axis-aligned
// cells (UniformPatchPlanes, UniformGimpPatch, UniformCpdiPatch of
// shape_function.h): the planes of a cell's patch and where a domain's
// corners lie in it.

#include <fmpm/shape_function.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fmpm
{
  namespace ShapeFunction
  {
    template <int dim>
    void
    UniformPatchPlanes<dim>::reinit(const GridTransfer<dim> &transfer,
                                    const unsigned int       cell_index)
    {
      const auto &own = transfer.cell_data(cell_index);
      for (unsigned int d = 0; d < dim; ++d)
        {
          h[d]        = own.upper()[d] - own.lower()[d];
          plane[d][0] = own.lower()[d] - h[d];
          plane[d][1] = own.lower()[d];
          plane[d][2] = own.upper()[d];
          plane[d][3] = own.upper()[d] + h[d];
        }
      local_index.fill(numbers::invalid_unsigned_int);
      has_cell.fill(false);
      Assert(own.uniform_patch,
             ExcMessage("UniformPatchPlanes needs a uniform patch."));
      for (const unsigned int other : transfer.patch(cell_index))
        {
          const auto  &cell   = transfer.cell_data(other);
          unsigned int column = 0, stride = 1;
          for (unsigned int d = 0; d < dim; ++d, stride *= 3)
            {
              const double centre = 0.5 * (cell.lower()[d] + cell.upper()[d]);
              column += stride * (centre < own.lower()[d] ? 0 :
                                  centre < own.upper()[d] ? 1 :
                                                            2);
            }
          has_cell[column] = true;
          // Each vertex's planes from its coordinates (any vertex order).
          for (unsigned int i = 0; i < GridTransfer<dim>::n_nodes; ++i)
            {
              unsigned int slot = 0;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const double       v = cell.vertex[i][d];
                  const unsigned int p = v < own.lower()[d] - 0.5 * h[d] ? 0 :
                                         v < own.lower()[d] + 0.5 * h[d] ? 1 :
                                         v < own.upper()[d] + 0.5 * h[d] ? 2 :
                                                                           3;
                  plane[d][p]          = v;
                  slot |= p << (2 * d);
                }
              local_index[slot] = cell.local_index[i];
              dof[slot]         = transfer.dof_index(cell, i);
            }
        }
    }



    template <int dim>
    bool
    UniformGimpPatch<dim>::applies(const Point<dim>     &x,
                                   const Tensor<1, dim> &l) const
    {
      unsigned int first[dim], last[dim];
      return columns_if_applies(x, l, first, last);
    }



    template <int dim>
    void
    UniformCpdiPatch<dim>::reinit(const GridTransfer<dim> &transfer,
                                  const unsigned int       cell_index)
    {
      const auto &own = transfer.cell_data(cell_index);
      Assert(own.uniform_patch,
             ExcMessage("UniformCpdiPatch needs a uniform patch."));
      // compute_support()'s h of the critical radius.
      smallest_extent = std::numeric_limits<double>::max();
      for (unsigned int d = 0; d < dim; ++d)
        smallest_extent =
          std::min(smallest_extent, own.upper()[d] - own.lower()[d]);
      double h[dim];
      for (unsigned int d = 0; d < dim; ++d)
        {
          h[d]               = own.upper()[d] - own.lower()[d];
          inverse_spacing[d] = 1. / h[d];
          plane[d][0]        = own.lower()[d] - h[d];
          plane[d][1]        = own.lower()[d];
          plane[d][2]        = own.upper()[d];
          plane[d][3]        = own.upper()[d] + h[d];
        }
      // The plane of each vertex coordinate (any vertex order).
      auto plane_of = [&](const double v, const unsigned int d) {
        return v < own.lower()[d] - 0.5 * h[d] ? 0u :
               v < own.lower()[d] + 0.5 * h[d] ? 1u :
               v < own.upper()[d] + 0.5 * h[d] ? 2u :
                                                 3u;
      };
      const auto &patch = transfer.patch(cell_index);
      for (const unsigned int other : patch)
        for (unsigned int i = 0; i < n_nodes; ++i)
          for (unsigned int d = 0; d < dim; ++d)
            {
              const double v           = transfer.cell_data(other).vertex[i][d];
              plane[d][plane_of(v, d)] = v;
            }

      has_cell.fill(false);
      this->cell_index.fill(numbers::invalid_unsigned_int);
      exact = true;
      for (const unsigned int other : patch)
        {
          const auto  &data   = transfer.cell_data(other);
          unsigned int column = 0, stride = 1;
          for (unsigned int d = 0; d < dim; ++d, stride *= 3)
            {
              const double centre = 0.5 * (data.lower()[d] + data.upper()[d]);
              column += stride * (centre < own.lower()[d] ? 0 :
                                  centre < own.upper()[d] ? 1 :
                                                            2);
            }
          has_cell[column]         = true;
          this->cell_index[column] = other;
          ColumnCell &column_cell  = cell[column];
          // ξ = diag(1/h) (x − x_lower) with the bits of
          // GridTransfer::reference_point(): the inverse Jacobian has no
          // off-diagonal entry and vertex 0 lies on the lower planes.
          unsigned int c = column;
          for (unsigned int d = 0; d < dim; ++d, c /= 3)
            {
              column_cell.inverse_extent[d] =
                data.inverse_jacobian_transpose[d][d];
              exact = exact && data.inverse_jacobian_transpose[d][d] > 0 &&
                      data.vertex[0][d] == plane[d][c % 3];
              for (unsigned int e = 0; e < dim; ++e)
                if (e != d)
                  exact = exact && data.inverse_jacobian_transpose[d][e] == 0;
            }
          for (unsigned int i = 0; i < n_nodes; ++i)
            {
              unsigned int slot = 0;
              for (unsigned int d = 0; d < dim; ++d)
                slot |= plane_of(data.vertex[i][d], d) << (2 * d);
              column_cell.local_index[i] = data.local_index[i];
              column_cell.slot[i]        = slot;
            }
        }
      exact = exact && own.uniform_patch;
    }



    template <int dim>
    bool
    UniformCpdiPatch<dim>::locate_in_general(const GridTransfer<dim> &transfer,
                                             const Point<dim>        &corner,
                                             const unsigned int       hint,
                                             unsigned int            &column,
                                             Point<dim>              &xi) const
    {
      typename GridTransfer<dim>::Location location;
      if (transfer.locate(cell_index[own_column],
                          corner,
                          cell_index[hint],
                          location) != GridTransfer<dim>::LocateStatus::found)
        return false;
      for (unsigned int c = 0; c < n_columns; ++c)
        if (has_cell[c] && cell_index[c] == location.cell)
          {
            column = c;
            xi     = location.xi;
            return true;
          }
      return false;
    }



    template class UniformCpdiPatch<2>;
    template class UniformCpdiPatch<3>;
    template struct UniformPatchPlanes<2>;
    template struct UniformPatchPlanes<3>;
    template class UniformGimpPatch<2>;
    template class UniformGimpPatch<3>;
  } // namespace ShapeFunction
} // namespace fmpm
