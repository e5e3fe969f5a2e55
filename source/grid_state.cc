// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/grid_state.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/velocity_conditions.h>

namespace fmpm
{
  template <int dim>
  void
  GridState<dim>::compute(const ParticleUpdate::GridField   field,
                          const FieldSolver<dim>           &solver,
                          const MassMatrix::Interface<dim> &mass_matrix,
                          const double                      time_step)
  {
    using namespace ParticleUpdate;
    if (this->computed[field])
      return;
    const double                   t_field    = solver.time_of(field);
    const bool                     is_accel   = solver.is_acceleration(field);
    const VelocityConditions<dim> *conditions = solver.conditions;
    if (conditions && conditions->uses_known_values() &&
        mass_matrix.reads_known_velocities())
      {
        conditions->known_values(t_field,
                                 known_velocity_mask,
                                 known_velocity_value);
        if (is_accel)
          {
            // Known accelerations: (v_b(t + Δt) − v_b(t)) / Δt.
            std::vector<GridScalar> mask_end(known_velocity_mask),
              value_end(known_velocity_value);
            conditions->known_values(solver.t_end, mask_end, value_end);
            for (unsigned int d = 0; d < dim; ++d)
              {
                known_velocity_value[d].sadd(-1., 1., value_end[d]);
                known_velocity_value[d] *= 1. / time_step;
              }
          }
      }
    // The padding layer's mirror is a constraint on the solved field itself
    // (the full mass couples the padding nodes to the interior), imposed
    // by the mass matrix in each iterate at the field's time.
    if (conditions && conditions->has_padding_mirrors())
      this->padding_mirror =
        [conditions, is_accel, t_field, &solver](GridVectorField &v) {
          if (is_accel)
            conditions->mirror_padding(v, solver.t_end, t_field, true);
          else
            conditions->mirror_padding(v, t_field, t_field, false);
        };
    solver.solve(
      *this,
      field,
      [&](const GridVectorField &q, GridVectorField &target) {
        // Iterative solves start from the field's value of the last step;
        // m̃ₖ⁻¹f is as accurate in a Δt as v in p.
        mass_matrix.solve_from_guess(q,
                                     target,
                                     field == acceleration ?
                                       this->momentum.l2_norm() / time_step +
                                         this->force.l2_norm() :
                                       0);
      },
      conditions && conditions->corrects_velocities(),
      field == updated_velocity ? &velocity_corrections[1] :
      field == velocity         ? &velocity_corrections[0] :
                                  nullptr);
    this->padding_mirror = nullptr;
  }

  template struct GridState<2>;
  template struct GridState<3>;
} // namespace fmpm
