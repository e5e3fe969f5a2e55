// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/material_points.h>

#include <algorithm>
#include <cstring>
#include <numeric>

namespace fmpm
{
  template <int dim>
  void
  MaterialPoints<dim>::initialize(
    const unsigned int               n_properties,
    const std::vector<unsigned int> &zero_slots,
    const std::vector<unsigned int> &invariant_slots)
  {
    position.clear();
    reference_position.clear();
    id.clear();
    cell.clear();
    moved_points.clear();
    columns.assign(n_properties, std::vector<double>());
    zero_slot.assign(n_properties, 0);
    for (const unsigned int s : zero_slots)
      zero_slot[s] = 1;
    invariant_slot.assign(n_properties, 0);
    for (const unsigned int s : invariant_slots)
      invariant_slot[s] = 1;
    uniform_slot = invariant_slot; // (no points yet)
    uniform_value.assign(n_properties, 0.);
    refresh_column_pointers();
    rebuild_cell_ranges();
  }



  template <int dim>
  std::vector<unsigned int>
  MaterialPoints<dim>::invariant_core_slots(const bool axisymmetric)
  {
    using Index                      = PropertyIndex<dim>;
    std::vector<unsigned int> result = {Index::mass,
                                        Index::initial_volume,
                                        Index::material_id,
                                        Index::body_id};
    for (unsigned int d = 0; d < dim; ++d)
      result.push_back(Index::initial_half_length + d);
    // Plane strain: F_33 = 1 (axisymmetric: the hoop stretch, updated by
    // the stress update).
    if (dim == 2 && !axisymmetric)
      result.push_back(Index::deformation_gradient + 8);
    return result;
  }



  namespace
  {
    /** Equal bit for bit (so that −0 and 0 are told apart). */
    bool
    same_value(const double a, const double b)
    {
      return std::memcmp(&a, &b, sizeof(double)) == 0;
    }
  } // namespace



  template <int dim>
  void
  MaterialPoints<dim>::find_uniform_slots()
  {
    for (unsigned int s = 0; s < columns.size(); ++s)
      if (invariant_slot[s] && !zero_slot[s])
        {
          std::vector<double> &values = columns[s];
          uniform_slot[s] =
            std::all_of(values.begin(), values.end(), [&](const double v) {
              return same_value(v, values.front());
            });
          if (uniform_slot[s])
            {
              if (!values.empty())
                uniform_value[s] = values.front();
              std::vector<double>().swap(values);
            }
        }
  }



  template <int dim>
  std::vector<unsigned int>
  MaterialPoints<dim>::plane_strain_zero_slots()
  {
    if (dim == 3)
      return {};
    using Index = PropertyIndex<dim>;
    return {Index::deformation_gradient + 2,
            Index::deformation_gradient + 5,
            Index::deformation_gradient + 6,
            Index::deformation_gradient + 7,
            Index::stress + 4,
            Index::stress + 5};
  }



  template <int dim>
  void
  MaterialPoints<dim>::refresh_column_pointers()
  {
    const std::size_t length = std::max(id.capacity(), id.size());
    if (zeros.size() < id.size())
      zeros.resize(length, 0.);
    // One array per distinct value of the uniform columns (a value 0
    // reads the zeros); arrays of values no column has any more go.
    std::vector<std::pair<double, std::vector<double>>> kept_arrays;
    auto array_of = [&](const double value) -> double * {
      if (same_value(value, 0.))
        return zeros.data();
      for (auto &[kept_value, values] : kept_arrays)
        if (same_value(kept_value, value))
          return values.data();
      for (auto &[old_value, values] : uniform_arrays)
        if (same_value(old_value, value) && !values.empty())
          {
            if (values.size() < id.size())
              values.assign(length, value);
            kept_arrays.emplace_back(value, std::move(values));
            return kept_arrays.back().second.data();
          }
      kept_arrays.emplace_back(value, std::vector<double>(length, value));
      return kept_arrays.back().second.data();
    };
    column_pointers.resize(columns.size());
    for (unsigned int s = 0; s < columns.size(); ++s)
      column_pointers[s] = zero_slot[s]    ? zeros.data() :
                           uniform_slot[s] ? array_of(uniform_value[s]) :
                                             columns[s].data();
    uniform_arrays.swap(kept_arrays);
  }



  template <int dim>
  void
  MaterialPoints<dim>::copy_record(const unsigned int k,
                                   double            *record_values) const
  {
    for (unsigned int s = 0; s < columns.size(); ++s)
      record_values[s] = zero_slot[s]    ? 0. :
                         uniform_slot[s] ? uniform_value[s] :
                                           columns[s][k];
  }



  template <int dim>
  void
  MaterialPoints<dim>::set_cell_order(std::vector<CellIterator> cells,
                                      const unsigned int        n_active_cells)
  {
    cell_key.assign(n_active_cells, numbers::invalid_unsigned_int);
    cell_of_key = std::move(cells);
    for (unsigned int c = 0; c < cell_of_key.size(); ++c)
      cell_key[cell_of_key[c]->active_cell_index()] = c;
    cell_received.assign(cell_of_key.size(), 0);
  }



  template <int dim>
  void
  MaterialPoints<dim>::pull_from(Particles::ParticleHandler<dim> &handler)
  {
    const unsigned int n = handler.n_locally_owned_particles();
    position.clear();
    reference_position.clear();
    id.clear();
    cell.clear();
    moved_points.clear();
    position.reserve(n);
    reference_position.reserve(n);
    id.reserve(n);
    cell.reserve(n);
    for (unsigned int s = 0; s < columns.size(); ++s)
      {
        columns[s].clear();
        if (!zero_slot[s])
          columns[s].reserve(n);
      }
    std::vector<typename Particles::ParticleHandler<dim>::particle_iterator>
      in_cell;
    for (const auto &c : cell_of_key)
      {
        in_cell.clear();
        const auto range = handler.particles_in_cell(c);
        for (auto particle = range.begin(); particle != range.end(); ++particle)
          in_cell.push_back(particle);
        std::sort(in_cell.begin(),
                  in_cell.end(),
                  [](const auto &a, const auto &b) {
                    return a->get_id() < b->get_id();
                  });
        for (const auto &particle : in_cell)
          {
            position.push_back(particle->get_location());
            reference_position.push_back(particle->get_reference_location());
            id.push_back(particle->get_id());
            cell.push_back(c->active_cell_index());
            const auto values = particle->get_properties();
            for (unsigned int s = 0; s < columns.size(); ++s)
              if (!zero_slot[s])
                columns[s].push_back(values[s]);
              else
                Assert(values[s] == 0, ExcInternalError());
          }
      }
    AssertThrow(id.size() == n,
                ExcMessage("The particle handler holds points outside the "
                           "locally owned cells."));
    find_uniform_slots();
    refresh_column_pointers();
    rebuild_cell_ranges();
    handler.clear_particles();
    handler.update_cached_numbers();
  }



  template <int dim>
  void
  MaterialPoints<dim>::reserve(const unsigned int n)
  {
    position.reserve(n);
    reference_position.reserve(n);
    id.reserve(n);
    cell.reserve(n);
    for (unsigned int s = 0; s < columns.size(); ++s)
      if (!zero_slot[s] && !uniform_slot[s])
        columns[s].reserve(n);
  }



  template <int dim>
  void
  MaterialPoints<dim>::push_to(Particles::ParticleHandler<dim> &handler) const
  {
    Assert(handler.n_locally_owned_particles() == 0, ExcInternalError());
    handler.reserve(n_points());
    std::vector<double> record_values(columns.size());
    for (unsigned int c = 0; c < n_cells(); ++c)
      for (unsigned int k = cell_point_begin[c]; k < cell_point_begin[c + 1];
           ++k)
        {
          copy_record(k, record_values.data());
          handler.insert_particle(position[k],
                                  reference_position[k],
                                  id[k],
                                  cell_iterator(c),
                                  make_array_view(record_values));
        }
    handler.update_cached_numbers();
  }



  template <int dim>
  void
  MaterialPoints<dim>::add(const types::particle_index id,
                           const Point<dim>           &x,
                           const Point<dim>           &xi,
                           const CellIterator         &cell,
                           const double               *record_values)
  {
    const unsigned int n_before = n_points();
    position.push_back(x);
    reference_position.push_back(xi);
    this->id.push_back(id);
    this->cell.push_back(cell->active_cell_index());
    for (unsigned int s = 0; s < columns.size(); ++s)
      if (!zero_slot[s])
        {
          if (uniform_slot[s])
            {
              if (n_before == 0)
                uniform_value[s] = record_values[s];
              if (n_before == 0 ||
                  same_value(record_values[s], uniform_value[s]))
                continue;
              // The first other value: the column gets its own array.
              uniform_slot[s] = 0;
              columns[s].reserve(this->id.capacity());
              columns[s].assign(n_before, uniform_value[s]);
            }
          columns[s].push_back(record_values[s]);
        }
    cell_received[key(this->cell.size() - 1)] = 1;
    moved_points.push_back(this->cell.size() - 1);
    any_change_since_rebin = true;
  }



  template <int dim>
  void
  MaterialPoints<dim>::rebin()
  {
    if (!any_change_since_rebin)
      return;
    any_change_since_rebin    = false;
    const unsigned int n      = n_points();
    const unsigned int n_keys = cell_of_key.size();

    // Stable counting sort by the cell's key; removed points are dropped.
    count.assign(n_keys + 1, 0);
    unsigned int n_kept = 0;
    for (unsigned int k = 0; k < n; ++k)
      if (cell[k] != numbers::invalid_unsigned_int)
        {
          ++count[key(k) + 1];
          ++n_kept;
        }
    std::partial_sum(count.begin(), count.end(), count.begin());
    permutation.resize(n_kept);
    {
      std::vector<unsigned int> &next = count; // count[key] = next place
      for (unsigned int k = 0; k < n; ++k)
        if (cell[k] != numbers::invalid_unsigned_int)
          permutation[next[key(k)]++] = k;
    }
    // In the cells that received points: by id (the order of a cell's
    // points is then that of a run that never moved them). count[c] is now
    // the end of cell c's places.
    for (const unsigned int k : moved_points)
      {
        if (cell[k] == numbers::invalid_unsigned_int)
          continue;
        const unsigned int c = key(k);
        if (!cell_received[c])
          continue;
        std::sort(permutation.begin() + (c == 0 ? 0 : count[c - 1]),
                  permutation.begin() + count[c],
                  [this](const unsigned int a, const unsigned int b) {
                    return id[a] < id[b];
                  });
        cell_received[c] = 0;
      }

    // The points that kept their cell keep their order (the store is in
    // cell order, by id in a cell): they shift as runs of consecutive
    // places, by the number of points that left or arrived before them.
    // Only the runs that shift and the points that moved are copied.
    // (point_moved is all zeros between rebins: only the moved points'
    // flags are set and reset.)
    point_moved.resize(n, 0);
    for (const unsigned int k : moved_points)
      point_moved[k] = 1;
    moved_places.clear();
    shifted_runs.clear();
    for (unsigned int to = 0; to < n_kept;)
      {
        const unsigned int from = permutation[to];
        if (point_moved[from])
          {
            moved_places.push_back({{to, from}});
            ++to;
            continue;
          }
        Assert(shifted_runs.empty() || from > shifted_runs.back()[1],
               ExcMessage("The points that kept their cell changed order."));
        unsigned int length = 1;
        while (to + length < n_kept &&
               permutation[to + length] == from + length &&
               !point_moved[from + length])
          ++length;
        if (to != from)
          shifted_runs.push_back({{to, from, length}});
        to += length;
      }
    for (const unsigned int k : moved_points)
      point_moved[k] = 0;
    moved_points.clear();
    // Per array: the moved points' values aside; the runs that shift to
    // lower places in ascending order, those that shift to higher places
    // in descending order (no run then writes a place another run has yet
    // to read); the moved points' values to their places.
    auto apply = [&](auto &values, auto &aside) {
      aside.resize(moved_places.size());
      for (unsigned int i = 0; i < moved_places.size(); ++i)
        aside[i] = values[moved_places[i][1]];
      for (const auto &[to, from, length] : shifted_runs)
        if (to < from)
          {
            if (length < 8)
              for (unsigned int j = 0; j < length; ++j)
                values[to + j] = values[from + j];
            else
              std::copy(values.begin() + from,
                        values.begin() + from + length,
                        values.begin() + to);
          }
      for (auto run = shifted_runs.rbegin(); run != shifted_runs.rend(); ++run)
        {
          const auto &[to, from, length] = *run;
          if (to > from)
            {
              if (length < 8)
                for (unsigned int j = length; j-- > 0;)
                  values[to + j] = values[from + j];
              else
                std::copy_backward(values.begin() + from,
                                   values.begin() + from + length,
                                   values.begin() + to + length);
            }
        }
      for (unsigned int i = 0; i < moved_places.size(); ++i)
        values[moved_places[i][0]] = aside[i];
      values.resize(n_kept);
    };
    apply(position, moved_point_values);
    apply(reference_position, moved_point_values);
    apply(id, moved_ids);
    apply(cell, moved_cells);
    for (unsigned int s = 0; s < columns.size(); ++s)
      if (!zero_slot[s] && !uniform_slot[s])
        apply(columns[s], moved_values);
    // After the points were created or arrived all at once, their work
    // arrays are as long as the store: give the memory back (a step moves
    // a few per cent).
    if (moved_places.size() > n_kept / 4)
      {
        std::vector<std::array<unsigned int, 2>>().swap(moved_places);
        std::vector<double>().swap(moved_values);
        std::vector<Point<dim>>().swap(moved_point_values);
        std::vector<types::particle_index>().swap(moved_ids);
        std::vector<unsigned int>().swap(moved_cells);
        std::vector<unsigned int>().swap(moved_points);
      }
    refresh_column_pointers();
    rebuild_cell_ranges();
  }



  template <int dim>
  void
  MaterialPoints<dim>::rebuild_cell_ranges()
  {
    cell_index.clear();
    cell_point_begin.assign(1, 0);
    for (unsigned int k = 0; k < n_points(); ++k)
      if (k == 0 || cell[k] != cell[k - 1])
        {
          if (k > 0)
            cell_point_begin.push_back(k);
          cell_index.push_back(cell[k]);
        }
    if (n_points() > 0)
      cell_point_begin.push_back(n_points());
  }



  template <int dim>
  std::size_t
  MaterialPoints<dim>::memory_consumption() const
  {
    std::size_t bytes =
      position.capacity() * sizeof(Point<dim>) +
      reference_position.capacity() * sizeof(Point<dim>) +
      id.capacity() * sizeof(types::particle_index) +
      cell.capacity() * sizeof(unsigned int) +
      moved_values.capacity() * sizeof(double) +
      moved_point_values.capacity() * sizeof(Point<dim>) +
      moved_ids.capacity() * sizeof(types::particle_index) +
      moved_cells.capacity() * sizeof(unsigned int) +
      permutation.capacity() * sizeof(unsigned int) +
      moved_points.capacity() * sizeof(unsigned int) +
      point_moved.capacity() * sizeof(char) +
      moved_places.capacity() * sizeof(std::array<unsigned int, 2>) +
      shifted_runs.capacity() * sizeof(std::array<unsigned int, 3>) +
      zeros.capacity() * sizeof(double);
    for (const auto &values : columns)
      bytes += values.capacity() * sizeof(double);
    for (const auto &[value, values] : uniform_arrays)
      bytes += values.capacity() * sizeof(double);
    return bytes;
  }

  template class MaterialPoints<2>;
  template class MaterialPoints<3>;
} // namespace fmpm
