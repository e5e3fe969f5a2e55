// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/constitutive_model/interface.h>
#include <fmpm/geometry/body_shape.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_update/interface.h>
#include <fmpm/shape_function.h>

#include <deal.II/base/numbers.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <limits>
#include <sstream>

namespace fmpm
{
  namespace
  {
    std::string
    join(const std::vector<double> &values, const unsigned int n)
    {
      std::ostringstream out;
      for (unsigned int i = 0; i < n; ++i)
        out << (i ? ", " : "") << format_number(values[i]);
      return out.str();
    }

    std::string
    join(const std::vector<unsigned int> &values, const unsigned int n)
    {
      std::ostringstream out;
      for (unsigned int i = 0; i < n; ++i)
        out << (i ? ", " : "") << values[i];
      return out.str();
    }

    /** A list of exactly @p dim doubles. */
    Patterns::List
    point_pattern(const unsigned int dim)
    {
      return Patterns::List(Patterns::Double(), dim, dim, ",");
    }

    std::vector<double>
    get_doubles(ParameterHandler &prm, const std::string &name)
    {
      return Utilities::string_to_double(
        Utilities::split_string_list(prm.get(name)));
    }

    /** The message of a deal.II exception without its source location. */
    std::string
    message_of(const ExceptionBase &e)
    {
      std::ostringstream out;
      e.print_info(out);
      // Drop the indentation and trailing newlines deal.II adds.
      std::string text  = out.str();
      const auto  first = text.find_first_not_of(" \n\t");
      const auto  last  = text.find_last_not_of(" \n\t");
      return first == std::string::npos ? text :
                                          text.substr(first, last - first + 1);
    }

    /** The text of a boolean default: "true" or "false". */
    std::string
    bool_text(const bool value)
    {
      return value ? "true" : "false";
    }

    /** The first @p n entries of the list @p text ("0, 0, 0" -> "0, 0"). */
    std::string
    first_components(const std::string &text, const unsigned int n)
    {
      const std::vector<std::string> entries =
        Utilities::split_string_list(text, ',');
      std::string result;
      for (unsigned int i = 0; i < n && i < entries.size(); ++i)
        result += (i ? ", " : "") + entries[i];
      return result;
    }

    /** 'Time/Courant number limit' of TimeParameters::courant_limit. */
    std::string
    courant_limit_text(const double courant_limit)
    {
      if (courant_limit == 0)
        return "auto";
      return std::isinf(courant_limit) ? "none" : format_number(courant_limit);
    }
  } // namespace



  std::map<std::string, double>
  parse_function_constants(const std::string &text, const std::string &where)
  {
    // pi is always available in the expressions.
    std::map<std::string, double> constants{{"pi", numbers::PI}};
    for (const auto &entry : Utilities::split_string_list(text, ','))
      {
        const auto pair = Utilities::split_string_list(entry, '=');
        AssertThrow(pair.size() == 2,
                    ExcMessage(where + ": <" + entry +
                               "> is not of the form name=value."));
        constants[pair[0]] = Utilities::string_to_double(pair[1]);
      }
    return constants;
  }



  std::string
  to_function_expressions(const std::string &value)
  {
    if (value.find(';') != std::string::npos)
      return value;
    std::string result;
    for (const auto &component : Utilities::split_string_list(value, ','))
      result += (result.empty() ? "" : ";") + component;
    return result;
  }



  std::string
  error_message(const std::exception &e)
  {
    if (const auto *deal_ii = dynamic_cast<const ExceptionBase *>(&e))
      return message_of(*deal_ii);
    return e.what();
  }



  std::string
  format_number(const double value, const unsigned int max_digits)
  {
    if (!std::isfinite(value))
      return std::isnan(value) ? "nan" : (value > 0 ? "inf" : "-inf");
    // The fewest significant digits that read back as the same double
    // (17 always do).
    std::string text;
    for (unsigned int digits = 1; digits <= std::min(max_digits, 17u); ++digits)
      {
        std::ostringstream out;
        out << std::setprecision(digits) << value;
        text = out.str();
        if (std::strtod(text.c_str(), nullptr) == value)
          break;
      }
    // "1e+308" -> "1e308", "1e-05" -> "1e-5".
    const auto e = text.find('e');
    if (e == std::string::npos)
      return text;
    // Below 1e6 without exponent: "10", "1500", not "1e1", "1.5e3".
    const int exponent_value = std::atoi(text.c_str() + e + 1);
    if (exponent_value >= 0 && exponent_value < 6)
      {
        std::ostringstream out;
        // %g switches to an exponent only at precision <= exponent.
        out << std::setprecision(exponent_value + 1) << value;
        return out.str();
      }
    std::string exponent = text.substr(e + 1);
    const bool  negative = !exponent.empty() && exponent[0] == '-';
    if (!exponent.empty() && (exponent[0] == '-' || exponent[0] == '+'))
      exponent.erase(0, 1);
    exponent.erase(0,
                   std::min(exponent.find_first_not_of('0'),
                            exponent.size() - 1));
    return text.substr(0, e + 1) + (negative ? "-" : "") + exponent;
  }



  std::string
  numbered_subsection(const std::string &name, const unsigned int index)
  {
    return name + " " + std::to_string(index);
  }



  void
  SceneSize::declare_parameters(ParameterHandler &prm)
  {
    const SceneSize defaults;
    prm.declare_entry("Dimension",
                      std::to_string(defaults.dimension),
                      Patterns::Integer(2, 3),
                      "Space dimension of the scene: 2 (plane strain) or 3. "
                      "Units: none.");
    prm.declare_entry("Number of bodies",
                      std::to_string(defaults.n_bodies),
                      Patterns::Integer(1, 1000),
                      "How many bodies the scene has; each is described in a "
                      "subsection 'Body N', N = 0, 1, .... Units: none.");
    prm.declare_entry("Number of materials",
                      std::to_string(defaults.n_materials),
                      Patterns::Integer(1, 1000),
                      "How many materials the scene has; each is described "
                      "in a subsection 'Material N'. Units: none.");
    prm.declare_entry("Number of moving walls",
                      std::to_string(defaults.n_moving_walls),
                      Patterns::Integer(0, 1000),
                      "How many prescribed-velocity conditions (moving walls, "
                      "pistons) the scene has; each is described in "
                      "'Boundary conditions/Moving wall N'. Units: none.");
    prm.declare_entry("Number of tractions",
                      std::to_string(defaults.n_tractions),
                      Patterns::Integer(0, 1000),
                      "How many traction loads the scene has; each is "
                      "described in 'Boundary conditions/Traction N'. "
                      "Units: none.");
  }



  void
  SceneSize::parse_parameters(ParameterHandler &prm)
  {
    dimension      = prm.get_integer("Dimension");
    n_bodies       = prm.get_integer("Number of bodies");
    n_materials    = prm.get_integer("Number of materials");
    n_moving_walls = prm.get_integer("Number of moving walls");
    n_tractions    = prm.get_integer("Number of tractions");
  }



  void
  MeshParameters::declare_parameters(ParameterHandler  &prm,
                                     const unsigned int dim)
  {
    const MeshParameters defaults;
    prm.enter_subsection("Mesh");
    {
      prm.declare_entry("Type",
                        type_names.name(defaults.type),
                        Patterns::Selection(type_names.pattern()),
                        "'box': a rectangle/box subdivided into cells, with "
                        "boundary ids 0,1 (x min/max), 2,3 (y), 4,5 (z); "
                        "'gmsh': quadrilateral/hexahedral mesh read from "
                        "'File name' with its physical boundary ids; "
                        "'ball': a disk/ball (GridGenerator::hyper_ball) "
                        "inscribed in the box of the corners (radius half "
                        "its x extent), boundary id 0, whose refined "
                        "boundary vertices lie on the circle/sphere (a "
                        "curved boundary; cells stay (bi/tri)linear). "
                        "Units: none.");
      prm.declare_entry("Lower corner",
                        join(defaults.lower_corner, dim),
                        point_pattern(dim),
                        "Lower corner of the box. Units: m.");
      prm.declare_entry("Upper corner",
                        join(defaults.upper_corner, dim),
                        point_pattern(dim),
                        "Upper corner of the box. Units: m.");
      prm.declare_entry("Subdivisions",
                        join(defaults.subdivisions, dim),
                        Patterns::List(Patterns::Integer(1), dim, dim, ","),
                        "Number of cells of the box in each direction. "
                        "Units: none.");
      prm.declare_entry("File name",
                        defaults.file_name,
                        Patterns::Anything(),
                        "Gmsh .msh file for 'Type = gmsh', relative to the "
                        "folder of the scene file that sets it (to the "
                        "working directory for standard input). Units: "
                        "none.");
      prm.declare_entry("Initial global refinement",
                        std::to_string(defaults.global_refinement),
                        Patterns::Integer(0, 12),
                        "Number of times every cell is split in 2^dim before "
                        "the run. Units: none.");
      prm.declare_entry("Random distortion",
                        format_number(defaults.distortion),
                        Patterns::Double(0, 0.5),
                        "Move every interior vertex by a random vector of "
                        "up to this fraction of its shortest edge "
                        "(GridTools::distort_random, fixed seed) after the "
                        "global refinement: an unstructured quadrilateral/"
                        "hexahedral mesh. 0 keeps the mesh. Units: none.");
      prm.declare_entry(
        "Periodic directions",
        "",
        Patterns::List(Patterns::Selection("x|y|z"), 0, 3, ","),
        "Axes along which the box is periodic, e.g. 'x' or 'x, z' ('Type = "
        "box' only): the two faces across each axis (boundary ids 0 and 1 "
        "for x, 2 and 3 for y, 4 and 5 for z) are one. A material point "
        "leaving through one face enters through the other (its position "
        "and initial position shift by the box length, its deformation is "
        "kept), and the nodes of the two faces are one node: masses, momenta "
        "and forces of both sides add up there. No velocity condition may be "
        "set on those boundary ids. Classic shape functions only; not with "
        "multimaterial contact or mesh adaptation. Empty: none. Units: "
        "none.");
    }
    prm.leave_subsection();
  }



  void
  MeshParameters::parse_parameters(ParameterHandler  &prm,
                                   const unsigned int dim)
  {
    prm.enter_subsection("Mesh");
    type         = type_names.value(prm.get("Type"));
    lower_corner = get_doubles(prm, "Lower corner");
    upper_corner = get_doubles(prm, "Upper corner");
    subdivisions.clear();
    for (const double n : get_doubles(prm, "Subdivisions"))
      subdivisions.push_back(static_cast<unsigned int>(n));
    file_name         = prm.get("File name");
    global_refinement = prm.get_integer("Initial global refinement");
    distortion        = prm.get_double("Random distortion");
    periodic          = {{false, false, false}};
    for (const std::string &axis :
         Utilities::split_string_list(prm.get("Periodic directions")))
      {
        const unsigned int d = axis[0] - 'x';
        AssertThrow(d < dim,
                    ExcMessage("Mesh/Periodic directions = <" +
                               prm.get("Periodic directions") +
                               "> names the axis " + axis + ", which a " +
                               std::to_string(dim) +
                               "D scene does not have; allowed: " +
                               (dim == 2 ? "x, y." : "x, y, z.")));
        periodic[d] = true;
      }
    prm.leave_subsection();
    AssertThrow(!any_periodic() || type == Type::box,
                ExcMessage("Mesh/Periodic directions needs Mesh/Type = box "
                           "(whose opposite faces match node for node); this "
                           "scene has Mesh/Type = " +
                           std::string(type_names.name(type)) + "."));
    if (type == Type::box || type == Type::ball)
      for (unsigned int d = 0; d < dim; ++d)
        AssertThrow(upper_corner[d] > lower_corner[d],
                    ExcMessage("Mesh/Upper corner must be above Mesh/Lower "
                               "corner in every direction; direction " +
                               std::to_string(d) + " is not."));
    if (type == Type::gmsh)
      {
        AssertThrow(!file_name.empty(),
                    ExcMessage("Mesh/Type = gmsh needs Mesh/File name."));
        std::ifstream test(file_name);
        AssertThrow(test,
                    ExcMessage("Mesh/File name = <" + file_name +
                               "> cannot be opened: no such file or not "
                               "readable."));
      }
  }



  void
  MeshRefinementParameters::declare_parameters(ParameterHandler &prm)
  {
    const MeshRefinementParameters defaults;
    prm.enter_subsection("Mesh refinement");
    {
      prm.declare_entry(
        "Strategy",
        strategy_names.name(defaults.strategy),
        Patterns::Selection(strategy_names.pattern()),
        "How the mesh adapts to the scene. 'none': the mesh stays as built. "
        "'material points': cells that hold material points, plus 'Buffer "
        "layers' of neighbours, are refined up to 'Maximum level'; other "
        "cells are coarsened down to 'Minimum level'. 'material boundary': "
        "the same for the cells where material meets empty space. 'kelly': "
        "deal.II's KellyErrorEstimator on the lumped grid velocity m^-1 p "
        "refines the 'Refine fraction' of cells with the largest jumps and "
        "coarsens the 'Coarsen fraction' with the smallest. Material points "
        "keep all their properties through refinement and coarsening. "
        "Units: none.");
      prm.declare_entry("Interval",
                        std::to_string(defaults.interval),
                        Patterns::Integer(0),
                        "Adapt the mesh every this many steps (0: only "
                        "before the first step). Units: steps.");
      prm.declare_entry("Minimum level",
                        std::to_string(defaults.minimum_level),
                        Patterns::Integer(0, 20),
                        "Cells are not coarsened below this level (level 0 "
                        "is the mesh before 'Mesh/Initial global "
                        "refinement'). Units: none.");
      prm.declare_entry("Maximum level",
                        std::to_string(defaults.maximum_level),
                        Patterns::Integer(0, 20),
                        "Cells are not refined beyond this level. Units: "
                        "none.");
      prm.declare_entry("Buffer layers",
                        std::to_string(defaults.buffer_layers),
                        Patterns::Integer(0, 1000),
                        "Layers of neighbouring cells (sharing a vertex) "
                        "refined together with the marked cells, so that "
                        "material moving between two adaptations stays in "
                        "fine cells. Units: none.");
      prm.declare_entry("Refine fraction",
                        format_number(defaults.refine_fraction),
                        Patterns::Double(0, 1),
                        "'kelly': fraction of the cells refined. Units: "
                        "none.");
      prm.declare_entry("Coarsen fraction",
                        format_number(defaults.coarsen_fraction),
                        Patterns::Double(0, 1),
                        "'kelly': fraction of the cells coarsened. Units: "
                        "none.");
      prm.declare_entry("Initial refinement",
                        bool_text(defaults.initial_refinement),
                        Patterns::Bool(),
                        "Adapt the mesh to the bodies before the first step "
                        "(the material points are then created on the "
                        "adapted mesh, 'Points per cell' in the fine cells). "
                        "Units: none.");
      prm.declare_entry("Point weight",
                        format_number(defaults.point_weight),
                        Patterns::Integer(0, 100000),
                        "Load balancing across MPI ranks, before the first "
                        "step, whenever the mesh is adapted and when a "
                        "checkpoint is resumed on another number of ranks: "
                        "a cell weighs 1 plus this number per material "
                        "point it holds. 0 balances cells. Units: none.");
    }
    prm.leave_subsection();
  }



  void
  MeshRefinementParameters::parse_parameters(ParameterHandler     &prm,
                                             const MeshParameters &mesh)
  {
    prm.enter_subsection("Mesh refinement");
    strategy           = strategy_names.value(prm.get("Strategy"));
    interval           = prm.get_integer("Interval");
    minimum_level      = prm.get_integer("Minimum level");
    maximum_level      = prm.get_integer("Maximum level");
    buffer_layers      = prm.get_integer("Buffer layers");
    refine_fraction    = prm.get_double("Refine fraction");
    coarsen_fraction   = prm.get_double("Coarsen fraction");
    initial_refinement = prm.get_bool("Initial refinement");
    point_weight       = prm.get_integer("Point weight");
    prm.leave_subsection();
    AssertThrow(maximum_level >= minimum_level,
                ExcMessage("Mesh refinement/Maximum level = " +
                           std::to_string(maximum_level) +
                           " is below Mesh refinement/Minimum level = " +
                           std::to_string(minimum_level) +
                           ". Allowed: Maximum level >= Minimum level."));
    AssertThrow(!adaptive() || maximum_level >= mesh.global_refinement,
                ExcMessage("Mesh refinement/Maximum level = " +
                           std::to_string(maximum_level) +
                           " is below Mesh/Initial global refinement = " +
                           std::to_string(mesh.global_refinement) +
                           ". Allowed: Maximum level >= Initial global "
                           "refinement."));
    AssertThrow(refine_fraction + coarsen_fraction <= 1,
                ExcMessage("Mesh refinement/Refine fraction + Coarsen "
                           "fraction must not exceed 1."));
  }



  void
  MovingWallParameters::declare_parameters(ParameterHandler  &prm,
                                           const unsigned int dim)
  {
    const MovingWallParameters defaults;
    prm.declare_entry("Boundary ids",
                      join(defaults.boundary_ids, defaults.boundary_ids.size()),
                      Patterns::List(Patterns::Integer(0, 255)),
                      "Boundary ids whose nodes move with the wall; "
                      "leave empty to use 'Box lower/upper corner'. "
                      "Units: none.");
    prm.declare_entry("Box lower corner",
                      join(defaults.box_lower, defaults.box_lower.size()),
                      Patterns::List(Patterns::Double(), 0, dim, ","),
                      "Lower corner of the box region of the wall at "
                      "t = 0 (empty with 'Boundary ids'); the box moves "
                      "with the wall and material points do not enter "
                      "it. Units: m.");
    prm.declare_entry("Box upper corner",
                      join(defaults.box_upper, defaults.box_upper.size()),
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
                      join(defaults.direction, dim),
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
                      join(defaults.box_lower, dim),
                      point_pattern(dim),
                      "Lower corner of the box that selects the loaded "
                      "material points (at t = 0). Units: m.");
    prm.declare_entry("Box upper corner",
                      join(defaults.box_upper, dim),
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
                      "along the other axes. Units: none.");
    prm.declare_entry("Function constants",
                      defaults.constants,
                      Patterns::Anything(),
                      "Constants for 'Traction'. Units: as used.");
  }



  void
  TractionParameters::parse_parameters(ParameterHandler &prm)
  {
    box_lower   = get_doubles(prm, "Box lower corner");
    box_upper   = get_doubles(prm, "Box upper corner");
    traction    = prm.get("Traction");
    normal_axis = prm.get_integer("Normal axis");
    constants   = prm.get("Function constants");
  }



  void
  BoundaryConditionParameters::declare_parameters(ParameterHandler &prm,
                                                  const SceneSize  &size)
  {
    const BoundaryConditionParameters defaults;
    prm.enter_subsection("Boundary conditions");
    {
      prm.declare_entry("Fixed boundary ids",
                        join(defaults.fixed, defaults.fixed.size()),
                        Patterns::List(Patterns::Integer(0, 255)),
                        "Boundary ids on which all grid velocity components "
                        "are zero. Units: none.");
      prm.declare_entry("Roller boundary ids",
                        join(defaults.roller, defaults.roller.size()),
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



  namespace
  {
    /** The entries of 'Particle update' and 'Mass matrix' with their
     * plugins' subsections, for one dim. */
    template <int dim>
    void
    declare_method_plugin_parameters(ParameterHandler &prm)
    {
      const MethodParameters defaults;
      prm.enter_subsection("Particle update");
      prm.declare_entry(
        "Model name",
        defaults.particle_update,
        Patterns::Selection(
          ParticleUpdate::Registry<dim>::instance().pattern()),
        "How material points get their new velocity and "
        "position from the grid ([Nairn2023-FMPM] Table 2.1). " +
          ParticleUpdate::Registry<dim>::instance().documentation() +
          "Units: none.");
      prm.declare_entry(
        "Grid damping",
        format_number(defaults.grid_damping),
        Patterns::Double(),
        "alpha_g of [Nairn2018-extrap] Eqs. 1.17-1.24: the update "
        "subtracts alpha_g S v dt from the particle velocity "
        "(and half of it times dt from the position); for "
        "quasi-static scenes. Units: 1/s.");
      prm.declare_entry(
        "Particle damping",
        format_number(defaults.particle_damping),
        Patterns::Double(),
        "alpha_p of [Nairn2018-extrap] Eqs. 1.17-1.24: the update "
        "subtracts alpha_p V dt from the particle velocity. "
        "Units: 1/s.");
      ParticleUpdate::Registry<dim>::instance().declare_parameters(prm);
      prm.leave_subsection();

      prm.enter_subsection("Mass matrix");
      prm.declare_entry(
        "Model name",
        defaults.mass_matrix,
        Patterns::Selection(MassMatrix::Registry<dim>::instance().pattern()),
        "How grid velocities follow from grid momenta. " +
          MassMatrix::Registry<dim>::instance().documentation() +
          "Units: none.");
      MassMatrix::Registry<dim>::instance().declare_parameters(prm);
      prm.leave_subsection();
    }



    /** The entries of one 'Material N' with the constitutive models'. */
    template <int dim>
    void
    declare_material_parameters(ParameterHandler &prm)
    {
      const MaterialParameters defaults;
      prm.declare_entry(
        "Model name",
        defaults.model_name,
        Patterns::Selection(
          ConstitutiveModel::Registry<dim>::instance().pattern()),
        "Constitutive model of this material. " +
          ConstitutiveModel::Registry<dim>::instance().documentation() +
          "Units: none.");
      prm.declare_entry("Density",
                        format_number(defaults.density),
                        Patterns::Double(),
                        "Mass density in the reference configuration. "
                        "Must be positive. Units: kg/m^3.");
      ConstitutiveModel::Registry<dim>::instance().declare_parameters(prm);
    }
  } // namespace



  void
  MethodParameters::declare_parameters(ParameterHandler &prm)
  {
    const MethodParameters defaults;
    prm.enter_subsection("Time");
    {
      prm.declare_entry(
        "Strain update",
        defaults.strain_update,
        Patterns::Selection("usf|usl|usl+|usavg|usavg+"),
        "When stresses are updated ([Nairn2023-FMPM] §2.1-2.2): "
        "'usf' before the force extrapolation with v from p; "
        "'usl' (USL-) after the particle update with the grid "
        "velocity v+; 'usl+' after re-extrapolating the "
        "updated point momenta; 'usavg' and 'usavg+' half a "
        "step (dt/2) first as USF and half last as USL- or "
        "USL+. Units: none.");
      prm.declare_entry(
        "Strain update mass matrix",
        strain_update_mass_matrix_names.name(defaults.lumped_strain_velocities),
        Patterns::Selection(strain_update_mass_matrix_names.pattern()),
        "Which mass matrix turns momenta into the grid "
        "velocities of the strain update ([Nairn2023-FMPM] §3.3 "
        "question 2): 'same' as the particle update, or "
        "'lumped'. Units: none.");
    }
    prm.leave_subsection();

    prm.enter_subsection("Shape function");
    {
      prm.declare_entry(
        "Type",
        defaults.shape_function,
        Patterns::Selection(ShapeFunction::pattern()),
        "The grid shape functions S and G of the transfers ([Vaango-MPM], "
        "'Shape functions for MPM, GIMP, and CPDI'): 'classic' the FE_Q(1) "
        "basis at the point; 'ugimp' GIMP averages over the box of the "
        "initial half-lengths; 'cpgimp' GIMP over the box circumscribing the "
        "deformed point F diag(l0); 'cpdi' the deformed parallelogram/"
        "parallelepiped with corners x_p +- F diag(l0) r. On uniform "
        "axis-aligned cells GIMP uses the closed forms, on other meshes a "
        "quadrature split at cell faces. A point's domain must stay within "
        "the cells sharing a vertex with its cell (the run stops otherwise). "
        "Units: none.");
      prm.declare_entry(
        "CPDI critical radius",
        format_number(defaults.cpdi_critical_radius),
        Patterns::Double(0),
        "CPDI only: each half-diagonal of a point's domain longer than this "
        "many times the smallest extent of the point's cell is shortened to "
        "it, and the domain rebuilt from its diagonals (NairnMPM's "
        "CPDIrcrit). Keeps long, thin domains of large deformations within "
        "the neighbour cells (a value of at most 1 guarantees it) while their "
        "short directions stay as F gives them. The point's volume and "
        "deformation gradient are not changed, only the reach of its shape "
        "functions. 0: no limit. Units: cells.");
    }
    prm.leave_subsection();

    prm.enter_subsection("Deformation gradient");
    {
      prm.declare_entry("Update",
                        deformation_gradient_update_names.name(
                          defaults.deformation_gradient_update),
                        Patterns::Selection(
                          deformation_gradient_update_names.pattern()),
                        "How F^(n+1) follows from F^n and the velocity "
                        "gradient L ([Vaango-MPM], computeDeformationGradient"
                        "FromVelocity): 'first order' (I + L dt) F; 'taylor' "
                        "sum_k (L dt)^k/k! F with 'Taylor terms' terms; "
                        "'subcycle' first-order substeps with |L dt_sub| "
                        "below 'Subcycle strain increment'; 'cayley' "
                        "(I - L dt/2)^-1 (I + L dt/2) F, the default: as "
                        "accurate as 'taylor' at the cost of 'first order' "
                        "and exact in rotation (rigid rotation, 2000 steps: "
                        "spurious strain energy 2e-5 against 8.5e-4 of the "
                        "kinetic energy with 'first order'). Units: none.");
      prm.declare_entry("Taylor terms",
                        std::to_string(defaults.taylor_terms),
                        Patterns::Integer(1, 20),
                        "Number of terms after the identity of the 'taylor' "
                        "update. Units: none.");
      prm.declare_entry("Subcycle strain increment",
                        format_number(defaults.subcycle_strain_increment),
                        Patterns::Double(1e-8, 1),
                        "Largest |L| dt of one substep of the 'subcycle' "
                        "update. Units: none.");
    }
    prm.leave_subsection();
  }



  void
  MethodParameters::declare_plugin_parameters(ParameterHandler  &prm,
                                              const unsigned int dim)
  {
    if (dim == 2)
      declare_method_plugin_parameters<2>(prm);
    else
      declare_method_plugin_parameters<3>(prm);
  }



  void
  MethodParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Time");
    strain_update            = prm.get("Strain update");
    strain_update_scheme     = StrainUpdateScheme::of(strain_update);
    lumped_strain_velocities = strain_update_mass_matrix_names.value(
      prm.get("Strain update mass matrix"));
    prm.leave_subsection();

    prm.enter_subsection("Shape function");
    shape_function       = prm.get("Type");
    cpdi_critical_radius = prm.get_double("CPDI critical radius");
    prm.leave_subsection();

    prm.enter_subsection("Deformation gradient");
    deformation_gradient_update =
      deformation_gradient_update_names.value(prm.get("Update"));
    taylor_terms              = prm.get_integer("Taylor terms");
    subcycle_strain_increment = prm.get_double("Subcycle strain increment");
    prm.leave_subsection();

    prm.enter_subsection("Particle update");
    particle_update  = prm.get("Model name");
    grid_damping     = prm.get_double("Grid damping");
    particle_damping = prm.get_double("Particle damping");
    prm.leave_subsection();
    prm.enter_subsection("Mass matrix");
    mass_matrix = prm.get("Model name");
    prm.leave_subsection();
  }



  void
  MaterialParameters::declare_parameters(ParameterHandler  &prm,
                                         const unsigned int dim)
  {
    if (dim == 2)
      declare_material_parameters<2>(prm);
    else
      declare_material_parameters<3>(prm);
  }



  void
  MaterialParameters::parse_parameters(ParameterHandler  &prm,
                                       const std::string &where)
  {
    model_name = prm.get("Model name");
    density    = prm.get_double("Density");
    AssertThrow(density > 0,
                ExcMessage(where + "/Density = " + format_number(density) +
                           " is not positive. Allowed: any value > 0 "
                           "(kg/m^3)."));
  }



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
                      join(defaults.center, dim),
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
  BodyParameters::declare_parameters(ParameterHandler  &prm,
                                     const unsigned int dim)
  {
    const BodyParameters defaults;
    Geometry::declare_body_shape_parameters(prm);
    prm.declare_entry("Center",
                      join(defaults.center, dim),
                      point_pattern(dim),
                      "Center of the shape. Units: m.");
    prm.declare_entry("Half lengths",
                      join(defaults.half_lengths, dim),
                      point_pattern(dim),
                      "Half widths of the box, or semi-axes of the "
                      "ellipsoid; the first is the sphere's radius. "
                      "Units: m.");
    prm.declare_entry("Material",
                      std::to_string(defaults.material),
                      Patterns::Integer(0),
                      "Index N of the 'Material N' the body is made of. "
                      "Units: none.");
    prm.declare_entry("Points per cell",
                      std::to_string(defaults.points_per_cell),
                      Patterns::Integer(1, 10),
                      "Material points per cell in each direction, "
                      "placed at the centres of a regular subdivision of "
                      "each cell. Units: none.");
    prm.declare_entry("Initial velocity",
                      join(defaults.velocity, dim),
                      Patterns::Anything(),
                      "Initial velocity of the points: either dim numbers "
                      "separated by ',', or dim FunctionParser "
                      "expressions in x, y, z separated by ';' (for "
                      "example 'v0*sin(beta*x); 0'). Units: m/s.");
    prm.declare_entry("Function constants",
                      defaults.function_constants,
                      Patterns::Anything(),
                      "Constants for the 'Initial velocity' expressions, "
                      "e.g. 'v0=0.1, beta=1.5708'. Units: as used.");
    prm.declare_entry("Initial stress from gravity",
                      bool_text(defaults.initial_stress_from_gravity),
                      Patterns::Bool(),
                      "Start with the stress in equilibrium with gravity "
                      "([Vaango-MPM], initializeStressWithBodyForce): "
                      "sigma = -rho |g| depth along g, with lateral "
                      "stresses of uniaxial strain, so that a column "
                      "under gravity starts at rest. Depth is measured "
                      "from the body's top surface. Units: none.");
  }



  void
  BodyParameters::parse_parameters(ParameterHandler  &prm,
                                   const SceneSize   &size,
                                   const std::string &where)
  {
    center                      = get_doubles(prm, "Center");
    half_lengths                = get_doubles(prm, "Half lengths");
    material                    = prm.get_integer("Material");
    points_per_cell             = prm.get_integer("Points per cell");
    velocity_expression         = prm.get("Initial velocity");
    function_constants          = prm.get("Function constants");
    initial_stress_from_gravity = prm.get_bool("Initial stress from gravity");
    AssertThrow(material < size.n_materials,
                ExcMessage(where + "/Material = " + std::to_string(material) +
                           " does not exist: the scene has 'Number of "
                           "materials' = " +
                           std::to_string(size.n_materials) +
                           ", so allowed values are 0 to " +
                           std::to_string(size.n_materials - 1) + "."));
    for (unsigned int d = 0; d < size.dimension; ++d)
      AssertThrow(half_lengths[d] > 0,
                  ExcMessage(where + "/Half lengths must all be positive."));
    Geometry::parse_body_shape_parameters(prm, *this, size.dimension, where);
  }



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



  void
  Parameters::declare_parameters(ParameterHandler &prm, const SceneSize &size)
  {
    const unsigned int dim = size.dimension;
    const Parameters   defaults;
    SceneSize::declare_parameters(prm);
    MeshParameters::declare_parameters(prm, dim);
    MeshRefinementParameters::declare_parameters(prm);
    BoundaryConditionParameters::declare_parameters(prm, size);
    TimeParameters::declare_parameters(prm);
    MethodParameters::declare_parameters(prm);

    prm.enter_subsection("Body force");
    prm.declare_entry("Gravity",
                      join(defaults.gravity, dim),
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

    for (unsigned int b = 0; b < size.n_bodies; ++b)
      {
        prm.enter_subsection(numbered_subsection("Body", b));
        BodyParameters::declare_parameters(prm, dim);
        prm.leave_subsection();
      }

    OutputParameters::declare_parameters(prm);
    Contact::Parameters::declare_parameters(prm);
    CheckpointParameters::declare_parameters(prm);
    FailureParameters::declare_parameters(prm);
    ReferenceSolutionParameters::declare_parameters(prm, dim);

    prm.enter_subsection("Test");
    prm.declare_entry("Enable",
                      bool_text(defaults.test_mode),
                      Patterns::Bool(),
                      "Print mass, momentum and energy every output and the "
                      "points sorted by id at the end, at fixed precision, "
                      "instead of progress and timings (for regression "
                      "tests). Units: none.");
    prm.leave_subsection();

    prm.enter_subsection("Performance");
    prm.declare_entry("Fast point sorting",
                      bool_text(defaults.fast_point_sorting),
                      Patterns::Bool(),
                      "After each step, find the new cell of only the "
                      "material points that left their cell (their reference "
                      "coordinates are kept up to date during the particle "
                      "update), send only the points that leave the MPI "
                      "rank, and re-bin the point store in cell order; "
                      "deal.II's full sort runs only when a point is not "
                      "found near its old cell or leaves the mesh. false: "
                      "deal.II's full sort of every point every step (for "
                      "checking; the points are in the same order either "
                      "way, so the physics is the same). Units: none.");
    prm.leave_subsection();

    prm.enter_subsection("Timer");
    prm.declare_entry("Type",
                      timer_type_names.name(defaults.print_timer_summary),
                      Patterns::Selection(timer_type_names.pattern()),
                      "Whether to print the TimerOutput summary at the end. "
                      "Units: none.");
    prm.leave_subsection();

    MethodParameters::declare_plugin_parameters(prm, dim);
    for (unsigned int m = 0; m < size.n_materials; ++m)
      {
        prm.enter_subsection(numbered_subsection("Material", m));
        MaterialParameters::declare_parameters(prm, dim);
        prm.leave_subsection();
      }
  }



  void
  Parameters::parse_parameters(ParameterHandler &prm)
  {
    size.parse_parameters(prm);
    mesh.parse_parameters(prm, size.dimension);
    refinement.parse_parameters(prm, mesh);
    boundary_conditions.parse_parameters(prm, size);
    time.parse_parameters(prm);

    prm.enter_subsection("Body force");
    gravity                     = get_doubles(prm, "Gravity");
    body_acceleration           = prm.get("Acceleration");
    body_acceleration_constants = prm.get("Function constants");
    body_acceleration_at_initial_position =
      prm.get_bool("Acceleration at initial position");
    rotating_frame.parse_parameters(prm);
    prm.leave_subsection();

    method.parse_parameters(prm);

    materials.resize(size.n_materials);
    for (unsigned int m = 0; m < size.n_materials; ++m)
      {
        const std::string where = numbered_subsection("Material", m);
        prm.enter_subsection(where);
        materials[m].parse_parameters(prm, where);
        prm.leave_subsection();
      }

    bodies.resize(size.n_bodies);
    for (unsigned int b = 0; b < size.n_bodies; ++b)
      {
        const std::string where = numbered_subsection("Body", b);
        prm.enter_subsection(where);
        bodies[b].parse_parameters(prm, size, where);
        prm.leave_subsection();
      }

    output.parse_parameters(prm);
    contact.parse_parameters(prm, size.n_materials);
    checkpoint.parse_parameters(prm);
    failure.parse_parameters(prm);
    reference.parse_parameters(prm);

    prm.enter_subsection("Test");
    test_mode = prm.get_bool("Enable");
    prm.leave_subsection();

    prm.enter_subsection("Performance");
    fast_point_sorting = prm.get_bool("Fast point sorting");
    prm.leave_subsection();

    prm.enter_subsection("Timer");
    print_timer_summary = timer_type_names.value(prm.get("Type"));
    prm.leave_subsection();
  }



  namespace
  {
    /** The text of a scene source: a file, or standard input for "-". */
    std::string
    read_source(const std::string &file)
    {
      if (file == "-")
        return std::string(std::istreambuf_iterator<char>(std::cin),
                           std::istreambuf_iterator<char>());
      AssertThrow(!std::filesystem::is_directory(file),
                  ExcMessage("The scene file <" + file +
                             "> is a directory, not a parameter file. Give "
                             "a text .prm file (see fmpm "
                             "--print-default-scene)."));
      std::ifstream in(file);
      AssertThrow(in,
                  ExcMessage("Cannot open the scene file <" + file +
                             ">: no such file or not readable."));
      return std::string(std::istreambuf_iterator<char>(in),
                         std::istreambuf_iterator<char>());
    }

    /**
     * Refuse a source that is not a parameter file: binary data, or text
     * without a single 'set', 'subsection' or 'include' line (a mesh or a
     * results file given by mistake), which deal.II would otherwise accept
     * as a scene with every parameter at its default value.
     */
    void
    check_is_parameter_file(const std::string &name,
                            const std::string &text,
                            const bool         is_override)
    {
      for (const char c : text)
        AssertThrow(c == '\t' || c == '\n' || c == '\r' || c == '\f' ||
                      c == '\v' || static_cast<unsigned char>(c) >= 32,
                    ExcMessage("The scene file <" + name +
                               "> is not a parameter file: it holds binary "
                               "data. Give a text .prm file with 'set' and "
                               "'subsection' lines (see fmpm "
                               "--print-default-scene)."));
      std::istringstream in(text);
      std::string        line;
      bool               only_comments = true;
      while (std::getline(in, line))
        {
          std::istringstream words(line);
          std::string        first;
          words >> first;
          if (first == "set" || first == "subsection" || first == "include")
            return;
          only_comments = only_comments && (first.empty() || first[0] == '#');
        }
      // An empty or comment-only override changes nothing (its settings
      // commented out); as the scene itself it is a mistake.
      if (only_comments && is_override)
        return;
      AssertThrow(false,
                  ExcMessage("The scene file <" + name +
                             "> is not a parameter file: it has no 'set' or "
                             "'subsection' line. Give a text .prm file "
                             "(see fmpm --print-default-scene)."));
    }

    std::string
    lower_case(std::string text)
    {
      for (char &c : text)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return text;
    }

    /** Levenshtein distance of @p a and @p b, ignoring case. */
    unsigned int
    edit_distance(const std::string &a, const std::string &b)
    {
      std::vector<unsigned int> previous(b.size() + 1), current(b.size() + 1);
      for (unsigned int j = 0; j <= b.size(); ++j)
        previous[j] = j;
      for (unsigned int i = 1; i <= a.size(); ++i)
        {
          current[0] = i;
          for (unsigned int j = 1; j <= b.size(); ++j)
            current[j] = std::min(
              {previous[j] + 1,
               current[j - 1] + 1,
               previous[j - 1] +
                 (std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                      std::tolower(static_cast<unsigned char>(b[j - 1])) ?
                    0u :
                    1u)});
          std::swap(previous, current);
        }
      return previous[b.size()];
    }

    /**
     * The subsections (@p subsections true) or entries declared in @p prm
     * inside the subsection @p path, from deal.II's PRM listing.
     */
    std::vector<std::string>
    declared_names(const ParameterHandler         &prm,
                   const std::vector<std::string> &path,
                   const bool                      subsections)
    {
      std::stringstream listing;
      prm.print_parameters(listing, ParameterHandler::PRM);
      std::vector<std::string> current, names;
      std::string              line;
      while (std::getline(listing, line))
        {
          line = Utilities::trim(line.substr(0, line.find('#')));
          if (line.rfind("subsection ", 0) == 0)
            {
              const std::string name = Utilities::trim(line.substr(11));
              if (subsections && current == path)
                names.push_back(name);
              current.push_back(name);
            }
          else if (line == "end" && !current.empty())
            current.pop_back();
          else if (line.rfind("set ", 0) == 0 && !subsections &&
                   current == path)
            names.push_back(
              Utilities::trim(line.substr(4, line.find('=') - 4)));
        }
      return names;
    }

    /**
     * For deal.II's errors about an undeclared entry or subsection at a
     * line of @p text: " Did you mean ...?" with the declared names nearest
     * to the one written, or the names declared there; empty otherwise.
     */
    std::string
    nearest_names_hint(const ParameterHandler &prm,
                       const std::string      &text,
                       const std::string      &message)
    {
      const std::string entry_marker = "No entry with name <";
      const std::string section_marker =
        "There is no such subsection to be entered: ";
      const std::string line_marker = "Line <";
      const auto        line_at     = message.find(line_marker);
      if (line_at == std::string::npos)
        return "";
      const unsigned int line_number = static_cast<unsigned int>(
        std::atoi(message.c_str() + line_at + line_marker.size()));
      std::string written;
      bool        subsection = false;
      if (const auto at = message.find(entry_marker); at != std::string::npos)
        {
          const auto begin = at + entry_marker.size();
          written = message.substr(begin, message.find('>', begin) - begin);
        }
      else if (const auto at = message.find(section_marker);
               at != std::string::npos)
        {
          written = Utilities::trim(message.substr(at + section_marker.size(),
                                                   message.find('\n', at) - at -
                                                     section_marker.size()));
          // deal.II names the subsection with its path: "Mass matrix.Fmmp".
          if (written.find('.') != std::string::npos)
            written = written.substr(written.rfind('.') + 1);
          subsection = true;
        }
      else
        return "";

      // The subsection path in force at that line.
      std::vector<std::string> path;
      std::istringstream       in(text);
      std::string              line;
      for (unsigned int number = 1;
           number < line_number && std::getline(in, line);
           ++number)
        {
          line = Utilities::trim(line.substr(0, line.find('#')));
          if (line.rfind("subsection ", 0) == 0)
            path.push_back(Utilities::trim(line.substr(11)));
          else if (line == "end" && !path.empty())
            path.pop_back();
        }
      const std::vector<std::string> names =
        declared_names(prm, path, subsection);
      if (names.empty())
        return "";
      std::vector<std::pair<unsigned int, std::string>> ranked;
      const std::string lower_written = lower_case(written);
      for (const auto &name : names)
        {
          const unsigned int distance = edit_distance(written, name);
          const bool         contains =
            !lower_written.empty() &&
            (lower_case(name).find(lower_written) != std::string::npos ||
             lower_written.find(lower_case(name)) != std::string::npos);
          if (contains ||
              distance <= std::max<std::size_t>(2, written.size() / 3))
            ranked.emplace_back(contains ? 0 : distance, name);
        }
      std::sort(ranked.begin(), ranked.end());
      std::string where;
      for (const auto &name : path)
        where += (where.empty() ? "" : "/") + name;
      where = where.empty() ? "at the top level" : "in '" + where + "'";
      std::string hint;
      if (!ranked.empty())
        {
          hint = "\n    Did you mean ";
          for (unsigned int i = 0; i < std::min<std::size_t>(3, ranked.size());
               ++i)
            hint += (i > 0 ? " or '" : "'") + ranked[i].second + "'";
          hint += "?";
        }
      else
        {
          hint = "\n    " +
                 std::string(subsection ? "Subsections" : "Parameters") + " " +
                 where + ": ";
          for (unsigned int i = 0; i < names.size(); ++i)
            hint += (i > 0 ? ", '" : "'") + names[i] + "'";
          hint += ".";
        }
      return hint;
    }

    void
    parse_source(ParameterHandler  &prm,
                 const std::string &text,
                 const std::string &name,
                 const bool         skip_undefined)
    {
      std::istringstream in(text);
      try
        {
          prm.parse_input(in, name, "", skip_undefined);
        }
      catch (const ExceptionBase &e)
        {
          const std::string message = message_of(e);
          AssertThrow(false,
                      ExcMessage("Error in the scene <" + name + ">:\n    " +
                                 message +
                                 nearest_names_hint(prm, text, message)));
        }
    }
  } // namespace



  namespace
  {
    /**
     * The files a scene names ('include' lines, 'Mesh/File name' and
     * 'Body N/File name') are
     * relative to the scene file's folder: @p text with those relative
     * paths made absolute against the folder of @p scene_file.
     */
    std::string
    with_paths_relative_to(const std::string &text,
                           const std::string &scene_file)
    {
      const std::filesystem::path folder =
        std::filesystem::absolute(scene_file).parent_path();
      const auto resolved = [&folder](const std::string &file) {
        const std::filesystem::path path(file);
        return file.empty() || path.is_absolute() ?
                 file :
                 (folder / path).lexically_normal().string();
      };
      std::vector<std::string> path;
      std::istringstream       in(text);
      std::ostringstream       out;
      std::string              line;
      while (std::getline(in, line))
        {
          const std::string code =
            Utilities::trim(line.substr(0, line.find('#')));
          const std::string comment = line.find('#') == std::string::npos ?
                                        "" :
                                        line.substr(line.find('#'));
          if (code.rfind("subsection ", 0) == 0)
            path.push_back(Utilities::trim(code.substr(11)));
          else if (code == "end" && !path.empty())
            path.pop_back();
          else if (code.rfind("include ", 0) == 0)
            line = "include " + resolved(Utilities::trim(code.substr(8))) +
                   (comment.empty() ? "" : " " + comment);
          else if (code.rfind("set ", 0) == 0 &&
                   (path == std::vector<std::string>{"Mesh"} ||
                    (path.size() == 1 && path[0].rfind("Body ", 0) == 0)) &&
                   code.find('=') != std::string::npos &&
                   Utilities::trim(code.substr(4, code.find('=') - 4)) ==
                     "File name")
            line = "  set File name = " +
                   resolved(Utilities::trim(code.substr(code.find('=') + 1))) +
                   (comment.empty() ? "" : " " + comment);
          out << line << '\n';
        }
      return out.str();
    }
  } // namespace



  std::vector<std::pair<std::string, std::string>>
  load_scene_sources(const std::vector<std::string> &files)
  {
    std::vector<std::pair<std::string, std::string>> sources;
    if (files.empty())
      sources.emplace_back("default scene", default_scene());
    for (const auto &file : files)
      {
        sources.emplace_back(file == "-" ? "standard input" : file,
                             read_source(file));
        check_is_parameter_file(sources.back().first,
                                sources.back().second,
                                sources.size() > 1);
        if (file != "-")
          sources.back().second =
            with_paths_relative_to(sources.back().second, file);
      }
    return sources;
  }



  namespace
  {
    /** Where a scene writes a subsection or sets a parameter. */
    struct SceneLine
    {
      std::string  path; // "Boundary conditions/Moving wall 1"
      std::string  source;
      unsigned int line;
    };

    /**
     * The subsections a scene writes and the parameters it sets, each with
     * its full path, following deal.II's syntax ('subsection', 'end',
     * 'set', '#' comments, 'include' of another file).
     */
    void
    scan_scene_text(const std::string      &text,
                    const std::string      &source,
                    std::vector<SceneLine> &subsections,
                    std::vector<SceneLine> &settings,
                    const unsigned int      depth = 0)
    {
      std::vector<std::string> path;
      std::istringstream       in(text);
      std::string              line;
      unsigned int             number = 0;
      const auto               joined = [&path](const std::string &last) {
        std::string result;
        for (const auto &name : path)
          result += name + "/";
        return result + last;
      };
      while (std::getline(in, line))
        {
          ++number;
          line = Utilities::trim(line.substr(0, line.find('#')));
          if (line.rfind("subsection ", 0) == 0)
            {
              const std::string name = Utilities::trim(line.substr(11));
              subsections.push_back({joined(name), source, number});
              path.push_back(name);
            }
          else if (line == "end")
            {
              if (!path.empty())
                path.pop_back();
            }
          else if (line.rfind("set ", 0) == 0)
            {
              const std::string entry = line.substr(4);
              settings.push_back(
                {joined(Utilities::trim(entry.substr(0, entry.find('=')))),
                 source,
                 number});
            }
          else if (line.rfind("include ", 0) == 0 && depth < 10)
            {
              const std::string file = Utilities::trim(line.substr(8));
              std::ifstream     included(file);
              if (included)
                scan_scene_text(std::string(std::istreambuf_iterator<char>(
                                              included),
                                            std::istreambuf_iterator<char>()),
                                file,
                                subsections,
                                settings,
                                depth + 1);
            }
        }
    }

    /**
     * Every numbered subsection a scene announces with 'Number of ...' must
     * be written (deal.II would give an unwritten one its default values: a
     * silent default body), and every one written must be announced.
     */
    void
    check_numbered_subsections(
      const std::vector<std::pair<std::string, std::string>> &sources,
      const SceneSize                                        &size)
    {
      std::vector<SceneLine> subsections, settings;
      for (const auto &source : sources)
        scan_scene_text(source.second, source.first, subsections, settings);

      struct Family
      {
        std::string  count_parameter; // "Number of bodies"
        std::string  parent;          // "" or "Boundary conditions/"
        std::string  name;            // "Body"
        unsigned int count;
      };
      const std::vector<Family> families = {
        {"Number of bodies", "", "Body", size.n_bodies},
        {"Number of materials", "", "Material", size.n_materials},
        {"Number of moving walls",
         "Boundary conditions/",
         "Moving wall",
         size.n_moving_walls},
        {"Number of tractions",
         "Boundary conditions/",
         "Traction",
         size.n_tractions}};
      for (const Family &family : families)
        {
          const std::string prefix = family.parent + family.name + " ";
          std::vector<bool> written(family.count, false);
          for (const SceneLine &subsection : subsections)
            {
              if (subsection.path.rfind(prefix, 0) != 0)
                continue;
              const std::string index = subsection.path.substr(prefix.size());
              if (index.empty() ||
                  index.find_first_not_of("0123456789") != std::string::npos)
                continue;
              const unsigned long n = std::stoul(index);
              AssertThrow(n < family.count,
                          ExcMessage(
                            "Line <" + std::to_string(subsection.line) +
                            "> of <" + subsection.source +
                            "> opens 'subsection " + family.name + " " + index +
                            "', but '" + family.count_parameter + " = " +
                            std::to_string(family.count) + "' declares only " +
                            (family.count == 0 ?
                               std::string("none") :
                               family.name + " 0 to " + family.name + " " +
                                 std::to_string(family.count - 1)) +
                            ". Set '" + family.count_parameter + " = " +
                            std::to_string(n + 1) +
                            "' (at the top level of the scene) or remove the "
                            "subsection."));
              written[n] = true;
            }
          // A count the scene leaves at its default announces nothing.
          const SceneLine *announced = nullptr;
          for (const SceneLine &setting : settings)
            if (setting.path == family.count_parameter)
              announced = &setting;
          if (announced == nullptr)
            continue;
          for (unsigned int n = 0; n < family.count; ++n)
            AssertThrow(
              written[n],
              ExcMessage("Line <" + std::to_string(announced->line) + "> of <" +
                         announced->source + "> sets '" +
                         family.count_parameter + " = " +
                         std::to_string(family.count) +
                         "' but the scene has no 'subsection " + family.parent +
                         family.name + " " + std::to_string(n) +
                         "': write that subsection (an unwritten one would "
                         "silently take every default value) or lower '" +
                         family.count_parameter + "'."));
        }
    }
  } // namespace



  SceneSize
  read_scene_size(
    const std::vector<std::pair<std::string, std::string>> &sources)
  {
    ParameterHandler size_prm;
    SceneSize::declare_parameters(size_prm);
    for (const auto &source : sources)
      parse_source(size_prm, source.second, source.first, true);
    SceneSize size;
    size.parse_parameters(size_prm);
    return size;
  }



  void
  read_scene(const std::vector<std::pair<std::string, std::string>> &sources,
             ParameterHandler                                       &prm,
             Parameters                                             &parameters)
  {
    // Pass 1: how many bodies and materials, and which dimension.
    const SceneSize size = read_scene_size(sources);
    check_numbered_subsections(sources, size);

    // Pass 2: everything, strictly.
    Parameters::declare_parameters(prm, size);
    for (const auto &source : sources)
      parse_source(prm, source.second, source.first, false);
    try
      {
        parameters.parse_parameters(prm);
      }
    catch (const ExceptionBase &e)
      {
        std::string where;
        for (const auto &source : sources)
          where += (where.empty() ? "" : ", ") + source.first;
        AssertThrow(false,
                    ExcMessage("Error in the scene <" + where + ">:\n    " +
                               message_of(e)));
      }
  }
} // namespace fmpm
