// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The time step of seed 000 §2.2 as a list of stages: the strain-update
// scheme (USF, USL±, USAVG±) chooses the list once, at set-up.

#include <fmpm/simulator.h>

namespace fmpm
{
  template <int dim>
  void
  Simulator<dim>::choose_step_stages()
  {
    const StrainUpdateScheme &scheme = parameters.method.strain_update_scheme;
    const bool half = scheme.average; // USAVG±: each stress update Δt/2
    step_stages.clear();
    step_stages.push_back({"extrapolate to the grid", &Simulator::extrapolate});
    if (scheme.update_first)
      step_stages.push_back(
        {half ? "stresses over dt/2 from v" : "stresses from v",
         &Simulator::update_stresses_first});
    step_stages.push_back({"momentum update", &Simulator::update_grid_momenta});
    step_stages.push_back({"grid fields", &Simulator::solve_grid_fields});
    step_stages.push_back({"particle update", &Simulator::update_points});
    if (scheme.update_last && scheme.re_extrapolate)
      step_stages.push_back(
        {"re-extrapolate the momenta", &Simulator::re_extrapolate});
    if (scheme.update_last)
      step_stages.push_back(
        {scheme.re_extrapolate ?
           (half ? "stresses over dt/2 from the new v" :
                   "stresses from the new v") :
           (half ? "stresses over dt/2 from v+" : "stresses from v+"),
         &Simulator::update_stresses_last});
    step_stages.push_back(
      {"sort points into cells", &Simulator::sort_particles_into_cells});
    point_loops.momenta_in_particle_update =
      scheme.update_last && scheme.re_extrapolate;
  }



  template <int dim>
  std::string
  Simulator<dim>::point_loop_description() const
  {
    std::string description =
      "extrapolate to the grid: supports built in its loop";
    if (shape_function == ShapeFunction::Type::classic)
      description += " (computed in each loop on affine cells)";
    if (point_loops.momenta_in_particle_update)
      description += "; re-extrapolate the momenta: in the particle update";
    return description;
  }



  template <int dim>
  void
  Simulator<dim>::do_time_step()
  {
    begin_step();
    // One timer section per stage, named as the run header prints it.
    for (const StepStage &stage : step_stages)
      {
        TimerOutput::Scope timer(computing_timer, stage.name);
        (this->*stage.run)();
      }
    finish_step();
    check_step_failures();
  }



  template <int dim>
  void
  Simulator<dim>::begin_step()
  {
    // Adapt the mesh every 'Mesh refinement/Interval' steps (before the
    // time step, which depends on the smallest cell).
    if (parameters.refinement.adaptive() &&
        parameters.refinement.interval > 0 && control.step_number() > 0 &&
        control.step_number() % parameters.refinement.interval == 0)
      adapt_mesh();
    TimerOutput::Scope timer(computing_timer, "step set-up");
    control.calculate_time_step(control.signal_speed(),
                                control.minimum_cell_size());
    const double t  = control.time();
    const double dt = control.time_step();
    particle_updates.series_step =
      mass_matrix->begin_step(control.step_number(), t, dt);
    // b(x, t) at the middle of the step: second order in time (first order
    // at t^n, measured on the manufactured solution).
    external_loads.begin_step(t + 0.5 * dt);
    centre_of_mass.computed.fill(false);
    for (auto &impulse : reactions.step_impulse)
      impulse = Tensor<1, dim>();
    // Box walls that move and regions in t: their nodes at t.
    if (velocity_conditions.nodes_move())
      velocity_conditions.move_nodes(t);
  }



  template <int dim>
  void
  Simulator<dim>::extrapolate()
  {
    // 1. m = SᵀM, p = SᵀMV and, unless the stresses are updated first, f
    //    from the last stresses (Eqs. 2.14-2.15); the velocity conditions
    //    on p (seed 000 §2.1.1); contact: the conditions on every material
    //    field and the first correction p^α = p^α0 + Δp^α (seed 004 Eq.
    //    26, §3.2).
    const double t = control.time();
    particles_to_grid(!parameters.method.strain_update_scheme.update_first);
    centre_of_mass.momentum_time = t;
    impose_velocity_conditions(centre_of_mass.momentum, t, nullptr);
    if (contact)
      contact->correct_extrapolated_momenta(t, Contact::Stage::extrapolated);
  }



  template <int dim>
  void
  Simulator<dim>::update_stresses_first()
  {
    // 2. USF / USAVG: stresses with v = m̃ₖ⁻¹p (Δt/2 for USAVG), then the
    //    forces in the same sweep.
    using namespace ParticleUpdate;
    const double dt = control.time_step();
    update_stresses(lumped_strain_velocity() ? lumped_velocity : velocity,
                    parameters.method.strain_update_scheme.average ? dt / 2 :
                                                                     dt,
                    true);
  }



  template <int dim>
  void
  Simulator<dim>::update_grid_momenta()
  {
    // 3.-4. p⁺ = p + (f + f^(BC))Δt (Eqs. 2.16, 2.42): the conditions'
    //    forces f^(BC) make p⁺ satisfy them at t + Δt (§2.1.3), and f
    //    includes them. (The velocity method corrects the velocities
    //    instead, §2.1.4.) Contact: p^α0+ = p^α + f^α0Δt (Eq. 30), the
    //    conditions, then the second correction p^α+ = p^α0+ + Δp^α+ (Eq.
    //    31).
    const double dt    = control.time_step();
    const double t_end = control.time() + dt;
    set_scaled_sum(centre_of_mass.updated_momentum,
                   centre_of_mass.momentum,
                   dt,
                   centre_of_mass.force);
    impose_velocity_conditions(centre_of_mass.updated_momentum,
                               t_end,
                               &reactions.step_impulse);
    set_scaled_sum(centre_of_mass.force,
                   centre_of_mass.updated_momentum,
                   -1.,
                   centre_of_mass.momentum,
                   1. / dt);
    if (contact)
      {
        contact->update_momenta(dt, t_end);
        contact->apply(Contact::Stage::updated);
      }
  }



  template <int dim>
  void
  Simulator<dim>::solve_grid_fields()
  {
    // The fields the particle update reads (Table 2.1), each solved once.
    using namespace ParticleUpdate;
    const double dt    = control.time_step();
    const double t_end = control.time() + dt;
    // With contact the points read their material's fields; the centre-of-
    // mass series (m̃ₖ⁻¹ of the total momenta) is then needed only for the
    // grid output that follows this step and the velocity method's
    // reactions.
    const bool measure_reactions     = velocity_method_reactions();
    const bool centre_of_mass_series = !contact || grid_output_follows_step(dt);
    const auto &needed               = active_fields();
    for (unsigned int f = 0; f < n_grid_fields; ++f)
      if ((needed[f] &&
           (centre_of_mass_series || f == lumped_velocity ||
            f == lumped_updated_velocity || f == lumped_acceleration)) ||
          (measure_reactions && (f == updated_velocity || f == velocity)))
        compute_field(static_cast<GridField>(f));
    if (contact)
      for (unsigned int f = 0; f < n_grid_fields; ++f)
        if (needed[f])
          contact->compute_field(static_cast<GridField>(f));
    // Seed 000 Eq. 4.1: f holds the conditions' forces, and the solve sets
    // the known accelerations of the corrected nodes (Δv⁺/Δt).
    if (parameters.output.write_grid_acceleration &&
        grid_output_follows_step(dt))
      compute_field(acceleration);
    // How well v⁺ satisfies the conditions (summary.json).
    if (centre_of_mass.computed[updated_velocity])
      {
        const auto &v = centre_of_mass.fields[updated_velocity];
        for (const auto &c : velocity_conditions.node_conditions())
          if (centre_of_mass.mass.local_element(c.local_index) >
              centre_of_mass.mass_floor)
            {
              double v_n = 0;
              for (unsigned int d = 0; d < dim; ++d)
                v_n += v.block(d).local_element(c.local_index) * c.normal[d];
              reactions.max_condition_error =
                std::max(reactions.max_condition_error,
                         std::abs(v_n - velocity_conditions.value(c, t_end)));
            }
      }
    // Velocity method: f^(b) = m̃ a^(b) with a^(b)Δt = Δv⁺ − Δv, whose sum
    // over nodes is Σ m_j a_j^(b) (columns of m̃ sum to m).
    if (measure_reactions)
      for (unsigned int c = 0;
           c < centre_of_mass.velocity_corrections[1].size();
           ++c)
        {
          const auto  &condition = velocity_conditions.node_conditions()[c];
          const double impulse =
            centre_of_mass.mass.local_element(condition.local_index) *
            (centre_of_mass.velocity_corrections[1][c] -
             centre_of_mass.velocity_corrections[0][c]);
          reactions.step_impulse[condition.source] +=
            impulse * condition.normal;
          velocity_conditions.add_condition_impulse(c, impulse);
        }
  }



  template <int dim>
  void
  Simulator<dim>::update_points()
  {
    // 5. The particle update (Table 2.1).
    update_particles();
    if (parameters.output.track_dissipation)
      {
        energy_balance.dissipated_energy +=
          Utilities::MPI::sum(local_dissipation, mpi_communicator);
        local_dissipation = 0;
      }
  }



  template <int dim>
  void
  Simulator<dim>::re_extrapolate()
  {
    // USL+ / USAVG+: p from the updated points (Eqs. 2.17-2.18) at t + Δt,
    // the conditions, and with contact a third correction.
    using namespace ParticleUpdate;
    const double t_end = control.time() + control.time_step();
    Assert(point_loops.momenta_in_particle_update, ExcInternalError());
    finish_re_extrapolation();
    centre_of_mass.momentum_time = t_end;
    impose_velocity_conditions(centre_of_mass.momentum, t_end, nullptr);
    centre_of_mass.computed[velocity] =
      centre_of_mass.computed[lumped_velocity] = false;
    if (contact)
      contact->correct_extrapolated_momenta(t_end,
                                            Contact::Stage::re_extrapolated);
  }



  template <int dim>
  void
  Simulator<dim>::update_stresses_last()
  {
    // 6. USL- / USAVG-: stresses from v⁺; USL+ / USAVG+: from the
    //    re-extrapolated momenta (Δt/2 for USAVG±). Solves v itself.
    using namespace ParticleUpdate;
    const StrainUpdateScheme &scheme = parameters.method.strain_update_scheme;
    const double              dt     = control.time_step();
    const bool                lumped = lumped_strain_velocity();
    const GridField           v      = scheme.re_extrapolate ?
                                         (lumped ? lumped_velocity : velocity) :
                                         (lumped ? lumped_updated_velocity : updated_velocity);
    update_stresses(v, scheme.average ? dt / 2 : dt);
  }



  template <int dim>
  void
  Simulator<dim>::finish_step()
  {
    TimerOutput::Scope timer(computing_timer, "step end");
    const double       dt = control.time_step();
    // Reaction forces: the impulse each boundary gave in this step over Δt.
    if (!reactions.step_impulse.empty())
      {
        std::vector<double> values;
        for (const auto &impulse : reactions.step_impulse)
          for (unsigned int d = 0; d < dim; ++d)
            values.push_back(impulse[d] / dt);
        Utilities::MPI::sum(values, mpi_communicator, values);
        for (unsigned int s = 0; s < reactions.forces.size(); ++s)
          for (unsigned int d = 0; d < dim; ++d)
            reactions.forces[s][d] = values[s * dim + d];
      }
    // External work: moving walls (reaction · n̂ v(t + Δt/2) Δt) and
    // tractions (Σ F_p · V_p Δt).
    if (external_loads.has_tractions() || !reactions.forces.empty())
      external_loads.add_step_work(
        velocity_conditions.wall_work(reactions.forces, control.time(), dt),
        dt,
        energy_balance.mesh_diameter,
        mpi_communicator);
    velocity_conditions.advance_walls(control.time(), dt);

    control.advance();
    counters.particle_steps += counters.n_material_points;
    if (parameters.refinement.adaptive())
      {
        const unsigned long long n_cells =
          triangulation.n_global_active_cells();
        counters.cell_steps += n_cells;
        counters.max_cells = std::max(counters.max_cells, n_cells);
      }
  }



  template <int dim>
  void
  Simulator<dim>::check_step_failures()
  {
    // Failures found by any rank in this step stop every rank.
    TimerOutput::Scope timer(computing_timer, "failure checks");
    // The largest wave speed and the largest point speed are reduced
    // separately, as one rank finds them: the maximum over ranks of their
    // per-rank sums is smaller when they lie on different ranks, and the
    // time step would then depend on the partition. The checkpoint request
    // (a signal or the wall time, on any rank) takes the same reduction.
    const double flags[5] = {local_failure.empty() ? 0. : 1.,
                             static_cast<double>(lost.n),
                             local_max_wave_speed,
                             local_max_point_speed,
                             static_cast<double>(local_checkpoint_request())};
    double global_flags[5];
    Utilities::MPI::max(make_array_view(flags),
                        mpi_communicator,
                        make_array_view(global_flags));
    control.set_signal_speed(global_flags[2] + global_flags[3]);
    checkpoint_state.request = static_cast<int>(global_flags[4]);
    if (global_flags[0] > 0)
      {
        const auto messages =
          Utilities::MPI::all_gather(mpi_communicator, local_failure);
        const auto failed_points =
          Utilities::MPI::all_gather(mpi_communicator, local_failed_point);
        for (unsigned int rank = 0; rank < messages.size(); ++rank)
          if (!messages[rank].empty())
            throw SimulationFailure(messages[rank],
                                    control.step_number(),
                                    control.time(),
                                    failed_points[rank]);
      }
    if (global_flags[1] > 0)
      {
        const unsigned long long n_lost =
          Utilities::MPI::sum(lost.n, mpi_communicator);
        const auto messages =
          Utilities::MPI::all_gather(mpi_communicator, lost.messages);
        const auto points_lost =
          Utilities::MPI::all_gather(mpi_communicator, lost.points);
        std::string first;
        FailedPoint first_point;
        for (unsigned int rank = 0; rank < messages.size(); ++rank)
          if (!messages[rank].empty() && first.empty())
            {
              first       = messages[rank].front();
              first_point = points_lost[rank].front();
            }
        if (parameters.failure.lost_points ==
            FailureParameters::LostPoints::stop)
          throw SimulationFailure(first + " (" + std::to_string(n_lost) +
                                    " point(s) left the mesh; set Failure "
                                    "detection/Points leaving the mesh = "
                                    "delete to remove them instead)",
                                  control.step_number(),
                                  control.time(),
                                  first_point);
        pcout << "    " << n_lost << " material point(s) left the mesh and "
              << "were deleted; first: " << first << std::endl;
        counters.total_lost_points += n_lost;
        lost.clear();
      }
  }



  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
