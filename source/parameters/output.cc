// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Output, Checkpoint, Failure detection, Reference solution.

#include <fmpm/parameters.h>

namespace fmpm
{
  void
  OutputParameters::declare_parameters(ParameterHandler &prm)
  {
    const OutputParameters defaults;
    prm.enter_subsection("Output");
    {
      prm.declare_entry("Directory",
                        defaults.directory,
                        Patterns::Anything(),
                        "Directory for all results (created if missing). "
                        "Units: none.");
      prm.declare_entry("Interval",
                        format_number(defaults.interval),
                        Patterns::Double(0),
                        "Simulated time between outputs (history row and "
                        "VTU files): an output at t = 0, after the first "
                        "step that reaches each multiple of it (at that "
                        "step's time, up to one step late; exactly at the "
                        "multiple with 'Exact output times'), and after the "
                        "last step; 0 writes every 'Step interval' steps. "
                        "Units: s.");
      prm.declare_entry(
        "Exact output times",
        bool_text(defaults.exact_output_times),
        Patterns::Bool(),
        "With 'Interval' > 0: shorten the step that would pass a multiple "
        "of 'Interval' so that it ends on it (the step before is shortened "
        "too when the rest is less than two steps, as at 'End time', so "
        "that no step is shorter than half the others); false: the output "
        "follows the first step that reaches the multiple, at its time. "
        "Units: none.");
      prm.declare_entry(
        "Tracked points",
        defaults.tracked_points,
        Patterns::Anything(),
        "Material points whose displacement u = x - X, velocity and Cauchy "
        "stress history.csv records at each row (columns trackN_ux, "
        "trackN_uy[, trackN_uz], trackN_vx, ..., trackN_sxx, trackN_syy, "
        "trackN_sxy in 2D (3D: sxx, syy, szz, sxy, sxz, syz), N = 1, 2, "
        "... in the order given; nan once the point has left the mesh). "
        "Entries separated by ';', each either a position (dim numbers "
        "separated by ',': the point nearest to it at the start, which "
        "must lie inside a body) or a point id (one integer). Empty: "
        "none. Units: m (positions).");
      prm.declare_entry("Step interval",
                        std::to_string(defaults.step_interval),
                        Patterns::Integer(0),
                        "Steps between outputs when 'Interval' is 0; 0 means "
                        "every step. Units: none.");
      prm.declare_entry("Write vtu",
                        bool_text(defaults.write_vtu),
                        Patterns::Bool(),
                        "Write particle and grid fields as VTU/PVTU with PVD "
                        "records for ParaView. Units: none.");
      prm.declare_entry("Compression",
                        compression_names.name(defaults.compression),
                        Patterns::Selection(compression_names.pattern()),
                        "zlib compression of the binary VTU data: 'best "
                        "speed' (files about as small as 'best compression' "
                        "at a fraction of its cost), 'best compression', "
                        "'default' (zlib's), or 'none'. Units: none.");
      prm.declare_entry(
        "Write particle csv",
        bool_text(defaults.write_particle_csv),
        Patterns::Bool(),
        "Write particles_NNNNN.csv at each output: one file gathered from "
        "all ranks, rows sorted by point id, columns id, body, material, "
        "position, velocity, Cauchy stress (2D: xx, yy, xy; 3D: xx, yy, zz, "
        "xy, xz, yz), pressure, J, internal_energy (per unit mass) and "
        "plastic_strain (0 where the model has none). Units: SI.");
      prm.declare_entry(
        "Write grid acceleration",
        bool_text(defaults.write_grid_acceleration),
        Patterns::Bool(),
        "Add the grid acceleration a = m~_k^-1 f + dv+/dt of [Nairn2023-FMPM] Eq. "
        "(4.1) (the series' acceleration of the forces plus the change the "
        "velocity conditions make) to the grid VTU as acceleration_x/y/z, "
        "for crack and J-integral codes; solved only in the steps before a "
        "grid output. With contact it is the centre-of-mass field (contact "
        "forces cancel in it). Units: none.");
      prm.declare_entry(
        "Track dissipated energy",
        bool_text(defaults.track_dissipation),
        Patterns::Bool(),
        "Sum the energy each particle update dissipates "
        "compared with a non-dissipative FLIP update "
        "([Nairn2018-extrap] Eqs. 1.44-1.50) and write it, accumulated, as "
        "the column dissipated_energy of history.csv. Costs "
        "two extra grid-to-point interpolations. Units: "
        "none.");
      prm.declare_entry("Progress interval",
                        format_number(defaults.progress_seconds),
                        Patterns::Double(0),
                        "Wall-clock seconds between progress lines on the "
                        "terminal. Units: s.");
    }
    prm.leave_subsection();
  }



  void
  OutputParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    directory               = prm.get("Directory");
    interval                = prm.get_double("Interval");
    step_interval           = prm.get_integer("Step interval");
    exact_output_times      = prm.get_bool("Exact output times");
    tracked_points          = prm.get("Tracked points");
    write_vtu               = prm.get_bool("Write vtu");
    compression             = compression_names.value(prm.get("Compression"));
    write_particle_csv      = prm.get_bool("Write particle csv");
    write_grid_acceleration = prm.get_bool("Write grid acceleration");
    progress_seconds        = prm.get_double("Progress interval");
    track_dissipation       = prm.get_bool("Track dissipated energy");
    prm.leave_subsection();
  }



  void
  CheckpointParameters::declare_parameters(ParameterHandler &prm)
  {
    const CheckpointParameters defaults;
    prm.enter_subsection("Checkpoint");
    {
      prm.declare_entry("Step interval",
                        std::to_string(defaults.step_interval),
                        Patterns::Integer(0),
                        "Write a checkpoint every this many steps into "
                        "<Output/Directory>/checkpoint/ (0: not by step "
                        "count). 'fmpm --resume scene.prm' continues from "
                        "the newest one. A checkpoint is also written when "
                        "the run receives SIGTERM or SIGINT, after which it "
                        "stops. Units: none.");
      prm.declare_entry("Wall time interval",
                        format_number(defaults.wall_time_interval),
                        Patterns::Double(0),
                        "Write a checkpoint whenever this much wall-clock "
                        "time has passed since the start or the last "
                        "checkpoint (0: not by wall time). Units: min.");
      prm.declare_entry("Keep",
                        std::to_string(defaults.keep),
                        Patterns::Integer(1),
                        "How many complete checkpoints to keep; older ones "
                        "are deleted once a new one is complete. Units: "
                        "none.");
    }
    prm.leave_subsection();
  }



  void
  CheckpointParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Checkpoint");
    step_interval      = prm.get_integer("Step interval");
    wall_time_interval = prm.get_double("Wall time interval");
    keep               = prm.get_integer("Keep");
    prm.leave_subsection();
  }



  void
  FailureParameters::declare_parameters(ParameterHandler &prm)
  {
    const FailureParameters defaults;
    prm.enter_subsection("Failure detection");
    {
      prm.declare_entry("Energy growth limit",
                        format_number(defaults.energy_growth_limit),
                        Patterns::Double(1),
                        "The run fails when the energy balance E - E0 - W "
                        "(W the work of walls and tractions; potential "
                        "energy from the initial configuration) exceeds "
                        "this factor minus 1 times the largest of the "
                        "scale of summary.json's energy_error (initial "
                        "kinetic + strain energy, energy exchanged, gross "
                        "external work), the work gravity can do across "
                        "the mesh's diagonal, and the kinetic energy of all "
                        "material at the fastest moving wall's speed. "
                        "Units: none.");
      prm.declare_entry(
        "Kinetic energy limit",
        format_number(defaults.kinetic_energy_limit),
        Patterns::Double(0),
        "The run fails when the kinetic energy exceeds this; 0: no limit. "
        "For quasi-static scenes (a slow piston, a compression test): an "
        "unstable method there shows as kinetic energy far above the "
        "quasi-static level while the total energy stays below the work the "
        "walls did, which the energy growth limit cannot see. Units: J (per "
        "unit thickness in 2D).");
      prm.declare_entry("Points leaving the mesh",
                        lost_points_names.name(defaults.lost_points),
                        Patterns::Selection(lost_points_names.pattern()),
                        "'stop': a point that leaves the mesh stops the run "
                        "with a message naming it; 'delete': such points are "
                        "removed and counted. Units: none.");
    }
    prm.leave_subsection();
  }



  void
  FailureParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Failure detection");
    energy_growth_limit  = prm.get_double("Energy growth limit");
    kinetic_energy_limit = prm.get_double("Kinetic energy limit");
    lost_points = lost_points_names.value(prm.get("Points leaving the mesh"));
    prm.leave_subsection();
  }



  void
  ReferenceSolutionParameters::declare_parameters(ParameterHandler  &prm,
                                                  const unsigned int dim)
  {
    const ReferenceSolutionParameters defaults;
    prm.enter_subsection("Reference solution");
    {
      prm.declare_entry("Enable",
                        bool_text(defaults.enable),
                        Patterns::Bool(),
                        "Measure the error of each output against the "
                        "analytical velocity and displacement below. "
                        "Units: none.");
      prm.declare_entry("Velocity",
                        first_components(defaults.velocity, dim),
                        Patterns::Anything(),
                        "Velocity as function of the initial position "
                        "(x, y, z) and time t (FunctionParser syntax, one "
                        "expression per component, separated by ';'). "
                        "Units: m/s.");
      prm.declare_entry("Displacement",
                        first_components(defaults.displacement, dim),
                        Patterns::Anything(),
                        "Displacement as function of the initial position "
                        "and t, as 'Velocity'. Units: m.");
      prm.declare_entry("Function constants",
                        defaults.constants,
                        Patterns::Anything(),
                        "Constants for the expressions, e.g. "
                        "'v0=0.1, omega=3.2'. Units: as used.");
    }
    prm.leave_subsection();
  }



  void
  ReferenceSolutionParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Reference solution");
    enable       = prm.get_bool("Enable");
    velocity     = prm.get("Velocity");
    displacement = prm.get("Displacement");
    constants    = prm.get("Function constants");
    prm.leave_subsection();
  }
} // namespace fmpm
