// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_vertex_cells_h
#define fmpm_vertex_cells_h

#include <deal.II/base/array_view.h>
#include <deal.II/grid/tria.h>

#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The active cells around each vertex: the cells of deal.II's
   * GridTools::vertex_to_cell_map() (hanging vertices included: the coarse
   * cell beside a hanging vertex, and in 3D the cells whose edge is split
   * there), in its order (by level, then index), stored as one array of
   * offsets and one of cells instead of a std::set per vertex (20 bytes a
   * vertex in 2D instead of about 300). Built once per mesh change.
   *
   * @tparam dim space dimension
   */
  template <int dim>
  class VertexCells
  {
  public:
    /** A cell by its level and index on that level. */
    struct Cell
    {
      int level;
      int index;
    };

    /** @brief Build the map of the active cells of @p triangulation
     * (artificial cells included, as deal.II's map has them). */
    void
    reinit(const Triangulation<dim> &triangulation);

    /** @brief The cells around vertex @p vertex_index. */
    ArrayView<const Cell>
    operator[](const unsigned int vertex_index) const
    {
      return make_array_view(cells.data() + begin[vertex_index],
                             cells.data() + begin[vertex_index + 1]);
    }

    /** @brief The iterator of @p cell (an active cell). */
    typename Triangulation<dim>::active_cell_iterator
    iterator(const Cell &cell) const
    {
      return typename Triangulation<dim>::active_cell_iterator(triangulation,
                                                               cell.level,
                                                               cell.index);
    }

    /** @brief Bytes held (capacity). */
    std::size_t
    memory_consumption() const
    {
      return begin.capacity() * sizeof(unsigned int) +
             cells.capacity() * sizeof(Cell);
    }

  private:
    const Triangulation<dim> *triangulation = nullptr;
    /** The cells of vertex v are cells[begin[v]] to cells[begin[v+1]]. */
    std::vector<unsigned int> begin;
    std::vector<Cell>         cells;
  };
} // namespace fmpm

#endif
