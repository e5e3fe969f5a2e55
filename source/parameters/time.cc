// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Time.

#include <fmpm/parameters.h>

#include <cmath>
#include <cstdlib>
#include <limits>

namespace fmpm
{
  namespace
  {

    /** 'Time/Courant number limit' of TimeParameters::courant_limit. */
    std::string
    courant_limit_text(const double courant_limit)
    {
      if (courant_limit == 0)
        return "auto";
      return std::isinf(courant_limit) ? "none" : format_number(courant_limit);
    }
  } // namespace



  void
  TimeParameters::declare_parameters(ParameterHandler &prm)
  {
    const TimeParameters defaults;
    prm.enter_subsection("Time");
    {
      prm.declare_entry("End time",
                        format_number(defaults.end_time),
                        Patterns::Double(0),
                        "Time at which the run stops. Units: s.");
      prm.declare_entry("Time step",
                        format_number(defaults.time_step),
                        Patterns::Double(0),
                        "Fixed time step; 0 chooses it every step from the "
                        "Courant number. Must not exceed the stable limit "
                        "h_min / (wave speed + point speed). Units: s.");
      prm.declare_entry("Courant number",
                        format_number(defaults.courant_number),
                        Patterns::Double(0, 10),
                        "The automatic time step (used when 'Time step' is "
                        "0) as a fraction of the cell-crossing time: dt = C "
                        "h_min / (largest wave speed + largest point "
                        "speed), as in the MPM literature, capped at the "
                        "method's measured critical Courant number ('Courant "
                        "number limit'). Values above 1 exceed the stable "
                        "limit of lumped-mass MPM and are only accepted "
                        "with 'Check stability limit = false' (stability "
                        "studies). Units: none.");
      prm.declare_entry(
        "Courant number limit",
        courant_limit_text(defaults.courant_limit),
        Patterns::Anything(),
        "The largest Courant number the automatic time step uses. 'auto': "
        "the measured critical Courant number of the chosen mass matrix, "
        "its order, particle update, strain update, strain-update mass "
        "matrix and shape function (doc/studies/stability.md: none for the "
        "lumped mass matrix, 0.5 to 0.9 for FMPM(k) of k = 2 to 10, "
        "1.18/sqrt(k) above with CPDI or with GIMP and USAVG, min(0.12, "
        "2.56/k) otherwise, 0.12 for the exact full mass matrix, with "
        "full-mass strain velocities); the run says "
        "so when it caps 'Courant number'. 'none': no cap (stability "
        "studies that measure the limits). Or a number > 0, a cap of your "
        "own. Units: none.");
      prm.declare_entry("Check stability limit",
                        bool_text(defaults.check_stability),
                        Patterns::Bool(),
                        "Refuse a 'Time step' or 'Courant number' above the "
                        "stable limit h_min / (wave speed + point speed). "
                        "Stability studies switch this off to find where "
                        "methods fail. Units: none.");
      prm.declare_entry("Maximum number of steps",
                        std::to_string(defaults.max_steps),
                        Patterns::Integer(1),
                        "The run stops after this many steps even before "
                        "'End time'. Units: none.");
    }
    prm.leave_subsection();
  }



  void
  TimeParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Time");
    end_time        = prm.get_double("End time");
    time_step       = prm.get_double("Time step");
    courant_number  = prm.get_double("Courant number");
    max_steps       = prm.get_integer("Maximum number of steps");
    check_stability = prm.get_bool("Check stability limit");
    const std::string courant_limit_value = prm.get("Courant number limit");
    prm.leave_subsection();
    if (courant_limit_value == "auto")
      courant_limit = 0;
    else if (courant_limit_value == "none")
      courant_limit = std::numeric_limits<double>::infinity();
    else
      {
        char *end     = nullptr;
        courant_limit = std::strtod(courant_limit_value.c_str(), &end);
        AssertThrow(end != courant_limit_value.c_str() && *end == '\0' &&
                      courant_limit > 0 && std::isfinite(courant_limit),
                    ExcMessage("Time/Courant number limit = <" +
                               courant_limit_value +
                               "> is not allowed. Allowed: 'auto' (the "
                               "method's measured limit), 'none' or a "
                               "number > 0."));
      }
    AssertThrow(!check_stability || courant_number <= 1,
                ExcMessage(
                  "Time/Courant number = " + format_number(courant_number) +
                  " is above the stable limit 1. Allowed: (0, 1], "
                  "or set Time/Check stability limit = false."));
    AssertThrow(time_step > 0 || courant_number > 0,
                ExcMessage("Time/Time step and Time/Courant number are both "
                           "0: set one of them to a positive value."));
  }
} // namespace fmpm
