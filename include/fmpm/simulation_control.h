// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_simulation_control_h
#define fmpm_simulation_control_h

#include <fmpm/parameters.h>

#include <deal.II/base/mpi.h>

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace fmpm
{
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
      : end_time(time.end_time)
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
      archive &current_time &current_time_step &step &next_output_time
        &n_output;
    }

  private:
    bool
    reaches_end_time(const double t) const
    {
      return t >= end_time * (1 - 1e-12);
    }

    const double       end_time;
    const unsigned int max_steps;
    const double       output_interval;
    const unsigned int output_step_interval;
    const bool         exact_output_times;
    const unsigned int checkpoint_step_interval;
    const double       checkpoint_wall_interval;

    double       current_time      = 0;
    double       current_time_step = 0;
    unsigned int step              = 0;
    double       next_output_time  = 0;
    unsigned int n_output          = 0;
    unsigned int last_output_step  = std::numeric_limits<unsigned int>::max();
    double       last_checkpoint_wall = 0;
  };
} // namespace fmpm

#endif
