// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The run loop and the MPM time step of seed 000 §2.2.

#include <fmpm/function_parser.h>
#include <fmpm/simulator.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_tools.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <set>
#include <sstream>

namespace fmpm
{
  template <int dim>
  Simulator<dim>::Simulator(const Parameters &parameters_in,
                            ParameterHandler &prm,
                            MPI_Comm          mpi_communicator_in,
                            const bool        resume)
    : mpi_communicator(mpi_communicator_in)
    , parameters(parameters_in)
    , pcout(std::cout,
            Utilities::MPI::this_mpi_process(mpi_communicator) == 0 &&
              !parameters.test_mode)
    // Rank 0's timings (no MPI communicator: an error during set-up must not
    // leave the timer waiting for other ranks).
    , computing_timer(pcout,
                      (!parameters.print_timer_summary ||
                       parameters.test_mode) ?
                        TimerOutput::never :
                        TimerOutput::summary,
                      TimerOutput::wall_times)
    , triangulation(mpi_communicator)
    , mapping(1)
    , fe(1)
    , dof_handler(triangulation)
    , control(parameters.time, parameters.output, parameters.checkpoint)
    , tout(std::cout,
           Utilities::MPI::this_mpi_process(mpi_communicator) == 0 &&
             parameters.test_mode)
    , resume_from_checkpoint(resume)
  {
    // An error found during set-up (bad input the parameter checks cannot
    // see) propagates out of this constructor; the TimerOutput would then
    // print its summary from its destructor, in front of the error message
    // that main() prints. A run that never started has no timings to show.
    try
      {
        set_up(prm);
        find_tracked_points();
      }
    catch (...)
      {
        computing_timer.disable_output();
        throw;
      }
  }



  template <int dim>
  void
  Simulator<dim>::set_up(ParameterHandler &prm)
  {
    wall_start = MPI_Wtime();
    TimerOutput::Scope timer(computing_timer, "setup");
    shape_function = ShapeFunction::parse(parameters.method.shape_function);
    choose_step_stages();
    make_grid();
    setup_plugins(prm);
    // Multimaterial contact: its laws and normal method (its fields follow
    // the mesh, setup_contact()).
    if (parameters.contact.multimaterial && parameters.size.n_materials > 1)
      {
        contact = std::make_unique<Contact::Manager<dim>>();
        contact->initialize_simulator(*this);
        contact->initialize();
      }
    if (resume_from_checkpoint)
      {
        load_checkpoint();
        return;
      }
    setup_dofs();
    mass_matrix->initialize();
    initialize_particle_handler();
    create_material_points();
    setup_boundary_conditions();
    initialize_stress_from_gravity();
    compute_mass_floor();
    if (parameters.refinement.adaptive() &&
        parameters.refinement.initial_refinement)
      adapt_initial_mesh();
    // Load balancing by material points (deal.II step-68): from the first
    // step on, and whenever the mesh is adapted.
    connect_cell_weights();
    if (parameters.refinement.point_weight > 0 &&
        Utilities::MPI::n_mpi_processes(mpi_communicator) > 1)
      {
        points_to_handler();
        particle_handler.prepare_for_coarsening_and_refinement();
        triangulation.repartition();
        particle_handler.unpack_after_coarsening_and_refinement();
        setup_after_mesh_change();
        points_from_handler();
      }

    max_signal_speed = compute_max_signal_speed();
    check_scene();
  }



  template <int dim>
  void
  Simulator<dim>::initialize_particle_handler()
  {
    // Every active cell an axis-aligned box on every rank (and no curved
    // manifold, so refinement keeps it so): the points use the Cartesian
    // mapping.
    bool boxes = true;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        if (!boxes)
          break;
        if (cell->is_artificial())
          continue;
        if (cell->manifold_id() != numbers::flat_manifold_id)
          boxes = false;
        const Point<dim> lower = cell->vertex(0);
        const Point<dim> upper =
          cell->vertex(GeometryInfo<dim>::vertices_per_cell - 1);
        const double tolerance = 1e-12 * lower.distance(upper);
        for (const unsigned int v : cell->vertex_indices())
          for (unsigned int d = 0; d < dim; ++d)
            if (std::abs(cell->vertex(v)[d] -
                         ((v >> d) & 1 ? upper[d] : lower[d])) > tolerance)
              boxes = false;
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->manifold_id() != numbers::flat_manifold_id)
            boxes = false;
      }
    points_use_cartesian_mapping =
      Utilities::MPI::min(boxes ? 1 : 0, mpi_communicator) == 1;
    if (points_use_cartesian_mapping)
      particle_handler.initialize(triangulation,
                                  cartesian_mapping,
                                  particle_properties.n_properties());
    else
      particle_handler.initialize(triangulation,
                                  mapping,
                                  particle_properties.n_properties());
    points.initialize(particle_properties.n_properties(),
                      MaterialPoints<dim>::plane_strain_zero_slots(),
                      MaterialPoints<dim>::invariant_core_slots());
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
                    << particle->get_location() << ") at time "
                    << control.time();
            lost_point_messages.push_back(message.str());
          }
      });
  }



  template <int dim>
  void
  Simulator<dim>::points_to_handler()
  {
    TimerOutput::Scope timer(computing_timer, "point store: to handler");
    points.push_to(particle_handler);
  }



  template <int dim>
  void
  Simulator<dim>::points_from_handler()
  {
    TimerOutput::Scope timer(computing_timer, "point store: from handler");
    points.pull_from(particle_handler);
    n_global_material_points =
      Utilities::MPI::sum<unsigned long long>(points.n_points(),
                                              mpi_communicator);
  }



  template <int dim>
  void
  Simulator<dim>::connect_cell_weights()
  {
    if (parameters.refinement.point_weight > 0)
      triangulation.signals.weight.connect(
        [this](const typename parallel::distributed::Triangulation<
                 dim>::cell_iterator                        &cell,
               const typename Triangulation<dim>::CellStatus status) {
          return cell_weight(cell, status);
        });
  }



  template <int dim>
  void
  Simulator<dim>::compute_mass_floor()
  {
    // Nodes with less than a tiny fraction of a typical point mass are empty.
    double              min_point_mass = std::numeric_limits<double>::max();
    const double *const mass = points.column(PropertyIndex<dim>::mass);
    for (unsigned int k = 0; k < points.n_points(); ++k)
      min_point_mass = std::min(min_point_mass, mass[k]);
    mass_floor_value =
      1e-12 * Utilities::MPI::min(min_point_mass, mpi_communicator);
  }



  template <int dim>
  Simulator<dim>::~Simulator()
  {
    // The writer holds patches only; its errors were reported or do not
    // matter any more.
    if (output_writer.valid())
      output_writer.wait();
    particle_handler.clear();
  }



  template <int dim>
  double
  Simulator<dim>::compute_max_signal_speed() const
  {
    using Index  = PropertyIndex<dim>;
    double speed = 0;
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const PointRecord  p = points.record(k);
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
      dt = std::min(parameters.time.courant_number, stability.max_courant) *
           minimum_cell_size / max_signal_speed;
    // Do not step past the end time, nor past the next output time with
    // Output/Exact output times (avoid a tiny step by splitting the rest
    // evenly when it is less than two steps).
    const double rest = std::min(parameters.time.end_time - control.time(),
                                 control.time_to_next_output());
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
    TimerOutput::Scope start_timer(computing_timer, "run start");
    const bool         is_root =
      Utilities::MPI::this_mpi_process(mpi_communicator) == 0;
    if (is_root)
      std::filesystem::create_directories(parameters.output.directory);
    history.open(parameters.output.directory + "/history.csv",
                 is_root,
                 parameters.reference.enable,
                 parameters.output.track_dissipation,
                 velocity_conditions.labels(),
                 history_extra_columns());

    pcout << "fmpm: " << dim << "D, "
          << Utilities::MPI::n_mpi_processes(mpi_communicator)
          << " MPI rank(s), " << triangulation.n_global_active_cells()
          << " cells, " << dof_handler.n_dofs() << " nodes, "
          << n_global_material_points << " material points, "
          << "particle update '" << parameters.method.particle_update
          << "', mass matrix '" << parameters.method.mass_matrix
          << "', strain update '" << parameters.method.strain_update << "'"
          << std::endl
          << "      output in " << parameters.output.directory << std::endl;
    pcout << "      each step:";
    for (unsigned int s = 0; s < step_stages.size(); ++s)
      pcout << (s == 0 ? " " : ", ") << step_stages[s].name;
    pcout << std::endl;
    if (parameters.time.time_step == 0)
      {
        pcout << "      time step: Courant number "
              << format_number(parameters.time.courant_number);
        if (parameters.time.courant_number > stability.max_courant)
          pcout << " capped at the method's limit "
                << format_number(stability.max_courant, 3) << " ("
                << stability.basis << ")";
        pcout << std::endl;
      }
    // Bodies that fill every cell of the mesh (a confined bar) have no free
    // surface to warn about.
    if (stability.warning_only_with_free_surfaces)
      {
        const bool every_cell_filled =
          points.n_cells() == triangulation.n_locally_owned_active_cells();
        // Keep what check_scene() added (" Also: ...").
        const auto also = stability.warning.find(" Also: ");
        if (Utilities::MPI::min(every_cell_filled ? 1 : 0, mpi_communicator) ==
            1)
          stability.warning =
            also == std::string::npos ? "" : stability.warning.substr(also + 7);
      }

    if (!stability.warning.empty() && is_root && !parameters.test_mode)
      std::cerr << "fmpm: warning: " << stability.warning << std::endl;

    install_signal_handlers();
    control.checkpoint_written(MPI_Wtime());
    if (resume_from_checkpoint)
      {
        // Also in test mode: tests check where a run resumed.
        pcout << "      resumed from " << resumed_checkpoint << " at step "
              << control.step_number() << ", t = " << control.time()
              << std::endl;
        tout << "resumed from " << resumed_checkpoint << " at step "
             << control.step_number() << std::endl;
      }
    start_timer.stop();

    try
      {
        GlobalStatistics<dim> statistics = compute_statistics();
        if (resume_from_checkpoint)
          history.restore(restored_history_rows);
        else
          {
            TimerOutput::Scope diameter_timer(computing_timer, "run start");
            initial_total_energy   = statistics.total_energy();
            initial_kinetic_energy = statistics.kinetic_energy;
            initial_strain_energy  = statistics.strain_energy;
            double g               = 0;
            for (unsigned int d = 0; d < dim; ++d)
              g += parameters.gravity[d] * parameters.gravity[d];
            // The diagonal of the mesh's bounding box (GridTools::diameter
            // compares all pairs of boundary vertices: seconds on big meshes).
            Point<dim> lower, upper;
            for (unsigned int d = 0; d < dim; ++d)
              {
                lower[d] = std::numeric_limits<double>::max();
                upper[d] = -std::numeric_limits<double>::max();
              }
            const auto &used = triangulation.get_used_vertices();
            for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
              if (used[v])
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    lower[d] =
                      std::min(lower[d], triangulation.get_vertices()[v][d]);
                    upper[d] =
                      std::max(upper[d], triangulation.get_vertices()[v][d]);
                  }
            double diameter = 0;
            for (unsigned int d = 0; d < dim; ++d)
              diameter += Utilities::fixed_power<2>(
                Utilities::MPI::max(upper[d], mpi_communicator) +
                Utilities::MPI::max(-lower[d], mpi_communicator));
            diameter      = std::sqrt(diameter);
            mesh_diameter = diameter;
            initial_energy_scale =
              std::max({statistics.kinetic_energy + statistics.strain_energy,
                        statistics.mass * std::sqrt(g) * diameter,
                        1e-300});
            diameter_timer.stop();
            output_results(statistics);
          }
        print_progress(statistics, true);

        while (!control.finished())
          {
            do_time_step();

            TimerOutput::Scope schedule_timer(computing_timer, "step end");
            const bool         output_now = control.output_due_now();
            const bool         progress_now =
              Utilities::MPI::broadcast(mpi_communicator,
                                        MPI_Wtime() - last_progress_wall >
                                          parameters.output.progress_seconds,
                                        0);
            schedule_timer.stop();
            if (output_now || progress_now || control.reached_end_time())
              {
                statistics = compute_statistics();
                check_energy(statistics);
                if (output_now || control.reached_end_time())
                  output_results(statistics);
                if (progress_now)
                  print_progress(statistics, false);
              }
            if (checkpoint_due())
              {
                if (stop_requested)
                  {
                    // Message and summary first: under mpirun, SIGINT and
                    // SIGTERM kill the ranks a second after they arrive.
                    stopped_on_signal = true;
                    pcout << "*** Stopped by a signal at step "
                          << control.step_number() << ", t = " << control.time()
                          << "; writing a checkpoint" << std::endl;
                    statistics = compute_statistics();
                    write_summary("stopped: signal", nullptr, statistics);
                  }
                write_checkpoint();
                if (stop_requested)
                  break;
              }
          }
        statistics = compute_statistics();
        // The last step a run takes is always written.
        if (!control.output_written_now())
          output_results(statistics);
        print_progress(statistics, true);
        const bool reached_end = control.reached_end_time();
        if (!stopped_on_signal && !reached_end)
          pcout << "*** Stopped by Time/Maximum number of steps = "
                << parameters.time.max_steps << " at t = " << control.time()
                << " (End time " << parameters.time.end_time << ")"
                << std::endl;
        if (stopped_on_signal)
          pcout << "*** Stopped by a signal at step " << control.step_number()
                << " after writing a checkpoint; continue with fmpm --resume"
                << std::endl;
        print_test_particles();
        wait_for_output_writer();
        write_summary(stopped_on_signal ? "stopped: signal" :
                      reached_end       ? "completed" :
                                          "stopped: step limit",
                      nullptr,
                      statistics);
        pcout << "      timer sections cover " << std::fixed
              << std::setprecision(1) << 100 * timer_coverage
              << " % of the wall time" << std::defaultfloat << std::endl;
      }
    catch (const SimulationFailure &failure)
      {
        pcout << std::endl
              << "*** The run failed at step " << failure.step << ", time "
              << failure.time << ":" << std::endl
              << "    " << failure.what() << std::endl;
        // A failure at a body's edge or at a boundary condition names that
        // cause; otherwise: stresses from full-mass velocities need about
        // 1/√3 of the lumped stable time step (doc/benchmarks.md).
        const std::string location_hint = failure_location_hint(failure);
        if (!location_hint.empty())
          pcout << "    " << location_hint << std::endl;
        else if (!parameters.method.lumped_strain_velocities &&
                 mass_matrix->order() > 1)
          pcout << "    The stresses are updated with velocities from the "
                << "mass matrix '" << parameters.method.mass_matrix
                << "', which needs a smaller time step than the lumped one "
                << "(this run's Courant number limit: "
                << format_number(stability.max_courant, 3) << ", "
                << stability.basis << "): lower Time/Courant number or "
                << "Time step, or set Time/Strain update mass matrix = "
                << "lumped." << std::endl;
        if (!stability.note.empty())
          pcout << "    Note: " << stability.note << std::endl;
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
  Simulator<dim>::grid_output_follows_step(const double dt) const
  {
    // The run writes after the step when the schedule says so and after
    // its last step.
    return parameters.output.write_vtu && control.output_follows_step(dt);
  }



  template <int dim>
  FieldSolver<dim>
  Simulator<dim>::field_solver() const
  {
    FieldSolver<dim> solver;
    solver.conditions        = &velocity_conditions;
    solver.constraints       = &constraints;
    solver.has_hanging_nodes = has_hanging_nodes;
    solver.mass_floor        = mass_floor_value;
    // The time of the momenta and of the updated momenta (acceleration: over
    // the step).
    solver.t_begin = momentum_time;
    solver.t_end   = control.time() + control.time_step();
    return solver;
  }



  template <int dim>
  void
  Simulator<dim>::compute_field(const ParticleUpdate::GridField field)
  {
    using namespace ParticleUpdate;
    if (centre_of_mass.computed[field])
      return;
    TimerOutput::Scope timer(computing_timer, "grid solve");
    centre_of_mass.allocate(field);
    const FieldSolver<dim> solver          = field_solver();
    GridVectorField       &target          = centre_of_mass.fields[field];
    const double           t_field         = solver.time_of(field);
    const bool             is_acceleration = solver.is_acceleration(field);
    if (velocity_conditions.uses_known_values() && known_velocities_read())
      {
        velocity_conditions.known_values(t_field,
                                         known_velocity_mask,
                                         known_velocity_value);
        if (is_acceleration)
          {
            // Known accelerations: (v_b(t + Δt) − v_b(t)) / Δt.
            std::vector<GridScalar> mask_end(known_velocity_mask),
              value_end(known_velocity_value);
            velocity_conditions.known_values(solver.t_end, mask_end, value_end);
            for (unsigned int d = 0; d < dim; ++d)
              {
                known_velocity_value[d].sadd(-1., 1., value_end[d]);
                known_velocity_value[d] *= 1. / control.time_step();
              }
          }
      }
    const GridVectorField &momentum = centre_of_mass.momentum;
    const GridVectorField &force    = centre_of_mass.force;
    // Iterative solves start from the field's value of the last step.
    switch (field)
      {
        case updated_velocity: // v⁺ = m̃ₖ⁻¹ p⁺
          mass_matrix->solve_from_guess(centre_of_mass.updated_momentum,
                                        target,
                                        0);
          break;
        case acceleration: // m̃ₖ⁻¹ f, as accurate in a Δt as v in p
          mass_matrix->solve_from_guess(force,
                                        target,
                                        momentum.l2_norm() /
                                            control.time_step() +
                                          force.l2_norm());
          break;
        case velocity: // v = m̃ₖ⁻¹ p
          mass_matrix->solve_from_guess(momentum, target, 0);
          break;
        case lumped_velocity: // m⁻¹ p
          solver.lumped(centre_of_mass, field, momentum);
          break;
        case lumped_updated_velocity: // m⁻¹ p⁺
          solver.lumped(centre_of_mass, field, centre_of_mass.updated_momentum);
          break;
        case lumped_acceleration: // m⁻¹ f
          solver.lumped(centre_of_mass, field, force);
          break;
        default:
          Assert(false, ExcInternalError());
      }
    // Lumped fields satisfy the conditions exactly; full-mass fields where
    // the method promises it (constrained, velocity: Eq. 2.53).
    solver.finish(centre_of_mass,
                  field,
                  solver.is_lumped(field) ||
                    velocity_conditions.corrects_velocities(),
                  field == updated_velocity ? &velocity_corrections[1] :
                  field == velocity         ? &velocity_corrections[0] :
                                              nullptr);
  }



  template <int dim>
  typename VelocityConditions<dim>::Operators
  Simulator<dim>::velocity_condition_operators() const
  {
    typename VelocityConditions<dim>::Operators operators;
    operators.lumped_mass = &centre_of_mass.mass;
    operators.mass_floor  = mass_floor_value;
    operators.solve = [this](const GridVectorField &p, GridVectorField &v) {
      mass_matrix->solve(p, v);
    };
    operators.forward = [this](const GridVectorField &v, GridVectorField &p) {
      GridVectorField v_ghosted(v);
      v_ghosted.update_ghost_values();
      mass_matrix->vmult(v_ghosted, p);
    };
    operators.full_mass = [this](const GridVectorField &v, GridVectorField &p) {
      for (unsigned int d = 0; d < dim; ++d)
        full_mass_matrix.vmult(p.block(d), v.block(d));
    };
    return operators;
  }



  template <int dim>
  void
  Simulator<dim>::impose_velocity_conditions(
    GridVectorField             &q,
    const double                 t,
    std::vector<Tensor<1, dim>> *impulse)
  {
    // With the constrained method the solves inside a method hold no known
    // values (the method is then lumped on momenta anyway).
    if (velocity_conditions.uses_known_values() && known_velocities_read())
      for (unsigned int d = 0; d < dim; ++d)
        known_velocity_mask[d] = 0;
    velocity_conditions.impose_on_momenta(q,
                                          t,
                                          velocity_condition_operators(),
                                          impulse);
  }



  template <int dim>
  GlobalStatistics<dim>
  Simulator<dim>::compute_statistics() const
  {
    TimerOutput::Scope timer(computing_timer, "statistics");
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
        reference_velocity         = std::make_unique<FunctionParser<dim>>(dim);
        reference_displacement     = std::make_unique<FunctionParser<dim>>(dim);
        const std::string expected = std::to_string(dim) +
                                     " expressions in x, y" +
                                     (dim == 3 ? ", z" : "") + ", t";
        parse_function(*reference_velocity,
                       "Reference solution/Velocity",
                       parameters.reference.velocity,
                       to_function_expressions(parameters.reference.velocity),
                       FunctionParser<dim>::default_variable_names() + ",t",
                       constants,
                       true,
                       expected);
        parse_function(*reference_displacement,
                       "Reference solution/Displacement",
                       parameters.reference.displacement,
                       to_function_expressions(
                         parameters.reference.displacement),
                       FunctionParser<dim>::default_variable_names() + ",t",
                       constants,
                       true,
                       expected);
        reference_velocity->set_time(control.time());
        reference_displacement->set_time(control.time());
      }

    // In the store's order: cell by cell in the order of the cells' ids
    // (CellId) on adapted meshes, by id in a cell. Neither depends on the
    // history of the points' moves, and a resumed run shares it (bitwise
    // equal sums).
    const unsigned int n_materials = parameters.size.n_materials;
    const unsigned int stride      = GlobalStatistics<dim>::material_stride();
    if (n_materials > 1)
      s.per_material.assign(n_materials * stride, 0.);
    constexpr unsigned int stress_slots[6] = {0, 1, 3, 2, 4, 5};
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const PointRecord    p = points.record(k);
        const double         M = p[Index::mass];
        const Tensor<1, dim> V = get_vector<dim>(p, Index::velocity);
        const Point<dim>    &x = points.position[k];
        if (n_materials > 1)
          {
            double *const sums =
              &s.per_material[static_cast<unsigned int>(p[Index::material_id]) *
                              stride];
            const double volume = p[Index::volume];
            sums[0] += M;
            for (unsigned int d = 0; d < dim; ++d)
              sums[1 + d] += M * V[d];
            sums[1 + dim] += volume;
            // 2D: xx, yy, xy = stored slots 0, 1, 3.
            for (unsigned int c = 0; c < GlobalStatistics<dim>::n_stress; ++c)
              sums[2 + dim + c] +=
                volume * p[Index::stress + (dim == 2 ? stress_slots[c] : c)];
            sums[stride - 2] += 0.5 * M * V * V;
            sums[stride - 1] +=
              p[Index::initial_volume] * p[Index::strain_energy_density];
          }
        s.mass += M;
        s.momentum += M * V;
        s.kinetic_energy += 0.5 * M * V * V;
        s.strain_energy +=
          p[Index::initial_volume] * p[Index::strain_energy_density];
        // Gravity's potential energy relative to the initial configuration
        // (independent of where the origin lies): -Σ M g·(x - X).
        const Point<dim> X(get_vector<dim>(p, Index::initial_position));
        s.potential_energy -= M * (gravity * (x - X));
        if (reference_velocity)
          {
            Tensor<1, dim> v_ref, u_ref;
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
    // The energy stored in imperfect interfaces (their springs) at the last
    // correction of the updated momenta.
    if (contact)
      s.strain_energy += contact->local_interface_energy();

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
    values.insert(values.end(), s.per_material.begin(), s.per_material.end());
    Utilities::MPI::sum(values, mpi_communicator, values);
    std::copy(values.end() - s.per_material.size(),
              values.end(),
              s.per_material.begin());
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
    TimerOutput::Scope timer(computing_timer, "statistics");
    const double       E = statistics.total_energy();
    // Energies are measured from the initial state; gravity's potential
    // energy makes the reference the initial total, which may be of any
    // sign, so the bound is on the growth relative to the initial kinetic +
    // strain energy scale. A moving wall that starts to drive material at
    // rest gives it of order ½ M v_w² in the first steps, when its work so
    // far is still small: that is a scale too.
    const double wall_speed =
      velocity_conditions.fastest_wall_speed(control.time());
    const double scale =
      std::max({energy_error_scale(statistics),
                initial_energy_scale,
                0.5 * statistics.mass * wall_speed * wall_speed});
    if (!std::isfinite(E))
      throw SimulationFailure("total energy is not finite (NaN or Inf)",
                              control.step_number(),
                              control.time());
    if (E - initial_total_energy - external_work >
        (parameters.failure.energy_growth_limit - 1) * scale)
      {
        std::ostringstream message;
        message << "total energy grew from " << initial_total_energy << " to "
                << E << " J (external work " << external_work
                << " J), past Failure detection/Energy growth limit = "
                << parameters.failure.energy_growth_limit << "; "
                << fastest_point();
        throw SimulationFailure(message.str(),
                                control.step_number(),
                                control.time());
      }
    const double kinetic_limit = parameters.failure.kinetic_energy_limit;
    if (kinetic_limit > 0 && statistics.kinetic_energy > kinetic_limit)
      throw SimulationFailure(
        "kinetic energy " + format_number(statistics.kinetic_energy, 6) +
          " J is above Failure detection/Kinetic energy limit = " +
          format_number(kinetic_limit) + " J (total energy " +
          format_number(E, 6) + " J, external work " +
          format_number(external_work, 6) + " J); " + fastest_point(),
        control.step_number(),
        control.time());
  }



  template <int dim>
  std::string
  Simulator<dim>::failure_location_hint(const SimulationFailure &failure) const
  {
    // The failure messages of one point start "material point <id> ".
    const std::string message = failure.what();
    const std::string prefix  = "material point ";
    if (message.rfind(prefix, 0) != 0)
      return "";
    std::istringstream    id_text(message.substr(prefix.size()));
    types::particle_index id = 0;
    if (!(id_text >> id))
      return "";

    // 1. A point that left the mesh of a box through a face with a velocity
    //    condition (boundary ids 2d, 2d + 1 of direction d).
    const std::string left = "left the mesh at position (";
    const auto        at   = message.find(left);
    if (at != std::string::npos)
      {
        std::istringstream position_text(message.substr(at + left.size()));
        Point<dim>         x;
        for (unsigned int d = 0; d < dim; ++d)
          position_text >> x[d];
        if (!position_text || parameters.mesh.type != MeshParameters::Type::box)
          return "";
        const auto                  &bc = parameters.boundary_conditions;
        std::set<types::boundary_id> held(bc.fixed.begin(), bc.fixed.end());
        held.insert(bc.roller.begin(), bc.roller.end());
        for (const auto &wall : bc.moving_walls)
          held.insert(wall.boundary_ids.begin(), wall.boundary_ids.end());
        for (unsigned int d = 0; d < dim; ++d)
          for (const unsigned int side : {0u, 1u})
            {
              const double face = side == 0 ? parameters.mesh.lower_corner[d] :
                                              parameters.mesh.upper_corner[d];
              const bool   beyond = side == 0 ? x[d] < face : x[d] > face;
              const types::boundary_id id_of_face = 2 * d + side;
              if (beyond && held.count(id_of_face) > 0)
                // FMPM's, XPIC's and PIC midpoint's position updates read
                // the point's own velocity when psi > 0 (seed 000 Table 2.1,
                // Eq. 2.28).
                return "Where: the point crossed boundary id " +
                       std::to_string(id_of_face) +
                       ", which has a velocity condition: the condition holds "
                       "the grid velocity at the boundary's nodes, not the "
                       "points. A position update that moves a point also "
                       "with its own velocity ('Position update psi' > 0 in "
                       "'Particle update/Fmpm', '/Xpic' or '/Pic midpoint') "
                       "can carry it through; with psi = 0 the points move "
                       "with the grid velocity.";
            }
        return "";
      }

    // 2. An inverted or failed point: how full the nodes of its cell are.
    //    A node inside a body holds about ρ₀ times the measure of a cell
    //    (each of its 2^dim cells gives it 1/2^dim); a node at a free face
    //    about half of that, at a free corner a quarter.
    using Index     = PropertyIndex<dim>;
    double min_fill = -1;
    int    body     = -1;
    for (unsigned int c = 0; c < points.n_cells(); ++c)
      for (unsigned int k = points.cell_point_begin[c];
           k < points.cell_point_begin[c + 1];
           ++k)
        if (points.id[k] == id)
          {
            const PointRecord p   = points.record(k);
            const double density0 = p[Index::mass] / p[Index::initial_volume];
            const auto  &cell     = points.cell_iterator(c);
            std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
            typename DoFHandler<dim>::active_cell_iterator dof_cell(
              &triangulation, cell->level(), cell->index(), &dof_handler);
            dof_cell->get_dof_indices(dofs);
            min_fill = std::numeric_limits<double>::max();
            for (const auto dof : dofs)
              min_fill = std::min(min_fill,
                                  centre_of_mass.mass(dof) /
                                    (density0 * cell->measure()));
            body = static_cast<int>(p[Index::body_id]);
          }
    min_fill = Utilities::MPI::max(min_fill, mpi_communicator);
    body     = Utilities::MPI::max(body, mpi_communicator);
    if (min_fill < 0 || min_fill >= 0.75)
      return "";
    std::string hint =
      "Where: the point is at a free " +
      std::string(min_fill < 0.375 ? "corner" : "surface") + " of Body " +
      std::to_string(body) + " (the lightest node of its cell holds " +
      format_number(100 * min_fill, 2) +
      " % of the mass of a node inside the body). The nodes there rest on "
      "few points, so their velocities and the deformation they give the "
      "point are the least accurate of the body: the likely cause is the "
      "resolution of the edge, not the time step. Likely remedies: more "
      "'Points per cell' or a finer mesh";
    if (!parameters.method.lumped_strain_velocities && mass_matrix->order() > 1)
      hint += ", or 'Time/Strain update mass matrix = lumped' (the lumped "
              "velocity p/m of a node is an average of its points' "
              "velocities; the series of the mass matrix '" +
              parameters.method.mass_matrix +
              "' can amplify the momenta of nearly empty nodes)";
    return hint + ".";
  }



  template <int dim>
  double
  Simulator<dim>::energy_exchanged(
    const GlobalStatistics<dim> &statistics) const
  {
    // The potential energy is measured from the initial configuration
    // (compute_statistics()), so its change is its value.
    return std::max(
      {max_energy_exchanged,
       std::abs(statistics.kinetic_energy - initial_kinetic_energy),
       std::abs(statistics.strain_energy - initial_strain_energy),
       std::abs(statistics.potential_energy)});
  }



  template <int dim>
  double
  Simulator<dim>::energy_error_scale(
    const GlobalStatistics<dim> &statistics) const
  {
    return std::max({initial_kinetic_energy + initial_strain_energy,
                     energy_exchanged(statistics),
                     external_work_scale,
                     std::numeric_limits<double>::min()});
  }



  template <int dim>
  double
  Simulator<dim>::energy_error(const GlobalStatistics<dim> &statistics) const
  {
    return (statistics.total_energy() - initial_total_energy - external_work) /
           energy_error_scale(statistics);
  }



  template <int dim>
  std::string
  Simulator<dim>::fastest_point() const
  {
    using Index          = PropertyIndex<dim>;
    double      speed    = -1;
    std::string location = "no material points";
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const PointRecord p = points.record(k);
        const double      v = get_vector<dim>(p, Index::velocity).norm();
        if (v > speed)
          {
            speed = v;
            std::ostringstream text;
            text << "the fastest material point, " << points.id[k]
                 << " of Body " << static_cast<unsigned int>(p[Index::body_id])
                 << ", moves at " << format_number(v, 6) << " m/s at position ("
                 << points.position[k] << ")";
            location = text.str();
          }
      }
    const auto speeds = Utilities::MPI::all_gather(mpi_communicator, speed);
    const auto locations =
      Utilities::MPI::all_gather(mpi_communicator, location);
    return locations[std::max_element(speeds.begin(), speeds.end()) -
                     speeds.begin()];
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
