// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_simulation_control_h
#define fmpm_simulation_control_h

#include <fmpm/parameters.h>
#include <fmpm/time_step_stability.h>

#include <deal.II/base/mpi.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace fmpm
{
  /**
   * @brief The rule of the time step: a fixed Time/Time step, or the
   * Courant condition dt = min(C, C_max) h_min / (c + |v|)_max with the
   * Courant number C of the scene and the method's measured limit C_max
   * (StabilityLimit), and the warnings the method and a fixed step carry.
   */
  class TimeStepRule
  {
  public:
    explicit TimeStepRule(const TimeParameters &time)
      : fixed_time_step(time.time_step)
      , courant_number(time.courant_number)
      , courant_limit(time.courant_limit)
      , check_stability(time.check_stability)
    {}

    /** The method's limit (MassMatrix::Interface::stability_limit()); a
     * Time/Courant number limit replaces it, naming it in the basis. */
    void
    set_method_limit(const StabilityLimit &method_limit)
    {
      limit = method_limit;
      if (courant_limit > 0)
        {
          limit.basis =
            "Time/Courant number limit (the method's: " +
            (std::isfinite(limit.max_courant) ?
               format_number(limit.max_courant, 3) + ", " + limit.basis :
               std::string("none")) +
            ")";
          limit.max_courant = courant_limit;
        }
      method_warning = limit.warning;
      method_warning_only_with_free_surfaces =
        limit.warning_only_with_free_surfaces;
    }

    /** The step before the clamps: the fixed one, or the Courant
     * condition with the signal speed @p signal_speed (m/s) on cells of
     * smallest edge @p h_min (m). Units: s. */
    double
    time_step(const double signal_speed, const double h_min) const
    {
      if (fixed_time_step != 0)
        return fixed_time_step;
      return std::min(courant_number, limit.max_courant) * h_min / signal_speed;
    }

    /** Empty when the fixed step is stable, else why not (h_min / (c +
     * |v|) with the signal speed and h_min of the scene at set-up or of
     * the mesh after an adaptation @p adapted_mesh). At set-up, a fixed
     * step above the method's limit is warned of. */
    std::string
    check_fixed_time_step(const double signal_speed,
                          const double h_min,
                          const bool   adapted_mesh)
    {
      const double stable = h_min / signal_speed;
      if (adapted_mesh)
        {
          if (fixed_time_step > 0 && check_stability &&
              fixed_time_step > stable)
            return "Time/Time step = " + format_number(fixed_time_step) +
                   " s is above the stable limit h_min / (wave speed + point "
                   "speed) = " +
                   format_number(stable, 6) +
                   " s of the adapted mesh. Choose a smaller time step, a "
                   "lower Mesh refinement/Maximum level, or Time/Courant "
                   "number.";
          return "";
        }
      if (check_stability && fixed_time_step > stable)
        return "Time/Time step = " + format_number(fixed_time_step) +
               " s is above the stable limit h_min / (wave speed "
               "+ point speed) = " +
               format_number(stable, 6) +
               " s of this scene. Choose a smaller time step, or "
               "set it to 0 and use Time/Courant number (or set Time/Check "
               "stability limit = false for a stability study).";
      if (fixed_time_step > limit.max_courant * stable)
        fixed_step_warning =
          "Time/Time step = " + format_number(fixed_time_step) +
          " s is above this method's stable limit, its critical Courant "
          "number " +
          format_number(limit.max_courant, 3) +
          " x h_min / (wave speed + point speed) = " +
          format_number(limit.max_courant * stable, 6) +
          " s; set Time step = 0 to use Time/Courant number.";
      return "";
    }

    /** Bodies that fill every cell of the mesh have no free surface: the
     * method's warning about free surfaces does not apply. */
    void
    no_free_surfaces()
    {
      if (method_warning_only_with_free_surfaces)
        method_warning.clear();
    }

    /** Whether the method's warning is about free surfaces only. */
    bool
    method_warning_needs_free_surfaces() const
    {
      return method_warning_only_with_free_surfaces;
    }

    /** The warnings of the run: the method's, then the fixed step's. */
    std::vector<std::string>
    warnings() const
    {
      std::vector<std::string> list;
      for (const std::string *w : {&method_warning, &fixed_step_warning})
        if (!w->empty())
          list.push_back(*w);
      return list;
    }

    /** The run header's line of the automatic step ("Courant number C",
     * and the cap when C is above it); empty for a fixed step. */
    std::string
    description() const
    {
      if (fixed_time_step != 0)
        return "";
      std::string text =
        "time step: Courant number " + format_number(courant_number);
      if (courant_number > limit.max_courant)
        text += " capped at the method's limit " +
                format_number(limit.max_courant, 3) + " (" + limit.basis + ")";
      return text;
    }

    /** The limit and its basis ("0.12, full mass matrix ..."). */
    std::string
    limit_description() const
    {
      return format_number(limit.max_courant, 3) + ", " + limit.basis;
    }

    /** A setting to consider when a run fails (StabilityLimit::note). */
    const std::string &
    note() const
    {
      return limit.note;
    }

  private:
    const double   fixed_time_step;
    const double   courant_number;
    const double   courant_limit;
    const bool     check_stability;
    StabilityLimit limit;
    std::string    method_warning;
    bool           method_warning_only_with_free_surfaces = false;
    std::string    fixed_step_warning;
  };



  /**
   * @brief Time, step number and time step of a run, and its schedules:
   * when the run ends, when it writes output (Output/Interval or Step
   * interval) and when it checkpoints (Checkpoint/Step interval, Wall time
   * interval). Checkpoints serialize it whole.
   */
  class SimulationControl
  {
  public:
    SimulationControl(const TimeParameters       &time,
                      const OutputParameters     &output,
                      const CheckpointParameters &checkpoint)
      : rule(time)
      , end_time(time.end_time)
      , max_steps(time.max_steps)
      , output_interval(output.interval)
      , output_step_interval(std::max(1u, output.step_interval))
      , exact_output_times(output.exact_output_times)
      , checkpoint_step_interval(checkpoint.step_interval)
      , checkpoint_wall_interval(60 * checkpoint.wall_time_interval)
    {}

    /** The time t^n of the current step's start. Units: s. */
    double
    time() const
    {
      return current_time;
    }

    /** The time step Δt of the current step. Units: s. */
    double
    time_step() const
    {
      return current_time_step;
    }

    /** The number of steps taken. */
    unsigned int
    step_number() const
    {
      return step;
    }

    /** The rule of the time step (set-up: the method's limit, the checks
     * of a fixed step; the header and the warnings). */
    TimeStepRule &
    time_step_rule()
    {
      return rule;
    }

    const TimeStepRule &
    time_step_rule() const
    {
      return rule;
    }

    /**
     * Δt of the step about to be taken: the rule's step with the signal
     * speed @p signal_speed (m/s) and the smallest edge @p h_min (m), not
     * past End time nor, with Output/Exact output times, past the next
     * output time. When less than two steps remain it takes the rest in
     * two equal steps (no tiny last step). Units: s.
     */
    double
    calculate_time_step(const double signal_speed, const double h_min)
    {
      double       dt = rule.time_step(signal_speed, h_min);
      const double rest =
        std::min(end_time - current_time, time_to_next_output());
      if (rest < dt * (1 + 1e-12))
        dt = rest;
      else if (rest < 2 * dt)
        dt = rest / 2;
      current_time_step = dt;
      return dt;
    }

    /** The largest wave speed + point speed over the points at the end
     * of the last step (the signal speed of the next Δt). Units: m/s. */
    double
    signal_speed() const
    {
      return max_signal_speed;
    }

    void
    set_signal_speed(const double speed)
    {
      max_signal_speed = speed;
    }

    /** The smallest edge h_min of the mesh's cells (set with the mesh; the
     * Courant condition's length). Units: m. */
    double
    minimum_cell_size() const
    {
      return min_cell_size;
    }

    void
    set_minimum_cell_size(const double h_min)
    {
      min_cell_size = h_min;
    }

    /** Set Δt for the step about to be taken. */
    void
    set_time_step(const double dt)
    {
      current_time_step = dt;
    }

    /** t += Δt, one more step. */
    void
    advance()
    {
      current_time += current_time_step;
      ++step;
    }

    /** Whether the time reached End time (up to round-off). */
    bool
    reached_end_time() const
    {
      return reaches_end_time(current_time);
    }

    /** Whether the run stops: End time or Maximum number of steps. */
    bool
    finished() const
    {
      return reached_end_time() || step >= max_steps;
    }

    unsigned int
    max_number_of_steps() const
    {
      return max_steps;
    }

    /** Whether output is due at time @p t after step @p step_number. */
    bool
    output_due(const double t, const unsigned int step_number) const
    {
      if (output_interval > 0)
        return t >= next_output_time * (1 - 1e-12);
      return step_number % output_step_interval == 0;
    }

    /** The time from now to the next output time when the steps land on
     * the output times (Output/Exact output times with Output/Interval >
     * 0), else infinity. Units: s. */
    double
    time_to_next_output() const
    {
      if (output_interval > 0 && exact_output_times)
        return next_output_time - current_time;
      return std::numeric_limits<double>::infinity();
    }

    /** Whether output is due now. */
    bool
    output_due_now() const
    {
      return output_due(current_time, step);
    }

    /** Whether output follows the step of length @p dt about to be taken
     * (the schedule's, or the run's last step). */
    bool
    output_follows_step(const double dt) const
    {
      return output_due(current_time + dt, step + 1) ||
             reaches_end_time(current_time + dt) || step + 1 >= max_steps;
    }

    /** Output was written now: the next output time passes t, the output
     * count grows. */
    void
    output_written()
    {
      if (output_interval > 0)
        while (next_output_time <= current_time * (1 + 1e-12))
          next_output_time += output_interval;
      last_output_step = step;
    }

    /** The number of the next output file (outputs written so far). */
    unsigned int
    output_number() const
    {
      return n_output;
    }

    /** One more output file was written. */
    void
    count_output()
    {
      ++n_output;
    }

    /** Whether the last output was written at the current step. */
    bool
    output_written_now() const
    {
      return last_output_step == step;
    }

    /** Whether Checkpoint/Step interval asks for one after this step. */
    bool
    checkpoint_step_due() const
    {
      return checkpoint_step_interval > 0 &&
             step % checkpoint_step_interval == 0;
    }

    /** Whether Checkpoint/Wall time interval has passed since the last
     * checkpoint_written() (@p wall_time: MPI_Wtime() now; ranks may
     * disagree, the caller reduces). */
    bool
    checkpoint_wall_time_due(const double wall_time) const
    {
      return checkpoint_wall_interval > 0 &&
             wall_time - last_checkpoint_wall >= checkpoint_wall_interval;
    }

    /** A checkpoint was written (or the run started) at @p wall_time. */
    void
    checkpoint_written(const double wall_time)
    {
      last_checkpoint_wall = wall_time;
    }

    /** What a checkpoint keeps (the schedule's settings come from the
     * scene). */
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &current_time &current_time_step &step &next_output_time &n_output
        &max_signal_speed;
    }

  private:
    bool
    reaches_end_time(const double t) const
    {
      return t >= end_time * (1 - 1e-12);
    }

    TimeStepRule       rule;
    const double       end_time;
    const unsigned int max_steps;
    const double       output_interval;
    const unsigned int output_step_interval;
    const bool         exact_output_times;
    const unsigned int checkpoint_step_interval;
    const double       checkpoint_wall_interval;

    double       current_time      = 0;
    double       current_time_step = 0;
    double       max_signal_speed  = 0;
    double       min_cell_size     = 0;
    unsigned int step              = 0;
    double       next_output_time  = 0;
    unsigned int n_output          = 0;
    unsigned int last_output_step  = std::numeric_limits<unsigned int>::max();
    double       last_checkpoint_wall = 0;
  };
} // namespace fmpm

#endif
