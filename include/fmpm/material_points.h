// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_material_points_h
#define fmpm_material_points_h

#include <fmpm/particle_properties.h>

#include <deal.II/base/point.h>
#include <deal.II/base/types.h>
#include <deal.II/grid/tria.h>
#include <deal.II/particles/particle_handler.h>

#include <array>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The one store of every locally owned material point's state.
   *
   * One contiguous array per quantity: the position x_p, the reference
   * position ξ_p in its cell, the id, the active cell index, and one column
   * per property slot of ParticleProperties (M, V₀, V, F, σ, ... and the
   * slots plugins request). The points are in cell order — the cells in the
   * order of the passes (set_cell_order()), and in a cell by id — so
   * that every sum over points runs in an order that depends neither on the
   * history of the moves nor on the number of ranks.
   *
   * Every pass of the time step reads and writes these arrays by the point's
   * place k. deal.II's ParticleHandler sees the points only at the events
   * that need its parallel machinery — mesh adaptation and repartitioning,
   * checkpoints, and the full sort that finds lost points — through
   * push_to() and pull_from(); between them it holds no point.
   *
   * @tparam dim space dimension
   */
  template <int dim>
  class MaterialPoints
  {
  public:
    using CellIterator = typename Triangulation<dim>::active_cell_iterator;

    /**
     * @brief Set the number of property columns; forget every point.
     *
     * The slots in @p zero_slots are zero for every point (in 2D, plane
     * strain: F_xz, F_yz, F_zx, F_zy, σ_xz, σ_yz): they take no memory,
     * and their columns read as zeros. Nothing may write another value.
     */
    void
    initialize(const unsigned int               n_properties,
               const std::vector<unsigned int> &zero_slots      = {},
               const std::vector<unsigned int> &invariant_slots = {});

    /** @brief The core slots no pass writes after a point is created or
     * arrives: M, V₀, material, body, l₀ and in 2D plane strain F_33 (not
     * @p axisymmetric: there F_33 is the hoop stretch). A column of such a
     * slot whose values are all equal (one material, uniform points) stays
     * so, and rebin() does not permute it. */
    static std::vector<unsigned int>
    invariant_core_slots(const bool axisymmetric);

    /** @brief The slots that are zero in 2D (plane strain): F_xz, F_yz,
     * F_zx, F_zy, σ_xz, σ_yz; none in 3D. */
    static std::vector<unsigned int>
    plane_strain_zero_slots();

    /** @brief Number of points on this rank. */
    unsigned int
    n_points() const
    {
      return id.size();
    }

    /** @brief Number of cells with points. */
    unsigned int
    n_cells() const
    {
      return cell_index.size();
    }

    /** @brief The iterator of the @p c-th cell with points. */
    const CellIterator &
    cell_iterator(const unsigned int c) const
    {
      return cell_of_key[cell_key[cell_index[c]]];
    }

    /** @brief Number of property columns. */
    unsigned int
    n_properties() const
    {
      return columns.size();
    }

    /** @brief The column of property slot @p slot (one value per point;
     * a zero slot's column reads zeros and must not be written). */
    double *
    column(const unsigned int slot)
    {
      return column_pointers[slot];
    }

    const double *
    column(const unsigned int slot) const
    {
      return column_pointers[slot];
    }

    /** @brief The properties of point @p k, addressed by slot. */
    PointRecord
    record(const unsigned int k) const
    {
      return PointRecord{column_pointers.data(), k};
    }

    /** @brief The properties of point @p k as one record (output, MPI). */
    void
    copy_record(const unsigned int k, double *record_values) const;

    /**
     * @brief The order of the cells (the passes' order): a cell's place
     * in @p cells is its key. Call after every mesh change.
     */
    void
    set_cell_order(std::vector<CellIterator> cells,
                   const unsigned int        n_active_cells);

    /**
     * @brief Take every locally owned point of @p handler, in cell order,
     * and empty the handler.
     */
    void
    pull_from(Particles::ParticleHandler<dim> &handler);

    /** @brief Reserve memory for @p n points. */
    void
    reserve(const unsigned int n);

    /** @brief Give every point to the (empty) @p handler. */
    void
    push_to(Particles::ParticleHandler<dim> &handler) const;

    /** @name Re-binning the points that left their cells (one step) */
    /** @{ */
    /** @brief Point @p k now lies in the owned cell @p cell at @p xi. */
    void
    move(const unsigned int k, const CellIterator &cell, const Point<dim> &xi)
    {
      this->cell[k]         = cell->active_cell_index();
      reference_position[k] = xi;
      cell_received[key(k)] = 1;
      moved_points.push_back(k);
      any_change_since_rebin = true;
    }

    /** @brief Point @p k left this rank (it was sent to its new owner). */
    void
    remove(const unsigned int k)
    {
      cell[k]                = numbers::invalid_unsigned_int;
      any_change_since_rebin = true;
    }

    /** @brief A point that arrived from another rank (or is created), in
     * the owned @p cell; rebin() must follow before the columns are read. */
    void
    add(const types::particle_index id,
        const Point<dim>           &x,
        const Point<dim>           &xi,
        const CellIterator         &cell,
        const double               *record_values);

    /**
     * @brief Put the points back in cell order after move(), remove() and
     * add(): one stable counting sort by cell, then by id in the cells that
     * received points; every array follows the one permutation.
     */
    void
    rebin();
    /** @} */

    /** @brief Bytes held (capacity), for the benchmark's memory figure. */
    std::size_t
    memory_consumption() const;

    /** @name Per point, in cell order */
    /** @{ */
    /** x_p. Units: m. */
    std::vector<Point<dim>> position;
    /** ξ_p, the reference coordinates of x_p in its cell. */
    std::vector<Point<dim>> reference_position;
    /** The point's id (unique over ranks, independent of the rank count). */
    std::vector<types::particle_index> id;
    /** Active cell index of the point's cell. */
    std::vector<unsigned int> cell;
    /** @} */

    /** @name Per cell with points, in cell order */
    /** @{ */
    std::vector<unsigned int> cell_index;
    /** The cell's points are [cell_point_begin[c], cell_point_begin[c+1]). */
    std::vector<unsigned int> cell_point_begin;
    /** @} */

  private:
    /** The place of point k's cell in the cell order. */
    unsigned int
    key(const unsigned int k) const
    {
      return cell_key[cell[k]];
    }

    /** Per slot: written only at creation (initialize()), and whether all
     * its values are equal now. A uniform slot has no column of its own:
     * it reads an array of its value, shared by the uniform slots of that
     * value (uniform_arrays; the zeros for 0). */
    std::vector<char>   invariant_slot, uniform_slot;
    std::vector<double> uniform_value;
    std::vector<std::pair<double, std::vector<double>>> uniform_arrays;
    /** uniform_slot of the invariant slots from the values. */
    void
    find_uniform_slots();
    /** Rebuild cell_index and cell_point_begin. */
    void
    rebuild_cell_ranges();

    /** Refresh column_pointers after a column's memory changed. */
    void
    refresh_column_pointers();

    std::vector<std::vector<double>> columns;
    std::vector<double *>            column_pointers;
    /** Whether a slot is always zero, and the zeros its column reads. */
    std::vector<char>   zero_slot;
    std::vector<double> zeros;
    /** By active cell index: the cell's place in the order, and back. */
    std::vector<unsigned int> cell_key;
    std::vector<CellIterator> cell_of_key;
    /** By key: whether the cell received a point since the last rebin. */
    std::vector<char> cell_received;
    bool              any_change_since_rebin = false;
    /** The points move() or add() gave a cell since the last rebin(). */
    std::vector<unsigned int> moved_points;
    /** Work arrays of rebin(), kept between steps: the new place's old
     * place; per old place whether the point moved; the moved points'
     * (new place, old place); the runs of points that kept their cell and
     * shift, (first new place, first old place, length); the moved
     * points' values of one array. */
    std::vector<unsigned int>                permutation, count;
    std::vector<char>                        point_moved;
    std::vector<std::array<unsigned int, 2>> moved_places;
    std::vector<std::array<unsigned int, 3>> shifted_runs;
    std::vector<double>                      moved_values;
    std::vector<Point<dim>>                  moved_point_values;
    std::vector<types::particle_index>       moved_ids;
    std::vector<unsigned int>                moved_cells;
  };
} // namespace fmpm

#endif
