// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks that every default is written once: the text each declare_entry()
// writes as its default parses back into the member initializers of its
// struct. Every parameter struct (with the Contact subsection) and every
// plugin with parameters (mass matrices, particle updates, constitutive
// models) is declared, parsed without any 'set' line, and compared field by
// field with a default-constructed instance. A default written twice that
// drifts (a literal "0.3" against an initializer 0.25, a text that rounds)
// fails here.

#include <fmpm/constitutive_model/linear_elastic.h>
#include <fmpm/constitutive_model/mie_gruneisen.h>
#include <fmpm/constitutive_model/neo_hookean.h>
#include <fmpm/mass_matrix/fmpm.h>
#include <fmpm/mass_matrix/full.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_update/flip.h>
#include <fmpm/particle_update/flip_pic_blend.h>
#include <fmpm/particle_update/fmpm.h>
#include <fmpm/particle_update/xpic.h>

#include <deal.II/base/parameter_handler.h>

#include <memory>
#include <string>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;

#define EXPECT_FIELD(field) \
  EXPECT_EQ(parsed.field, defaults.field) << "member " #field

  /** A 3D scene of one body, one material and one traction, declared with
   * every default and parsed without any 'set' line. */
  fmpm::Parameters
  parse_defaults(ParameterHandler &prm)
  {
    fmpm::SceneSize size;
    size.dimension   = 3;
    size.n_tractions = 1;
    fmpm::Parameters::declare_parameters(prm, size);
    prm.set("Dimension", "3");
    prm.set("Number of tractions", "1");
    fmpm::Parameters parameters;
    parameters.parse_parameters(prm);
    return parameters;
  }

  /** The plugin @p name of @p Registry parsed from its declared defaults in
   * the subsection @p section of @p prm, as @p Plugin. */
  template <typename Plugin, typename Registry>
  std::unique_ptr<Plugin>
  create_from_defaults(const Registry    &registry,
                       const std::string &name,
                       const std::string &section,
                       ParameterHandler  &prm)
  {
    prm.enter_subsection(section);
    auto plugin = registry.create(name, prm);
    prm.leave_subsection();
    auto *typed = dynamic_cast<Plugin *>(plugin.get());
    EXPECT_NE(typed, nullptr) << name;
    plugin.release();
    return std::unique_ptr<Plugin>(typed);
  }



  TEST(ParameterDefaults, SceneMeshTimeAndMethod)
  {
    ParameterHandler       prm;
    const fmpm::Parameters all = parse_defaults(prm);
    {
      const fmpm::MeshParameters &parsed = all.mesh;
      const fmpm::MeshParameters  defaults;
      EXPECT_FIELD(type);
      EXPECT_FIELD(lower_corner);
      EXPECT_FIELD(upper_corner);
      EXPECT_FIELD(subdivisions);
      EXPECT_FIELD(file_name);
      EXPECT_FIELD(global_refinement);
      EXPECT_FIELD(distortion);
      EXPECT_FIELD(periodic);
    }
    {
      const fmpm::MeshRefinementParameters &parsed = all.refinement;
      const fmpm::MeshRefinementParameters  defaults;
      EXPECT_FIELD(strategy);
      EXPECT_FIELD(interval);
      EXPECT_FIELD(minimum_level);
      EXPECT_FIELD(maximum_level);
      EXPECT_FIELD(buffer_layers);
      EXPECT_FIELD(refine_fraction);
      EXPECT_FIELD(coarsen_fraction);
      EXPECT_FIELD(initial_refinement);
      EXPECT_FIELD(point_weight);
    }
    {
      const fmpm::TimeParameters &parsed = all.time;
      const fmpm::TimeParameters  defaults;
      EXPECT_FIELD(end_time);
      EXPECT_FIELD(time_step);
      EXPECT_FIELD(courant_number);
      EXPECT_FIELD(max_steps);
      EXPECT_FIELD(check_stability);
      EXPECT_FIELD(courant_limit);
    }
    {
      const fmpm::MethodParameters &parsed = all.method;
      const fmpm::MethodParameters  defaults;
      EXPECT_FIELD(particle_update);
      EXPECT_FIELD(mass_matrix);
      EXPECT_FIELD(strain_update);
      EXPECT_FIELD(strain_update_scheme.name());
      EXPECT_FIELD(lumped_strain_velocities);
      EXPECT_FIELD(shape_function);
      EXPECT_FIELD(cpdi_critical_radius);
      EXPECT_FIELD(deformation_gradient_update);
      EXPECT_FIELD(taylor_terms);
      EXPECT_FIELD(subcycle_strain_increment);
      EXPECT_FIELD(grid_damping);
      EXPECT_FIELD(particle_damping);
    }
  }



  TEST(ParameterDefaults, BodiesMaterialsLoadsAndConditions)
  {
    ParameterHandler       prm;
    const fmpm::Parameters all = parse_defaults(prm);
    {
      const fmpm::Parameters &parsed = all;
      const fmpm::Parameters  defaults;
      EXPECT_FIELD(gravity);
      EXPECT_FIELD(body_acceleration);
      EXPECT_FIELD(body_acceleration_constants);
      EXPECT_FIELD(body_acceleration_at_initial_position);
      EXPECT_FIELD(test_mode);
      EXPECT_FIELD(fast_point_sorting);
      EXPECT_FIELD(print_timer_summary);
    }
    {
      ASSERT_EQ(all.materials.size(), 1u);
      const fmpm::MaterialParameters &parsed = all.materials[0];
      const fmpm::MaterialParameters  defaults;
      EXPECT_FIELD(model_name);
      EXPECT_FIELD(density);
    }
    {
      ASSERT_EQ(all.bodies.size(), 1u);
      const fmpm::BodyParameters &parsed = all.bodies[0];
      const fmpm::BodyParameters  defaults;
      EXPECT_FIELD(shape);
      EXPECT_FIELD(center);
      EXPECT_FIELD(half_lengths);
      EXPECT_FIELD(material);
      EXPECT_FIELD(points_per_cell);
      EXPECT_FIELD(velocity_expression);
      EXPECT_FIELD(function_constants);
      EXPECT_FIELD(initial_stress_from_gravity);
      EXPECT_FIELD(initial_stress_expression);
      EXPECT_FIELD(physical_groups);
    }
    {
      const fmpm::RotatingFrameParameters &parsed = all.rotating_frame;
      const fmpm::RotatingFrameParameters  defaults;
      EXPECT_FIELD(enable);
      EXPECT_FIELD(angular_velocity);
      EXPECT_FIELD(center);
      EXPECT_FIELD(constants);
    }
    {
      const fmpm::BoundaryConditionParameters &parsed = all.boundary_conditions;
      const fmpm::BoundaryConditionParameters  defaults;
      EXPECT_FIELD(fixed);
      EXPECT_FIELD(roller);
      EXPECT_FIELD(fixed_region);
      EXPECT_FIELD(method);
    }
    {
      ASSERT_EQ(all.boundary_conditions.tractions.size(), 1u);
      const fmpm::TractionParameters &parsed =
        all.boundary_conditions.tractions[0];
      const fmpm::TractionParameters defaults;
      EXPECT_FIELD(box_lower);
      EXPECT_FIELD(box_upper);
      EXPECT_FIELD(traction);
      EXPECT_FIELD(normal_axis);
      EXPECT_FIELD(constants);
    }
  }



  TEST(ParameterDefaults, MovingWall)
  {
    // A wall needs one of its three kinds: every other entry keeps its
    // default.
    ParameterHandler prm;
    fmpm::MovingWallParameters::declare_parameters(prm, 3);
    prm.set("Region", "x");
    fmpm::MovingWallParameters parsed;
    parsed.parse_parameters(prm, 3, "Moving wall 0");
    const fmpm::MovingWallParameters defaults;
    EXPECT_FIELD(boundary_ids);
    EXPECT_FIELD(box_lower);
    EXPECT_FIELD(box_upper);
    EXPECT_FIELD(direction);
    EXPECT_FIELD(velocity);
    EXPECT_FIELD(constants);
  }



  TEST(ParameterDefaults, OutputCheckpointFailureReference)
  {
    ParameterHandler       prm;
    const fmpm::Parameters all = parse_defaults(prm);
    {
      const fmpm::OutputParameters &parsed = all.output;
      const fmpm::OutputParameters  defaults;
      EXPECT_FIELD(directory);
      EXPECT_FIELD(interval);
      EXPECT_FIELD(step_interval);
      EXPECT_FIELD(exact_output_times);
      EXPECT_FIELD(write_vtu);
      EXPECT_FIELD(tracked_points);
      EXPECT_FIELD(compression);
      EXPECT_FIELD(write_particle_csv);
      EXPECT_FIELD(write_grid_acceleration);
      EXPECT_FIELD(progress_seconds);
      EXPECT_FIELD(track_dissipation);
    }
    {
      const fmpm::CheckpointParameters &parsed = all.checkpoint;
      const fmpm::CheckpointParameters  defaults;
      EXPECT_FIELD(step_interval);
      EXPECT_FIELD(wall_time_interval);
      EXPECT_FIELD(keep);
    }
    {
      const fmpm::FailureParameters &parsed = all.failure;
      const fmpm::FailureParameters  defaults;
      EXPECT_FIELD(energy_growth_limit);
      EXPECT_FIELD(kinetic_energy_limit);
      EXPECT_FIELD(lost_points);
    }
    {
      const fmpm::ReferenceSolutionParameters &parsed = all.reference;
      const fmpm::ReferenceSolutionParameters  defaults;
      EXPECT_FIELD(enable);
      EXPECT_FIELD(velocity);
      EXPECT_FIELD(displacement);
      EXPECT_FIELD(constants);
    }
  }



  TEST(ParameterDefaults, Contact)
  {
    ParameterHandler                 prm;
    const fmpm::Parameters           all    = parse_defaults(prm);
    const fmpm::Contact::Parameters &parsed = all.contact;
    const fmpm::Contact::Parameters  defaults;
    EXPECT_FIELD(multimaterial);
    EXPECT_FIELD(normals_name);
    EXPECT_FIELD(specified_normal);
    EXPECT_FIELD(critical_separation);
    EXPECT_FIELD(touching_tolerance);
    EXPECT_FIELD(gap_closing);
    EXPECT_FIELD(friction_coefficient);
    EXPECT_FIELD(interface_normal_stiffness);
    EXPECT_FIELD(interface_tangential_stiffness);
    EXPECT_FIELD(default_law.name);
    EXPECT_FIELD(default_law.coefficients);
    EXPECT_FIELD(pair_laws.size());
    EXPECT_FIELD(corrections_per_step);
    EXPECT_FIELD(three_or_more);
    EXPECT_FIELD(xpic_contact_term);
    EXPECT_FIELD(net_incremental);
  }



  TEST(ParameterDefaults, MassMatrices)
  {
    ParameterHandler prm;
    parse_defaults(prm);
    const auto &registry = fmpm::MassMatrix::Registry<3>::instance();
    {
      const auto parsed_plugin =
        create_from_defaults<fmpm::MassMatrix::Full<3>>(registry,
                                                        "full",
                                                        "Mass matrix",
                                                        prm);
      const auto                     &parsed = *parsed_plugin;
      const fmpm::MassMatrix::Full<3> defaults;
      EXPECT_FIELD(tolerance);
      EXPECT_FIELD(max_iterations);
      EXPECT_FIELD(weak_node_threshold);
      EXPECT_FIELD(lumped_fraction);
      // Contact's exact solve holds no defaults of its own: it reads these.
      const auto exact = parsed.exact_solve();
      ASSERT_TRUE(exact.has_value());
      EXPECT_EQ(exact->tolerance, defaults.tolerance);
      EXPECT_EQ(exact->max_iterations, defaults.max_iterations);
      EXPECT_EQ(exact->weak_node_threshold, defaults.weak_node_threshold);
    }
    {
      const auto parsed_plugin =
        create_from_defaults<fmpm::MassMatrix::Fmpm<3>>(registry,
                                                        "fmpm",
                                                        "Mass matrix",
                                                        prm);
      const auto                     &parsed = *parsed_plugin;
      const fmpm::MassMatrix::Fmpm<3> defaults;
      EXPECT_FIELD(k);
      EXPECT_FIELD(tolerance);
      EXPECT_FIELD(period);
      EXPECT_FIELD(period_time);
    }
  }



  TEST(ParameterDefaults, ParticleUpdates)
  {
    ParameterHandler prm;
    parse_defaults(prm);
    const auto &registry = fmpm::ParticleUpdate::Registry<3>::instance();
    const auto  flip     = create_from_defaults<fmpm::ParticleUpdate::Flip<3>>(
      registry, "flip", "Particle update", prm);
    EXPECT_EQ(flip->psi, fmpm::ParticleUpdate::Flip<3>().psi);
    // 'auto': ψ follows the strain update.
    EXPECT_EQ(flip->psi_from_strain_update,
              fmpm::ParticleUpdate::Flip<3>().psi_from_strain_update);
    const auto xpic = create_from_defaults<fmpm::ParticleUpdate::Xpic<3>>(
      registry, "xpic", "Particle update", prm);
    EXPECT_EQ(xpic->psi, fmpm::ParticleUpdate::Xpic<3>().psi);
    const auto fmpm_update =
      create_from_defaults<fmpm::ParticleUpdate::Fmpm<3>>(registry,
                                                          "fmpm",
                                                          "Particle update",
                                                          prm);
    EXPECT_EQ(fmpm_update->psi, fmpm::ParticleUpdate::Fmpm<3>().psi);
    const auto blend =
      create_from_defaults<fmpm::ParticleUpdate::FlipPicBlend<3>>(
        registry, "flip pic blend", "Particle update", prm);
    EXPECT_EQ(blend->alpha, fmpm::ParticleUpdate::FlipPicBlend<3>().alpha);
  }



  TEST(ParameterDefaults, ConstitutiveModels)
  {
    ParameterHandler prm;
    parse_defaults(prm);
    const auto &registry = fmpm::ConstitutiveModel::Registry<3>::instance();
    {
      const auto parsed_plugin =
        create_from_defaults<fmpm::ConstitutiveModel::LinearElastic<3>>(
          registry, "linear elastic", "Material 0", prm);
      const auto                                     &parsed = *parsed_plugin;
      const fmpm::ConstitutiveModel::LinearElastic<3> defaults;
      EXPECT_FIELD(youngs_modulus);
      EXPECT_FIELD(poissons_ratio);
      EXPECT_FIELD(strain_measure);
    }
    {
      const auto parsed_plugin =
        create_from_defaults<fmpm::ConstitutiveModel::NeoHookean<3>>(
          registry, "neo hookean", "Material 0", prm);
      const auto                                  &parsed = *parsed_plugin;
      const fmpm::ConstitutiveModel::NeoHookean<3> defaults;
      EXPECT_FIELD(bulk_modulus);
      EXPECT_FIELD(shear_modulus);
      EXPECT_FIELD(energy_form);
    }
    {
      const auto parsed_plugin =
        create_from_defaults<fmpm::ConstitutiveModel::MieGruneisen<3>>(
          registry, "mie gruneisen", "Material 0", prm);
      const auto                                    &parsed = *parsed_plugin;
      const fmpm::ConstitutiveModel::MieGruneisen<3> defaults;
      EXPECT_FIELD(bulk_modulus);
      EXPECT_FIELD(shear_modulus);
      EXPECT_FIELD(gruneisen_gamma);
      EXPECT_FIELD(s1);
      EXPECT_FIELD(artificial_viscosity_a1);
      EXPECT_FIELD(artificial_viscosity_a2);
      EXPECT_FIELD(plasticity.yield_stress);
      EXPECT_FIELD(plasticity.hardening_modulus);
    }
  }
} // namespace
