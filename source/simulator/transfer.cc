// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The particle-grid passes of the time step: the support cache (S, G of
// every point, once per step), extrapolations to the grid (Sᵀ, Gᵀ), the
// particle update (S) and the strain update (G, with the kinematics of
// transfer/kinematics.h), and the re-sorting of moved points into cells
// (PointSort). Every pass loops over the support cache.

#include <fmpm/simulator.h>
#include <fmpm/transfer/kinematics.h>
#include <fmpm/transfer/sinks.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace fmpm
{
  namespace
  {
    /** Points per batch of the strain update (constitutive model calls). */
    constexpr unsigned int stress_batch_size =
      ConstitutiveModel::StressUpdateInputs::capacity;
  } // namespace



  template <int dim>
  template <typename... Text>
  void
  Simulator<dim>::report_point_failure(const unsigned int       k,
                                       const FailedPoint::Cause cause,
                                       const Text &...text)
  {
    if (!local_failure.empty())
      return;
    std::ostringstream message;
    switch (cause)
      {
        case FailedPoint::Cause::support_outside_patch:
          message << "the domain of ";
          break;
        case FailedPoint::Cause::velocity_not_finite:
          message << "velocity of ";
          break;
        case FailedPoint::Cause::stress_not_finite:
          message << "stress of ";
          break;
        default:
          break;
      }
    message << "material point " << points.id[k] << " at ("
            << points.position[k] << ") ";
    (message << ... << text);
    local_failure            = message.str();
    local_failed_point.cause = cause;
    local_failed_point.id    = points.id[k];
    for (unsigned int d = 0; d < dim; ++d)
      local_failed_point.position[d] = points.position[k][d];
  }



  template <int dim>
  void
  Simulator<dim>::update_particles()
  {
    TimerOutput::Scope timer(computing_timer, "particle update");
    using Index = PropertyIndex<dim>;

    unsigned int fields[ParticleUpdate::n_grid_fields];
    unsigned int n_fields = 0;
    using FieldViews      = std::array<std::array<const double *, dim>,
                                  ParticleUpdate::n_grid_fields>;
    // The fields of the centre of mass, or with contact of each material
    // (the point reads its material's field, Eq. 32).
    const bool              contact = contact_active();
    std::vector<FieldViews> views(
      contact ? this->contact->material_fields().size() : 1);
    const auto &needed = active_fields();
    for (unsigned int f = 0; f < ParticleUpdate::n_grid_fields; ++f)
      if (needed[f])
        {
          fields[n_fields++] = f;
          for (unsigned int a = 0; a < views.size(); ++a)
            for (unsigned int d = 0; d < dim; ++d)
              views[a][f][d] =
                (contact ? this->contact->material_fields()[a].fields[f] :
                           centre_of_mass.fields[f])
                  .block(d)
                  .begin();
        }

    // Periodic FMPM(k): FLIP in the lumped steps between the series.
    ParticleUpdate::Interface<dim> &update = active_update();
    ParticleUpdate::Batch<dim>      batch;
    batch.time_step = control.time_step();
    point_sort.clear();
    const bool   track_dissipation = parameters.output.track_dissipation;
    const double grid_damping      = parameters.method.grid_damping;
    const double particle_damping  = parameters.method.particle_damping;
    std::vector<Tensor<1, dim>> old_velocity, damping_velocity;
    std::vector<Point<dim>>     old_position;
    double                      max_V2 = 0;
    const bool has_moving_walls        = velocity_conditions.has_moving_boxes();
    SupportReader<dim> support_of(supports, transfer, points.cell.data());
    double            *velocity_column[dim];
    for (unsigned int d = 0; d < dim; ++d)
      velocity_column[d] = points.column(Index::velocity + d);
    const double *const mass_column = points.column(Index::mass);
    // USL+/USAVG+: p = SᵀMV^{n+1} in this sweep, into momentum_target[d]
    // (with contact p^α of the point's material α: [α dim + d], and what
    // the normals and laws read of the moved points).
    const bool re_extrapolate = point_loops.momenta_in_particle_update;
    Contact::GeometrySink<dim>        no_contact_geometry;
    const Contact::GeometrySink<dim> &contact_geometry =
      re_extrapolate && contact ? this->contact->begin_geometry(points) :
                                  no_contact_geometry;
    double *p[dim] = {};
    if (re_extrapolate && !contact)
      {
        centre_of_mass.momentum = 0;
        for (unsigned int d = 0; d < dim; ++d)
          p[d] = centre_of_mass.momentum.block(d).begin();
      }
    const Transfer::MassMomentumSink<dim, false> momentum(points, nullptr, p);
    Transfer::PerMaterial<Transfer::MassMomentumSink<dim, false>>
      material_momentum(supports.material.data());
    if (re_extrapolate && contact)
      for (auto &field : this->contact->material_fields())
        {
          field.momentum = 0;
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = field.momentum.block(d).begin();
          material_momentum.sinks.emplace_back(points, nullptr, p);
        }

    // Point k's share of p = SᵀMV^{n+1} (Eq. 5 with contact) and of the
    // contact geometry once its V and X are final (in the store): the
    // operations of particles_to_grid().
    const auto re_extrapolate_point =
      [&](const unsigned int k, const auto &data) DEAL_II_ALWAYS_INLINE {
        support_of.visit(
          k,
          data,
          contact_geometry.needs_gradients(),
          [&](const unsigned int *const   node,
              const double *const         S,
              const Tensor<1, dim> *const G,
              const auto                  n_entries) DEAL_II_ALWAYS_INLINE {
            if (contact)
              {
                material_momentum.point(k, node, S, G, n_entries);
                contact_geometry.add_point(
                  k, supports.material[k], node, S, G, n_entries);
              }
            else
              momentum.point(k, node, S, G, n_entries);
          });
      };

    // One batch per cell with points (the plugin's virtual call per batch).
    for (unsigned int c = 0; c < points.n_cells(); ++c)
      {
        const unsigned int first_point = points.cell_point_begin[c];
        const unsigned int n_points =
          points.cell_point_begin[c + 1] - first_point;
        const auto &data = transfer.cell_data(points.cell_index[c]);
        batch.resize(n_points);

        // Gather: V, X and the requested fields extrapolated with S.
        for (unsigned int q = 0; q < n_points; ++q)
          {
            const unsigned int k = first_point + q;
            for (unsigned int d = 0; d < dim; ++d)
              batch.velocity[q][d] = velocity_column[d][k];
            batch.position[q] = points.position[k];
            const FieldViews &field_values =
              views[contact ? supports.material[k] : 0];
            support_of.visit(
              k,
              data,
              false,
              [&](const unsigned int *const node,
                  const double *const       S,
                  const Tensor<1, dim> *,
                  const auto n_entries) {
                for (unsigned int field = 0; field < n_fields; ++field)
                  {
                    const unsigned int f = fields[field];
                    Kinematics::interpolate<dim>(node,
                                                 S,
                                                 0,
                                                 n_entries,
                                                 field_values[f].data(),
                                                 batch.grid[f][q]);
                  }
              });
          }

        // Keep V^(n), X^(n) where damping or the dissipation measure need
        // them.
        if (track_dissipation)
          {
            old_velocity.assign(batch.velocity.begin(), batch.velocity.end());
            old_position.assign(batch.position.begin(), batch.position.end());
          }
        const std::vector<Tensor<1, dim>> *V_n = &batch.velocity;
        if (particle_damping != 0)
          {
            damping_velocity.assign(batch.velocity.begin(),
                                    batch.velocity.end());
            V_n = &damping_velocity;
          }

        update.update(batch);

        // Damping (seed 003 Eqs. 1.21-1.25): the acceleration loses
        // A_damp = α_g S v + α_p V^(n); V^(n+1) -= A_damp Δt and, the
        // effective velocity being unchanged, X^(n+1) -= A_damp Δt²/2.
        if (grid_damping != 0 || particle_damping != 0)
          for (unsigned int q = 0; q < n_points; ++q)
            {
              Tensor<1, dim> A_damp;
              if (grid_damping != 0)
                A_damp +=
                  grid_damping * batch.grid[ParticleUpdate::velocity][q];
              if (particle_damping != 0)
                A_damp += particle_damping * (*V_n)[q];
              batch.velocity[q] -= A_damp * control.time_step();
              batch.position[q] -=
                A_damp * (0.5 * control.time_step() * control.time_step());
            }

        // Energy dissipated compared with non-dissipative FLIP (seed 003
        // Eqs. 1.44-1.45): M [A_g→p Δt·(V_g→p + A_g→p Δt/2) − ΔV·ΔX/Δt].
        if (track_dissipation)
          for (unsigned int q = 0; q < n_points; ++q)
            {
              const double         M = mass_column[first_point + q];
              const Tensor<1, dim> a_dt =
                batch.grid[ParticleUpdate::acceleration][q] *
                control.time_step();
              const Tensor<1, dim> &v_g =
                batch.grid[ParticleUpdate::velocity][q];
              const Tensor<1, dim> dV = batch.velocity[q] - old_velocity[q];
              const Tensor<1, dim> dX_dt =
                (batch.position[q] - old_position[q]) / control.time_step();
              local_dissipation += M * (a_dt * (v_g + 0.5 * a_dt) - dV * dX_dt);
            }

        // Scatter the new V and X, and the new reference location of each
        // point still in its cell (the batch has read its supports; later
        // passes of the step read the support cache's copy of ξ); the
        // others are re-binned at the step's end.
        for (unsigned int q = 0; q < n_points; ++q)
          {
            const unsigned int    k  = first_point + q;
            const Tensor<1, dim> &V  = batch.velocity[q];
            const double          V2 = V * V;
            if (!std::isfinite(V2))
              report_point_failure(k,
                                   FailedPoint::Cause::velocity_not_finite,
                                   "is not finite (NaN or Inf)");
            max_V2 = std::max(max_V2, V2);
            for (unsigned int d = 0; d < dim; ++d)
              velocity_column[d][k] = V[d];
            // Points do not enter a moving wall's box.
            if (has_moving_walls)
              velocity_conditions.push_out_of_walls(batch.position[q]);
            points.position[k] = batch.position[q];
            if (re_extrapolate)
              re_extrapolate_point(k, data);
            const Point<dim> xi =
              GridTransfer<dim>::reference_point(data,
                                                 batch.position[q],
                                                 points.reference_position[k]);
            if (GridTransfer<dim>::is_inside(xi))
              points.reference_position[k] = xi;
            else
              point_sort.left_cell(k);
          }
      }
    local_max_point_speed = std::sqrt(max_V2);
  }



  template <int dim>
  void
  Simulator<dim>::update_stresses(const ParticleUpdate::GridField field,
                                  const double                    dt,
                                  const bool                      with_forces)
  {
    // The velocities of the centre of mass, or with contact of the group's
    // material (Eq. 28); their solves time themselves.
    const bool contact = contact_active();
    if (contact)
      this->contact->compute_field(field);
    else
      compute_field(field);
    TimerOutput::Scope timer(computing_timer, "stress update");
    using Index                                 = PropertyIndex<dim>;
    const unsigned int              n_materials = constitutive_models.size();
    const DeformationGradientUpdate F_update =
      parameters.method.deformation_gradient_update;
    // The batch's entry arrays (zero: in 2D the out-of-plane entries stay
    // so).
    ConstitutiveModel::StressUpdateInputs  inputs;
    ConstitutiveModel::StressUpdateOutputs outputs;
    inputs.time_step = dt;
    Kinematics::BatchEntries dF, F_gathered;
    double                   wave_speed = 0;
    const double            *v_a[dim];
    auto                     view_velocities = [&](const GridVectorField &v) {
      for (unsigned int a = 0; a < dim; ++a)
        v_a[a] = v.block(a).begin();
    };
    view_velocities(centre_of_mass.fields[field]);
    SupportReader<dim> support_of(supports, transfer, points.cell.data());
    // Computed supports: S and G of the batch's points (by place in the
    // batch).
    constexpr unsigned int              n_nodes = GridTransfer<dim>::n_nodes;
    std::array<double, n_nodes>         batch_S[stress_batch_size];
    std::array<Tensor<1, dim>, n_nodes> batch_G[stress_batch_size];
    const unsigned int                 *batch_node[stress_batch_size];

    // USF/USAVG: f (and with contact f^α0, Eq. 29) from the new stresses
    // in this sweep, each batch's points in the store's order once their
    // stresses are updated.
    // (With contact f is set from the f^α0 after the sweep.)
    if (with_forces && !contact)
      centre_of_mass.force = 0;
    double *f[dim];
    for (unsigned int d = 0; d < dim; ++d)
      f[d] = centre_of_mass.force.block(d).begin();
    const Transfer::ForceSink<dim> force(points, external_loads, f);
    Transfer::PerMaterial<Transfer::ForceSink<dim>> material_force(
      supports.material.data());
    if (with_forces && contact)
      for (auto &material_field : this->contact->material_fields())
        {
          material_field.force = 0;
          double *f_alpha[dim];
          for (unsigned int d = 0; d < dim; ++d)
            f_alpha[d] = material_field.force.block(d).begin();
          material_force.sinks.emplace_back(points, external_loads, f_alpha);
        }

    // Cell sizes (Eq. 52's Δx) only for models that read them, by active
    // cell index for the cells with points.
    bool needs_cell_size = false;
    for (const auto &model : constitutive_models)
      needs_cell_size = needs_cell_size || model->needs_cell_size();
    if (needs_cell_size)
      {
        cell_size_by_index.resize(triangulation.n_active_cells());
        for (unsigned int c = 0; c < points.n_cells(); ++c)
          cell_size_by_index[points.cell_index[c]] =
            points.cell_iterator(c)->minimum_vertex_distance();
      }

    // Points of a batch grouped by material for the model call (one group
    // when the scene has one material).
    std::vector<std::vector<unsigned int>> by_material(n_materials);
    for (auto &group : by_material)
      group.reserve(stress_batch_size);
    unsigned int group_points[stress_batch_size];
    double       J_of_group[stress_batch_size];
    // F (row major) and σ in the store. In 2D (plane strain) only the 2x2
    // block and F_33 of F, and σ_xx, σ_yy, σ_zz, σ_xy are stored: the other
    // entries are zero and are not written.
    double                *F_column[9], *stress_column[6];
    constexpr unsigned int n_stress_entries = dim == 3 ? 6 : 4;
    for (unsigned int c = 0; c < 9; ++c)
      F_column[c] = points.column(Index::deformation_gradient + c);
    for (unsigned int c = 0; c < 6; ++c)
      stress_column[c] = points.column(Index::stress + c);
    double *const energy_column = points.column(Index::strain_energy_density);
    double *const volume_column = points.column(Index::volume);
    const double *const initial_volume_column =
      points.column(Index::initial_volume);

    for (unsigned int batch_begin = 0; batch_begin < supports.n_points();
         batch_begin += stress_batch_size)
      {
        const unsigned int batch_end =
          std::min(batch_begin + stress_batch_size, supports.n_points());
        if (n_materials > 1)
          {
            for (unsigned int m = 0; m < n_materials; ++m)
              by_material[m].clear();
            for (unsigned int k = batch_begin; k < batch_end; ++k)
              by_material[supports.material[k]].push_back(k);
          }

        for (unsigned int m = 0; m < n_materials; ++m)
          {
            const unsigned int n_group = n_materials == 1 ?
                                           batch_end - batch_begin :
                                           by_material[m].size();
            if (n_group == 0)
              continue;
            if (n_materials == 1)
              std::iota(group_points, group_points + n_group, batch_begin);
            else
              std::copy(by_material[m].begin(),
                        by_material[m].end(),
                        group_points);
            // (one material: the batch, stored one after another)
            const unsigned int k0 = group_points[0];
            const bool         contiguous =
              group_points[n_group - 1] == k0 + n_group - 1;
            if (contact)
              view_velocities(
                this->contact->material_fields()[m].fields[field]);
            inputs.resize(n_group);
            inputs.reference_density = parameters.materials[m].density;
            if (constitutive_models[m]->needs_cell_size())
              for (unsigned int q = 0; q < n_group; ++q)
                inputs.cell_size[q] =
                  cell_size_by_index[points.cell[group_points[q]]];
            // L = ∇v = Σ_i v_i ⊗ G_pi (Eqs. 2.7, 2.18), plane strain in 2D;
            // σ^n, W^n and the history slots if the model reads them.
            for (unsigned int q = 0; q < n_group; ++q)
              {
                const unsigned int k = group_points[q];
                if (supports.implicit_classic)
                  {
                    // Computed once for L and the forces.
                    const unsigned int b = k - batch_begin;
                    const auto &cell     = transfer.cell_data(points.cell[k]);
                    support_of.compute(k, cell, true, batch_S[b], batch_G[b]);
                    batch_node[b] = cell.local_index.data();
                    Kinematics::velocity_gradient<dim>(
                      batch_node[b],
                      batch_G[b].data(),
                      0,
                      std::integral_constant<unsigned int, n_nodes>(),
                      v_a,
                      inputs.velocity_gradient,
                      q);
                  }
                else
                  support_of.visit(k,
                                   true,
                                   [&](const unsigned int *const node,
                                       const double *,
                                       const Tensor<1, dim> *const G,
                                       const auto                  n_entries) {
                                     Kinematics::velocity_gradient<dim>(
                                       node,
                                       G,
                                       0,
                                       n_entries,
                                       v_a,
                                       inputs.velocity_gradient,
                                       q);
                                   });
              }
            if (constitutive_models[m]->reads_old_state())
              {
                if (contiguous)
                  {
                    for (unsigned int c = 0; c < n_stress_entries; ++c)
                      std::copy(stress_column[c] + k0,
                                stress_column[c] + k0 + n_group,
                                inputs.old_stress[c]);
                    std::copy(energy_column + k0,
                              energy_column + k0 + n_group,
                              inputs.old_strain_energy_density);
                  }
                else
                  for (unsigned int q = 0; q < n_group; ++q)
                    {
                      const unsigned int k = group_points[q];
                      for (unsigned int c = 0; c < n_stress_entries; ++c)
                        inputs.old_stress[c][q] = stress_column[c][k];
                      inputs.old_strain_energy_density[q] = energy_column[k];
                    }
                for (unsigned int q = 0; q < n_group; ++q)
                  inputs.properties[q] = points.record(group_points[q]);
              }
            if (constitutive_models[m]->needs_old_volume_ratio())
              for (unsigned int q = 0; q < n_group; ++q)
                inputs.old_volume_ratio[q] =
                  volume_column[group_points[q]] /
                  initial_volume_column[group_points[q]];
            auto &F = inputs.deformation_gradient;
            auto &J = inputs.volume_ratio;
            if (F_update == DeformationGradientUpdate::cayley)
              {
                // F^n: the store's columns, or gathered for a group spread
                // over the batch (several materials).
                std::array<const double *, 9> F_old;
                for (unsigned int c = 0; c < 9; ++c)
                  if (contiguous)
                    F_old[c] = F_column[c] + k0;
                  else
                    {
                      for (unsigned int q = 0; q < n_group; ++q)
                        F_gathered[c][q] = F_column[c][group_points[q]];
                      F_old[c] = F_gathered[c];
                    }
                Kinematics::cayley_update<dim>(
                  n_group, dt, inputs.velocity_gradient, F_old, F, J);
              }
            else
              {
                Kinematics::increments<dim>(F_update,
                                            parameters.method,
                                            inputs.velocity_gradient,
                                            dt,
                                            n_group,
                                            dF);
                // F^{n+1} = ΔF F^n and J = det F^{n+1} (the operations of
                // deal.II's Tensor product and determinant()); in 2D on the
                // 2x2 block, F_33 kept (plane strain).
                for (unsigned int q = 0; q < n_group; ++q)
                  {
                    const unsigned int k = group_points[q];
                    if constexpr (dim == 2)
                      {
                        const double a = F_column[0][k], b = F_column[1][k],
                                     c = F_column[3][k], e = F_column[4][k];
                        F[0][q] = dF[0][q] * a + dF[1][q] * c;
                        F[1][q] = dF[0][q] * b + dF[1][q] * e;
                        F[3][q] = dF[3][q] * a + dF[4][q] * c;
                        F[4][q] = dF[3][q] * b + dF[4][q] * e;
                        F[8][q] = F_column[8][k];
                      }
                    else
                      for (unsigned int a = 0; a < 3; ++a)
                        for (unsigned int b = 0; b < 3; ++b)
                          F[3 * a + b][q] =
                            dF[3 * a][q] * F_column[b][k] +
                            dF[3 * a + 1][q] * F_column[3 + b][k] +
                            dF[3 * a + 2][q] * F_column[6 + b][k];
                  }
                for (unsigned int q = 0; q < n_group; ++q)
                  if constexpr (dim == 2)
                    // The same value without the plane-strain zeros' products.
                    J[q] = F[0][q] * (F[4][q] * F[8][q]) -
                           F[1][q] * (F[3][q] * F[8][q]);
                  else
                    {
                      const double C0 = F[4][q] * F[8][q] - F[5][q] * F[7][q];
                      const double C1 = F[5][q] * F[6][q] - F[3][q] * F[8][q];
                      const double C2 = F[3][q] * F[7][q] - F[4][q] * F[6][q];
                      J[q] = F[0][q] * C0 + F[1][q] * C1 + F[2][q] * C2;
                    }
              }
            for (unsigned int q = 0; q < n_group; ++q)
              if (!(J[q] > 0))
                report_point_failure(group_points[q],
                                     FailedPoint::Cause::inverted,
                                     "has an inverted deformation gradient, "
                                     "J = ",
                                     J[q]);

            outputs.failed_point = -1;
            constitutive_models[m]->update_stress(inputs, outputs);
            if (outputs.failed_point >= 0)
              report_point_failure(group_points[outputs.failed_point],
                                   FailedPoint::Cause::model_failure,
                                   outputs.failure);

            // F, σ, W and V = J V0 into the store (in 2D the plane-strain
            // zero entries are not stored; F_33 is unchanged).
            if (contiguous)
              {
                for (unsigned int c = 0; c < 9; ++c)
                  if (dim == 3 || c == 0 || c == 1 || c == 3 || c == 4)
                    std::copy(F[c], F[c] + n_group, F_column[c] + k0);
                for (unsigned int c = 0; c < n_stress_entries; ++c)
                  std::copy(outputs.cauchy_stress[c],
                            outputs.cauchy_stress[c] + n_group,
                            stress_column[c] + k0);
                std::copy(outputs.strain_energy_density,
                          outputs.strain_energy_density + n_group,
                          energy_column + k0);
                for (unsigned int q = 0; q < n_group; ++q)
                  {
                    volume_column[k0 + q] =
                      J[q] * initial_volume_column[k0 + q];
                    J_of_group[q] = J[q] > 0 ? J[q] : 1;
                  }
              }
            else
              for (unsigned int q = 0; q < n_group; ++q)
                {
                  const unsigned int k = group_points[q];
                  for (unsigned int c = 0; c < 9; ++c)
                    if (dim == 3 || c == 0 || c == 1 || c == 3 || c == 4)
                      F_column[c][k] = F[c][q];
                  for (unsigned int c = 0; c < n_stress_entries; ++c)
                    stress_column[c][k] = outputs.cauchy_stress[c][q];
                  energy_column[k] = outputs.strain_energy_density[q];
                  volume_column[k] = J[q] * initial_volume_column[k];
                  // Inverted points are reported above; they give no speed.
                  J_of_group[q] = J[q] > 0 ? J[q] : 1;
                }
            for (unsigned int q = 0; q < n_group; ++q)
              if (!std::isfinite(outputs.strain_energy_density[q]))
                report_point_failure(group_points[q],
                                     FailedPoint::Cause::stress_not_finite,
                                     "is not finite (NaN or Inf)");
            if (constitutive_models[m]->computes_wave_speed())
              for (unsigned int q = 0; q < n_group; ++q)
                wave_speed = std::max(wave_speed, outputs.wave_speed[q]);
            else
              wave_speed =
                std::max(wave_speed,
                         constitutive_models[m]->max_wave_speed(
                           parameters.materials[m].density,
                           ArrayView<const double>(J_of_group, n_group)));
          }
        // f of the batch's points from their new stresses, in the
        // store's order (with contact f^α0 of the point's material, Eq.
        // 29).
        if (with_forces)
          for (unsigned int k = batch_begin; k < batch_end; ++k)
            {
              auto add_force = [&](const unsigned int *const   node,
                                   const double *const         S,
                                   const Tensor<1, dim> *const G,
                                   const auto n_entries) DEAL_II_ALWAYS_INLINE {
                if (contact)
                  material_force.point(k, node, S, G, n_entries);
                else
                  force.point(k, node, S, G, n_entries);
              };
              if (supports.implicit_classic)
                {
                  const unsigned int b = k - batch_begin;
                  add_force(batch_node[b],
                            batch_S[b].data(),
                            batch_G[b].data(),
                            std::integral_constant<unsigned int, n_nodes>());
                }
              else
                support_of.visit(k, true, add_force);
            }
      }
    local_max_wave_speed = wave_speed;
    if (with_forces)
      {
        if (contact) // f = Σ_α f^α0
          centre_of_mass.set_to_sum(this->contact->material_fields(),
                                    false,
                                    false,
                                    true);
        centre_of_mass.force.compress(VectorOperation::add);
        if (contact)
          for (auto &material_field : this->contact->material_fields())
            material_field.force.compress(VectorOperation::add);
      }
  }



  template <int dim>
  void
  Simulator<dim>::sort_particles_into_cells()
  {
    TimerOutput::Scope timer(computing_timer, "sort points into cells");
    // The points that left their cells, to their new cells nearby (on this
    // rank or their new owner's); else deal.II's sort of every point (a
    // point not found nearby or outside the mesh: it reports lost points).
    if (parameters.fast_point_sorting && point_sort.sort(points))
      return;
    point_sort.prepare_full_sort(points);
    points_to_handler();
    particle_handler.sort_particles_into_subdomains_and_cells();
    points_from_handler();
  }

  template class Simulator<2>;
  template class Simulator<3>;
  template void
  Simulator<2>::report_point_failure(const unsigned int,
                                     const FailedPoint::Cause,
                                     const std::string &);
  template void
  Simulator<3>::report_point_failure(const unsigned int,
                                     const FailedPoint::Cause,
                                     const std::string &);
} // namespace fmpm
