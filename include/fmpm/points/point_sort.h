// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_points_point_sort_h
#define fmpm_points_point_sort_h

#include <fmpm/grid_transfer.h>
#include <fmpm/material_points.h>
#include <fmpm/vertex_cells.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/tria.h>

#include <array>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The re-sorting of the points that left their cells in a step.
   *
   * The particle update sets the reference positions of the points that
   * stayed in their cells and lists the others (left_cell()). sort() gives
   * each of these the cell that now holds it, searched around its old cell:
   * across the face the point crossed, from neighbour to neighbour, else
   * among the cells around the old cell's vertices. A locally owned cell
   * takes the point in the store (MaterialPoints::move()); a ghost cell's
   * owner receives it in one point-to-point exchange of only these points
   * (MaterialPoints::remove() and add()); the store then puts its points
   * back in cell order (MaterialPoints::rebin()). A point not found nearby
   * makes every rank sort all its points with deal.II instead (the caller,
   * after prepare_full_sort()).
   *
   * Along a periodic direction of the box, a point that crosses a face
   * enters through the opposite one: its position and initial position
   * shift by the box's length (u = x − X and F are kept).
   *
   * @tparam dim space dimension
   */
  template <int dim>
  class PointSort
  {
  public:
    /**
     * @brief Set up for the mesh of @p triangulation (after every mesh
     * change): the cells around each vertex, and the cell data of
     * @p transfer (which must outlive this object; it may be reinitialized
     * after this call with vertex_cells()).
     *
     * @param[in] lower_corner, upper_corner The box's corners (read along
     * the periodic directions only).
     * @param[in] periodic Whether each direction is periodic.
     */
    void
    reinit(const parallel::distributed::Triangulation<dim> &triangulation,
           const GridTransfer<dim>                         &transfer,
           const Point<dim>                                &lower_corner,
           const Point<dim>                                &upper_corner,
           const std::array<bool, dim>                     &periodic);

    /** @brief The active cells around each vertex of the mesh. */
    const VertexCells<dim> &
    vertex_cells() const
    {
      return vertex_to_cells;
    }

    /** @brief Forget the points listed so far (at the particle update's
     * start). */
    void
    clear()
    {
      points_that_left_their_cell.clear();
    }

    /** @brief Point @p k of the store left its cell (listed in store
     * order). */
    void
    left_cell(const unsigned int k)
    {
      points_that_left_their_cell.push_back(k);
    }

    /**
     * @brief Move the listed points into their new cells, on this rank or
     * on the owner of the new cell, and rebin @p points. Collective.
     *
     * @return false if some rank did not find a point's new cell nearby:
     * then no point has moved, and the caller must sort every point with
     * deal.II after prepare_full_sort() (the same answer on every rank).
     */
    bool
    sort(MaterialPoints<dim> &points);

    /** @brief Forget the listed points and bring every point of @p points
     * that crossed a periodic face back through the opposite face, for
     * deal.II's sort of all points. */
    void
    prepare_full_sort(MaterialPoints<dim> &points);

  private:
    /** Shift point @p k and its initial position by @p shift. */
    static void
    shift_point(MaterialPoints<dim>  &points,
                const unsigned int    k,
                const Tensor<1, dim> &shift);

    /** The owned or ghost cell that now holds point @p k, which left
     * @p cell (invalid if not found nearby), and its ξ there. */
    typename Triangulation<dim>::active_cell_iterator
    find_new_cell(MaterialPoints<dim> &points,
                  const unsigned int   k,
                  const typename Triangulation<dim>::active_cell_iterator &cell,
                  Point<dim> &xi) const;

    /** A point that left its cell for an owned cell or another rank's. */
    struct PointMove
    {
      unsigned int                                      k;
      typename Triangulation<dim>::active_cell_iterator cell;
      Point<dim>                                        xi;
    };

    const parallel::distributed::Triangulation<dim> *triangulation = nullptr;
    const GridTransfer<dim>                         *transfer      = nullptr;
    Point<dim>                                       lower_corner, upper_corner;
    /** The box's length along each periodic direction (0 along the
     * others). */
    Tensor<1, dim>            period;
    VertexCells<dim>          vertex_to_cells;
    std::vector<unsigned int> points_that_left_their_cell;
    std::vector<PointMove>    point_moves;
  };
} // namespace fmpm

#endif
