// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/axisymmetric_shape_function.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <limits>
#include <sstream>

namespace fmpm
{
  namespace ShapeFunction
  {
    namespace Axisymmetric
    {
      namespace
      {
        /** Add S, G and T of node i of a cell, summing repeated nodes
         * (inlined: CPDI calls it for the 4 nodes of each of 4 corners). */
        DEAL_II_ALWAYS_INLINE inline void
        add_node(std::vector<Node>                        &support,
                 const GridTransfer<2>                    &transfer,
                 const typename GridTransfer<2>::CellData &cell,
                 const unsigned int                        i,
                 const double                              S,
                 const Tensor<1, 2>                       &G,
                 const double                              T)
        {
          for (auto &node : support)
            if (node.local_index == cell.local_index[i])
              {
                node.S += S;
                node.G += G;
                node.T += T;
                return;
              }
          support.push_back(Node{cell.local_index[i],
                                 transfer.dof_index(cell, i),
                                 ((cell.constrained_nodes >> i) & 1) != 0,
                                 S,
                                 G,
                                 T});
        }

        /**
         * S, G, T of the cut box over the cells of the patch of @p home:
         * on each piece box ∩ cell (axis-aligned cells) a 2x3 Gauss rule
         * (3 points in r: N_i r is quadratic in r and linear in z there, so
         * the rule is exact). The pieces must cover the box.
         */
        Status
        gimp_quadrature(const GridTransfer<2> &transfer,
                        const unsigned int     home,
                        const Point<2>        &x,
                        const Tensor<1, 2>    &l,
                        std::vector<Node>     &support)
        {
          const double lo[2] = {std::max(x[0] - l[0], 0.0), x[1] - l[1]};
          const double hi[2] = {x[0] + l[0], x[1] + l[1]};
          // ∫ r dA over the box.
          const double r_area =
            0.5 * (hi[0] * hi[0] - lo[0] * lo[0]) * (hi[1] - lo[1]);
          const double box_area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
          // Gauss-Legendre on [0, 1]: 3 points in r, 2 in z.
          constexpr double            r_point[3]  = {0.5 - 0.3872983346207417,
                                                     0.5,
                                                     0.5 + 0.3872983346207417};
          constexpr double            r_weight[3] = {5. / 18, 8. / 18, 5. / 18};
          constexpr double            z_point[2]  = {0.5 - 0.28867513459481287,
                                                     0.5 + 0.28867513459481287};
          double                      covered     = 0;
          std::array<double, 4>       N;
          std::array<Tensor<1, 2>, 4> dN;
          for (const unsigned int index : transfer.patch(home))
            {
              const auto &cell = transfer.cell_data(index);
              double      a[2], b[2];
              bool        overlaps = true;
              for (unsigned int d = 0; d < 2; ++d)
                {
                  // A boundary cell's basis extends half a cell beyond the
                  // mesh (as GridTransfer::locate()): a box that pokes out
                  // of the mesh by less is integrated there.
                  const double half = 0.5 * (cell.upper()[d] - cell.lower()[d]);
                  const double lower =
                    cell.lower()[d] -
                    ((cell.boundary_faces >> (2 * d)) & 1 ? half : 0.);
                  const double upper =
                    cell.upper()[d] +
                    ((cell.boundary_faces >> (2 * d + 1)) & 1 ? half : 0.);
                  a[d]     = std::max(lo[d], lower);
                  b[d]     = std::min(hi[d], upper);
                  overlaps = overlaps && b[d] > a[d];
                }
              if (!overlaps)
                continue;
              if (!cell.is_axis_aligned)
                return Status::needs_axis_aligned_cells;
              covered += (b[0] - a[0]) * (b[1] - a[1]);
              double                      S[4] = {}, T[4] = {};
              std::array<Tensor<1, 2>, 4> G;
              for (unsigned int i = 0; i < 3; ++i)
                for (unsigned int j = 0; j < 2; ++j)
                  {
                    const Point<2> y(a[0] + r_point[i] * (b[0] - a[0]),
                                     a[1] + z_point[j] * (b[1] - a[1]));
                    const double   w =
                      r_weight[i] * 0.5 * (b[0] - a[0]) * (b[1] - a[1]);
                    GridTransfer<2>::values_and_gradients(
                      cell,
                      GridTransfer<2>::reference_point(cell, y, Point<2>()),
                      N,
                      dN);
                    for (unsigned int k = 0; k < 4; ++k)
                      {
                        S[k] += w * N[k] * y[0];
                        G[k] += (w * y[0]) * dN[k];
                        T[k] += w * N[k];
                      }
                  }
              for (unsigned int k = 0; k < 4; ++k)
                {
                  // Nodes at r < 0 are dropped (their weights vanish).
                  if ((k & 1 ? cell.upper()[0] : cell.lower()[0]) < 0)
                    continue;
                  add_node(support,
                           transfer,
                           cell,
                           k,
                           S[k] / r_area,
                           G[k] / r_area,
                           T[k] / r_area);
                }
            }
          if (covered < box_area * (1 - 1e-12))
            {
              support.clear();
              return Status::beyond_neighbors;
            }
          return Status::ok;
        }

        Status
        status_of(const GridTransfer<2>::LocateStatus s)
        {
          return s == GridTransfer<2>::LocateStatus::outside_mesh ?
                   Status::outside_mesh :
                   Status::beyond_neighbors;
        }
      } // namespace



      bool
      UniformGimpPatch::columns_if_applies(const Point<2>     &x,
                                           const Tensor<1, 2> &l,
                                           unsigned int (&first)[2],
                                           unsigned int (&last)[2]) const
      {
        for (unsigned int d = 0; d < 2; ++d)
          {
            if (l[d] > 0.5 * h[d] || x[d] < plane[d][1] || x[d] > plane[d][2])
              return false;
            // In r the box is cut at the axis.
            const double lo = d == 0 ? std::max(x[d] - l[d], 0.0) : x[d] - l[d];
            const double hi = x[d] + l[d];
            if (!(hi > lo))
              return false;
            first[d] = 3;
            last[d]  = 0;
            for (unsigned int c = 0; c < 3; ++c)
              if (plane[d][c] < hi && plane[d][c + 1] > lo)
                {
                  first[d] = std::min(first[d], c);
                  last[d]  = c + 1;
                }
          }
        for (unsigned int c0 = first[0]; c0 < last[0]; ++c0)
          for (unsigned int c1 = first[1]; c1 < last[1]; ++c1)
            if (!has_cell[c0 + 3 * c1])
              return false;
        return true;
      }



      Status
      compute_support(const Type             type,
                      const GridTransfer<2> &transfer,
                      const unsigned int     cell_index,
                      const Point<2>        &x,
                      const Tensor<2, 2>    &F,
                      const Tensor<1, 2>    &l0,
                      std::vector<Node>     &support,
                      const bool             allow_closed_form)
      {
        using Transfer = GridTransfer<2>;
        support.clear();
        std::array<double, 4>       N;
        std::array<Tensor<1, 2>, 4> dN;
        Transfer::Location          location;
        switch (type)
          {
            case Type::classic:
              {
                if (!(x[0] > 0))
                  return Status::on_axis;
                const auto s =
                  transfer.locate(cell_index, x, cell_index, location);
                if (s != Transfer::LocateStatus::found)
                  return status_of(s);
                const auto &cell = transfer.cell_data(location.cell);
                Transfer::values_and_gradients(cell, location.xi, N, dN);
                for (unsigned int i = 0; i < 4; ++i)
                  add_node(
                    support, transfer, cell, i, N[i], dN[i], N[i] / x[0]);
                return Status::ok;
              }

            case Type::cpdi:
              {
                if (!(x[0] > 0))
                  return Status::on_axis;
                Tensor<2, 2> s;
                for (unsigned int c = 0; c < 2; ++c)
                  for (unsigned int j = 0; j < 2; ++j)
                    s[c][j] = F[c][j] * l0[j];
                keep_cpdi_domain_off_axis(x[0], s);
                std::array<double, 4>       w;
                std::array<Tensor<1, 2>, 4> g;
                double                      t;
                cpdi_corner_weights(x[0], s, w, g, t);
                unsigned int hint = cell_index;
                for (unsigned int alpha = 0; alpha < 4; ++alpha)
                  {
                    Tensor<1, 2> r;
                    r[0]                  = (alpha & 1) ? 1. : -1.;
                    r[1]                  = (alpha & 2) ? 1. : -1.;
                    const Point<2> corner = x + s * r;
                    const auto     found =
                      transfer.locate(cell_index, corner, hint, location);
                    if (found != Transfer::LocateStatus::found)
                      return status_of(found);
                    hint             = location.cell;
                    const auto &cell = transfer.cell_data(location.cell);
                    Transfer::values(location.xi, N);
                    for (unsigned int i = 0; i < 4; ++i)
                      add_node(support,
                               transfer,
                               cell,
                               i,
                               w[alpha] * N[i],
                               N[i] * g[alpha],
                               t * N[i]);
                  }
                return Status::ok;
              }

            case Type::ugimp:
            case Type::cpgimp:
              {
                const Tensor<1, 2> l = gimp_half_lengths<2>(type, F, l0);
                if (!(x[0] + l[0] > 0))
                  return Status::on_axis;
                if (!allow_closed_form ||
                    !transfer.cell_data(cell_index).uniform_patch)
                  return gimp_quadrature(transfer, cell_index, x, l, support);
                UniformGimpPatch patch;
                patch.reinit(transfer, cell_index);
                // (A box beyond the patch's cells, e.g. out of the mesh:
                // the quadrature.)
                if (!patch.for_each_node_if_applies(
                      x,
                      l,
                      [&](const unsigned int            local,
                          const types::global_dof_index dof,
                          const double                  S,
                          const Tensor<1, 2>           &G,
                          const double                  T) {
                        support.push_back(Node{local, dof, false, S, G, T});
                      }))
                  return gimp_quadrature(transfer, cell_index, x, l, support);
                return Status::ok;
              }

            case Type::b2spline:
            case Type::b3spline:
            case Type::b2gimp:
            case Type::b2cpdi:
              Assert(false,
                     ExcMessage("Axisymmetric B-splines are refused at set-up "
                                "(Geometry = axisymmetric)."));
              break;
          }
        return Status::ok;
      }



      void
      check_mesh(const parallel::TriangulationBase<2> &triangulation,
                 const std::string                    &where)
      {
        double smallest_r = std::numeric_limits<double>::max();
        double largest_h  = 0;
        for (const auto &cell : triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              for (const unsigned int v : cell->vertex_indices())
                smallest_r = std::min(smallest_r, cell->vertex(v)[0]);
              largest_h = std::max(largest_h, cell->diameter());
            }
        smallest_r =
          Utilities::MPI::min(smallest_r, triangulation.get_communicator());
        largest_h =
          Utilities::MPI::max(largest_h, triangulation.get_communicator());
        std::ostringstream message;
        message << where
                << " = axisymmetric: the mesh reaches r = " << smallest_r
                << " < 0 (x is the radius r, y the axial coordinate z). "
                   "Allowed: meshes at r >= 0 that start on the axis r = 0 "
                   "(on a grid line) or beyond it.";
        AssertThrow(smallest_r >= -1e-12 * largest_h,
                    ExcMessage(message.str()));
      }
    } // namespace Axisymmetric
  }   // namespace ShapeFunction
} // namespace fmpm
