// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Adaptive background meshes: refinement that follows the material points,
// the material boundary or the Kelly indicator of the grid velocity; the
// transfer of the points through refinement and coarsening; load balancing
// weighted by the points per cell (deal.II step-68).

#include <fmpm/simulator.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/numerics/error_estimator.h>

namespace fmpm
{
  template <int dim>
  unsigned int
  Simulator<dim>::cell_weight(
    const typename parallel::distributed::Triangulation<dim>::cell_iterator
                                                 &cell,
    const typename Triangulation<dim>::CellStatus status) const
  {
    const unsigned int point_weight = parameters.refinement.point_weight;
    unsigned int       n_points     = 0;
    switch (status)
      {
        case Triangulation<dim>::CELL_PERSIST:
          n_points = particle_handler.n_particles_in_cell(cell);
          break;
        case Triangulation<dim>::CELL_REFINE:
          // Called for each child with the parent: share its points.
          n_points = (particle_handler.n_particles_in_cell(cell) +
                      GeometryInfo<dim>::max_children_per_cell - 1) /
                     GeometryInfo<dim>::max_children_per_cell;
          break;
        case Triangulation<dim>::CELL_COARSEN:
          for (const auto &child : cell->child_iterators())
            n_points += particle_handler.n_particles_in_cell(child);
          break;
        default:
          break;
      }
    return 1 + point_weight * n_points;
  }



  template <int dim>
  bool
  Simulator<dim>::mark_cells()
  {
    const MeshRefinementParameters &refinement = parameters.refinement;
    using Strategy              = MeshRefinementParameters::Strategy;
    const Strategy     strategy = refinement.strategy;
    const unsigned int n_cells  = triangulation.n_active_cells();

    // Cells to be at the maximum level (the others may coarsen), by active
    // cell index; used by the two material strategies.
    std::vector<bool>                    in_region(n_cells, false);
    std::vector<types::global_dof_index> dofs(fe.dofs_per_cell);

    // Mark the nodes of the cells in @p cells in @p nodes (ghosted result).
    GridScalar nodes(centre_of_mass.mass.get_partitioner());
    auto       mark_nodes = [&](const std::vector<bool> &cells) {
      nodes = 0;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() && cells[cell->active_cell_index()])
          {
            cell->get_dof_indices(dofs);
            for (const auto dof : dofs)
              nodes(dof) += 1;
          }
      nodes.compress(VectorOperation::add);
      nodes.update_ghost_values();
    };
    auto touches_marked_node = [&](const auto &cell) {
      cell->get_dof_indices(dofs);
      for (const auto dof : dofs)
        if (nodes(dof) > 0)
          return true;
      return false;
    };

    if (strategy == Strategy::material_points ||
        strategy == Strategy::material_boundary)
      {
        std::vector<bool> has_points(n_cells, false);
        for (const unsigned int c : points.cell_index)
          has_points[c] = true;
        if (strategy == Strategy::material_points)
          in_region = has_points;
        else
          {
            // Cells around a node shared by a cell with points and one
            // without.
            std::vector<bool> empty(n_cells, false);
            for (const auto &cell : triangulation.active_cell_iterators())
              if (cell->is_locally_owned())
                empty[cell->active_cell_index()] =
                  !has_points[cell->active_cell_index()];
            mark_nodes(empty);
            // (The copy holds the owned values only: update its ghosts.)
            GridScalar near_empty(nodes);
            near_empty.update_ghost_values();
            mark_nodes(has_points);
            for (const auto &cell : dof_handler.active_cell_iterators())
              if (cell->is_locally_owned())
                {
                  cell->get_dof_indices(dofs);
                  for (const auto dof : dofs)
                    if (nodes(dof) > 0 && near_empty(dof) > 0)
                      in_region[cell->active_cell_index()] = true;
                }
          }
        // Buffer layers of vertex neighbours.
        for (unsigned int layer = 0; layer < refinement.buffer_layers; ++layer)
          {
            mark_nodes(in_region);
            for (const auto &cell : dof_handler.active_cell_iterators())
              if (cell->is_locally_owned() && touches_marked_node(cell))
                in_region[cell->active_cell_index()] = true;
          }

        for (const auto &cell : triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const unsigned int level = cell->level();
              if (in_region[cell->active_cell_index()])
                {
                  if (level < refinement.maximum_level)
                    cell->set_refine_flag();
                  else if (level > refinement.maximum_level)
                    cell->set_coarsen_flag();
                }
              else if (level > refinement.minimum_level)
                cell->set_coarsen_flag();
            }
      }
    else if (strategy == Strategy::kelly)
      {
        // The lumped grid velocity m⁻¹p, continuous across hanging nodes
        // (supports of the points on the current mesh).
        particles_to_grid(false);
        centre_of_mass.allocate(ParticleUpdate::lumped_velocity);
        GridVectorField &v =
          centre_of_mass.fields[ParticleUpdate::lumped_velocity];
        MassMatrix::apply_lumped_inverse(centre_of_mass.mass,
                                         centre_of_mass.momentum,
                                         v,
                                         centre_of_mass.mass_floor);
        for (unsigned int d = 0; d < dim; ++d)
          {
            if (has_hanging_nodes)
              constraints.distribute(v.block(d));
            v.block(d).update_ghost_values();
          }
        centre_of_mass.computed.fill(false);
        Vector<float> indicator(n_cells), component(n_cells);
        const std::map<types::boundary_id, const Function<dim> *> no_neumann;
        for (unsigned int d = 0; d < dim; ++d)
          {
            component = 0;
            KellyErrorEstimator<dim>::estimate(mapping,
                                               dof_handler,
                                               QGauss<dim - 1>(2),
                                               no_neumann,
                                               v.block(d),
                                               component);
            for (unsigned int c = 0; c < n_cells; ++c)
              indicator[c] += component[c] * component[c];
          }
        parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(
          triangulation,
          indicator,
          refinement.refine_fraction,
          refinement.coarsen_fraction);
        for (const auto &cell : triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const unsigned int level = cell->level();
              if (level >= refinement.maximum_level)
                cell->clear_refine_flag();
              if (level <= refinement.minimum_level)
                cell->clear_coarsen_flag();
            }
      }

    // deal.II's smoothing (2:1 balance, whole families for coarsening)
    // drops flags that cannot take effect; no flag left means no change.
    triangulation.prepare_coarsening_and_refinement();
    bool any_flag = false;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned() &&
          (cell->refine_flag_set() || cell->coarsen_flag_set()))
        any_flag = true;
    return Utilities::MPI::max(any_flag ? 1u : 0u, mpi_communicator) > 0;
  }



  template <int dim>
  void
  Simulator<dim>::setup_after_mesh_change()
  {
    setup_dofs();
    mass_matrix->initialize();
    setup_boundary_conditions();
    centre_of_mass.computed.fill(false);
  }



  template <int dim>
  bool
  Simulator<dim>::adapt_mesh()
  {
    TimerOutput::Scope timer(computing_timer, "mesh adaptation");
    if (!mark_cells())
      return false;
    triangulation.prepare_coarsening_and_refinement();
    points_to_handler();
    particle_handler.prepare_for_coarsening_and_refinement();
    triangulation.execute_coarsening_and_refinement();
    particle_handler.unpack_after_coarsening_and_refinement();
    setup_after_mesh_change();
    points_from_handler();
    ++counters.mesh_adaptations;
    // A fixed time step must stay stable on the new smallest cell.
    const std::string unstable = control.time_step_rule().check_fixed_time_step(
      control.signal_speed(), control.minimum_cell_size(), true);
    if (!unstable.empty())
      throw SimulationFailure(unstable, control.step_number(), control.time());
    return true;
  }



  template <int dim>
  void
  Simulator<dim>::adapt_initial_mesh()
  {
    // Each pass refines the cells holding points (or flagged otherwise) by
    // one level; the points are then created anew in the finer cells, so
    // that 'Points per cell' holds in the cells the material fills.
    const unsigned int max_passes = parameters.refinement.maximum_level + 1;
    for (unsigned int pass = 0; pass < max_passes; ++pass)
      {
        if (!mark_cells())
          break;
        // The points are created anew in the finer cells.
        points.initialize(particle_properties.n_properties(),
                          MaterialPoints<dim>::plane_strain_zero_slots(),
                          MaterialPoints<dim>::invariant_core_slots(
                            parameters.axisymmetric));
        triangulation.prepare_coarsening_and_refinement();
        triangulation.execute_coarsening_and_refinement();
        setup_after_mesh_change();
        create_material_points();
        compute_mass_floor();
      }
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
