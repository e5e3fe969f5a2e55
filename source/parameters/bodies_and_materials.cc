// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Body N and Material N.

#include <fmpm/constitutive_model/interface.h>
#include <fmpm/geometry/body_shape.h>
#include <fmpm/parameters.h>

namespace fmpm
{
  namespace
  {
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
  BodyParameters::declare_parameters(ParameterHandler  &prm,
                                     const unsigned int dim)
  {
    const BodyParameters defaults;
    Geometry::declare_body_shape_parameters(prm);
    prm.declare_entry("Center",
                      list_text(defaults.center, dim),
                      point_pattern(dim),
                      "Center of the shape. Units: m.");
    prm.declare_entry("Half lengths",
                      list_text(defaults.half_lengths, dim),
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
                      first_components(defaults.velocity_expression, dim),
                      Patterns::Anything(),
                      "Initial velocity of the points: either dim numbers "
                      "separated by ',', or dim FunctionParser "
                      "expressions in x, y, z separated by ';' (for "
                      "example 'v0*sin(beta*x); 0'). Units: m/s.");
    prm.declare_entry("Function constants",
                      defaults.function_constants,
                      Patterns::Anything(),
                      "Constants for the 'Initial velocity' and 'Initial "
                      "stress' expressions and the shape formula, "
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
    prm.declare_entry(
      "Initial stress",
      defaults.initial_stress_expression,
      Patterns::Anything(),
      "Initial Cauchy stress of the points as FunctionParser expressions "
      "in x, y, z separated by ';', with the body's 'Function constants': "
      "xx; yy; xy in 2D (sigma_zz then follows from plane strain), "
      "xx; yy; zz; xy; xz; yz in 3D; for example the geostatic "
      "'K0*rho*g*(y - H); rho*g*(y - H); 0'. The points start pre-strained "
      "by the symmetric stretch F = I + eps for which the material's model "
      "gives this stress (found by Newton iterations), so every model "
      "continues from it consistently and the strain energy is the "
      "model's. Empty: no initial stress. Not together with 'Initial "
      "stress from gravity'. Units: Pa.");
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
    initial_stress_expression   = prm.get("Initial stress");
    AssertThrow(!initial_stress_from_gravity ||
                  initial_stress_expression.find_first_not_of(" \t") ==
                    std::string::npos,
                ExcMessage(where +
                           ": 'Initial stress' and 'Initial stress from "
                           "gravity = true' both set the initial stress; "
                           "give only one of them."));
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
} // namespace fmpm
