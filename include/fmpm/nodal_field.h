// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_nodal_field_h
#define fmpm_nodal_field_h

#include <fmpm/grid_vectors.h>
#include <fmpm/particle_update/interface.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/lac/affine_constraints.h>

#include <array>
#include <memory>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  template <int dim>
  class VelocityConditions;

  /**
   * @brief One velocity field on the grid (seed 004 Eqs. 5-6): the lumped
   * masses, momenta, forces and updated momenta the points give the nodes,
   * and the fields the updates read, solved from them. The centre of mass
   * holds one, and with contact every material one more
   * (Contact::MaterialField).
   *
   * @tparam dim spatial dimension
   */
  template <int dim>
  struct NodalField
  {
    /** m = SᵀM (seed 000 Eq. 1.6; m^α of a material) */
    GridScalar mass;
    /** p = SᵀMV (p^α0, then the corrected p^α of seed 004 Eq. 26) */
    GridVectorField momentum;
    /** f = −Gᵀσ V + SᵀM b (f^α0, seed 004 Eq. 29) */
    GridVectorField force;
    /** p⁺ = p + f Δt (p^α+, seed 004 Eq. 31) */
    GridVectorField updated_momentum;
    /** The fields of Table 2.1 (seed 000), by ParticleUpdate::GridField;
     * empty until allocate() gives one its layout. */
    std::array<GridVectorField, ParticleUpdate::n_grid_fields> fields;
    /** Whether each field is solved for the current momenta. */
    std::array<bool, ParticleUpdate::n_grid_fields> computed{};
    /** The owned nodes where each field may be nonzero, for the solves on
     * the nodes of one material only (FieldSolver::lumped_on_nodes()). */
    std::array<std::vector<unsigned int>, ParticleUpdate::n_grid_fields>
      written_nodes;

    /**
     * @brief m, p, f, p⁺ on @p partitioner (owned and ghost nodes, zero),
     * every field with it too if @p all_fields, else empty; nothing
     * computed.
     */
    void
    reinit(
      const std::shared_ptr<const Utilities::MPI::Partitioner> &partitioner,
      const bool                                                all_fields);

    /** @brief Give fields[@p field] dim components on the layout of m
     * (kept if it has them). */
    void
    allocate(const ParticleUpdate::GridField field);

    /**
     * @brief The centre of mass as the sum of the materials (seed 004 Eq.
     * 6): m = Σ_α m^α, p = Σ_α p^α, f = Σ_α f^α, each where asked, on the
     * local (owned and ghost) entries of what the point loops scattered,
     * before the ghosts are added to their owners. Summed from zero in
     * material order.
     */
    template <class Material>
    void
    set_to_sum(const std::vector<Material> &materials,
               const bool                   sum_mass,
               const bool                   sum_momentum,
               const bool                   sum_force);
  };



  /**
   * @brief The solve of a NodalField's fields, one for the centre of mass
   * and for every material: the lumped solve v = m⁻¹q (on every owned node,
   * or on the nodes of one material), and the tail every solve ends with:
   * the velocity conditions, the hanging-node constraints and the ghost
   * values. The full-mass solves (FMPM(k) series, exact) come between the
   * two.
   *
   * @tparam dim spatial dimension
   */
  template <int dim>
  struct FieldSolver
  {
    /** The velocity conditions of the scene (nullptr: none). */
    const VelocityConditions<dim> *conditions = nullptr;
    /** The hanging-node constraints, applied if has_hanging_nodes. */
    const AffineConstraints<double> *constraints       = nullptr;
    bool                             has_hanging_nodes = false;
    /** Nodes with m <= mass_floor are empty: their field is zero. */
    double mass_floor = 0;
    /** The time of the momenta p (t_begin) and of p⁺ (t_end = t + Δt). */
    double t_begin = 0, t_end = 0;

    /** @brief Whether @p field is an acceleration. */
    static bool
    is_acceleration(const ParticleUpdate::GridField field)
    {
      return field == ParticleUpdate::acceleration ||
             field == ParticleUpdate::lumped_acceleration;
    }

    /** @brief Whether @p field is solved from p⁺. */
    static bool
    is_updated(const ParticleUpdate::GridField field)
    {
      return field == ParticleUpdate::updated_velocity ||
             field == ParticleUpdate::lumped_updated_velocity;
    }

    /** @brief Whether @p field is solved with the lumped masses. */
    static bool
    is_lumped(const ParticleUpdate::GridField field)
    {
      return field == ParticleUpdate::lumped_velocity ||
             field == ParticleUpdate::lumped_updated_velocity ||
             field == ParticleUpdate::lumped_acceleration;
    }

    /** @brief The time of the velocities of @p field (t_begin for an
     * acceleration). */
    double
    time_of(const ParticleUpdate::GridField field) const
    {
      return is_updated(field) ? t_end : t_begin;
    }

    /**
     * @brief fields[@p field] = m⁻¹ @p q on the owned nodes, zero on the
     * empty ones (seed 000 Eq. 1.7; seed 004 Eqs. 26, 31-34).
     */
    void
    lumped(NodalField<dim>                &field_set,
           const ParticleUpdate::GridField field,
           const GridVectorField          &q) const;

    /**
     * @brief fields[@p field] = m⁻¹ q on @p nodes only (a material's nodes,
     * m > floor), zero where the last solve of the field wrote: q = p, p⁺,
     * or (p⁺ − p)/Δt for an acceleration (seed 004 Eqs. 26, 31-34).
     * written_nodes[@p field] becomes @p nodes and the condition nodes.
     * Meant for meshes without hanging nodes.
     */
    void
    lumped_on_nodes(NodalField<dim>                 &field_set,
                    const ParticleUpdate::GridField  field,
                    const std::vector<unsigned int> &nodes,
                    const double                     time_step) const;

    /** @brief The momenta @p field is solved from: p⁺ for v⁺, f for an
     * acceleration, p for v. */
    static const GridVectorField &
    source(const NodalField<dim>          &field_set,
           const ParticleUpdate::GridField field)
    {
      return is_acceleration(field) ? field_set.force :
             is_updated(field)      ? field_set.updated_momentum :
                                      field_set.momentum;
    }

    /**
     * @brief The solve of fields[@p field] of a NodalField, the centre of
     * mass's or a material's, unless it is computed: with q = source(), a
     * lumped field is m⁻¹q (seed 000 Eq. 1.7), a full-mass field
     * @p full_mass_solve(q, target) (m̃ₖ⁻¹q: the FMPM(k) series or the exact
     * solve; a material's lumped start of its series, seed 004 Eq. 37);
     * then finish(), with the conditions on lumped fields and, if
     * @p conditions_on_full_mass, on full-mass ones.
     */
    template <class FullMassSolve>
    void
    solve(NodalField<dim>                &field_set,
          const ParticleUpdate::GridField field,
          FullMassSolve                 &&full_mass_solve,
          const bool                      conditions_on_full_mass,
          std::vector<double>            *corrections = nullptr) const
    {
      if (field_set.computed[field])
        return;
      field_set.allocate(field);
      const GridVectorField &q = source(field_set, field);
      if (is_lumped(field))
        lumped(field_set, field, q);
      else
        full_mass_solve(q, field_set.fields[field]);
      finish(field_set,
             field,
             is_lumped(field) || conditions_on_full_mass,
             corrections);
    }

    /**
     * @brief The tail of every solve: with @p apply_conditions the velocity
     * conditions (seed 000 Eq. 2.53; accelerations over [t_begin, t_end]),
     * @p corrections receiving Δv of each node condition if given; then
     * the hanging nodes take their masters' interpolation, the ghost values
     * are updated, and the field counts as computed.
     */
    void
    finish(NodalField<dim>                &field_set,
           const ParticleUpdate::GridField field,
           const bool                      apply_conditions,
           std::vector<double>            *corrections = nullptr) const;
  };



  namespace internal
  {
    /** total = Σ @p terms (from zero, in order) on the local entries of
     * @p total, ghosts included; their values are zeroed first. */
    void
    set_to_sum(GridScalar &total, const std::vector<const double *> &terms);
  } // namespace internal



  template <int dim>
  template <class Material>
  void
  NodalField<dim>::set_to_sum(const std::vector<Material> &materials,
                              const bool                   sum_mass,
                              const bool                   sum_momentum,
                              const bool                   sum_force)
  {
    std::vector<const double *> terms(materials.size());
    if (sum_mass)
      {
        for (unsigned int a = 0; a < materials.size(); ++a)
          terms[a] = materials[a].mass.begin();
        internal::set_to_sum(mass, terms);
      }
    for (unsigned int d = 0; d < dim; ++d)
      {
        if (sum_momentum)
          {
            for (unsigned int a = 0; a < materials.size(); ++a)
              terms[a] = materials[a].momentum.block(d).begin();
            internal::set_to_sum(momentum.block(d), terms);
          }
        if (sum_force)
          {
            for (unsigned int a = 0; a < materials.size(); ++a)
              terms[a] = materials[a].force.block(d).begin();
            internal::set_to_sum(force.block(d), terms);
          }
      }
  }
} // namespace fmpm

#endif
