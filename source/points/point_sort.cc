// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/neighbour_exchange.h>
#include <fmpm/particle_properties.h>
#include <fmpm/points/point_sort.h>

#include <deal.II/base/array_view.h>
#include <deal.II/grid/cell_id.h>

#include <algorithm>
#include <cstdint>
#include <map>

namespace fmpm
{
  template <int dim>
  void
  PointSort<dim>::reinit(
    const parallel::distributed::Triangulation<dim> &triangulation,
    const GridTransfer<dim>                         &transfer,
    const Point<dim>                                &lower_corner,
    const Point<dim>                                &upper_corner,
    const std::array<bool, dim>                     &periodic)
  {
    this->triangulation = &triangulation;
    this->transfer      = &transfer;
    this->lower_corner  = lower_corner;
    this->upper_corner  = upper_corner;
    period              = Tensor<1, dim>();
    for (unsigned int d = 0; d < dim; ++d)
      if (periodic[d])
        period[d] = upper_corner[d] - lower_corner[d];
    vertex_to_cells.reinit(triangulation);
    points_that_left_their_cell.clear();
  }



  template <int dim>
  void
  PointSort<dim>::shift_point(MaterialPoints<dim>  &points,
                              const unsigned int    k,
                              const Tensor<1, dim> &shift)
  {
    points.position[k] += shift;
    for (unsigned int d = 0; d < dim; ++d)
      points.column(PropertyIndex<dim>::initial_position + d)[k] += shift[d];
  }



  template <int dim>
  void
  PointSort<dim>::prepare_full_sort(MaterialPoints<dim> &points)
  {
    points_that_left_their_cell.clear();
    if (period.norm_square() == 0)
      return;
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        Tensor<1, dim> shift;
        for (unsigned int d = 0; d < dim; ++d)
          if (period[d] > 0)
            {
              const double x = points.position[k][d];
              if (x < lower_corner[d])
                shift[d] = period[d];
              else if (x >= upper_corner[d])
                shift[d] = -period[d];
            }
        if (shift.norm_square() > 0)
          shift_point(points, k, shift);
      }
  }



  template <int dim>
  typename Triangulation<dim>::active_cell_iterator
  PointSort<dim>::find_new_cell(
    MaterialPoints<dim>                                     &points,
    const unsigned int                                       k,
    const typename Triangulation<dim>::active_cell_iterator &cell,
    Point<dim>                                              &xi) const
  {
    Point<dim> center;
    for (unsigned int d = 0; d < dim; ++d)
      center[d] = 0.5;
    const Point<dim> x = points.position[k];

    // Across the face the point crossed, from neighbour to neighbour (a
    // corner takes two steps); where that meets a boundary, a finer
    // neighbour or an artificial cell, the cells around the old cell's
    // vertices. Across a periodic face the walk goes on in the twin cell,
    // with x shifted by the period (x_walk).
    typename Triangulation<dim>::active_cell_iterator target;
    Point<dim>                                        x_walk = x;
    {
      auto       walk    = cell;
      Point<dim> xi_walk = GridTransfer<dim>::reference_point(
        transfer->cell_data(cell->active_cell_index()), x, center);
      for (unsigned int hop = 0; hop <= dim; ++hop)
        {
          unsigned int face = numbers::invalid_unsigned_int;
          for (unsigned int d = 0; d < dim; ++d)
            if (xi_walk[d] < -1e-12 || xi_walk[d] > 1 + 1e-12)
              {
                face = 2 * d + (xi_walk[d] > 1 ? 1 : 0);
                break;
              }
          if (face == numbers::invalid_unsigned_int)
            {
              if (walk != cell)
                {
                  target = walk;
                  xi     = xi_walk;
                }
              break;
            }
          if (walk->at_boundary(face))
            {
              if (!walk->has_periodic_neighbor(face) ||
                  walk->periodic_neighbor(face)->has_children())
                break;
              x_walk[face / 2] += (face % 2 == 1 ? -1. : 1.) * period[face / 2];
              walk = walk->periodic_neighbor(face);
            }
          else if (walk->neighbor(face)->has_children())
            break;
          else
            walk = walk->neighbor(face);
          if (walk->is_artificial())
            break;
          xi_walk = GridTransfer<dim>::reference_point(
            transfer->cell_data(walk->active_cell_index()), x_walk, center);
        }
      if (target.state() == IteratorState::valid && x_walk != x)
        shift_point(points, k, x_walk - x);
    }
    if (target.state() != IteratorState::valid)
      for (const unsigned int v : cell->vertex_indices())
        {
          for (const auto &other : vertex_to_cells[cell->vertex_index(v)])
            {
              const auto candidate = vertex_to_cells.iterator(other);
              if (candidate == cell || candidate->is_artificial())
                continue;
              xi = GridTransfer<dim>::reference_point(
                transfer->cell_data(candidate->active_cell_index()), x, center);
              if (GridTransfer<dim>::is_inside(xi))
                {
                  target = candidate;
                  break;
                }
            }
          if (target.state() == IteratorState::valid)
            break;
        }
    return target;
  }



  template <int dim>
  bool
  PointSort<dim>::sort(MaterialPoints<dim> &points)
  {
    point_moves.clear();
    std::uint64_t n_sent         = 0;
    bool          need_full_sort = false;
    Assert(std::is_sorted(points_that_left_their_cell.begin(),
                          points_that_left_their_cell.end()),
           ExcInternalError());
    unsigned int cell_with_points = 0;
    for (const unsigned int k : points_that_left_their_cell)
      {
        // The points that left are listed in store order: the cell's place
        // follows with a cursor.
        while (points.cell_point_begin[cell_with_points + 1] <= k)
          ++cell_with_points;
        Point<dim>  xi;
        const auto &target =
          find_new_cell(points, k, points.cell_iterator(cell_with_points), xi);
        if (target.state() == IteratorState::valid)
          {
            point_moves.push_back({k, target, xi});
            if (!target->is_locally_owned())
              ++n_sent;
          }
        else
          need_full_sort = true;
      }
    // One reduction: does any rank need the full sort, how many points left
    // their cells and how many their rank, on all ranks (the same decision
    // on every rank).
    const MPI_Comm      communicator    = triangulation->get_communicator();
    const std::uint64_t local_counts[3] = {need_full_sort ? 1u : 0u,
                                           points_that_left_their_cell.size(),
                                           n_sent};
    std::uint64_t global_counts[3] = {0, 0, 0};
    Utilities::MPI::sum(make_array_view(local_counts),
                        communicator,
                        make_array_view(global_counts));
    points_that_left_their_cell.clear();
    if (global_counts[0] != 0)
      return false;
    if (global_counts[1] == 0)
      return true;

    // Per receiving rank, per point: id, x, the new cell's CellId (binary),
    // the properties.
    const unsigned int n_properties = points.n_properties();
    std::map<unsigned int, std::vector<double>> sent;
    for (const PointMove &move : point_moves)
      if (move.cell->is_locally_owned())
        points.move(move.k, move.cell, move.xi);
      else
        {
          std::vector<double> &buffer = sent[move.cell->subdomain_id()];
          buffer.push_back(points.id[move.k]);
          for (unsigned int d = 0; d < dim; ++d)
            buffer.push_back(points.position[move.k][d]);
          for (const unsigned int word :
               move.cell->id().template to_binary<dim>())
            buffer.push_back(word);
          const std::size_t first = buffer.size();
          buffer.resize(first + n_properties);
          points.copy_record(move.k, buffer.data() + first);
          points.remove(move.k);
        }
    // Only the points that change rank travel, to the owners of their new
    // cells. A new cell is owned or a ghost cell, so each rank exchanges
    // one message (empty if no point moves) with each owner of its ghost
    // cells: a neighbour exchange without collectives. With one ghost layer
    // the ghost owners are symmetric (a ghost cell touches an owned cell,
    // so that cell is a ghost cell on the other rank). The full sort covers
    // everything else.
    if (global_counts[2] != 0)
      {
        Point<dim> center;
        for (unsigned int d = 0; d < dim; ++d)
          center[d] = 0.5;
        const std::vector<unsigned int> neighbours(
          triangulation->ghost_owners().begin(),
          triangulation->ghost_owners().end());
        const std::map<unsigned int, std::vector<double>> received =
          neighbour_exchange(communicator,
                             neighbours,
                             neighbours,
                             sent,
                             MPITags::point_exchange);
        const unsigned int record = 1 + dim + 4 + n_properties;
        for (const auto &from_rank : received)
          {
            const std::vector<double> &buffer = from_rank.second;
            AssertDimension(buffer.size() % record, 0);
            for (std::size_t r = 0; r < buffer.size(); r += record)
              {
                const double *const entry = buffer.data() + r;
                Point<dim>          x;
                for (unsigned int d = 0; d < dim; ++d)
                  x[d] = entry[1 + d];
                CellId::binary_type binary;
                for (unsigned int w = 0; w < 4; ++w)
                  binary[w] = static_cast<unsigned int>(entry[1 + dim + w]);
                const typename Triangulation<dim>::active_cell_iterator cell =
                  triangulation->create_cell_iterator(CellId(binary));
                Assert(cell->is_locally_owned(), ExcInternalError());
                const Point<dim> xi = GridTransfer<dim>::reference_point(
                  transfer->cell_data(cell->active_cell_index()), x, center);
                points.add(static_cast<types::particle_index>(entry[0]),
                           x,
                           xi,
                           cell,
                           entry + 1 + dim + 4);
              }
          }
      }
    points.rebin();
    return true;
  }



  template class PointSort<2>;
  template class PointSort<3>;
} // namespace fmpm
