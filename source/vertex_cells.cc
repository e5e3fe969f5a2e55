// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/vertex_cells.h>

#include <algorithm>
#include <utility>

namespace fmpm
{
  template <int dim>
  void
  VertexCells<dim>::reinit(const Triangulation<dim> &triangulation_in)
  {
    triangulation            = &triangulation_in;
    const unsigned int n     = triangulation->n_vertices();
    const auto         order = [](const Cell &a, const Cell &b) {
      return a.level != b.level ? a.level < b.level : a.index < b.index;
    };

    // The cells of each vertex: the active cells are visited by level, then
    // index, so every vertex's list comes out in deal.II's order.
    std::vector<unsigned int>().swap(begin);
    std::vector<Cell>().swap(cells);
    begin.assign(n + 1, 0);
    for (const auto &cell : triangulation->active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        ++begin[cell->vertex_index(v) + 1];
    for (unsigned int v = 0; v < n; ++v)
      begin[v + 1] += begin[v];
    cells.resize(begin[n]);
    {
      std::vector<unsigned int> next(begin.begin(), begin.end() - 1);
      for (const auto &cell : triangulation->active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          cells[next[cell->vertex_index(v)]++] = {cell->level(), cell->index()};
    }

    // Hanging vertices (as GridTools::vertex_to_cell_map): the active
    // neighbour across a face joins the face's vertices, and in 3D a cell
    // joins the middle vertex of each of its split edges. Only the pairs
    // not yet present are kept (repeats among them go when the lists are
    // merged); a mesh of one level has none.
    if (triangulation->n_levels() == 1)
      return;
    std::vector<std::pair<unsigned int, Cell>> extra;
    const auto add = [&](const unsigned int v, const Cell &c) {
      for (unsigned int i = begin[v]; i < begin[v + 1]; ++i)
        if (cells[i].level == c.level && cells[i].index == c.index)
          return;
      extra.emplace_back(v, c);
    };
    for (const auto &cell : triangulation->active_cell_iterators())
      {
        for (const unsigned int f : cell->face_indices())
          if (!cell->at_boundary(f) && cell->neighbor(f)->is_active())
            {
              const auto neighbor = cell->neighbor(f);
              for (unsigned int j = 0; j < cell->face(f)->n_vertices(); ++j)
                add(cell->face(f)->vertex_index(j),
                    {neighbor->level(), neighbor->index()});
            }
        if (dim == 3)
          for (unsigned int l = 0; l < cell->n_lines(); ++l)
            if (cell->line(l)->has_children())
              add(cell->line(l)->child(0)->vertex_index(1),
                  {cell->level(), cell->index()});
      }
    if (extra.empty())
      return;
    std::vector<unsigned int> merged_begin(n + 1, 0);
    for (unsigned int v = 0; v < n; ++v)
      merged_begin[v + 1] = begin[v + 1] - begin[v];
    for (const auto &e : extra)
      ++merged_begin[e.first + 1];
    for (unsigned int v = 0; v < n; ++v)
      merged_begin[v + 1] += merged_begin[v];
    std::vector<Cell>         merged(merged_begin[n]);
    std::vector<unsigned int> next(merged_begin.begin(),
                                   merged_begin.end() - 1);
    for (unsigned int v = 0; v < n; ++v)
      for (unsigned int i = begin[v]; i < begin[v + 1]; ++i)
        merged[next[v]++] = cells[i];
    for (const auto &e : extra)
      merged[next[e.first]++] = e.second;
    // Sorted and without repeats, compacted in place.
    const auto same = [](const Cell &a, const Cell &b) {
      return a.level == b.level && a.index == b.index;
    };
    unsigned int end = 0;
    for (unsigned int v = 0; v < n; ++v)
      {
        const auto first = merged.begin() + merged_begin[v];
        const auto last  = merged.begin() + merged_begin[v + 1];
        std::sort(first, last, order);
        const auto unique_last = std::unique(first, last, same);
        begin[v]               = end;
        end =
          std::move(first, unique_last, merged.begin() + end) - merged.begin();
      }
    begin[n] = end;
    merged.resize(end);
    merged.shrink_to_fit();
    cells.swap(merged);
  }

  template class VertexCells<2>;
  template class VertexCells<3>;
} // namespace fmpm
