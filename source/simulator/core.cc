// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The run loop and the MPM time step of seed 000 §2.2.

#include <fmpm/postprocess/point_csv.h>
#include <fmpm/postprocess/progress.h>
#include <fmpm/postprocess/summary_file.h>
#include <fmpm/postprocess/test_output.h>
#include <fmpm/postprocess/visualization.h>
#include <fmpm/simulator.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
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
    , checkpoint_state(resume)
  {
    // An error found during set-up (bad input the parameter checks cannot
    // see) propagates out of this constructor; the TimerOutput would then
    // print its summary from its destructor, in front of the error message
    // that main() prints. A run that never started has no timings to show.
    try
      {
        set_up(prm);
        postprocessors.template find<Postprocess::HistoryFile<dim>>()
          ->find_tracked_points();
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
    counters.wall_start = MPI_Wtime();
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
    if (parameters.test_mode)
      postprocessors.add(std::make_unique<Postprocess::TestOutput<dim>>(),
                         *this);
    postprocessors.add(std::make_unique<Postprocess::HistoryFile<dim>>(),
                       *this);
    if (parameters.output.write_particle_csv)
      postprocessors.add(std::make_unique<Postprocess::PointCsv<dim>>(), *this);
    if (parameters.output.write_vtu)
      postprocessors.add(std::make_unique<Postprocess::Visualization<dim>>(),
                         *this);
    postprocessors.add(std::make_unique<Postprocess::Progress<dim>>(), *this);
    postprocessors.add(std::make_unique<Postprocess::SummaryFile<dim>>(),
                       *this);
    if (checkpoint_state.resume)
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

    control.set_signal_speed(compute_max_signal_speed());
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
    const bool points_use_cartesian_mapping =
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
                      MaterialPoints<dim>::invariant_core_slots(
                        parameters.axisymmetric));
    particle_handler.signals.particle_lost.connect(
      [this](const typename Particles::ParticleIterator<dim> &particle,
             const typename Triangulation<dim>::active_cell_iterator &) {
        ++lost.n;
        if (lost.messages.size() < 10)
          {
            std::ostringstream message;
            const auto         properties = particle->get_properties();
            message << "material point " << particle->get_id() << " of Body "
                    << static_cast<unsigned int>(
                         properties[PropertyIndex<dim>::body_id])
                    << " left the mesh at position ("
                    << particle->get_location() << ") at time "
                    << control.time();
            lost.messages.push_back(message.str());
            FailedPoint point;
            point.cause = FailedPoint::Cause::left_mesh;
            point.id    = particle->get_id();
            for (unsigned int d = 0; d < dim; ++d)
              point.position[d] = particle->get_location()[d];
            lost.points.push_back(point);
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
    counters.n_material_points =
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
    centre_of_mass.mass_floor =
      1e-12 * Utilities::MPI::min(min_point_mass, mpi_communicator);
  }



  template <int dim>
  Simulator<dim>::~Simulator()
  {
    // (The postprocessors wait for their writers when destroyed.)
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
  void
  Simulator<dim>::run()
  {
    start_run();
    try
      {
        GlobalStatistics<dim> statistics = compute_statistics();
        if (!checkpoint_state.resume)
          {
            start_energy_balance(statistics);
            output_results(statistics);
          }
        postprocessors.progress(statistics);

        while (!control.finished())
          {
            do_time_step();
            postprocess_step();
            if (checkpoint_due() && checkpoint_and_maybe_stop())
              break;
          }
        finish_run();
      }
    catch (const SimulationFailure &failure)
      {
        report_failure(failure);
        throw;
      }
  }



  template <int dim>
  void
  Simulator<dim>::start_run()
  {
    TimerOutput::Scope start_timer(computing_timer, "run start");
    const bool         is_root =
      Utilities::MPI::this_mpi_process(mpi_communicator) == 0;
    if (is_root)
      std::filesystem::create_directories(parameters.output.directory);
    postprocessors.start();

    pcout << "fmpm: " << dim << "D, "
          << Utilities::MPI::n_mpi_processes(mpi_communicator)
          << " MPI rank(s), " << triangulation.n_global_active_cells()
          << " cells, " << dof_handler.n_dofs() << " nodes, "
          << counters.n_material_points << " material points, "
          << "particle update '" << parameters.method.particle_update
          << "', mass matrix '" << parameters.method.mass_matrix
          << "', strain update '" << parameters.method.strain_update << "'"
          << std::endl;
    if (parameters.axisymmetric)
      pcout << "      axisymmetric (x = r, y = z): masses, forces and energies "
               "per radian"
            << std::endl;
    pcout << "      output in " << parameters.output.directory << std::endl;
    pcout << "      each step:";
    for (unsigned int s = 0; s < step_stages.size(); ++s)
      pcout << (s == 0 ? " " : ", ") << step_stages[s].name;
    pcout << std::endl
          << "      point loops: " << point_loop_description() << std::endl;
    TimeStepRule &rule = control.time_step_rule();
    if (!rule.description().empty())
      pcout << "      " << rule.description() << std::endl;
    // Bodies that fill every cell of the mesh (a confined bar) have no free
    // surface to warn about.
    if (rule.method_warning_needs_free_surfaces())
      {
        const bool every_cell_filled =
          points.n_cells() == triangulation.n_locally_owned_active_cells();
        if (Utilities::MPI::min(every_cell_filled ? 1 : 0, mpi_communicator) ==
            1)
          rule.no_free_surfaces();
      }
    const std::vector<std::string> warnings = rule.warnings();
    if (!warnings.empty() && is_root && !parameters.test_mode)
      {
        std::cerr << "fmpm: warning: " << warnings[0];
        for (unsigned int w = 1; w < warnings.size(); ++w)
          std::cerr << " Also: " << warnings[w];
        std::cerr << std::endl;
      }

    install_signal_handlers();
    control.checkpoint_written(MPI_Wtime());
    if (checkpoint_state.resume)
      {
        // Also in test mode: tests check where a run resumed.
        pcout << "      resumed from " << checkpoint_state.resumed_from
              << " at step " << control.step_number()
              << ", t = " << control.time() << std::endl;
      }
  }



  namespace
  {
    /** The diagonal of the bounding box of the mesh's vertices on all ranks
     * (GridTools::diameter compares all pairs of boundary vertices: seconds
     * on big meshes). */
    template <int dim>
    double
    bounding_box_diagonal(
      const parallel::distributed::Triangulation<dim> &triangulation)
    {
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
              lower[d] = std::min(lower[d], triangulation.get_vertices()[v][d]);
              upper[d] = std::max(upper[d], triangulation.get_vertices()[v][d]);
            }
      const MPI_Comm comm     = triangulation.get_communicator();
      double         diameter = 0;
      for (unsigned int d = 0; d < dim; ++d)
        diameter +=
          Utilities::fixed_power<2>(Utilities::MPI::max(upper[d], comm) +
                                    Utilities::MPI::max(-lower[d], comm));
      return std::sqrt(diameter);
    }
  } // namespace



  template <int dim>
  void
  Simulator<dim>::start_energy_balance(const GlobalStatistics<dim> &statistics)
  {
    TimerOutput::Scope timer(computing_timer, "run start");
    double             g = 0;
    for (unsigned int d = 0; d < dim; ++d)
      g += parameters.gravity[d] * parameters.gravity[d];
    energy_balance.mesh_diameter = bounding_box_diagonal(triangulation);
    energy_balance.start(
      statistics,
      std::max({statistics.kinetic_energy + statistics.strain_energy,
                statistics.mass * std::sqrt(g) * energy_balance.mesh_diameter,
                1e-300}));
  }



  template <int dim>
  void
  Simulator<dim>::postprocess_step()
  {
    TimerOutput::Scope schedule_timer(computing_timer, "step end");
    const bool         output_now = control.output_due_now();
    const bool         progress_now =
      Utilities::MPI::broadcast(mpi_communicator,
                                postprocessors.progress_due(),
                                0);
    schedule_timer.stop();
    if (output_now || progress_now || control.reached_end_time())
      {
        const GlobalStatistics<dim> statistics = compute_statistics();
        check_energy(statistics);
        if (output_now || control.reached_end_time())
          output_results(statistics);
        if (progress_now)
          postprocessors.progress(statistics);
      }
  }



  template <int dim>
  bool
  Simulator<dim>::checkpoint_and_maybe_stop()
  {
    if (checkpoint_state.stop_requested)
      {
        // Message and summary first: under mpirun, SIGINT and SIGTERM kill
        // the ranks a second after they arrive.
        checkpoint_state.stopped_on_signal = true;
        pcout << "*** Stopped by a signal at step " << control.step_number()
              << ", t = " << control.time() << "; writing a checkpoint"
              << std::endl;
        postprocessors.stopping("stopped: signal");
      }
    write_checkpoint();
    return checkpoint_state.stop_requested;
  }



  template <int dim>
  void
  Simulator<dim>::finish_run()
  {
    const GlobalStatistics<dim> statistics = compute_statistics();
    // The last step a run takes is always written.
    if (!control.output_written_now())
      output_results(statistics);
    postprocessors.progress(statistics);
    const bool reached_end = control.reached_end_time();
    if (!checkpoint_state.stopped_on_signal && !reached_end)
      pcout << "*** Stopped by Time/Maximum number of steps = "
            << parameters.time.max_steps << " at t = " << control.time()
            << " (End time " << parameters.time.end_time << ")" << std::endl;
    if (checkpoint_state.stopped_on_signal)
      pcout << "*** Stopped by a signal at step " << control.step_number()
            << " after writing a checkpoint; continue with fmpm --resume"
            << std::endl;
    const std::string status = checkpoint_state.stopped_on_signal ?
                                 "stopped: signal" :
                               reached_end ? "completed" :
                                             "stopped: step limit";
    postprocessors.finish();
    postprocessors.end_of_run(status, nullptr);
  }



  template <int dim>
  void
  Simulator<dim>::report_failure(const SimulationFailure &failure)
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
            << control.time_step_rule().limit_description()
            << "): lower Time/Courant number or "
            << "Time step, or set Time/Strain update mass matrix = "
            << "lumped." << std::endl;
    if (!control.time_step_rule().note().empty())
      pcout << "    Note: " << control.time_step_rule().note() << std::endl;
    const std::string status = std::string("failed: ") + failure.what();
    postprocessors.end_of_run(status, &failure);
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
    solver.mass_floor        = centre_of_mass.mass_floor;
    // The time of the momenta and of the updated momenta (acceleration: over
    // the step).
    solver.t_begin = centre_of_mass.momentum_time;
    solver.t_end   = control.time() + control.time_step();
    return solver;
  }



  template <int dim>
  void
  Simulator<dim>::compute_field(const ParticleUpdate::GridField field)
  {
    if (centre_of_mass.computed[field])
      return;
    centre_of_mass.compute(field,
                           field_solver(),
                           *mass_matrix,
                           control.time_step());
  }



  template <int dim>
  typename VelocityConditions<dim>::Operators
  Simulator<dim>::velocity_condition_operators() const
  {
    typename VelocityConditions<dim>::Operators operators;
    operators.lumped_mass = &centre_of_mass.mass;
    operators.mass_floor  = centre_of_mass.mass_floor;
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
        centre_of_mass.full_mass_matrix.vmult(p.block(d), v.block(d));
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
        centre_of_mass.known_velocity_mask[d] = 0;
    velocity_conditions.impose_on_momenta(q,
                                          t,
                                          velocity_condition_operators(),
                                          impulse);
  }



  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
