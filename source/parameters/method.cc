// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Time/Strain update, Shape function, Deformation gradient, Particle update,
// Mass matrix.

#include <fmpm/bspline.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_update/interface.h>
#include <fmpm/shape_function.h>

namespace fmpm
{
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
        "B-splines on a mesh of equal axis-aligned boxes (Mesh/Type = box, "
        "no refinement; other meshes are refused): 'b2spline' quadratic "
        "(support +-1.5 cells, NairnMPM's B2SPLINE), 'b3spline' cubic (+-2 "
        "cells), 'b2gimp' the quadratic B-splines averaged over the box of "
        "the initial half-lengths (at most half a cell), 'b2cpdi' over the "
        "CPDI corners (at most a cell from the point); see 'B-spline "
        "boundary'. On more than one MPI rank the lattice vertices two cells "
        "beyond a rank's cells, which b2cpdi corners reach, are ghost nodes "
        "too. Units: none.");
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
      prm.declare_entry(
        "B-spline boundary",
        defaults.bspline_boundary,
        Patterns::Selection(BSpline::boundary_pattern()),
        "B-spline shape functions only: the basis at the mesh boundary. "
        "'open knots': knot vectors repeated at the boundary, so the basis "
        "is complete on the whole mesh and the boundary vertex's function is "
        "1 on the boundary, where velocity conditions act as with classic "
        "shape functions; 'padding': the uniform B-splines everywhere and "
        "the outer layer of cells kept free of points (NairnMPM's B2SPLINE; "
        "the run stops if a point enters it). With padding, Fixed, Roller "
        "and Moving wall conditions on boundary ids act on the wall one "
        "cell inside the mesh boundary: its nodes carry them, and each "
        "padding node mirrors the node across the wall (2 v_w - v along "
        "the held directions, v along the others; with the full mass, fmpm "
        "or full, in every iterate of the solve); it needs wall velocities "
        "in t only, and with the full mass Boundary conditions/Method = "
        "constrained and no multimaterial contact. Units: none.");
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
    bspline_boundary     = prm.get("B-spline boundary");
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
} // namespace fmpm
