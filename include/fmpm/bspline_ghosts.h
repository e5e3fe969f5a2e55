// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_bspline_ghosts_h
#define fmpm_bspline_ghosts_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>

#include <vector>

namespace fmpm
{
  using namespace dealii;

  namespace BSpline
  {
    /**
     * @brief The lattice vertices a rank's points can reach that lie beyond
     * its one layer of ghost cells, with their DoFs: the ghost entries the
     * nodal vectors need for supports that reach two cells beyond a point's
     * cell (b2gimp, b2cpdi). parallel::distributed::Triangulation keeps one
     * layer of ghost cells; instead of a second layer, the ghosted vectors
     * get these DoFs as further ghost indices, so that compress(add) sends
     * their sums to the owners and update_ghost_values() brings the nodal
     * fields back.
     */
    template <int dim>
    struct VerticesBeyondGhostCells
    {
      /** Their positions and DoFs (one per vertex, sorted by DoF). */
      std::vector<Point<dim>>              positions;
      std::vector<types::global_dof_index> dofs;

      /** The DoFs as an IndexSet of the size of the DoFHandler's. */
      IndexSet
      index_set(const types::global_dof_index n_dofs) const;
    };

    /**
     * @brief The vertices within @p reach cells of the locally owned cells
     * of a mesh of equal axis-aligned boxes (per direction: from @p reach
     * below a cell's lower vertex to @p reach above its upper one) whose
     * DoFs are not in @p locally_relevant_dofs.
     *
     * The lattice vertex -> DoF map is gathered once over @p communicator
     * (one global_dof_index per lattice vertex, e.g. 17 MB for 128³
     * cells). A mesh that is not such a lattice gives some set of
     * vertices; BSplineSupports::reinit() refuses that mesh anyway.
     */
    template <int dim>
    VerticesBeyondGhostCells<dim>
    vertices_beyond_ghost_cells(const DoFHandler<dim> &dof_handler,
                                const IndexSet        &locally_relevant_dofs,
                                const unsigned int     reach,
                                const MPI_Comm         communicator);
  } // namespace BSpline
} // namespace fmpm

#endif
