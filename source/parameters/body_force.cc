// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Body force and its Rotating frame.

#include <fmpm/parameters.h>

namespace fmpm
{
  void
  RotatingFrameParameters::declare_parameters(ParameterHandler  &prm,
                                              const unsigned int dim)
  {
    const RotatingFrameParameters defaults;
    prm.enter_subsection("Rotating frame");
    prm.declare_entry("Enable",
                      bool_text(defaults.enable),
                      Patterns::Bool(),
                      "Solve in a frame rotating with angular velocity w(t) "
                      "about 'Center': the body acceleration gains the "
                      "centrifugal -w x (w x r), Coriolis -2 w x V and Euler "
                      "-dw/dt x r terms ([Vaango-MPM], computing the body "
                      "force). Units: none.");
    prm.declare_entry("Angular velocity",
                      defaults.angular_velocity,
                      Patterns::Anything(),
                      "w(t): three numbers separated by ',' or three "
                      "expressions in t separated by ';' (in 2D only the z "
                      "component acts). Units: 1/s.");
    prm.declare_entry("Center",
                      list_text(defaults.center, dim),
                      point_pattern(dim),
                      "Centre of rotation. Units: m.");
    prm.declare_entry("Function constants",
                      defaults.constants,
                      Patterns::Anything(),
                      "Constants for 'Angular velocity'. Units: as used.");
    prm.leave_subsection();
  }



  void
  RotatingFrameParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Rotating frame");
    enable           = prm.get_bool("Enable");
    angular_velocity = prm.get("Angular velocity");
    center           = get_doubles(prm, "Center");
    constants        = prm.get("Function constants");
    prm.leave_subsection();
  }



  void
  Parameters::declare_body_force_parameters(ParameterHandler  &prm,
                                            const unsigned int dim)
  {
    const Parameters defaults;
    prm.enter_subsection("Body force");
    prm.declare_entry("Gravity",
                      list_text(defaults.gravity, dim),
                      point_pattern(dim),
                      "Gravitational acceleration b. Units: m/s^2.");
    prm.declare_entry("Acceleration",
                      defaults.body_acceleration,
                      Patterns::Anything(),
                      "An additional body acceleration b(x, y, z, t) at the "
                      "current point position, as dim FunctionParser "
                      "expressions separated by ';' (e.g. the body force of "
                      "a manufactured solution); empty for none. Its work is "
                      "not in the energy balance. Units: m/s^2.");
    prm.declare_entry("Function constants",
                      defaults.body_acceleration_constants,
                      Patterns::Anything(),
                      "Constants for the 'Acceleration' expressions, e.g. "
                      "'A=0.01, c=2'. Units: as used.");
    prm.declare_entry("Acceleration at initial position",
                      bool_text(defaults.body_acceleration_at_initial_position),
                      Patterns::Bool(),
                      "Evaluate 'Acceleration' at each point's initial "
                      "position X instead of its current position x (the "
                      "body force of a manufactured solution is a function "
                      "of X; exact at any deformation). Units: none.");
    RotatingFrameParameters::declare_parameters(prm, dim);
    prm.leave_subsection();
  }



  void
  Parameters::parse_body_force_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Body force");
    gravity                     = get_doubles(prm, "Gravity");
    body_acceleration           = prm.get("Acceleration");
    body_acceleration_constants = prm.get("Function constants");
    body_acceleration_at_initial_position =
      prm.get_bool("Acceleration at initial position");
    rotating_frame.parse_parameters(prm);
    prm.leave_subsection();
  }
} // namespace fmpm
