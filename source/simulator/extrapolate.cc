// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Particles to grid: m = SᵀM, p = SᵀMV (Eq. 1.6), f = −GᵀVσ + SᵀM b (Eq.
// 2.11) and m̃ = SᵀMS (Eq. 1.9), with contact per material (seed 004 Eqs.
// 5, 29, 37) and the contact geometry, in one point loop over a list of
// sinks (transfer/point_loop.h, transfer/sinks.h). The loop builds the
// step's supports as it goes (Transfer::SupportBuilder) or computes
// classic ones on affine cells (Transfer::ComputedSupports).

#include <fmpm/simulator.h>
#include <fmpm/transfer/point_loop.h>
#include <fmpm/transfer/sinks.h>
#include <fmpm/transfer/support_builder.h>

namespace fmpm
{
  template <int dim>
  template <typename... Sinks>
  void
  Simulator<dim>::for_each_point(const bool with_gradients, Sinks &...sinks)
  {
    if (supports.implicit_classic)
      {
        Transfer::ComputedSupports<dim> computed(supports,
                                                 transfer,
                                                 points,
                                                 with_gradients);
        Transfer::for_each_point(points, computed, sinks...);
      }
    else
      {
        Transfer::SupportBuilder<dim> builder = support_builder();
        Transfer::for_each_point(points, builder, sinks...);
        report_support_failure(builder);
      }
  }



  template <int dim>
  void
  Simulator<dim>::particles_to_grid(const bool with_forces)
  {
    prepare_supports();

    // m̃ as cell-wise matrices where the mass matrix accepts them, else the
    // assembled sparse matrix (the collection BC methods need its entries).
    centre_of_mass.use_cellwise_full_mass =
      mass_matrix->needs_full_mass_matrix() &&
      mass_matrix->accepts_cellwise_full_mass_matrix() &&
      !velocity_conditions.needs_full_mass_matrix();
    const bool assemble_full = !centre_of_mass.use_cellwise_full_mass &&
                               (mass_matrix->needs_full_mass_matrix() ||
                                velocity_conditions.needs_full_mass_matrix());
    // (With contact m, p and f are set from the material fields after the
    // sweep.)
    const bool contact = contact_active();
    if (!contact)
      {
        centre_of_mass.mass     = 0;
        centre_of_mass.momentum = 0;
        if (with_forces)
          centre_of_mass.force = 0;
      }
    typename Transfer::FullMassCellSink<dim>::Targets full_mass_targets;
    if (assemble_full)
      {
        centre_of_mass.full_mass_matrix = 0;
        full_mass_targets.assembled     = &centre_of_mass.full_mass_matrix;
        full_mass_targets.partitioner =
          centre_of_mass.mass.get_partitioner().get();
      }
    if (centre_of_mass.use_cellwise_full_mass)
      {
        centre_of_mass.cellwise_full_mass.clear();
        full_mass_targets.cellwise = &centre_of_mass.cellwise_full_mass;
      }

    // Per-material fields (contact, zeroed by the manager): m^α, p^α0,
    // f^α0, g^α, Σ S M X, and m̃^α = Σ_{p∈α} S M Sᵀ (seed 004 Eq. 37) for
    // the multimaterial series and exact solve.
    std::vector<Contact::MaterialField<dim>>  no_material_fields;
    std::vector<Contact::MaterialField<dim>> &material_fields =
      contact ? this->contact->material_fields() : no_material_fields;
    if (contact && this->contact->needs_material_full_mass())
      full_mass_targets.material = &this->contact->material_full_mass();
    const Contact::GeometrySink<dim>  no_contact_geometry;
    const Contact::GeometrySink<dim> &contact_geometry =
      contact ? this->contact->begin_extrapolation(points,
                                                   supports.material.data(),
                                                   with_forces) :
                no_contact_geometry;

    // The sinks of m, p (Sᵀ) and f (Gᵀ, body force) of the centre of mass
    // or, with contact, of the point's material (Eqs. 5, 29).
    double *p[dim], *f[dim];
    for (unsigned int d = 0; d < dim; ++d)
      {
        p[d] = centre_of_mass.momentum.block(d).begin();
        f[d] = centre_of_mass.force.block(d).begin();
      }
    const Transfer::MassMomentumSink<dim> mass_momentum(
      points, centre_of_mass.mass.begin(), p);
    const Transfer::ForceSink<dim> force(points, external_loads, f);
    Transfer::PerMaterial<Transfer::MassMomentumSink<dim>>
      material_mass_momentum(supports.material.data());
    Transfer::PerMaterial<Transfer::ForceSink<dim>> material_force(
      supports.material.data());
    for (auto &field : material_fields)
      {
        for (unsigned int d = 0; d < dim; ++d)
          {
            p[d] = field.momentum.block(d).begin();
            f[d] = field.force.block(d).begin();
          }
        material_mass_momentum.sinks.emplace_back(points,
                                                  field.mass.begin(),
                                                  p);
        material_force.sinks.emplace_back(points, external_loads, f);
      }
    const auto &partitioner = *centre_of_mass.mass.get_partitioner();
    Transfer::FullMassCellSink<dim> full_mass(points,
                                              supports,
                                              transfer,
                                              full_mass_targets,
                                              partitioner.locally_owned_size() +
                                                partitioner.n_ghost_indices());

    const bool with_gradients =
      with_forces || contact_geometry.needs_gradients();
    if (!contact && parameters.axisymmetric)
      {
        // With the hoop force.
        Transfer::ForceSink<dim, true> hoop_force(points, external_loads, f);
        hoop_force.read_hoop_function(supports);
        Transfer::IfActive<Transfer::ForceSink<dim, true>> forces(hoop_force,
                                                                  with_forces);
        for_each_point(with_gradients, mass_momentum, forces, full_mass);
      }
    else if (!contact)
      {
        Transfer::IfActive<Transfer::ForceSink<dim>> forces(force, with_forces);
        for_each_point(with_gradients, mass_momentum, forces, full_mass);
      }
    else
      {
        if (parameters.axisymmetric)
          {
            // f^α0 with the hoop force.
            Transfer::PerMaterial<Transfer::ForceSink<dim, true>>
              material_hoop_force(supports.material.data());
            for (auto &field : material_fields)
              {
                for (unsigned int d = 0; d < dim; ++d)
                  f[d] = field.force.block(d).begin();
                material_hoop_force.sinks.emplace_back(points,
                                                       external_loads,
                                                       f);
                material_hoop_force.sinks.back().read_hoop_function(supports);
              }
            Transfer::IfActive<
              Transfer::PerMaterial<Transfer::ForceSink<dim, true>>>
              forces(material_hoop_force, with_forces);
            for_each_point(with_gradients,
                           forces,
                           material_mass_momentum,
                           contact_geometry,
                           full_mass);
          }
        else
          {
            Transfer::IfActive<Transfer::PerMaterial<Transfer::ForceSink<dim>>>
              forces(material_force, with_forces);
            for_each_point(with_gradients,
                           forces,
                           material_mass_momentum,
                           contact_geometry,
                           full_mass);
          }
        // m = Σ_α m^α, p = Σ_α p^α, f = Σ_α f^α0 (and the ghosts of the
        // material fields).
        this->contact->finish_extrapolation(centre_of_mass, with_forces);
      }

    if (with_forces)
      add_face_traction_forces(contact);
    centre_of_mass.mass.compress(VectorOperation::add);
    centre_of_mass.momentum.compress(VectorOperation::add);
    if (with_forces)
      centre_of_mass.force.compress(VectorOperation::add);
    if (assemble_full)
      centre_of_mass.full_mass_matrix.compress(VectorOperation::add);
    centre_of_mass.mass.update_ghost_values();
    mass_matrix->setup();
  }



  template <int dim>
  void
  Simulator<dim>::add_face_traction_forces(const bool contact)
  {
    if (!external_loads.has_face_tractions())
      return;
    AssertThrow(!contact,
                ExcMessage("Boundary conditions/Traction N/Distribution = "
                           "face does not support contact yet; allowed with "
                           "contact: point."));
    double *f[dim];
    for (unsigned int d = 0; d < dim; ++d)
      f[d] = centre_of_mass.force.block(d).begin();
    external_loads.add_face_traction_forces(points, transfer, f);
  }



  template <int dim>
  void
  Simulator<dim>::finish_re_extrapolation()
  {
    // The tail of the re-extrapolation the particle update made: with
    // contact p = Σ_α p^α (Eq. 6); the ghosts added (with contact also of
    // g^α, Σ S M X, u^α, V^α where read).
    if (contact_active())
      this->contact->finish_re_extrapolation(centre_of_mass);
    centre_of_mass.momentum.compress(VectorOperation::add);
  }



  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
