// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The material fields v^α, v^α+, a^α the updates read: lumped (seed 004
// Eqs. 26, 31-34), the multimaterial XPIC(k)/FMPM(k) series (Eq. 37) and
// its exact limit.

#include <fmpm/contact/manager.h>
#include <fmpm/mass_matrix/fmpm.h>
#include <fmpm/mass_matrix/interface.h>
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
      const GridScalar                 &lumped_mass = this->get_lumped_mass();
      const double                      mass_floor  = this->get_mass_floor();
      const double                      time_step   = this->get_timestep();
      const double                   momentum_time  = this->get_momentum_time();
      const double                   time           = this->get_time();
      const VelocityConditions<dim> &velocity_conditions =
        this->get_velocity_conditions();
      const bool has_hanging_nodes                 = this->has_hanging_nodes();
      const AffineConstraints<double> &constraints = this->get_constraints();
      using namespace ParticleUpdate;
      TimerOutput::Scope timer(this->get_computing_timer(), "grid solve");
      const double       t_begin = momentum_time, t_end = time + time_step;
      for (auto &material : fields)
        {
          if (material.computed[field])
            continue;
          GridVectorField &target = material.fields[field];
          switch (field)
            {
              case velocity:
              case lumped_velocity: // v^α = p^α / m^α (Eq. 26)
                MassMatrix::apply_lumped_inverse(material.mass,
                                                 material.momentum,
                                                 target,
                                                 mass_floor);
                if (field == velocity &&
                    parameters.contact.xpic_contact_term ==
                      XpicContactTerm::uncorrected &&
                    mass_matrix.order() > 1)
                  {
                    // v^α0 = v^α − Δv^α: the series of Eq. 37 without the
                    // contact term (Eq. 48).
                    target.add(-1., material.delta_velocity);
                  }
                velocity_conditions.correct_velocities(target,
                                                       t_begin,
                                                       nullptr);
                break;
              case updated_velocity:
              case lumped_updated_velocity: // v^α+ = p^α+ / m^α (Eq. 31)
                MassMatrix::apply_lumped_inverse(material.mass,
                                                 material.updated_momentum,
                                                 target,
                                                 mass_floor);
                if (field == updated_velocity &&
                    parameters.contact.xpic_contact_term ==
                      XpicContactTerm::uncorrected &&
                    mass_matrix.order() > 1)
                  target.add(-1., material.delta_velocity);
                velocity_conditions.correct_velocities(target, t_end, nullptr);
                break;
              case acceleration:
              case lumped_acceleration:
                {
                  // a^α = (f^α0 + f^(BC) + Δp^α+/Δt) / m^α = (p^α+ − p^α) /
                  // (m^α Δt): the contact force of the second correction
                  // only (Eqs. 32-34, a^{α,1}).
                  // (f^α is not read after the momentum update: its storage
                  // holds the difference.)
                  GridVectorField &difference = material.force;
                  difference                  = material.updated_momentum;
                  difference.add(-1., material.momentum);
                  difference *= 1. / time_step;
                  MassMatrix::apply_lumped_inverse(material.mass,
                                                   difference,
                                                   target,
                                                   mass_floor);
                  velocity_conditions.correct_accelerations(target,
                                                            t_begin,
                                                            t_end);
                  break;
                }
              default:
                Assert(false, ExcInternalError());
            }
          if (has_hanging_nodes)
            for (unsigned int d = 0; d < dim; ++d)
              constraints.distribute(target.block(d));
          target.update_ghost_values();
          material.computed[field] = true;
        }

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
      if (material_exact_solve &&
          (field == velocity || field == updated_velocity))
        {
          solve_material_full_mass(field);
          return;
        }
      const unsigned int k = mass_matrix.order();
      if ((field != velocity && field != updated_velocity) || k < 2)
        return;
      const bool         updated         = field == updated_velocity;
      const double       t_field         = updated ? t_end : t_begin;
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
          {
            GridVectorField &target = material.fields[field];
            if (has_hanging_nodes)
              for (unsigned int d = 0; d < dim; ++d)
                constraints.distribute(target.block(d));
            target.update_ghost_values();
          }
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
      const GridScalar &lumped_mass      = this->get_lumped_mass();
      const double      mass_floor       = this->get_mass_floor();
      const MPI_Comm    mpi_communicator = this->get_mpi_communicator();
      const double      time_step        = this->get_timestep();
      const double      momentum_time    = this->get_momentum_time();
      const double      time             = this->get_time();
      const VelocityConditions<dim> &velocity_conditions =
        this->get_velocity_conditions();
      const bool has_hanging_nodes                 = this->has_hanging_nodes();
      const AffineConstraints<double> &constraints = this->get_constraints();
      // Multimaterial FMPM(k) with net incremental contact iterates
      //   z_{j+1} = z_j + (m^α)⁻¹ P(q^α − m̃^α z_j),   q^α = p^α − m^α Δv^α,
      // from the contact-corrected lumped velocity z₁ (seed 000 Eqs. 3.13-
      // 3.22), P the law of the increments: the materials of a pair in
      // contact take the same increment. As k → ∞ it converges to the z in
      // z₁ + (that subspace) where the residual q − m̃ z vanishes at every
      // node apart from equal and opposite forces between materials in
      // contact: each material's m̃^α, coupled at the contact pairs. CG finds
      // it with C = D Z (Zᵀ diag(m̃) Z)⁻¹ Zᵀ D, symmetric positive
      // semi-definite (Z: the materials in contact at a node share one
      // unknown; D: free components), whose range is that subspace. Fixed
      // components keep z₁: known (velocity conditions), empty, and weak
      // (m̃_ii < τ m_i, the single-material solve's remedy; at a node with
      // materials in contact the sums over them decide, so that perfect
      // interfaces give the single-material solve).
      using namespace ParticleUpdate;
      const bool         updated = field == updated_velocity;
      const double       t_field = updated ? time + time_step : momentum_time;
      const unsigned int n_materials = fields.size();
      const unsigned int n_owned     = lumped_mass.locally_owned_size();
      const double       floor       = mass_floor;
      const double       tau         = material_weak_threshold;
      const bool         has_known   = velocity_conditions.uses_known_values();
      if (has_known)
        velocity_conditions.known_values(t_field,
                                         known_velocity_mask,
                                         known_velocity_value);

      // m̃^α_ii from the cell matrices (into series_free's first block).
      std::vector<double *>       diagonal(n_materials);
      std::vector<const double *> m(n_materials);
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          fields[a].series_free = 0;
          full_mass[a].diagonal(fields[a].series_free.block(0));
          diagonal[a] = fields[a].series_free.block(0).begin();
          m[a]        = fields[a].mass.begin();
        }

      // The materials in contact at each node (bit a: material a), from the
      // last correction's contact states.
      find_contact_groups();

      // Weak nodes: m̃_ii < τ m_i, of the material or, where materials are in
      // contact, of their sums.
      std::vector<double> group_diagonal(n_owned, 0.), group_mass(n_owned, 0.);
      std::vector<unsigned int> group_of(n_owned, 0u);
      for (const auto &[i, group] : contact_groups)
        {
          group_of[i] = group;
          for (unsigned int a = 0; a < n_materials; ++a)
            if (group & (1u << a))
              {
                group_diagonal[i] += diagonal[a][i];
                group_mass[i] += m[a][i];
              }
        }
      material_weak.assign(n_materials * n_owned, 0);
      for (unsigned int a = 0; a < n_materials; ++a)
        for (unsigned int i = 0; i < n_owned; ++i)
          {
            const bool grouped = group_of[i] & (1u << a);
            material_weak[a * n_owned + i] =
              m[a][i] > floor &&
              (grouped ? group_diagonal[i] < tau * group_mass[i] :
                         diagonal[a][i] < tau * m[a][i]);
          }
      auto is_weak = [&](const unsigned int a, const unsigned int i) {
        return material_weak[a * n_owned + i] != 0;
      };
      // As in the single-material solve, the couplings of free nodes to weak
      // ones are lumped onto the diagonal: c^α = m̃^α 1_W (column sums stay
      // m^α). series_direction holds 1_W here.
      std::vector<GridVectorField *> z, direction, product;
      for (auto &material : fields)
        {
          z.push_back(&material.fields[field]);
          direction.push_back(&material.series_direction);
          product.push_back(&material.series_product);
        }
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          GridVectorField &indicator = fields[a].series_direction;
          indicator                  = 0;
          for (unsigned int i = 0; i < n_owned; ++i)
            if (is_weak(a, i))
              for (unsigned int c = 0; c < dim; ++c)
                indicator.block(c).local_element(i) = 1;
          indicator.update_ghost_values();
        }
      apply_material_full_mass(direction, product);
      for (auto &material : fields)
        material.weak_coupling = material.series_product.block(0);

      // series_free: the inverse diagonal of Zᵀ diag(m̃ + c) Z on free
      // components, 0 on fixed ones.
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          const double *const coupling = fields[a].weak_coupling.begin();
          for (unsigned int i = 0; i < n_owned; ++i)
            if (group_of[i] & (1u << a))
              group_diagonal[i] += coupling[i];
        }
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          GridVectorField    &free     = fields[a].series_free;
          const double *const coupling = fields[a].weak_coupling.begin();
          for (unsigned int i = 0; i < n_owned; ++i)
            {
              const bool   grouped = group_of[i] & (1u << a);
              const double d =
                grouped ? group_diagonal[i] : diagonal[a][i] + coupling[i];
              const bool is_free = m[a][i] > floor && !is_weak(a, i) && d > 0;
              for (unsigned int c = 0; c < dim; ++c)
                free.block(c).local_element(i) =
                  is_free && !(has_known &&
                               known_velocity_mask[c].local_element(i) != 0) ?
                    1. / d :
                    0.;
            }
        }
      const MPI_Comm comm = mpi_communicator;
      // y = C r into series_increment; returns r·y and |r|² (all ranks), r
      // of a node's materials in contact counted as their sum (the forces
      // between them are internal).
      auto precondition = [&]() {
        double local[2] = {}, global[2];
        for (unsigned int c = 0; c < dim; ++c)
          {
            for (auto &material : fields)
              {
                const double *const r =
                  material.series_residual.block(c).begin();
                const double *const inverse =
                  material.series_free.block(c).begin();
                double *const y = material.series_increment.block(c).begin();
                for (unsigned int i = 0; i < n_owned; ++i)
                  y[i] = inverse[i] * r[i];
              }
            for (const auto &[i, group] : contact_groups)
              {
                double sum = 0;
                for (unsigned int a = 0; a < n_materials; ++a)
                  if (group & (1u << a))
                    sum += fields[a].series_residual.block(c).local_element(i);
                for (unsigned int a = 0; a < n_materials; ++a)
                  if (group & (1u << a))
                    fields[a].series_increment.block(c).local_element(i) =
                      fields[a].series_free.block(c).local_element(i) * sum;
                local[1] += sum * sum;
              }
            for (unsigned int a = 0; a < n_materials; ++a)
              {
                const MaterialField<dim> &material = fields[a];
                const double *const       r =
                  material.series_residual.block(c).begin();
                const double *const y =
                  material.series_increment.block(c).begin();
                for (unsigned int i = 0; i < n_owned; ++i)
                  {
                    local[0] += r[i] * y[i];
                    if (!(group_of[i] & (1u << a)))
                      local[1] += r[i] * r[i];
                  }
              }
          }
        Utilities::MPI::sum(local, comm, global);
        return std::make_pair(global[0], global[1]);
      };

      // r₀ = q − (m̃ z₁' + c z₁) on free components, z₁' = z₁ off weak and
      // empty nodes; the scale |q|² of the stop.
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          GridVectorField &coupled_start = fields[a].series_direction;
          coupled_start                  = *z[a];
          for (unsigned int i = 0; i < n_owned; ++i)
            if (!(m[a][i] > floor) || is_weak(a, i))
              for (unsigned int c = 0; c < dim; ++c)
                coupled_start.block(c).local_element(i) = 0;
          coupled_start.update_ghost_values();
        }
      apply_material_full_mass(direction, product);
      double              scale_local = 0;
      std::vector<double> group_q(dim * n_owned, 0.);
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          MaterialField<dim>    &material = fields[a];
          const GridVectorField &p =
            updated ? material.updated_momentum : material.momentum;
          for (unsigned int c = 0; c < dim; ++c)
            {
              const double *const pd = p.block(c).begin();
              const double *const dv = material.delta_velocity.block(c).begin();
              const double *const mz = material.series_product.block(c).begin();
              const double *const free = material.series_free.block(c).begin();
              const double *const ma   = material.mass.begin();
              const double *const cw   = material.weak_coupling.begin();
              const double *const z1 = material.fields[field].block(c).begin();
              double *const       r = material.series_residual.block(c).begin();
              for (unsigned int i = 0; i < n_owned; ++i)
                {
                  const double q = pd[i] - ma[i] * dv[i];
                  r[i] = free[i] != 0 ? q - mz[i] - cw[i] * z1[i] : 0.;
                  if (free[i] == 0)
                    continue;
                  if (group_of[i] & (1u << a))
                    group_q[c * n_owned + i] += q;
                  else
                    scale_local += q * q;
                }
            }
        }
      for (const double q : group_q)
        scale_local += q * q;
      // Stop at |r| <= tolerance |p|, as the single-material solve.
      const double threshold = material_solve_tolerance *
                               material_solve_tolerance *
                               Utilities::MPI::sum(scale_local, comm);
      auto [r_dot_y, r_norm_squared] = precondition();
      for (auto &material : fields)
        {
          material.series_direction = material.series_increment;
          material.series_direction.update_ghost_values();
        }
      unsigned int iteration = 0;
      bool         converged = true;
      for (; r_norm_squared > threshold; ++iteration)
        {
          if (iteration == material_solve_max_iterations)
            {
              converged = false;
              break;
            }
          apply_material_full_mass(direction, product); // w = (m̃ + c) d
          double local = 0;
          for (auto &material : fields)
            for (unsigned int c = 0; c < dim; ++c)
              {
                const double *const dd =
                  material.series_direction.block(c).begin();
                const double *const cw = material.weak_coupling.begin();
                double *const w = material.series_product.block(c).begin();
                for (unsigned int i = 0; i < n_owned; ++i)
                  {
                    w[i] += cw[i] * dd[i];
                    local += dd[i] * w[i];
                  }
              }
          const double d_dot_w = Utilities::MPI::sum(local, comm);
          if (!(d_dot_w > 0))
            {
              converged = false;
              break;
            }
          const double alpha = r_dot_y / d_dot_w;
          for (auto &material : fields)
            for (unsigned int c = 0; c < dim; ++c)
              {
                const double *const dd =
                  material.series_direction.block(c).begin();
                const double *const w =
                  material.series_product.block(c).begin();
                const double *const free =
                  material.series_free.block(c).begin();
                double *const x = material.fields[field].block(c).begin();
                double *const r = material.series_residual.block(c).begin();
                for (unsigned int i = 0; i < n_owned; ++i)
                  {
                    x[i] += alpha * dd[i];
                    r[i] = free[i] != 0 ? r[i] - alpha * w[i] : 0.;
                  }
              }
          const auto [next, next_norm_squared] = precondition();
          const double beta                    = next / r_dot_y;
          r_dot_y                              = next;
          r_norm_squared                       = next_norm_squared;
          for (auto &material : fields)
            {
              material.series_direction.sadd(beta,
                                             1.,
                                             material.series_increment);
              material.series_direction.update_ghost_values();
            }
        }
      // Σ m z = Σ q holds for the exact solution (the columns of m̃^α + c^α
      // sum to m^α, the contact forces cancel); CG leaves it off by its
      // residual. As in the single-material solve, a uniform shift of the
      // free components restores it, where no known component carries mass.
      for (unsigned int c = 0; c < dim; ++c)
        {
          double local[3] = {}, global[3];
          for (unsigned int a = 0; a < n_materials; ++a)
            {
              const MaterialField<dim> &material = fields[a];
              const GridVectorField    &p =
                updated ? material.updated_momentum : material.momentum;
              const double *const pd = p.block(c).begin();
              const double *const dv = material.delta_velocity.block(c).begin();
              const double *const zc = material.fields[field].block(c).begin();
              const double *const free = material.series_free.block(c).begin();
              for (unsigned int i = 0; i < n_owned; ++i)
                {
                  local[0] += pd[i] - m[a][i] * dv[i] - m[a][i] * zc[i];
                  if (free[i] != 0)
                    local[1] += m[a][i];
                  if (has_known &&
                      known_velocity_mask[c].local_element(i) != 0 &&
                      m[a][i] > floor)
                    local[2] = 1;
                }
            }
          Utilities::MPI::sum(local, comm, global);
          if (global[2] != 0 || global[1] == 0)
            continue;
          const double shift = global[0] / global[1];
          for (auto &material : fields)
            {
              const double *const free = material.series_free.block(c).begin();
              double *const       zc = material.fields[field].block(c).begin();
              for (unsigned int i = 0; i < n_owned; ++i)
                if (free[i] != 0)
                  zc[i] += shift;
            }
        }
      ++material_solves;
      material_solve_iterations += iteration;
      material_solve_failures += converged ? 0 : 1;

      for (auto &material : fields)
        {
          GridVectorField &target = material.fields[field];
          velocity_conditions.correct_velocities(target, t_field, nullptr);
          if (has_hanging_nodes)
            for (unsigned int c = 0; c < dim; ++c)
              constraints.distribute(target.block(c));
          target.update_ghost_values();
        }
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
