// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Boundary conditions: fixed and roller ids, moving walls, tractions.

#include <fmpm/parameters.h>

#include <cmath>

namespace fmpm
{
  void
  MovingWallParameters::declare_parameters(ParameterHandler  &prm,
                                           const unsigned int dim)
  {
    const MovingWallParameters defaults;
    prm.declare_entry("Boundary ids",
                      list_text(defaults.boundary_ids,
                                defaults.boundary_ids.size()),
                      Patterns::List(Patterns::Integer(0, 255)),
                      "Boundary ids whose nodes move with the wall; "
                      "leave empty to use 'Box lower/upper corner'. "
                      "Units: none.");
    prm.declare_entry("Box lower corner",
                      list_text(defaults.box_lower, defaults.box_lower.size()),
                      Patterns::List(Patterns::Double(), 0, dim, ","),
                      "Lower corner of the box region of the wall at "
                      "t = 0 (empty with 'Boundary ids'); the box moves "
                      "with the wall and material points do not enter "
                      "it. Units: m.");
    prm.declare_entry("Box upper corner",
                      list_text(defaults.box_upper, defaults.box_upper.size()),
                      Patterns::List(Patterns::Double(), 0, dim, ","),
                      "Upper corner of the box region at t = 0. "
                      "Units: m.");
    prm.declare_entry(
      "Region",
      defaults.region,
      Patterns::Anything(),
      "Or the wall as the nodes where this FunctionParser "
      "expression in x, y, z, t is positive (e.g. "
      "'0.2 + 0.1*t - x' for a plane moving along x); "
      "evaluated at set-up and after each mesh change, and every step "
      "only if it names t. A piston that drives a body should "
      "also take the node less than one cell inside the body's face "
      "(every node whose shape functions reach the piston), else the "
      "body lags behind it (parameters/shock_nickel.prm). Units: m.");
    prm.declare_entry("Direction",
                      list_text(defaults.direction, dim),
                      point_pattern(dim),
                      "Direction n of the prescribed velocity component "
                      "(normalized); other components are free. "
                      "Units: none.");
    prm.declare_entry("Velocity",
                      defaults.velocity,
                      Patterns::Anything(),
                      "Velocity v(x, t) along the direction, a "
                      "FunctionParser expression in x, y, z (the node's "
                      "position) and t (e.g. 'v0*min(t/t0, 1)', or "
                      "'rate*y' for a simple shear). Evaluated once if "
                      "constant, once per time if it names t only, and "
                      "at every node of the wall if it names x, y or z "
                      "(not with a box, which moves as a whole). "
                      "Units: m/s.");
    prm.declare_entry("Function constants",
                      defaults.constants,
                      Patterns::Anything(),
                      "Constants for 'Velocity' and 'Region', e.g. "
                      "'v0=0.1'. Units: as used.");
  }



  void
  MovingWallParameters::parse_parameters(ParameterHandler  &prm,
                                         const unsigned int dim,
                                         const std::string &where)
  {
    for (const double id : get_doubles(prm, "Boundary ids"))
      boundary_ids.push_back(static_cast<types::boundary_id>(id));
    box_lower                  = get_doubles(prm, "Box lower corner");
    box_upper                  = get_doubles(prm, "Box upper corner");
    region                     = prm.get("Region");
    direction                  = get_doubles(prm, "Direction");
    velocity                   = prm.get("Velocity");
    constants                  = prm.get("Function constants");
    const bool         has_box = !box_lower.empty() || !box_upper.empty();
    const unsigned int n_kinds = (boundary_ids.empty() ? 0 : 1) +
                                 (has_box ? 1 : 0) + (region.empty() ? 0 : 1);
    AssertThrow(n_kinds == 1,
                ExcMessage(where + ": set either 'Boundary ids' or both "
                                   "'Box lower corner' and 'Box upper "
                                   "corner' or 'Region', exactly one of "
                                   "them."));
    if (has_box)
      {
        AssertThrow(box_lower.size() == dim && box_upper.size() == dim,
                    ExcMessage(where +
                               "/Box lower corner and Box upper "
                               "corner need " +
                               std::to_string(dim) + " numbers each."));
        for (unsigned int d = 0; d < dim; ++d)
          AssertThrow(box_upper[d] > box_lower[d],
                      ExcMessage(where + "/Box upper corner must be above "
                                         "Box lower corner in every "
                                         "direction."));
      }
    double norm = 0;
    for (unsigned int d = 0; d < dim; ++d)
      norm += direction[d] * direction[d];
    AssertThrow(norm > 0, ExcMessage(where + "/Direction must not be zero."));
    for (unsigned int d = 0; d < dim; ++d)
      direction[d] /= std::sqrt(norm);
  }



  void
  TractionParameters::declare_parameters(ParameterHandler  &prm,
                                         const unsigned int dim)
  {
    const TractionParameters defaults;
    prm.declare_entry("Box lower corner",
                      list_text(defaults.box_lower, dim),
                      point_pattern(dim),
                      "Lower corner of the box that selects the loaded "
                      "material points (at t = 0). Units: m.");
    prm.declare_entry("Box upper corner",
                      list_text(defaults.box_upper, dim),
                      point_pattern(dim),
                      "Upper corner of that box. Units: m.");
    prm.declare_entry("Traction",
                      first_components(defaults.traction, dim),
                      Patterns::Anything(),
                      "Traction vector t(t) with its load curve: dim "
                      "numbers separated by ',' or dim expressions in "
                      "t separated by ';' (e.g. '-p0*min(t/t0,1); 0'). "
                      "Each selected point gets the force t times its "
                      "face area (Eq. 2.10, f_T). Units: Pa.");
    prm.declare_entry("Normal axis",
                      std::to_string(defaults.normal_axis),
                      Patterns::Integer(0, dim - 1),
                      "Axis of the loaded face's normal; a point's face "
                      "area is the product of its initial side lengths "
                      "along the other axes (Geometry = axisymmetric: "
                      "per radian, times the radius of the face: the "
                      "point's r for Normal axis = 1, its side r +- l_r "
                      "toward the box's centre for Normal axis = 0). "
                      "Units: none.");
    prm.declare_entry("Function constants",
                      defaults.constants,
                      Patterns::Anything(),
                      "Constants for 'Traction'. Units: as used.");
    prm.declare_entry(
      "Distribution",
      "point",
      Patterns::Selection("point|face"),
      "How a selected point's traction force reaches the nodes. 'point': "
      "the force t A_p through the point's own shape functions, at the "
      "point (Eq. 2.10, f_T). 'face': the traction integrated over the "
      "point's loaded face, f_i = integral of t N_i dA with the grid's "
      "linear N_i (Gauss points on the face, located in the mesh), the "
      "face being the point's side toward the box's centre, deformed by "
      "F; Geometry = axisymmetric: per radian, dA = r ds. This loads "
      "the nodes of the face itself (as NairnMPM does). Needs a shape "
      "function on the linear grid (classic, ugimp, cpgimp, cpdi) and no "
      "contact. Allowed: point, face.");
  }



  void
  TractionParameters::parse_parameters(ParameterHandler &prm)
  {
    box_lower   = get_doubles(prm, "Box lower corner");
    box_upper   = get_doubles(prm, "Box upper corner");
    traction    = prm.get("Traction");
    normal_axis = prm.get_integer("Normal axis");
    constants   = prm.get("Function constants");
    on_face     = prm.get("Distribution") == "face";
  }



  void
  BoundaryConditionParameters::declare_parameters(ParameterHandler &prm,
                                                  const SceneSize  &size)
  {
    const BoundaryConditionParameters defaults;
    prm.enter_subsection("Boundary conditions");
    {
      prm.declare_entry("Fixed boundary ids",
                        list_text(defaults.fixed, defaults.fixed.size()),
                        Patterns::List(Patterns::Integer(0, 255)),
                        "Boundary ids on which all grid velocity components "
                        "are zero. Units: none.");
      prm.declare_entry("Roller boundary ids",
                        list_text(defaults.roller, defaults.roller.size()),
                        Patterns::List(Patterns::Integer(0, 255)),
                        "Boundary ids on which the normal grid velocity is "
                        "zero (free slip, symmetry). Units: none.");
      prm.declare_entry("Fixed region",
                        defaults.fixed_region,
                        Patterns::Anything(),
                        "Clamp a region anywhere in the mesh: every grid "
                        "velocity component is zero at the nodes where "
                        "this FunctionParser expression in x, y, z, t is "
                        "positive (e.g. '0.01 - abs(x)' for the nodes "
                        "within 1 cm of x = 0); its reactions are reported "
                        "as 'fixed_region'. Empty: none. Units: m.");
      prm.declare_entry(
        "Method",
        defaults.method,
        Patterns::Selection("constrained|lumped|velocity|unlumped 1|"
                            "unlumped 2|collection full|collection partial"),
        "How velocity conditions are imposed when the mass matrix is not "
        "lumped ([Nairn2023-FMPM] Sec. 2.4): 'constrained': lumped momentum and "
        "force changes, and the condition values are known values of every "
        "full-mass solve (the least-squares problem with the conditions as "
        "constraints); 'lumped': Eq. 2.52 only; 'velocity': Eq. 2.53, grid "
        "velocities corrected after each solve; 'unlumped 1': Eqs. "
        "2.54-2.55, m~ times the lumped velocity change; 'unlumped 2': Eq. "
        "2.56, the mass matrix times the full-mass velocity change; "
        "'collection full': forces on the condition nodes from the "
        "n_BC x n_BC system (n_BC + 1 mass-matrix solves per stage); "
        "'collection partial': those forces with a lumped mass matrix. All "
        "reduce to 'lumped' with a lumped mass matrix except 'unlumped 1' "
        "(as [Nairn2023-FMPM] remarks). Units: none.");
      for (unsigned int w = 0; w < size.n_moving_walls; ++w)
        {
          prm.enter_subsection(numbered_subsection("Moving wall", w));
          MovingWallParameters::declare_parameters(prm, size.dimension);
          prm.leave_subsection();
        }
      for (unsigned int n = 0; n < size.n_tractions; ++n)
        {
          prm.enter_subsection(numbered_subsection("Traction", n));
          TractionParameters::declare_parameters(prm, size.dimension);
          prm.leave_subsection();
        }
    }
    prm.leave_subsection();
  }



  void
  BoundaryConditionParameters::parse_parameters(ParameterHandler &prm,
                                                const SceneSize  &size)
  {
    prm.enter_subsection("Boundary conditions");
    for (const double id : get_doubles(prm, "Fixed boundary ids"))
      fixed.push_back(static_cast<types::boundary_id>(id));
    for (const double id : get_doubles(prm, "Roller boundary ids"))
      roller.push_back(static_cast<types::boundary_id>(id));
    fixed_region = prm.get("Fixed region");
    method       = prm.get("Method");
    moving_walls.resize(size.n_moving_walls);
    for (unsigned int w = 0; w < size.n_moving_walls; ++w)
      {
        prm.enter_subsection(numbered_subsection("Moving wall", w));
        moving_walls[w].parse_parameters(prm,
                                         size.dimension,
                                         "Boundary conditions/" +
                                           numbered_subsection("Moving wall",
                                                               w));
        prm.leave_subsection();
      }
    tractions.resize(size.n_tractions);
    for (unsigned int n = 0; n < size.n_tractions; ++n)
      {
        prm.enter_subsection(numbered_subsection("Traction", n));
        tractions[n].parse_parameters(prm);
        prm.leave_subsection();
      }
    prm.leave_subsection();
  }
} // namespace fmpm
