// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/simulator.h>
#include <fmpm/simulator_access.h>

namespace fmpm
{
  template <int dim>
  MPI_Comm
  SimulatorAccess<dim>::get_mpi_communicator() const
  {
    return get_simulator().mpi_communicator;
  }

  template <int dim>
  const ConditionalOStream &
  SimulatorAccess<dim>::get_pcout() const
  {
    return get_simulator().pcout;
  }

  template <int dim>
  const Parameters &
  SimulatorAccess<dim>::get_parameters() const
  {
    return get_simulator().parameters;
  }

  template <int dim>
  const parallel::distributed::Triangulation<dim> &
  SimulatorAccess<dim>::get_triangulation() const
  {
    return get_simulator().triangulation;
  }

  template <int dim>
  const DoFHandler<dim> &
  SimulatorAccess<dim>::get_dof_handler() const
  {
    return get_simulator().dof_handler;
  }

  template <int dim>
  const AffineConstraints<double> &
  SimulatorAccess<dim>::get_constraints() const
  {
    return get_simulator().constraints;
  }

  template <int dim>
  const MaterialPoints<dim> &
  SimulatorAccess<dim>::get_material_points() const
  {
    return get_simulator().points;
  }

  template <int dim>
  const ParticleProperties<dim> &
  SimulatorAccess<dim>::get_particle_properties() const
  {
    return get_simulator().particle_properties;
  }

  template <int dim>
  const GridScalar &
  SimulatorAccess<dim>::get_lumped_mass() const
  {
    return get_simulator().centre_of_mass.mass;
  }

  template <int dim>
  const TrilinosWrappers::SparseMatrix &
  SimulatorAccess<dim>::get_full_mass_matrix() const
  {
    return get_simulator().centre_of_mass.full_mass_matrix;
  }

  template <int dim>
  const std::vector<GridScalar> &
  SimulatorAccess<dim>::get_known_velocity_mask() const
  {
    return get_simulator().centre_of_mass.known_velocity_mask;
  }

  template <int dim>
  const std::vector<GridScalar> &
  SimulatorAccess<dim>::get_known_velocity_values() const
  {
    return get_simulator().centre_of_mass.known_velocity_value;
  }

  template <int dim>
  const std::function<void(GridVectorField &)> &
  SimulatorAccess<dim>::get_padding_mirror() const
  {
    return get_simulator().centre_of_mass.padding_mirror;
  }

  template <int dim>
  double
  SimulatorAccess<dim>::get_time() const
  {
    return get_simulator().control.time();
  }

  template <int dim>
  double
  SimulatorAccess<dim>::get_timestep() const
  {
    return get_simulator().control.time_step();
  }

  template <int dim>
  unsigned int
  SimulatorAccess<dim>::get_timestep_number() const
  {
    return get_simulator().control.step_number();
  }

  template <int dim>
  double
  SimulatorAccess<dim>::get_momentum_time() const
  {
    return get_simulator().centre_of_mass.momentum_time;
  }



  template <int dim>
  FieldSolver<dim>
  SimulatorAccess<dim>::get_field_solver() const
  {
    return get_simulator().field_solver();
  }

  template <int dim>
  double
  SimulatorAccess<dim>::get_mass_floor() const
  {
    return get_simulator().centre_of_mass.mass_floor;
  }

  template <int dim>
  bool
  SimulatorAccess<dim>::has_hanging_nodes() const
  {
    return get_simulator().has_hanging_nodes;
  }

  template <int dim>
  ShapeFunction::Type
  SimulatorAccess<dim>::get_shape_function_type() const
  {
    return get_simulator().shape_function;
  }

  template <int dim>
  const SupportCache<dim> &
  SimulatorAccess<dim>::get_support_cache() const
  {
    return get_simulator().supports;
  }

  template <int dim>
  const GridTransfer<dim> &
  SimulatorAccess<dim>::get_grid_transfer() const
  {
    return get_simulator().transfer;
  }

  template <int dim>
  const VelocityConditions<dim> &
  SimulatorAccess<dim>::get_velocity_conditions() const
  {
    return get_simulator().velocity_conditions;
  }

  template <int dim>
  const MassMatrix::Interface<dim> &
  SimulatorAccess<dim>::get_mass_matrix() const
  {
    return *get_simulator().mass_matrix;
  }

  template <int dim>
  TimerOutput &
  SimulatorAccess<dim>::get_computing_timer() const
  {
    return get_simulator().computing_timer;
  }

  template <int dim>
  const CellwiseMatrix *
  SimulatorAccess<dim>::get_cellwise_full_mass_matrix() const
  {
    const GridState<dim> &state = get_simulator().centre_of_mass;
    return state.use_cellwise_full_mass ? &state.cellwise_full_mass : nullptr;
  }

  template <int dim>
  const GridVectorField &
  SimulatorAccess<dim>::get_grid_field(
    const ParticleUpdate::GridField field) const
  {
    return get_simulator().centre_of_mass.fields[field];
  }

  template <int dim>
  const std::vector<HistoryRow<dim>> &
  SimulatorAccess<dim>::get_history() const
  {
    return get_simulator()
      .postprocessors.template find<Postprocess::HistoryFile<dim>>()
      ->rows();
  }

  template <int dim>
  const std::vector<Tensor<1, dim>> &
  SimulatorAccess<dim>::get_reaction_forces() const
  {
    return get_simulator().reactions.forces;
  }

  template <int dim>
  unsigned int
  SimulatorAccess<dim>::n_mesh_adaptations() const
  {
    return get_simulator().counters.mesh_adaptations;
  }

  template <int dim>
  GlobalStatistics<dim>
  SimulatorAccess<dim>::compute_statistics() const
  {
    return get_simulator().compute_statistics();
  }

  template class SimulatorAccess<2>;
  template class SimulatorAccess<3>;
} // namespace fmpm
