// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks SimulationControl's time step: the Courant condition
// dt = min(C, C_max) h_min / (c + |v|)_max, the method's cap and a Time/Courant
// number limit in its place, a fixed Time/Time step, the End time clamp with
// the rest split in two equal steps when less than two remain, the steps
// shortened to land on Output/Exact output times, and the warnings and errors
// of a fixed step.

#include <fmpm/parameters.h>
#include <fmpm/simulation_control.h>
#include <fmpm/time_step_stability.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  struct Settings
  {
    fmpm::TimeParameters       time;
    fmpm::OutputParameters     output;
    fmpm::CheckpointParameters checkpoint;
  };

  fmpm::StabilityLimit
  capped_at(const double max_courant, const std::string &basis)
  {
    fmpm::StabilityLimit limit;
    limit.max_courant = max_courant;
    limit.basis       = basis;
    return limit;
  }

  /** The steps a run takes to its end (at most @p max_steps) with a
   * constant signal speed and h_min, writing output when due. */
  std::vector<double>
  steps_to_end(fmpm::SimulationControl &control,
               const double             signal_speed,
               const double             h_min,
               const unsigned int       max_steps = 100)
  {
    std::vector<double> steps;
    control.output_written();
    while (!control.finished() && steps.size() < max_steps)
      {
        steps.push_back(control.calculate_time_step(signal_speed, h_min));
        control.advance();
        if (control.output_due_now())
          control.output_written();
      }
    return steps;
  }



  TEST(SimulationControl, CourantCondition)
  {
    Settings s;
    s.time.courant_number = 0.5;
    s.time.end_time       = 1;
    fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
    control.time_step_rule().set_method_limit(
      fmpm::Stability::lumped_mass_matrix_limit());
    // h_min = 0.1 m, c + |v| = 2000 m/s: dt = 0.5 * 0.1 / 2000.
    EXPECT_EQ(control.calculate_time_step(2000, 0.1), 0.5 * 0.1 / 2000);
    EXPECT_EQ(control.time_step(), 2.5e-5);
    // Twice the signal speed halves the step; half the cells halve it too.
    EXPECT_DOUBLE_EQ(control.calculate_time_step(4000, 0.1), 1.25e-5);
    EXPECT_DOUBLE_EQ(control.calculate_time_step(2000, 0.05), 1.25e-5);
    EXPECT_EQ(control.time_step_rule().description(),
              "time step: Courant number 0.5");
    EXPECT_TRUE(control.time_step_rule().warnings().empty());
  }



  TEST(SimulationControl, MethodCapsTheCourantNumber)
  {
    Settings s;
    s.time.courant_number = 0.5;
    fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
    control.time_step_rule().set_method_limit(
      capped_at(0.12, "full mass matrix"));
    EXPECT_DOUBLE_EQ(control.calculate_time_step(1000, 0.1), 0.12 * 0.1 / 1000);
    EXPECT_EQ(control.time_step_rule().description(),
              "time step: Courant number 0.5 capped at the method's limit "
              "0.12 (full mass matrix)");
    EXPECT_EQ(control.time_step_rule().limit_description(),
              "0.12, full mass matrix");

    // A Courant number below the cap is taken as it is.
    s.time.courant_number = 0.1;
    fmpm::SimulationControl below(s.time, s.output, s.checkpoint);
    below.time_step_rule().set_method_limit(
      capped_at(0.12, "full mass matrix"));
    EXPECT_DOUBLE_EQ(below.calculate_time_step(1000, 0.1), 0.1 * 0.1 / 1000);
    EXPECT_EQ(below.time_step_rule().description(),
              "time step: Courant number 0.1");
  }



  TEST(SimulationControl, CourantNumberLimitReplacesTheMethods)
  {
    Settings s;
    s.time.courant_number = 0.5;
    s.time.courant_limit  = 0.3;
    fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
    control.time_step_rule().set_method_limit(
      capped_at(0.12, "full mass matrix"));
    EXPECT_DOUBLE_EQ(control.calculate_time_step(1000, 0.1), 0.3 * 0.1 / 1000);
    EXPECT_EQ(control.time_step_rule().limit_description(),
              "0.3, Time/Courant number limit (the method's: 0.12, full mass "
              "matrix)");

    // No limit of the method: the basis says so.
    fmpm::SimulationControl lumped(s.time, s.output, s.checkpoint);
    lumped.time_step_rule().set_method_limit(
      fmpm::Stability::lumped_mass_matrix_limit());
    EXPECT_DOUBLE_EQ(lumped.calculate_time_step(1000, 0.1), 0.3 * 0.1 / 1000);
    EXPECT_EQ(lumped.time_step_rule().limit_description(),
              "0.3, Time/Courant number limit (the method's: none)");
  }



  TEST(SimulationControl, FixedTimeStep)
  {
    Settings s;
    s.time.time_step = 1e-5;
    fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
    control.time_step_rule().set_method_limit(
      capped_at(0.12, "full mass matrix"));
    EXPECT_EQ(control.calculate_time_step(1000, 0.1), 1e-5);
    EXPECT_EQ(control.calculate_time_step(1e6, 0.1), 1e-5);
    EXPECT_EQ(control.time_step_rule().description(), "");
  }



  TEST(SimulationControl, EndTimeClampAndHalfSteps)
  {
    Settings s;
    s.time.end_time  = 1;
    s.time.time_step = 0.25;
    {
      // The steps divide the interval: four of 0.25 land on End time.
      fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
      const auto              steps = steps_to_end(control, 1, 1);
      ASSERT_EQ(steps.size(), 4u);
      for (const double dt : steps)
        EXPECT_DOUBLE_EQ(dt, 0.25);
      EXPECT_TRUE(control.reached_end_time());
    }
    {
      // 0.4, then 0.6 is left: less than two steps, so two of 0.3 (not
      // 0.4 and a short 0.2).
      s.time.time_step = 0.4;
      fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
      const auto              steps = steps_to_end(control, 1, 1);
      ASSERT_EQ(steps.size(), 3u);
      EXPECT_DOUBLE_EQ(steps[0], 0.4);
      EXPECT_DOUBLE_EQ(steps[1], 0.3);
      EXPECT_DOUBLE_EQ(steps[2], 0.3);
      EXPECT_DOUBLE_EQ(control.time(), 1);
    }
    {
      // A step longer than the run is clamped to End time.
      s.time.time_step = 5;
      fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
      const auto              steps = steps_to_end(control, 1, 1);
      ASSERT_EQ(steps.size(), 1u);
      EXPECT_DOUBLE_EQ(steps[0], 1);
    }
    {
      // Maximum number of steps stops the run before End time.
      s.time.time_step = 0.1;
      s.time.max_steps = 3;
      fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
      EXPECT_EQ(steps_to_end(control, 1, 1).size(), 3u);
      EXPECT_FALSE(control.reached_end_time());
      EXPECT_TRUE(control.finished());
    }
  }



  TEST(SimulationControl, ExactOutputTimes)
  {
    Settings s;
    s.time.end_time             = 0.5;
    s.time.time_step            = 0.1;
    s.output.interval           = 0.25;
    s.output.exact_output_times = true;
    {
      // 0.1, then 0.15 to the output at 0.25 in two steps of 0.075; the
      // same to 0.5.
      fmpm::SimulationControl   control(s.time, s.output, s.checkpoint);
      const auto                steps    = steps_to_end(control, 1, 1);
      const std::vector<double> expected = {
        0.1, 0.075, 0.075, 0.1, 0.075, 0.075};
      ASSERT_EQ(steps.size(), expected.size());
      for (unsigned int n = 0; n < steps.size(); ++n)
        EXPECT_NEAR(steps[n], expected[n], 1e-15) << "step " << n;
      EXPECT_DOUBLE_EQ(control.time(), 0.5);
    }
    {
      // Without exact output times only End time shortens a step.
      s.output.exact_output_times = false;
      fmpm::SimulationControl   control(s.time, s.output, s.checkpoint);
      const auto                steps    = steps_to_end(control, 1, 1);
      const std::vector<double> expected = {0.1, 0.1, 0.1, 0.1, 0.1};
      ASSERT_EQ(steps.size(), expected.size());
      for (unsigned int n = 0; n < steps.size(); ++n)
        EXPECT_NEAR(steps[n], expected[n], 1e-15) << "step " << n;
    }
  }



  TEST(SimulationControl, FixedStepChecksAndWarnings)
  {
    Settings s;
    // h_min / (c + |v|) = 0.1 / 1000 = 1e-4 s.
    s.time.time_step = 2e-4;
    {
      fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
      control.time_step_rule().set_method_limit(
        capped_at(0.12, "full mass matrix"));
      const std::string error =
        control.time_step_rule().check_fixed_time_step(1000, 0.1, false);
      EXPECT_NE(error.find("Time/Time step = 0.0002 s is above the stable "
                           "limit"),
                std::string::npos)
        << error;
      EXPECT_NE(control.time_step_rule()
                  .check_fixed_time_step(1000, 0.1, true)
                  .find("of the adapted mesh"),
                std::string::npos);
      // A stable step passes both checks.
      EXPECT_EQ(control.time_step_rule().check_fixed_time_step(1000, 1, false),
                "");
      EXPECT_EQ(control.time_step_rule().check_fixed_time_step(1000, 1, true),
                "");
    }
    {
      // Below h_min / (c + |v|) but above the method's 0.12 of it: a
      // warning, no error.
      s.time.time_step           = 5e-5;
      fmpm::StabilityLimit limit = capped_at(0.12, "full mass matrix");
      limit.warning              = "FLIP with the full mass matrix fails.";
      limit.warning_only_with_free_surfaces = true;
      fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
      control.time_step_rule().set_method_limit(limit);
      EXPECT_EQ(
        control.time_step_rule().check_fixed_time_step(1000, 0.1, false), "");
      auto warnings = control.time_step_rule().warnings();
      ASSERT_EQ(warnings.size(), 2u);
      EXPECT_EQ(warnings[0], limit.warning);
      EXPECT_NE(warnings[1].find("above this method's stable limit, its "
                                 "critical Courant number 0.12"),
                std::string::npos)
        << warnings[1];
      // Without free surfaces only the fixed step's warning remains.
      EXPECT_TRUE(
        control.time_step_rule().method_warning_needs_free_surfaces());
      control.time_step_rule().no_free_surfaces();
      warnings = control.time_step_rule().warnings();
      ASSERT_EQ(warnings.size(), 1u);
      EXPECT_NE(warnings[0].find("critical Courant number"), std::string::npos);
    }
    {
      // Time/Check stability limit = false: no error above the limit.
      s.time.time_step       = 2e-4;
      s.time.check_stability = false;
      fmpm::SimulationControl control(s.time, s.output, s.checkpoint);
      control.time_step_rule().set_method_limit(
        fmpm::Stability::lumped_mass_matrix_limit());
      EXPECT_EQ(
        control.time_step_rule().check_fixed_time_step(1000, 0.1, false), "");
      EXPECT_EQ(control.time_step_rule().check_fixed_time_step(1000, 0.1, true),
                "");
    }
  }
} // namespace
