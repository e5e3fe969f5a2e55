// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The scene size and all parameters of a scene.

#include <fmpm/parameters.h>
#include <fmpm/shape_function.h>

namespace fmpm
{
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
  Parameters::declare_parameters(ParameterHandler &prm, const SceneSize &size)
  {
    const unsigned int dim = size.dimension;
    const Parameters   defaults;
    SceneSize::declare_parameters(prm);
    prm.declare_entry(
      "Geometry",
      geometry_names.name(defaults.axisymmetric),
      Patterns::Selection(geometry_names.pattern()),
      "What a 2D scene stands for: 'plane strain' (a slice of unit "
      "thickness, the default) or 'axisymmetric' (a body of revolution about "
      "the y axis: x = r >= 0, y = z; the mesh must start at r = 0 or beyond; "
      "nodes on r = 0 keep zero radial velocity; masses, volumes, forces, "
      "tractions and energies are per radian). Axisymmetric scenes take every "
      "shape function (classic, ugimp, cpgimp, cpdi, and b2spline, "
      "b3spline, b2gimp, b2cpdi, whose basis at the axis r = 0 needs "
      "'B-spline boundary = open knots'); multimaterial contact acts in the "
      "r-z plane. Dimension = 3 takes only 'plane "
      "strain' (which then means nothing). Units: none.");
    MeshParameters::declare_parameters(prm, dim);
    MeshRefinementParameters::declare_parameters(prm);
    BoundaryConditionParameters::declare_parameters(prm, size);
    TimeParameters::declare_parameters(prm);
    MethodParameters::declare_parameters(prm);

    declare_body_force_parameters(prm, dim);

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
    axisymmetric = geometry_names.value(prm.get("Geometry"));
    AssertThrow(!axisymmetric || size.dimension == 2,
                ExcMessage("Geometry = axisymmetric needs Dimension = 2 (the "
                           "r-z plane), not Dimension = " +
                           std::to_string(size.dimension) +
                           "; allowed for 3D: Geometry = plane strain."));
    mesh.parse_parameters(prm, size.dimension);
    refinement.parse_parameters(prm, mesh);
    boundary_conditions.parse_parameters(prm, size);
    time.parse_parameters(prm);

    parse_body_force_parameters(prm);

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
    if (axisymmetric)
      {
        AssertThrow(!mesh.periodic[0],
                    ExcMessage("Geometry = axisymmetric: Mesh/Periodic "
                               "directions cannot include x (= r)."));
      }
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
} // namespace fmpm
