// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The run loop and the MPM time step of seed 000 §2.2.

#include <fmpm/simulator.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_tools.h>

#include <cmath>
#include <filesystem>
#include <iomanip>

namespace fmpm
{
  template <int dim>
  Simulator<dim>::Simulator(const Parameters &parameters_in,
                            ParameterHandler &prm,
                            MPI_Comm          mpi_communicator_in)
    : mpi_communicator(mpi_communicator_in)
    , parameters(parameters_in)
    , pcout(std::cout,
            Utilities::MPI::this_mpi_process(mpi_communicator) == 0 &&
              !parameters.test_mode)
    // Rank 0's timings (no MPI communicator: an error during set-up must not
    // leave the timer waiting for other ranks).
    , computing_timer(pcout,
                      (parameters.timer_type == "none" ||
                       parameters.test_mode) ?
                        TimerOutput::never :
                        TimerOutput::summary,
                      TimerOutput::wall_times)
    , triangulation(mpi_communicator)
    , mapping(1)
    , fe(1)
    , dof_handler(triangulation)
    , tout(std::cout,
           Utilities::MPI::this_mpi_process(mpi_communicator) == 0 &&
             parameters.test_mode)
  {
    wall_start = MPI_Wtime();
    TimerOutput::Scope timer(computing_timer, "setup");
    shape_function = ShapeFunction::parse(parameters.method.shape_function);
    make_grid();
    setup_plugins(prm);
    setup_dofs();
    mass_matrix->initialize();
    particle_handler.initialize(triangulation,
                                mapping,
                                particle_properties.n_properties());
    particle_handler.signals.particle_lost.connect(
      [this](const typename Particles::ParticleIterator<dim> &particle,
             const typename Triangulation<dim>::active_cell_iterator &) {
        ++n_lost_points;
        if (lost_point_messages.size() < 10)
          {
            std::ostringstream message;
            const auto         properties = particle->get_properties();
            message << "material point " << particle->get_id() << " of Body "
                    << static_cast<unsigned int>(
                         properties[PropertyIndex<dim>::body_id])
                    << " left the mesh at position ("
                    << particle->get_location() << ") at time " << time;
            lost_point_messages.push_back(message.str());
          }
      });
    create_material_points();
    setup_boundary_conditions();

    // Nodes with less than a tiny fraction of a typical point mass are empty.
    double min_point_mass = std::numeric_limits<double>::max();
    for (const auto &particle : particle_handler)
      min_point_mass =
        std::min(min_point_mass,
                 particle.get_properties()[PropertyIndex<dim>::mass]);
    mass_floor_value =
      1e-12 * Utilities::MPI::min(min_point_mass, mpi_communicator);

    max_signal_speed = compute_max_signal_speed();
    check_scene();
  }



  template <int dim>
  Simulator<dim>::~Simulator()
  {
    particle_handler.clear();
  }



  template <int dim>
  double
  Simulator<dim>::compute_max_signal_speed() const
  {
    using Index  = PropertyIndex<dim>;
    double speed = 0;
    for (const auto &particle : particle_handler)
      {
        const auto         p = particle.get_properties();
        const double       J = p[Index::volume] / p[Index::initial_volume];
        const unsigned int material =
          static_cast<unsigned int>(p[Index::material_id]);
        const double c = constitutive_models[material]->wave_speed(
          parameters.materials[material].density, J);
        speed = std::max(speed, c + get_vector<dim>(p, Index::velocity).norm());
      }
    return Utilities::MPI::max(speed, mpi_communicator);
  }



  template <int dim>
  double
  Simulator<dim>::compute_time_step() const
  {
    double dt = parameters.time.time_step;
    if (dt == 0)
      dt =
        parameters.time.courant_number * minimum_cell_size / max_signal_speed;
    // Do not step past the end time (avoid a tiny last step by splitting the
    // rest evenly when it is less than two steps).
    const double rest = parameters.time.end_time - time;
    if (rest < dt * (1 + 1e-12))
      dt = rest;
    else if (rest < 2 * dt)
      dt = rest / 2;
    return dt;
  }



  template <int dim>
  void
  Simulator<dim>::run()
  {
    const bool is_root =
      Utilities::MPI::this_mpi_process(mpi_communicator) == 0;
    if (is_root)
      std::filesystem::create_directories(parameters.output.directory);
    history.open(parameters.output.directory + "/history.csv",
                 is_root,
                 parameters.reference.enable,
                 parameters.output.track_dissipation);

    pcout << "fmpm: " << dim << "D, "
          << Utilities::MPI::n_mpi_processes(mpi_communicator)
          << " MPI rank(s), " << triangulation.n_global_active_cells()
          << " cells, " << dof_handler.n_dofs() << " nodes, "
          << particle_handler.n_global_particles() << " material points, "
          << "particle update '" << parameters.method.particle_update
          << "', mass matrix '" << parameters.method.mass_matrix
          << "', strain update '" << parameters.method.strain_update << "'"
          << std::endl
          << "      output in " << parameters.output.directory << std::endl;

    try
      {
        GlobalStatistics<dim> statistics = compute_statistics();
        initial_total_energy             = statistics.total_energy();
        {
          double g = 0;
          for (unsigned int d = 0; d < dim; ++d)
            g += parameters.gravity[d] * parameters.gravity[d];
          const double diameter = GridTools::diameter(triangulation);
          initial_energy_scale =
            std::max({statistics.kinetic_energy + statistics.strain_energy,
                      statistics.mass * std::sqrt(g) * diameter,
                      1e-300});
        }
        output_results(statistics);
        print_progress(statistics, true);

        const double end = parameters.time.end_time;
        while (time < end * (1 - 1e-12) &&
               timestep_number < parameters.time.max_steps)
          {
            do_time_step();

            const bool output_now = is_output_step();
            const bool progress_now =
              Utilities::MPI::broadcast(mpi_communicator,
                                        MPI_Wtime() - last_progress_wall >
                                          parameters.output.progress_seconds,
                                        0);
            if (output_now || progress_now || time >= end * (1 - 1e-12))
              {
                statistics = compute_statistics();
                check_energy(statistics);
                if (output_now || time >= end * (1 - 1e-12))
                  output_results(statistics);
                if (progress_now)
                  print_progress(statistics, false);
              }
          }
        statistics = compute_statistics();
        print_progress(statistics, true);
        print_test_particles();
        write_summary("completed", nullptr, statistics);
      }
    catch (const SimulationFailure &failure)
      {
        pcout << std::endl
              << "*** The run failed at step " << failure.step << ", time "
              << failure.time << ":" << std::endl
              << "    " << failure.what() << std::endl;
        tout << "FAILED at step " << failure.step << ": " << failure.what()
             << std::endl;
        const GlobalStatistics<dim> statistics = compute_statistics();
        write_summary(std::string("failed: ") + failure.what(),
                      &failure,
                      statistics);
        throw;
      }
  }



  template <int dim>
  bool
  Simulator<dim>::is_output_step()
  {
    const OutputParameters &output = parameters.output;
    if (output.interval > 0)
      {
        if (time >= next_output_time * (1 - 1e-12))
          return true;
        return false;
      }
    const unsigned int every = std::max(1u, output.step_interval);
    return timestep_number % every == 0;
  }



  template <int dim>
  void
  Simulator<dim>::do_time_step()
  {
    using namespace ParticleUpdate;
    const std::string &strain_update = parameters.method.strain_update;
    const bool         update_first =
      (strain_update == "usf" || strain_update == "usavg" ||
       strain_update == "usavg+");
    const bool update_last = (strain_update != "usf");
    const bool re_extrapolate =
      (strain_update == "usl+" || strain_update == "usavg+");
    const bool average =
      (strain_update == "usavg" || strain_update == "usavg+");
    const bool lumped_strain_velocity =
      (parameters.method.strain_update_mass_matrix == "lumped");
    time_step       = compute_time_step();
    const double dt = time_step;
    // b(x, t) at the middle of the step: second order in time (first order
    // at t^n, measured on the manufactured solution).
    if (body_acceleration)
      body_acceleration->set_time(time + 0.5 * dt);
    field_computed.fill(false);
    if (shape_function != ShapeFunction::Type::classic)
      compute_supports();

    // 1. Extrapolate mass and momentum (and, when the stresses are not
    //    updated first, the forces from the last stresses):
    //    m = SᵀM, p = SᵀMV, f (Eqs. 2.14-2.15). Velocity conditions on p.
    particles_to_grid(!update_first);
    apply_velocity_conditions(momentum);

    // 2. USF / USAVG: update stresses with v = m̃ₖ⁻¹p (Δt/2 for USAVG),
    //    then extrapolate the forces.
    if (update_first)
      {
        const GridField v = lumped_strain_velocity ? lumped_velocity : velocity;
        compute_field(v);
        update_stresses(grid_fields[v], average ? dt / 2 : dt);
        compute_forces();
      }

    // 3.-4. Velocity conditions on forces; p⁺ = p + fΔt (Eq. 2.16), with the
    //    conditions imposed again.
    {
      TimerOutput::Scope timer(computing_timer, "grid solve");
      apply_velocity_conditions(force);
      updated_momentum = momentum;
      updated_momentum.add(dt, force);
      apply_velocity_conditions(updated_momentum);
      for (unsigned int f = 0; f < n_grid_fields; ++f)
        if (field_needed[f])
          compute_field(static_cast<GridField>(f));
    }

    // 5. Particle update (Table 2.1).
    update_particles();
    if (parameters.output.track_dissipation)
      {
        dissipated_energy +=
          Utilities::MPI::sum(local_dissipation, mpi_communicator);
        local_dissipation = 0;
      }

    // 6. USL- / USAVG-: stresses from v⁺; USL+ / USAVG+: from momenta
    //    re-extrapolated from the updated points (Eq. 2.17-2.18).
    if (update_last)
      {
        const double dt_last = average ? dt / 2 : dt;
        if (re_extrapolate)
          {
            particles_to_grid(false);
            apply_velocity_conditions(momentum);
            field_computed[velocity] = field_computed[lumped_velocity] = false;
            const GridField v =
              lumped_strain_velocity ? lumped_velocity : velocity;
            compute_field(v);
            update_stresses(grid_fields[v], dt_last);
          }
        else
          {
            const GridField v = lumped_strain_velocity ?
                                  lumped_updated_velocity :
                                  updated_velocity;
            compute_field(v);
            update_stresses(grid_fields[v], dt_last);
          }
      }

    sort_particles_into_cells();

    time += dt;
    ++timestep_number;
    particle_steps += particle_handler.n_global_particles();

    // Failures found by any rank in this step stop every rank.
    {
      TimerOutput::Scope timer(computing_timer, "failure checks");
      const double       flags[3] = {local_failure.empty() ? 0. : 1.,
                               static_cast<double>(n_lost_points),
                               local_max_wave_speed + local_max_point_speed};
      double global_flags[3];
      Utilities::MPI::max(make_array_view(flags),
                          mpi_communicator,
                          make_array_view(global_flags));
      max_signal_speed = global_flags[2];
      if (global_flags[0] > 0)
        {
          const auto messages =
            Utilities::MPI::all_gather(mpi_communicator, local_failure);
          for (const auto &message : messages)
            if (!message.empty())
              throw SimulationFailure(message, timestep_number, time);
        }
      if (global_flags[1] > 0)
        {
          const unsigned long long n_lost =
            Utilities::MPI::sum(n_lost_points, mpi_communicator);
          const auto messages =
            Utilities::MPI::all_gather(mpi_communicator, lost_point_messages);
          std::string first;
          for (const auto &rank_messages : messages)
            if (!rank_messages.empty() && first.empty())
              first = rank_messages.front();
          if (parameters.failure.lost_points == "stop")
            throw SimulationFailure(first + " (" + std::to_string(n_lost) +
                                      " point(s) left the mesh; set Failure "
                                      "detection/Points leaving the mesh = "
                                      "delete to remove them instead)",
                                    timestep_number,
                                    time);
          pcout << "    " << n_lost << " material point(s) left the mesh and "
                << "were deleted; first: " << first << std::endl;
          total_lost_points += n_lost;
          n_lost_points = 0;
          lost_point_messages.clear();
        }
    }
  }



  template <int dim>
  void
  Simulator<dim>::compute_field(const ParticleUpdate::GridField field)
  {
    using namespace ParticleUpdate;
    if (field_computed[field])
      return;
    TimerOutput::Scope timer(computing_timer, "grid solve");
    GridVectorField   &target = grid_fields[field];
    switch (field)
      {
        case updated_velocity: // v⁺ = m̃ₖ⁻¹ p⁺
          mass_matrix->solve(updated_momentum, target);
          break;
        case acceleration: // m̃ₖ⁻¹ f
          mass_matrix->solve(force, target);
          break;
        case velocity: // v = m̃ₖ⁻¹ p
          mass_matrix->solve(momentum, target);
          break;
        case lumped_velocity: // m⁻¹ p
          MassMatrix::apply_lumped_inverse(lumped_mass,
                                           momentum,
                                           target,
                                           mass_floor_value);
          break;
        case lumped_updated_velocity: // m⁻¹ p⁺
          MassMatrix::apply_lumped_inverse(lumped_mass,
                                           updated_momentum,
                                           target,
                                           mass_floor_value);
          break;
        case lumped_acceleration: // m⁻¹ f
          MassMatrix::apply_lumped_inverse(lumped_mass,
                                           force,
                                           target,
                                           mass_floor_value);
          break;
        default:
          Assert(false, ExcInternalError());
      }
    apply_velocity_conditions(target);
    constraints.distribute(target);
    target.update_ghost_values();
    field_computed[field] = true;
  }



  template <int dim>
  void
  Simulator<dim>::apply_velocity_conditions(GridVectorField &field) const
  {
    for (const auto &condition : node_conditions)
      {
        if (condition.fixed_all)
          for (unsigned int d = 0; d < dim; ++d)
            field.block(d).local_element(condition.local_index) = 0;
        else
          {
            double normal_component = 0;
            for (unsigned int d = 0; d < dim; ++d)
              normal_component +=
                field.block(d).local_element(condition.local_index) *
                condition.normal[d];
            for (unsigned int d = 0; d < dim; ++d)
              field.block(d).local_element(condition.local_index) -=
                normal_component * condition.normal[d];
          }
      }
  }



  template <int dim>
  GlobalStatistics<dim>
  Simulator<dim>::compute_statistics() const
  {
    using Index = PropertyIndex<dim>;
    GlobalStatistics<dim> s;
    Tensor<1, dim>        gravity;
    for (unsigned int d = 0; d < dim; ++d)
      gravity[d] = parameters.gravity[d];

    std::unique_ptr<FunctionParser<dim>> reference_velocity,
      reference_displacement;
    if (parameters.reference.enable)
      {
        const auto constants =
          parse_function_constants(parameters.reference.constants,
                                   "Reference solution/Function constants");
        reference_velocity     = std::make_unique<FunctionParser<dim>>(dim);
        reference_displacement = std::make_unique<FunctionParser<dim>>(dim);
        reference_velocity->initialize(
          FunctionParser<dim>::default_variable_names() + ",t",
          parameters.reference.velocity,
          constants,
          true);
        reference_displacement->initialize(
          FunctionParser<dim>::default_variable_names() + ",t",
          to_function_expressions(parameters.reference.displacement),
          constants,
          true);
        reference_velocity->set_time(time);
        reference_displacement->set_time(time);
      }

    for (const auto &particle : particle_handler)
      {
        const auto           p = particle.get_properties();
        const double         M = p[Index::mass];
        const Tensor<1, dim> V = get_vector<dim>(p, Index::velocity);
        const Point<dim>     x = particle.get_location();
        s.mass += M;
        s.momentum += M * V;
        s.kinetic_energy += 0.5 * M * V * V;
        s.strain_energy +=
          p[Index::initial_volume] * p[Index::strain_energy_density];
        s.potential_energy -= M * (gravity * x);
        if (reference_velocity)
          {
            const Point<dim> X(get_vector<dim>(p, Index::initial_position));
            Tensor<1, dim>   v_ref, u_ref;
            for (unsigned int d = 0; d < dim; ++d)
              {
                v_ref[d] = reference_velocity->value(X, d);
                u_ref[d] = reference_displacement->value(X, d);
              }
            const Tensor<1, dim> u = x - X;
            s.velocity_error_squared += M * (V - v_ref).norm_square();
            s.velocity_reference_squared += M * v_ref.norm_square();
            s.displacement_error_squared += M * (u - u_ref).norm_square();
            s.displacement_reference_squared += M * u_ref.norm_square();
          }
      }

    // One reduction for all sums.
    std::vector<double> values = {s.mass,
                                  s.kinetic_energy,
                                  s.strain_energy,
                                  s.potential_energy,
                                  s.velocity_error_squared,
                                  s.velocity_reference_squared,
                                  s.displacement_error_squared,
                                  s.displacement_reference_squared};
    for (unsigned int d = 0; d < dim; ++d)
      values.push_back(s.momentum[d]);
    Utilities::MPI::sum(values, mpi_communicator, values);
    s.mass                           = values[0];
    s.kinetic_energy                 = values[1];
    s.strain_energy                  = values[2];
    s.potential_energy               = values[3];
    s.velocity_error_squared         = values[4];
    s.velocity_reference_squared     = values[5];
    s.displacement_error_squared     = values[6];
    s.displacement_reference_squared = values[7];
    for (unsigned int d = 0; d < dim; ++d)
      s.momentum[d] = values[8 + d];
    return s;
  }



  template <int dim>
  void
  Simulator<dim>::check_energy(const GlobalStatistics<dim> &statistics)
  {
    const double E = statistics.total_energy();
    // Energies are measured from the initial state; gravity's potential
    // energy makes the reference the initial total, which may be of any
    // sign, so the bound is on the growth relative to the initial kinetic +
    // strain energy scale.
    const double scale =
      std::max(std::abs(initial_total_energy), initial_energy_scale);
    if (!std::isfinite(E))
      throw SimulationFailure("total energy is not finite (NaN or Inf)",
                              timestep_number,
                              time);
    if (E - initial_total_energy >
        (parameters.failure.energy_growth_limit - 1) * scale)
      {
        std::ostringstream message;
        message << "total energy grew from " << initial_total_energy << " to "
                << E << " J, past Failure detection/Energy growth limit = "
                << parameters.failure.energy_growth_limit;
        throw SimulationFailure(message.str(), timestep_number, time);
      }
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
