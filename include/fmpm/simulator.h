// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_simulator_h
#define fmpm_simulator_h

#include <fmpm/bspline_supports.h>
#include <fmpm/constitutive_model/interface.h>
#include <fmpm/contact/manager.h>
#include <fmpm/external_loads.h>
#include <fmpm/grid_state.h>
#include <fmpm/grid_transfer.h>
#include <fmpm/grid_vectors.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/material_points.h>
#include <fmpm/nodal_field.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_properties.h>
#include <fmpm/particle_update/interface.h>
#include <fmpm/particle_update/periodic_updates.h>
#include <fmpm/points/point_sort.h>
#include <fmpm/postprocess/energy_balance.h>
#include <fmpm/postprocess/global_statistics.h>
#include <fmpm/postprocess/history_file.h>
#include <fmpm/postprocess/interface.h>
#include <fmpm/simulation_control.h>
#include <fmpm/simulator_access.h>
#include <fmpm/support_cache.h>
#include <fmpm/time_step_stability.h>
#include <fmpm/timer_output.h>
#include <fmpm/velocity_conditions.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/function.h>
#include <deal.II/base/function_parser.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/mapping_cartesian.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/particles/particle_handler.h>

#include <array>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace fmpm
{
  namespace Transfer
  {
    template <int dim>
    class SupportBuilder;
  }

  /**
   * @brief The material point a failure is about, and what happened to it
   * (Simulator::failure_location_hint() reads it).
   */
  struct FailedPoint
  {
    enum class Cause : unsigned int
    {
      /** no point (another failure) */
      none,
      /** it left the mesh */
      left_mesh,
      /** its domain reaches beyond the cells around its cell */
      support_outside_patch,
      /** its velocity is not finite */
      velocity_not_finite,
      /** J = det F ≤ 0 */
      inverted,
      /** its constitutive model failed */
      model_failure,
      /** its stress is not finite */
      stress_not_finite
    };
    Cause                 cause = Cause::none;
    types::particle_index id    = 0;
    /** Its position (the first dim entries). */
    double position[3] = {0, 0, 0};

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &cause &id &position;
    }
  };

  /**
   * @brief The material points that left the mesh on this rank since the
   * last check: how many, and the first ten with a message each.
   */
  struct LostPoints
  {
    unsigned long long       n = 0;
    std::vector<std::string> messages;
    std::vector<FailedPoint> points;

    void
    clear()
    {
      n = 0;
      messages.clear();
      points.clear();
    }
  };

  /**
   * @brief Thrown when the numerical solution fails (NaN, energy growth,
   * inverted elements, points leaving the mesh). Carries the step, the time
   * and the point it is about.
   */
  class SimulationFailure : public std::runtime_error
  {
  public:
    SimulationFailure(const std::string &reason,
                      const unsigned int step,
                      const double       time,
                      const FailedPoint &point = FailedPoint())
      : std::runtime_error(reason)
      , step(step)
      , time(time)
      , point(point)
    {}
    unsigned int step;
    double       time;
    FailedPoint  point;
  };

  /**
   * @brief Orchestrates an MPM run: owns the background mesh, the DoFs, the
   * material points, the grid vectors and one object per plugin system.
   *
   * run() reads as the time step of seed 000 §2.2; each phase is a private
   * member function, timed by the TimerOutput.
   *
   * @tparam dim space dimension (2 or 3)
   */
  template <int dim>
  class Simulator
  {
  public:
    /**
     * @brief Set up from parsed parameters. @p prm must be the handler the
     * parameters were parsed from (plugins read their subsections).
     * @param[in] resume continue from the newest complete checkpoint in
     * <Output/Directory>/checkpoint/ instead of creating the material points
     * (throws, naming the directory or file, if there is none or it does
     * not fit the scene)
     */
    Simulator(const Parameters &parameters,
              ParameterHandler &prm,
              MPI_Comm          mpi_communicator,
              const bool        resume = false);

    ~Simulator();

    /**
     * @brief Run to the end time. Writes summary.json in every case. Throws
     * SimulationFailure after writing it if the run failed numerically.
     */
    void
    run();

    /**
     * @brief Whether run() stopped early because the process received
     * SIGTERM or SIGINT (after writing a checkpoint; summary.json status
     * "stopped: signal").
     */
    bool
    stopped_by_signal() const
    {
      return checkpoint_state.stopped_on_signal;
    }

    /** @brief The number of material points on all ranks. */
    unsigned long long
    n_material_points() const
    {
      return counters.n_material_points;
    }

    /** @brief No timing table at destruction (a scene set up, not run). */
    void
    disable_timing_summary()
    {
      computing_timer.disable_output();
    }

    /**
     * @brief Adapt the mesh now with the scene's Mesh refinement strategy
     * (collective; also used by tests). Returns whether the mesh changed.
     */
    bool
    adapt_mesh();

  private:
    /** Statistics of the material points now (collective). */
    GlobalStatistics<dim>
    compute_statistics() const;

    // --- set-up (simulator/setup.cc) ---
    /** Everything the constructor does (core.cc). */
    void
    set_up(ParameterHandler &prm);
    void
    make_grid();
    void
    setup_dofs();
    void
    create_material_points();
    void
    setup_boundary_conditions();
    void
    setup_plugins(ParameterHandler &prm);
    void
    check_scene();
    /** Initialize the ParticleHandler on the mesh and count lost points. */
    void
    initialize_particle_handler();
    /** Give every point of the store to the ParticleHandler, for an event
     * that needs deal.II's parallel machinery (adaptation, repartitioning,
     * checkpoint, full sort); points_from_handler() takes them back. */
    void
    points_to_handler();
    /** Take every point of the ParticleHandler into the store (in cell
     * order) and empty the handler; counts the points on all ranks. */
    void
    points_from_handler();
    /** Load balancing by points when the mesh is adapted (step-68). */
    void
    connect_cell_weights();
    /** Nodes with less than 1e-12 of the lightest point's mass are empty. */
    void
    compute_mass_floor();

    // --- mesh adaptation (simulator/adaptation.cc) ---
    /** Refine to the bodies before the first step, re-creating the points. */
    void
    adapt_initial_mesh();
    /** Set refine/coarsen flags by the strategy on locally owned cells.
     * Returns whether any rank flagged a cell. */
    bool
    mark_cells();
    /** DoFs, constraints, transfer cache, sparsity, grid vectors, the mass
     * matrix's mesh data and the velocity conditions for a new mesh. */
    void
    setup_after_mesh_change();
    /** Load-balancing weight of a cell: 1 + Point weight x its points. */
    unsigned int
    cell_weight(
      const typename parallel::distributed::Triangulation<dim>::cell_iterator
                                                   &cell,
      const typename Triangulation<dim>::CellStatus status) const;

    // --- the run (simulator/core.cc) ---
    /** history.csv opened, the run's header (method, stages, the time-step
     * rule and its warnings), the signal handlers, where a resumed run
     * starts. */
    void
    start_run();
    /** The initial energies and the scale of the energy-growth bound. */
    void
    start_energy_balance(const GlobalStatistics<dim> &statistics);
    /** After a step: the statistics, the energy check, the output and the
     * progress line when due. */
    void
    postprocess_step();
    /** Write the due checkpoint (and the summary first when a signal asked
     * to stop); returns whether the run stops. */
    bool
    checkpoint_and_maybe_stop();
    /** The last output, the closing lines, summary.json. */
    void
    finish_run();
    /** The failure, its likely cause and remedy, summary.json. */
    void
    report_failure(const SimulationFailure &failure);
    /** The largest wave speed + point speed over all points (collective). */
    double
    compute_max_signal_speed() const;

    // --- the time step (simulator/time_step.cc) ---

    /**
     * @brief Whether the grid VTU is written after the step of length dt
     * about to be taken (it needs the centre-of-mass velocities also when
     * contact runs on the material fields).
     */
    bool
    grid_output_follows_step(const double dt) const;
    /** One time step (seed 000 §2.2): begin_step(), the stages of
     * step_stages, finish_step() and check_step_failures(). */
    void
    do_time_step();
    /** A stage of the time step: a name for the run's header and its timer
     * section, and the member function that runs it. */
    struct StepStage
    {
      const char *name;
      void (Simulator::*run)();
    };
    /** The stages the scene's strain-update scheme runs, in order (chosen
     * once, at set-up). */
    std::vector<StepStage> step_stages;
    /** Which sinks ride on which point loop (chosen with the stages and
     * printed with them). The supports are built in the loop of the
     * extrapolation (Transfer::SupportBuilder). */
    struct PointLoops
    {
      /** USL+/USAVG+: p (with contact p^α and the geometry) in the loop
       * of the particle update. */
      bool momenta_in_particle_update = false;
    };
    PointLoops point_loops;
    void
    choose_step_stages();
    /** The point loops of the step, for the run's header. */
    std::string
    point_loop_description() const;
    /** Mesh adaptation when due, Δt, the load curves at t + Δt/2. */
    void
    begin_step();
    /** The supports S and G; m, p (and f unless the stresses come first),
     * the conditions, the first contact correction. */
    void
    extrapolate();
    /** USF/USAVG: stresses from v = m̃ₖ⁻¹p, then f. */
    void
    update_stresses_first();
    /** p⁺ = p + (f + f^(BC))Δt, the second contact correction. */
    void
    update_grid_momenta();
    /** The grid fields the particle update reads. */
    void
    solve_grid_fields();
    /** The particle update and its dissipation. */
    void
    update_points();
    /** USL+/USAVG+: p from the updated points, the conditions, the third
     * contact correction. */
    void
    re_extrapolate();
    /** USL/USAVG: stresses from v⁺ or the re-extrapolated v. */
    void
    update_stresses_last();
    /** Reaction forces, external work, the walls, t += Δt. */
    void
    finish_step();
    /** Failures any rank found in the step stop every rank; the signal
     * speed of the next Δt. */
    void
    check_step_failures();
    /** Whether the stresses read lumped velocities (Time/Strain update mass
     * matrix = lumped). */
    bool
    lumped_strain_velocity() const
    {
      return parameters.method.lumped_strain_velocities;
    }
    /** Whether the mass matrix's solves read the known velocities (else
     * they are not allocated); only the constrained method sets any. */
    bool
    known_velocities_read() const
    {
      return mass_matrix->reads_known_velocities();
    }
    /** Whether the velocity method's reactions are measured (they need v
     * and v⁺ of the centre of mass). */
    bool
    velocity_method_reactions() const
    {
      return velocity_conditions.get_method() ==
               VelocityConditions<dim>::Method::velocity &&
             !velocity_conditions.labels().empty();
    }
    /** Clear the support cache for this step; its materials; whether
     * classic supports are computed in each pass (affine cells without
     * hanging nodes) or stored. */
    void
    prepare_supports();
    /** The reader that builds and stores the supports in a point loop. */
    Transfer::SupportBuilder<dim>
    support_builder();
    /** Report the first point whose support @p builder could not build. */
    void
    report_support_failure(const Transfer::SupportBuilder<dim> &builder);
    /** Transfer::for_each_point() with the step's supports: computed, or
     * built and stored in this loop (G only if @p with_gradients for
     * computed ones). */
    template <typename... Sinks>
    void
    for_each_point(const bool with_gradients, Sinks &...sinks);
    /** Build the step's supports; m, p (and f with @p with_forces), m̃ and
     * with contact the material fields and geometry, in one point loop. */
    void
    particles_to_grid(const bool with_forces);
    /** The grid operators the velocity-condition methods use. */
    typename VelocityConditions<dim>::Operators
    velocity_condition_operators() const;
    /** Stage P/F of the velocity conditions on a momentum-like field. */
    void
    impose_velocity_conditions(GridVectorField             &q,
                               const double                 t,
                               std::vector<Tensor<1, dim>> *impulse);
    /** Set the initial stress of bodies that ask for it (gravity). */
    void
    initialize_stress_from_gravity();
    /** Compute a nodal field (once per step) with BCs, ghosts, constraints
     * (timed in the section of the stage that asks for it). */
    void
    compute_field(const ParticleUpdate::GridField field);
    /** The solver of the nodal fields at the current step's times. */
    FieldSolver<dim>
    field_solver() const;
    /** Update the stresses with the velocity field @p grid_velocity over
     * @p dt; with @p with_forces also f (Eq. 2.11; with contact f^α0, seed
     * 004 Eq. 29) from the new stresses in the same sweep, summed in the
     * store's point order. */
    void
    update_stresses(const ParticleUpdate::GridField grid_velocity,
                    const double                    dt,
                    const bool                      with_forces = false);

    // --- multimaterial contact (Contact::Manager, seed 004) ---
    /** Allocate the contact manager's fields on the current mesh (with
     * contact only). */
    void
    setup_contact();
    bool
    contact_active() const
    {
      return contact != nullptr;
    }
    void
    update_particles();
    /**
     * USL+/USAVG+: the particle update re-extrapolates point by point once
     * V^{n+1} and X^{n+1} are known — p = SᵀMV^{n+1}, with contact p^α and
     * what the normals and laws read of the moved points (g^α, Σ S M X,
     * u^α, V^α) — with the step's S and M (m, m̃, m^α, m̃^α and the mass
     * matrix's set-up stay those of the first extrapolation), in the order
     * and with the bits of particles_to_grid() (point_loops); the stage
     * re_extrapolate() only forms the sums and adds the ghosts.
     */
    void
    finish_re_extrapolation();

    /** Add the tractions with Distribution = face to f (before its
     * compress; an error with contact). */
    void
    add_face_traction_forces(const bool contact);
    void
    sort_particles_into_cells();

    // --- diagnostics (simulator/statistics.cc) ---
    /** Stop the run when the energy is not finite or grew past the
     * energy balance's bound (Failure detection). */
    void
    check_energy(const GlobalStatistics<dim> &statistics);

    /** Where the fastest material point is (id, body, position, speed), for
     * failure messages; collective. */
    std::string
    fastest_point() const;

    /** The first failure of a material point on this rank in this step
     * (later ones are not reported): point @p k of the store, what
     * happened to it, and the message "<subject of the cause>material point
     * <id> at (<x>) " followed by @p text. */
    template <typename... Text>
    void
    report_point_failure(const unsigned int       k,
                         const FailedPoint::Cause cause,
                         const Text &...text);

    /** Where a failure of one material point (SimulationFailure::point)
     * happened and what that points to: a point that left the mesh through
     * a boundary with a velocity condition, or an inverted/failed point at
     * a free surface or corner of its body (judged by the nodal masses of
     * its cell). Empty for other failures. Collective. */
    std::string
    failure_location_hint(const SimulationFailure &failure) const;

    // --- checkpoint and restart (simulator/checkpoint_restart.cc) ---
    /** Install the SIGTERM/SIGINT handler that requests a checkpoint. */
    void
    install_signal_handlers();
    /** This rank's checkpoint request: 2 after a signal, 1 when the wall
     * time interval has passed, else 0 (check_step_failures() reduces it
     * with its flags). */
    int
    local_checkpoint_request() const;
    /** Whether a checkpoint is due after this step (step interval, wall
     * time, or a signal on any rank: the request check_step_failures()
     * reduced). Sets checkpoint_state.stop_requested when a signal arrived. */
    bool
    checkpoint_due();
    /** Write <Output/Directory>/checkpoint/step-NNNNNN/ (through a
     * temporary directory renamed when complete) and delete old ones. */
    void
    write_checkpoint();
    /** Set-up of a resumed run: the coarse mesh exists; load the refined
     * mesh, the points, the grid fields and the scalar state. */
    void
    load_checkpoint();
    /** The Boost serialization of the scalar state (rank 0's copy). */
    template <class Archive>
    void
    serialize_scalar_state(Archive &archive);

    // --- output (simulator/output.cc) ---
    void
    output_results(const GlobalStatistics<dim> &statistics);

    MPI_Comm            mpi_communicator;
    const Parameters    parameters;
    ConditionalOStream  pcout;
    mutable TimerOutput computing_timer;

    parallel::distributed::Triangulation<dim> triangulation;
    MappingQ<dim>                             mapping;
    /** The points' mapping when every cell is an axis-aligned box (its
     * real-to-unit transform is a scaling; deal.II's sort of the points
     * then costs little), else @ref mapping. */
    MappingCartesian<dim>     cartesian_mapping;
    FE_Q<dim>                 fe;
    DoFHandler<dim>           dof_handler;
    AffineConstraints<double> constraints;
    /** Whether any rank has a hanging node (constraints to distribute). */
    bool                has_hanging_nodes = false;
    GridTransfer<dim>   transfer;
    ShapeFunction::Type shape_function = ShapeFunction::Type::classic;
    /** GIMP's closed forms around the cells with points that have a uniform
     * patch, built once per mesh: the patch of active cell c is
     * gimp_patches[gimp_patch_of_cell[c]] (invalid: not built yet). */
    std::vector<ShapeFunction::UniformGimpPatch<dim>> gimp_patches;
    std::vector<unsigned int>                         gimp_patch_of_cell;
    /** CPDI's corners located arithmetically, the same way: the patch of c
     * is cpdi_patches[cpdi_patch_of_cell[c]]. */
    std::vector<ShapeFunction::UniformCpdiPatch<dim>> cpdi_patches;
    std::vector<unsigned int>                         cpdi_patch_of_cell;
    /** B-spline shape functions: the lattice of the mesh (setup()). */
    ShapeFunction::BSplineSupports<dim> bspline_supports;

    /** Multimaterial contact: the per-material fields and the corrections
     * (null without contact). */
    std::unique_ptr<Contact::Manager<dim>> contact;
    /** Every locally owned material point: its state, in cell order. */
    MaterialPoints<dim> points;
    /** The number of points on all ranks (set when the store is filled). */
    /** The support (S, G) of every point of the store for this step. */
    SupportCache<dim> supports;

    ParticleProperties<dim> particle_properties;
    /** Smallest vertex distance of each active cell with points, for the
     * models that need it (artificial viscosity). */
    std::vector<double>             cell_size_by_index;
    Particles::ParticleHandler<dim> particle_handler;

    /** The centre-of-mass grid state (m, p, f, p⁺ in the notation of seed
     * 000, m̃, the known values). Its fields are allocated on the mesh when
     * a step may read them (field_needed, lumped_step_fields, contact), the
     * others when first computed. */
    GridState<dim> centre_of_mass;

    /** Grid velocity conditions and the method imposing them. */
    VelocityConditions<dim> velocity_conditions;
    /** The reactions of the velocity conditions and how well v⁺ meets
     * them. */
    ConditionReactions<dim> reactions;
    /** Gravity, b(x, t), the rotating frame and the tractions, and the
     * work of the walls and the tractions since the start. */
    ExternalLoads<dim> external_loads;
    /** The re-sorting of the points that left their cells (and the cells
     * around each vertex). */
    PointSort<dim> point_sort;

    std::vector<std::unique_ptr<ConstitutiveModel::Interface<dim>>>
                                                constitutive_models;
    std::unique_ptr<MassMatrix::Interface<dim>> mass_matrix;
    /** The particle update of the scene and of the lumped steps of a
     * periodic FMPM(k). */
    ParticleUpdate::PeriodicUpdates<dim> particle_updates;

    /** The update of this step: the configured one, or FLIP in a lumped
     * step of a periodic FMPM(k). */
    ParticleUpdate::Interface<dim> &
    active_update() const
    {
      return particle_updates.active();
    }

    /** The fields active_update() reads this step. */
    const std::array<bool, ParticleUpdate::n_grid_fields> &
    active_fields() const
    {
      return particle_updates.configured_active() ?
               centre_of_mass.field_needed :
               centre_of_mass.lumped_step_fields;
    }

    /** Time, step, Δt and the output and checkpoint schedules. */
    SimulationControl control;

    /** First numerical failure this rank saw in the current step, and the
     * point it is about (report_point_failure()). */
    std::string local_failure;
    FailedPoint local_failed_point;
    double      local_max_wave_speed  = 0;
    double      local_max_point_speed = 0;
    /** Energy dissipated by the particle updates on this rank in the
     * current step (seed 003 Eq. 1.46). */
    double local_dissipation = 0;
    /** The initial energies, the energy exchanged, the dissipated energy
     * and the reference errors of the run. */
    Postprocess::EnergyBalance<dim> energy_balance;
    /** Steps, cells, adaptations, lost points and wall clocks (summary). */
    Postprocess::RunCounters counters;
    /** What the outputs write: history.csv, VTU files, the points' csv
     * files (set-up). */
    Postprocess::Manager<dim> postprocessors;
    /** The points that left the mesh in this step (this rank). */
    LostPoints lost;

    /** Where the run resumed from, its checkpoints and the requests to
     * write one (simulator/checkpoint_restart.cc). */
    struct CheckpointState
    {
      explicit CheckpointState(const bool resume)
        : resume(resume)
      {}
      /** Resume from a checkpoint (set-up and run() skip the initial
       * state). */
      const bool resume;
      /** The checkpoint directory a resumed run read. */
      std::string resumed_from;
      /** The newest complete checkpoint of this run (or the one it resumed
       * from); summary.json names it. */
      std::string latest;
      /** The largest local_checkpoint_request() of the ranks in the last
       * check_step_failures(). */
      int request = 0;
      /** A signal asked to checkpoint and stop; the run stopped so. */
      bool stop_requested    = false;
      bool stopped_on_signal = false;
    };
    CheckpointState checkpoint_state;

    friend class SimulatorAccess<dim>;
    friend class Postprocess::Interface<dim>;
  };
} // namespace fmpm

#endif
