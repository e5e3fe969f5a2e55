// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Mesh and Mesh refinement.

#include <fmpm/parameters.h>

#include <deal.II/base/utilities.h>

#include <fstream>

namespace fmpm
{
  namespace
  {
    /** 'Mesh/Periodic directions' as the scene writes it: "x, z". */
    std::string
    periodic_directions_text(const std::array<bool, 3> &periodic)
    {
      std::string text;
      for (unsigned int d = 0; d < 3; ++d)
        if (periodic[d])
          text += (text.empty() ? "" : ", ") + std::string(1, 'x' + d);
      return text;
    }
  } // namespace



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
                        list_text(defaults.lower_corner, dim),
                        point_pattern(dim),
                        "Lower corner of the box. Units: m.");
      prm.declare_entry("Upper corner",
                        list_text(defaults.upper_corner, dim),
                        point_pattern(dim),
                        "Upper corner of the box. Units: m.");
      prm.declare_entry("Subdivisions",
                        list_text(defaults.subdivisions, dim),
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
        periodic_directions_text(defaults.periodic),
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
} // namespace fmpm
