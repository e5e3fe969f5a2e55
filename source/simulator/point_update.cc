// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The particle update (S: to points): per cell with points, the gather of
// V, X and the grid fields the update reads (v_p = Σ_i S_pi v_i), the
// particle update plugin's call, damping and the dissipation measure, and
// the scatter of V^{n+1}, X^{n+1} and ξ into the store; with USL+/USAVG+
// the re-extrapolation p = SᵀMV^{n+1} point by point; then the sort of
// the moved points into their new cells (PointSort).

#include <fmpm/simulator.h>
#include <fmpm/simulator.templates.h>
#include <fmpm/transfer/kinematics.h>
#include <fmpm/transfer/sinks.h>

#include <algorithm>
#include <cmath>

namespace fmpm
{
  namespace
  {
    /**
     * The grid fields a particle update reads (fields[0 .. n_fields)), as
     * raw views of their dim blocks: views[a][f][d] of the centre of mass
     * (a = 0), or with contact of material a (the point reads its
     * material's field, Eq. 32).
     */
    template <int dim>
    struct GridFieldViews
    {
      using Views = std::array<std::array<const double *, dim>,
                               ParticleUpdate::n_grid_fields>;

      /** @p sources: the centre of mass, or the materials' fields; each
       * has fields[f]. */
      template <typename Sources>
      GridFieldViews(
        const std::array<bool, ParticleUpdate::n_grid_fields> &needed,
        const Sources                                         &sources)
        : views(sources.size())
      {
        for (unsigned int f = 0; f < ParticleUpdate::n_grid_fields; ++f)
          if (needed[f])
            {
              fields[n_fields++] = f;
              for (unsigned int a = 0; a < views.size(); ++a)
                for (unsigned int d = 0; d < dim; ++d)
                  views[a][f][d] = sources[a].fields[f].block(d).begin();
            }
      }

      unsigned int       fields[ParticleUpdate::n_grid_fields];
      unsigned int       n_fields = 0;
      std::vector<Views> views;
    };

    /** The centre of mass as a one-entry source of GridFieldViews. */
    template <typename Field>
    struct OneSource
    {
      const Field &field;
      unsigned int
      size() const
      {
        return 1;
      }
      const Field &
      operator[](const unsigned int) const
      {
        return field;
      }
    };

    /**
     * The gather of the cell's @p n_points points from @p first_point: V,
     * X and the requested fields extrapolated with S (v_p = Σ_i S_pi v_i)
     * of the point's field set (with contact its @p material's, else
     * @p material is null).
     */
    template <int dim>
    void
    gather_batch(const unsigned int                          first_point,
                 const unsigned int                          n_points,
                 const typename GridTransfer<dim>::CellData &data,
                 const MaterialPoints<dim>                  &points,
                 const double *const                        *velocity_column,
                 const SupportReader<dim>                   &support_of,
                 const GridFieldViews<dim>                  &grid,
                 const unsigned char *const                  material,
                 ParticleUpdate::Batch<dim>                 &batch)
    {
      for (unsigned int q = 0; q < n_points; ++q)
        {
          const unsigned int k = first_point + q;
          for (unsigned int d = 0; d < dim; ++d)
            batch.velocity[q][d] = velocity_column[d][k];
          batch.position[q]        = points.position[k];
          const auto &field_values = grid.views[material ? material[k] : 0];
          support_of.visit(
            k,
            data,
            false,
            [&](const unsigned int *const node,
                const double *const       S,
                const Tensor<1, dim> *,
                const auto n_entries) {
              for (unsigned int field = 0; field < grid.n_fields; ++field)
                {
                  const unsigned int f = grid.fields[field];
                  Kinematics::interpolate<dim>(node,
                                               S,
                                               0,
                                               n_entries,
                                               field_values[f].data(),
                                               batch.grid[f][q]);
                }
            });
        }
    }

    /**
     * Damping (seed 003 Eqs. 1.21-1.25): the acceleration loses
     * A_damp = α_g S v + α_p V^(n); V^(n+1) -= A_damp Δt and, the
     * effective velocity being unchanged, X^(n+1) -= A_damp Δt²/2.
     */
    template <int dim>
    void
    apply_damping(const unsigned int                 n_points,
                  const double                       grid_damping,
                  const double                       particle_damping,
                  const std::vector<Tensor<1, dim>> &V_n,
                  const double                       dt,
                  ParticleUpdate::Batch<dim>        &batch)
    {
      for (unsigned int q = 0; q < n_points; ++q)
        {
          Tensor<1, dim> A_damp;
          if (grid_damping != 0)
            A_damp += grid_damping * batch.grid[ParticleUpdate::velocity][q];
          if (particle_damping != 0)
            A_damp += particle_damping * V_n[q];
          batch.velocity[q] -= A_damp * dt;
          batch.position[q] -= A_damp * (0.5 * dt * dt);
        }
    }

    /**
     * Energy dissipated compared with non-dissipative FLIP (seed 003
     * Eqs. 1.44-1.45), added point by point to @p dissipation:
     * M [A_g→p Δt·(V_g→p + A_g→p Δt/2) − ΔV·ΔX/Δt].
     */
    template <int dim>
    void
    add_dissipation(const unsigned int                 first_point,
                    const unsigned int                 n_points,
                    const double *const                mass_column,
                    const std::vector<Tensor<1, dim>> &old_velocity,
                    const std::vector<Point<dim>>     &old_position,
                    const ParticleUpdate::Batch<dim>  &batch,
                    const double                       dt,
                    double                            &dissipation)
    {
      for (unsigned int q = 0; q < n_points; ++q)
        {
          const double         M = mass_column[first_point + q];
          const Tensor<1, dim> a_dt =
            batch.grid[ParticleUpdate::acceleration][q] * dt;
          const Tensor<1, dim> &v_g = batch.grid[ParticleUpdate::velocity][q];
          const Tensor<1, dim>  dV  = batch.velocity[q] - old_velocity[q];
          const Tensor<1, dim>  dX_dt =
            (batch.position[q] - old_position[q]) / dt;
          dissipation += M * (a_dt * (v_g + 0.5 * a_dt) - dV * dX_dt);
        }
    }

    /** One momentum sink per material (contact; p^α zeroed by the
     * manager). */
    template <int dim, typename MaterialFields>
    Transfer::PerMaterial<Transfer::MassMomentumSink<dim, false>>
    material_momentum_sinks(const MaterialPoints<dim> &points,
                            const SupportCache<dim>   &supports,
                            MaterialFields            &material_fields)
    {
      Transfer::PerMaterial<Transfer::MassMomentumSink<dim, false>> sinks(
        supports.material.data());
      for (auto &field : material_fields)
        {
          double *p[dim];
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = field.momentum.block(d).begin();
          sinks.sinks.emplace_back(points, nullptr, p);
        }
      return sinks;
    }

    /** p = 0 of @p field (the centre of mass) and a momentum sink into
     * it; without @p field a sink that is not used. */
    template <int dim, typename Field>
    Transfer::MassMomentumSink<dim, false>
    momentum_sink(const MaterialPoints<dim> &points, Field *const field)
    {
      double *p[dim] = {};
      if (field != nullptr)
        {
          field->momentum = 0;
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = field->momentum.block(d).begin();
        }
      return Transfer::MassMomentumSink<dim, false>(points, nullptr, p);
    }

    /** V^(n) and X^(n) of the batch kept where the dissipation measure
     * (@p old_velocity, @p old_position) or particle damping need them;
     * returns the V^(n) damping reads. */
    template <int dim>
    const std::vector<Tensor<1, dim>> &
    keep_old_state(const ParticleUpdate::Batch<dim> &batch,
                   const bool                        track_dissipation,
                   const bool                        particle_damping,
                   std::vector<Tensor<1, dim>>      &old_velocity,
                   std::vector<Point<dim>>          &old_position,
                   std::vector<Tensor<1, dim>>      &damping_velocity)
    {
      if (track_dissipation)
        {
          old_velocity.assign(batch.velocity.begin(), batch.velocity.end());
          old_position.assign(batch.position.begin(), batch.position.end());
        }
      if (!particle_damping)
        return batch.velocity;
      damping_velocity.assign(batch.velocity.begin(), batch.velocity.end());
      return damping_velocity;
    }
  } // namespace



  template <int dim>
  void
  Simulator<dim>::update_particles()
  {
    using Index = PropertyIndex<dim>;

    // The fields of the centre of mass, or with contact of each material
    // (the point reads its material's field, Eq. 32).
    const bool                contact = contact_active();
    const GridFieldViews<dim> grid =
      contact ?
        GridFieldViews<dim>(active_fields(), this->contact->material_fields()) :
        GridFieldViews<dim>(
          active_fields(), OneSource<decltype(centre_of_mass)>{centre_of_mass});

    // Periodic FMPM(k): FLIP in the lumped steps between the series.
    ParticleUpdate::Interface<dim> &update = active_update();
    ParticleUpdate::Batch<dim>      batch;
    const double                    dt = control.time_step();
    batch.time_step                    = dt;
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
    // USL+/USAVG+: p = SᵀMV^{n+1} in this sweep (with contact p^α of the
    // point's material α, and what the normals and laws read of the moved
    // points).
    const bool re_extrapolate = point_loops.momenta_in_particle_update;
    Contact::GeometrySink<dim>        no_contact_geometry;
    const Contact::GeometrySink<dim> &contact_geometry =
      re_extrapolate && contact ?
        this->contact->begin_re_extrapolation(points,
                                              supports.material.data()) :
        no_contact_geometry;
    const Transfer::MassMomentumSink<dim, false> momentum =
      momentum_sink(points,
                    re_extrapolate && !contact ? &centre_of_mass : nullptr);
    const Transfer::PerMaterial<Transfer::MassMomentumSink<dim, false>>
      material_momentum =
        re_extrapolate && contact ?
          material_momentum_sinks(points,
                                  supports,
                                  this->contact->material_fields()) :
          Transfer::PerMaterial<Transfer::MassMomentumSink<dim, false>>(
            supports.material.data());

    // Point k's share of p = SᵀMV^{n+1} (Eq. 5 with contact) and of the
    // contact geometry once its V and X are final (in the store): the
    // operations of particles_to_grid().
    const auto re_extrapolate_point =
      [&](const unsigned int k, const auto &data) DEAL_II_ALWAYS_INLINE {
        support_of.visit(k,
                         data,
                         contact_geometry.needs_gradients(),
                         [&](const unsigned int *const   node,
                             const double *const         S,
                             const Tensor<1, dim> *const G,
                             const auto n_entries) DEAL_II_ALWAYS_INLINE {
                           if (contact)
                             {
                               material_momentum.point(
                                 k, node, S, G, n_entries);
                               contact_geometry.point(k, node, S, G, n_entries);
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
        gather_batch(first_point,
                     n_points,
                     data,
                     points,
                     velocity_column,
                     support_of,
                     grid,
                     contact ? supports.material.data() : nullptr,
                     batch);

        const std::vector<Tensor<1, dim>> &V_n =
          keep_old_state(batch,
                         track_dissipation,
                         particle_damping != 0,
                         old_velocity,
                         old_position,
                         damping_velocity);
        update.update(batch);

        if (grid_damping != 0 || particle_damping != 0)
          apply_damping(
            n_points, grid_damping, particle_damping, V_n, dt, batch);
        if (track_dissipation)
          add_dissipation(first_point,
                          n_points,
                          mass_column,
                          old_velocity,
                          old_position,
                          batch,
                          dt,
                          local_dissipation);

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
  Simulator<dim>::sort_particles_into_cells()
  {
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
} // namespace fmpm
