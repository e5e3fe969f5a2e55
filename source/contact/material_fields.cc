// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The material fields v^α, v^α+, a^α the updates read: lumped (seed 004
// Eqs. 26, 31-34), the multimaterial XPIC(k)/FMPM(k) series (Eq. 37) and
// its exact limit.

#include <fmpm/contact/manager.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/mass_matrix/series.h>
#include <fmpm/material_points.h>
#include <fmpm/support_cache.h>
#include <fmpm/velocity_conditions.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>

namespace fmpm
{
  namespace Contact
  {
    template <int dim>
    void
    Manager<dim>::compute_field(const ParticleUpdate::GridField field)
    {
      const ::fmpm::Parameters         &parameters  = this->get_parameters();
      const MassMatrix::Interface<dim> &mass_matrix = this->get_mass_matrix();
      const double                      time_step   = this->get_timestep();
      const bool has_hanging_nodes                  = this->has_hanging_nodes();
      using namespace ParticleUpdate;
      TimerOutput::Scope     timer(this->get_computing_timer(),
                               "contact: grid fields");
      const FieldSolver<dim> solver = this->get_field_solver();
      // Lumped fields without hanging nodes or a series after them: solved
      // on the material's nodes only, zero elsewhere (they were zeroed where
      // the last solve of the field wrote).
      const bool on_material_nodes =
        !has_hanging_nodes && mass_matrix.order() < 2 && !material_exact_solve;
      if (on_material_nodes && !multimaterial_nodes_valid)
        find_multimaterial_nodes();
      // The series of Eq. 37 without the contact term (Eq. 48) starts from
      // v^α0 = v^α − Δv^α.
      const bool uncorrected_series_start =
        parameters.contact.xpic_contact_term == XpicContactTerm::uncorrected &&
        mass_matrix.order() > 1;
      for (unsigned int alpha = 0; alpha < fields.size(); ++alpha)
        {
          MaterialField<dim> &material = fields[alpha];
          if (material.computed[field])
            continue;
          if (on_material_nodes)
            {
              solver.lumped_on_nodes(material,
                                     field,
                                     material_nodes[alpha],
                                     time_step);
              solver.finish(material, field, true);
              continue;
            }
          // a^α = (f^α0 + f^(BC) + Δp^α+/Δt) / m^α = (p^α+ − p^α) / (m^α
          // Δt): the contact force of the second correction only (Eqs.
          // 32-34, a^{α,1}). (f^α is not read after the momentum update:
          // its storage holds the difference, the source of a^α.)
          if (solver.is_acceleration(field))
            set_scaled_sum(material.force,
                           material.updated_momentum,
                           -1.,
                           material.momentum,
                           1. / time_step);
          // v^α = p^α / m^α (Eq. 26), v^α+ = p^α+ / m^α (Eq. 31): lumped, or
          // the start of the series or exact solve below.
          solver.solve(
            material,
            field,
            [&](const GridVectorField &q, GridVectorField &target) {
              solver.lumped(material, field, q);
              if (field != acceleration && uncorrected_series_start)
                target.add(-1., material.delta_velocity);
            },
            true);
        }

      if (field != velocity && field != updated_velocity)
        return;
      if (material_exact_solve)
        solve_material_full_mass(field);
      else if (mass_matrix.order() > 1)
        material_series(field);
    }



    template <int dim>
    void
    Manager<dim>::material_series(const ParticleUpdate::GridField field)
    {
      // Multimaterial XPIC(k) and FMPM(k) (seed 004 Eq. 37, seed 000 Eqs.
      // 3.13-3.22). With A^α = S^{+α}S = (m^α)⁻¹m̃^α and
      // (m̃ₖ^α)⁻¹ − (m̃ₖ₋₁^α)⁻¹ = (I − A^α)^{k−1}(m^α)⁻¹ (Eq. 3.15):
      //   v (XPIC):  (m̃ₖ^α)⁻¹p^α − (m̃ₖ₋₁^α)⁻¹Δp^α   (Eq. 3.18)
      //   v⁺ (FMPM): (m̃ₖ^α)⁻¹p^α+ − (m̃ₖ₋₁^α)⁻¹Δp^α  (Eq. 3.22),
      // both the series z₁ = (m^α)⁻¹q + Δv^α, z_{j+1} = z_j + (m^α)⁻¹(q −
      // m̃^α z_j) with q = p^α − Δp^α (resp. p^α+ − Δp^α): the FMPM(k)
      // series of each material, started from the contact-corrected velocity
      // (uncorrected: from (m^α)⁻¹q, Eq. 48). All materials share each sweep
      // over the support cache.
      const ::fmpm::Parameters         &parameters  = this->get_parameters();
      const MassMatrix::Interface<dim> &mass_matrix = this->get_mass_matrix();
      const GridScalar                 &lumped_mass = this->get_lumped_mass();
      const double                      mass_floor  = this->get_mass_floor();
      const VelocityConditions<dim>    &velocity_conditions =
        this->get_velocity_conditions();
      const FieldSolver<dim> solver = this->get_field_solver();
      using namespace ParticleUpdate;
      const unsigned int k               = mass_matrix.order();
      const bool         updated         = field == updated_velocity;
      const double       t_field         = solver.time_of(field);
      const unsigned int n_owned         = lumped_mass.locally_owned_size();
      const double       floor           = mass_floor;
      const bool         net_incremental = parameters.contact.net_incremental;
      // q^α = p^α − m^α Δv^α (resp. p^α+ − m^α Δv^α) of every material.
      std::vector<MassMatrix::SeriesField> series;
      std::vector<GridVectorField *>       products;
      for (auto &material : fields)
        {
          const GridVectorField &p =
            updated ? material.updated_momentum : material.momentum;
          for (unsigned int d = 0; d < dim; ++d)
            {
              double *const       q  = material.series_rhs.block(d).begin();
              const double *const pd = p.block(d).begin();
              const double *const dv = material.delta_velocity.block(d).begin();
              const double *const m  = material.mass.begin();
              for (unsigned int i = 0; i < n_owned; ++i)
                q[i] = pd[i] - m[i] * dv[i];
            }
          series.push_back(MassMatrix::SeriesField{&material.mass,
                                                   &material.series_rhs,
                                                   &material.fields[field]});
          products.push_back(&material.series_product);
        }
      MassMatrix::SeriesHooks hooks;
      // Net incremental contact: keep z_j; the increment after the velocity
      // conditions becomes the momenta m^α δz^α the contact laws correct:
      // z_{j+1} = z_j + (m^α)⁻¹(m^α δz^α + Δ^α) (Nairn 2026).
      if (net_incremental)
        hooks.before_update = [&](const unsigned int) {
          for (auto &material : fields)
            material.series_increment = material.fields[field];
        };
      hooks.after_update = [&](const unsigned int) {
        for (auto &material : fields)
          {
            GridVectorField &target = material.fields[field];
            velocity_conditions.correct_velocities(target, t_field, nullptr);
            if (net_incremental)
              for (unsigned int d = 0; d < dim; ++d)
                {
                  double *const dp = material.series_increment.block(d).begin();
                  double *const zd = target.block(d).begin();
                  const double *const m = material.mass.begin();
                  for (unsigned int i = 0; i < n_owned; ++i)
                    {
                      dp[i] = m[i] * (zd[i] - dp[i]); // m^α (z_{j+1} − z_j)
                      if (m[i] > floor)
                        zd[i] -= dp[i] / m[i]; // back to z_j
                    }
                }
          }
        if (net_incremental)
          {
            apply(Stage::increment);
            for (auto &material : fields)
              {
                GridVectorField &target = material.fields[field];
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    const double *const dp =
                      material.series_increment.block(d).begin();
                    double *const       zd = target.block(d).begin();
                    const double *const m  = material.mass.begin();
                    for (unsigned int i = 0; i < n_owned; ++i)
                      if (m[i] > floor)
                        zd[i] += dp[i] / m[i];
                  }
                velocity_conditions.correct_velocities(target,
                                                       t_field,
                                                       nullptr);
              }
          }
        for (auto &material : fields)
          solver.finish(material, field, false);
      };
      MassMatrix::fmpm_series(
        [this](const std::vector<GridVectorField *> &in,
               const std::vector<GridVectorField *> &out) {
          apply_material_full_mass(in, out);
        },
        series,
        products,
        k,
        floor,
        0,
        hooks);
    }



    template <int dim>
    void
    Manager<dim>::solve_material_full_mass(
      const ParticleUpdate::GridField field)
    {
      const GridScalar              &lumped_mass   = this->get_lumped_mass();
      const double                   time_step     = this->get_timestep();
      const double                   momentum_time = this->get_momentum_time();
      const double                   time          = this->get_time();
      const VelocityConditions<dim> &velocity_conditions =
        this->get_velocity_conditions();
      // Multimaterial FMPM(k) with net incremental contact iterates
      //   z_{j+1} = z_j + (m^α)⁻¹ P(q^α − m̃^α z_j),   q^α = p^α − m^α Δv^α,
      // from the contact-corrected lumped velocity z₁ (seed 000 Eqs. 3.13-
      // 3.22), P the law of the increments: the materials of a pair in
      // contact take the same increment. As k → ∞ it converges to the z in
      // z₁ + (that subspace) where the residual q − m̃ z vanishes at every
      // node apart from equal and opposite forces between materials in
      // contact: the systems m̃^α z^α = q^α, sharing their unknown at the
      // nodes where materials are in contact (solve_full_mass_systems()).
      // Fixed components keep z₁: known (velocity conditions), empty, and
      // weak (m̃_ii < τ m_i, the single-material solve's remedy; at a node
      // with materials in contact the sums over them decide, so that
      // perfect interfaces give the single-material solve).
      using namespace ParticleUpdate;
      const bool         updated = field == updated_velocity;
      const double       t_field = updated ? time + time_step : momentum_time;
      const unsigned int n_materials = fields.size();
      const unsigned int n_owned     = lumped_mass.locally_owned_size();
      const double       floor       = this->get_mass_floor();
      const double       tau       = material_exact_solve->weak_node_threshold;
      const bool         has_known = velocity_conditions.uses_known_values();
      if (has_known)
        velocity_conditions.known_values(t_field,
                                         known_velocity_mask,
                                         known_velocity_value);

      // q^α and m̃^α_ii (from the cell matrices).
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          MaterialField<dim>    &material = fields[a];
          const GridVectorField &p =
            updated ? material.updated_momentum : material.momentum;
          for (unsigned int c = 0; c < dim; ++c)
            {
              double *const       q  = material.series_rhs.block(c).begin();
              const double *const pc = p.block(c).begin();
              const double *const dv = material.delta_velocity.block(c).begin();
              const double *const m  = material.mass.begin();
              for (unsigned int i = 0; i < n_owned; ++i)
                q[i] = pc[i] - m[i] * dv[i];
            }
          full_mass[a].diagonal(material.full_mass_diagonal);
        }

      // The materials in contact at each node (bit a: material a), from the
      // last correction's contact states.
      find_contact_groups();

      // Weak nodes: m̃_ii < τ m_i, of the material or, where materials are in
      // contact, of their sums.
      for (auto &material : fields)
        for (unsigned int i = 0; i < n_owned; ++i)
          {
            const double m_i = material.mass.local_element(i);
            material.weak.local_element(i) =
              m_i > floor &&
                  material.full_mass_diagonal.local_element(i) < tau * m_i ?
                1. :
                0.;
          }
      for (const auto &[i, group] : contact_groups)
        {
          double group_diagonal = 0, group_mass = 0;
          for (unsigned int a = 0; a < n_materials; ++a)
            if (group & (1u << a))
              {
                group_diagonal += fields[a].full_mass_diagonal.local_element(i);
                group_mass += fields[a].mass.local_element(i);
              }
          for (unsigned int a = 0; a < n_materials; ++a)
            if (group & (1u << a))
              fields[a].weak.local_element(i) =
                fields[a].mass.local_element(i) > floor &&
                    group_diagonal < tau * group_mass ?
                  1. :
                  0.;
        }

      std::vector<MassMatrix::FullMassSystem<CellwiseMatrix>> systems;
      for (unsigned int a = 0; a < n_materials; ++a)
        systems.push_back({&full_mass[a],
                           &fields[a].full_mass_diagonal,
                           &fields[a].mass,
                           &fields[a].weak,
                           &fields[a].series_rhs,
                           &fields[a].fields[field],
                           &fields[a].solve_workspace});
      MassMatrix::FullMassSolveSettings settings;
      settings.tolerance      = material_exact_solve->tolerance;
      settings.max_iterations = material_exact_solve->max_iterations;
      settings.mass_floor     = floor;
      const MassMatrix::FullMassSolve result =
        MassMatrix::solve_full_mass_systems(systems,
                                            contact_groups,
                                            has_known ? &known_velocity_mask :
                                                        nullptr,
                                            MassMatrix::FullMassStart::given,
                                            settings);
      ++material_solves;
      material_solve_iterations += result.iterations;
      material_solve_failures += result.converged ? 0 : 1;

      const FieldSolver<dim> solver = this->get_field_solver();
      for (auto &material : fields)
        solver.finish(material, field, true);
    }



    template <int dim>
    void
    Manager<dim>::apply_material_full_mass(
      const std::vector<GridVectorField *> &in,
      const std::vector<GridVectorField *> &out)
    {
      // One pass over the cell matrices of each material (assembled by the
      // extrapolation), as the single-material m̃.
      for (unsigned int a = 0; a < in.size(); ++a)
        MassMatrix::apply_full_mass(full_mass[a], *out[a], *in[a]);
    }

    template class Manager<2>;
    template class Manager<3>;
  } // namespace Contact
} // namespace fmpm
