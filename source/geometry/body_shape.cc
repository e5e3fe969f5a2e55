// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The 'Shape' and 'File name' of a body, and the region they describe.

#include <fmpm/geometry/body_shape.h>
#include <fmpm/geometry/mesh_body.h>

#include <deal.II/base/utilities.h>

namespace fmpm
{
  namespace Geometry
  {
    void
    declare_body_shape_parameters(ParameterHandler &prm)
    {
      const BodyParameters defaults;
      prm.declare_entry(
        "Shape",
        BodyParameters::shape_names.name(defaults.shape),
        Patterns::Anything(),
        "Shape of the body: 'box' (a rectangle in 2D), 'sphere' (disk; "
        "radius = first half length) or 'ellipsoid' (ellipse; semi-axes = "
        "half lengths, axis aligned) about 'Center'; 'mesh': the cells of the "
        "volume mesh in 'File name' (Gmsh .msh, VTK .vtk, UCD .inp, Abaqus "
        ".inp; triangles, quadrilaterals, tetrahedra or hexahedra, independent "
        "of the background mesh), with 'Points per cell' Gauss points per "
        "direction in each of its cells, each point's volume the cell's JxW "
        "share; or a shape formula (the body then ignores Center and Half "
        "lengths). Formulas: box(center; half lengths), sphere(center; "
        "radius) (or disk), ellipsoid(center; semi-axes) (or ellipse), "
        "cylinder(end point; end point; radius) (a rectangle in 2D), "
        "polygon(x0, y0; x1, y1; ...) or polygon(file) (2D; the vertices in "
        "order along the boundary, one 'x y' a line in 'File name'; a polygon "
        "that intersects itself is refused), halfspace(point; outward "
        "normal), expression(\"f(x, y, z)\") (the region where the "
        "FunctionParser expression is <= 0, with the body's 'Function "
        "constants'), surface(file) (3D: the region enclosed by the closed "
        "STL surface (ASCII or binary) or OBJ surface (a '.obj' file name) "
        "in 'File name'; an open surface is "
        "refused); rotate(angle; [axis (3D);] [point;] shape) turns a shape "
        "counterclockwise by the angle in degrees about the point (default: "
        "the centre of its bounding box), translate(displacement; shape) "
        "moves it; A + B is the union, A - B the difference and A * B the "
        "intersection (* binds before + and -; parentheses group). Example: "
        "a ring 'disk(0.5, 0.5; 0.3) - disk(0.5, 0.5; 0.2)'. The points are "
        "the centres of a regular subdivision of each background cell that "
        "lie inside. Bodies may overlap: a point inside an earlier body "
        "(lower N) belongs to that body, and the later body gets no point "
        "there (fmpm warns with the number of points each body leaves to an "
        "earlier one). Units: none (lengths in m, angles in degrees).");
      prm.declare_entry("File name",
                        defaults.file_name,
                        Patterns::Anything(),
                        "The file a 'Shape' of 'mesh', polygon(file) or "
                        "surface(file) reads, relative to the scene file's "
                        "folder. Units: none.");
      prm.declare_entry(
        "Physical groups",
        "",
        Patterns::List(Patterns::Integer(0)),
        "Shape = mesh only: the physical groups (Gmsh physical tags, read as "
        "the cells' material ids) whose cells make the body, e.g. '1, 3'; "
        "one mesh file with several groups gives several bodies, each with "
        "its own Material. Empty: all cells. Units: none.");
    }



    void
    parse_body_shape_parameters(ParameterHandler  &prm,
                                BodyParameters    &body,
                                const unsigned int dim,
                                const std::string &where)
    {
      const std::string shape = Utilities::trim(prm.get("Shape"));
      body.file_name          = prm.get("File name");
      body.physical_groups.clear();
      for (const auto &group :
           Utilities::split_string_list(prm.get("Physical groups")))
        body.physical_groups.push_back(Utilities::string_to_int(group));
      AssertThrow(body.physical_groups.empty() || shape == "mesh",
                  ExcMessage(where +
                             "/Physical groups is set but Shape is not "
                             "'mesh': physical groups pick cells of a volume "
                             "mesh body only."));
      body.shape_formula.clear();
      body.from_mesh = false;
      bool legacy    = false;
      for (const auto &name : BodyParameters::shape_names.names)
        legacy = legacy || shape == name;
      if (legacy)
        body.shape = BodyParameters::shape_names.value(shape);
      else if (shape == "mesh")
        body.from_mesh = true;
      else
        body.shape_formula = shape;
      AssertThrow(!body.from_mesh || !body.file_name.empty(),
                  ExcMessage(where +
                             "/Shape = mesh needs the volume mesh's "
                             "'File name' (" +
                             where + "/File name)."));
      // Build the shape once now: the errors then come at parsing.
      if (dim == 2)
        create_body_shape<2>(body, where);
      else
        create_body_shape<3>(body, where);
    }



    template <int dim>
    std::unique_ptr<Shape<dim>>
    create_body_shape(const BodyParameters &body, const std::string &where)
    {
      if (body.from_mesh)
        return make_mesh_region<dim>(body.file_name,
                                     body.points_per_cell,
                                     where + "/File name",
                                     body.physical_groups);
      if (!body.shape_formula.empty())
        {
          ShapeContext context;
          context.where = where + "/Shape";
          context.constants =
            parse_function_constants(body.function_constants,
                                     where + "/Function constants");
          context.file_name      = body.file_name;
          context.file_parameter = where + "/File name";
          return parse_shape<dim>(body.shape_formula, context);
        }
      Point<dim>     center;
      Tensor<1, dim> half_lengths;
      for (unsigned int d = 0; d < dim; ++d)
        {
          center[d]       = body.center[d];
          half_lengths[d] = body.shape == BodyParameters::Shape::sphere ?
                              body.half_lengths[0] :
                              body.half_lengths[d];
        }
      if (body.shape == BodyParameters::Shape::box)
        return make_box<dim>(center, half_lengths);
      return make_ellipsoid<dim>(center, half_lengths);
    }



    template <int dim>
    std::vector<std::unique_ptr<Shape<dim>>>
    create_body_shapes(const std::vector<BodyParameters> &bodies)
    {
      std::vector<std::unique_ptr<Shape<dim>>> shapes;
      for (unsigned int b = 0; b < bodies.size(); ++b)
        shapes.push_back(
          create_body_shape<dim>(bodies[b], numbered_subsection("Body", b)));
      return shapes;
    }



    template std::unique_ptr<Shape<2>>
    create_body_shape<2>(const BodyParameters &, const std::string &);
    template std::vector<std::unique_ptr<Shape<2>>>
    create_body_shapes<2>(const std::vector<BodyParameters> &);
    template std::vector<std::unique_ptr<Shape<3>>>
    create_body_shapes<3>(const std::vector<BodyParameters> &);
    template std::unique_ptr<Shape<3>>
    create_body_shape<3>(const BodyParameters &, const std::string &);
  } // namespace Geometry
} // namespace fmpm
