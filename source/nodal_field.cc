// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/interface.h>
#include <fmpm/nodal_field.h>
#include <fmpm/velocity_conditions.h>

namespace fmpm
{
  template <int dim>
  void
  NodalField<dim>::reinit(
    const std::shared_ptr<const Utilities::MPI::Partitioner> &partitioner,
    const bool                                                all_fields)
  {
    mass.reinit(partitioner);
    for (GridVectorField *vector : {&momentum, &force, &updated_momentum})
      {
        vector->reinit(dim);
        for (unsigned int d = 0; d < dim; ++d)
          vector->block(d).reinit(partitioner);
        vector->collect_sizes();
      }
    for (unsigned int f = 0; f < ParticleUpdate::n_grid_fields; ++f)
      {
        fields[f].reinit(0);
        written_nodes[f].clear();
        if (all_fields)
          allocate(static_cast<ParticleUpdate::GridField>(f));
      }
    computed.fill(false);
  }



  template <int dim>
  void
  NodalField<dim>::allocate(const ParticleUpdate::GridField field)
  {
    GridVectorField &target = fields[field];
    if (target.n_blocks() == dim)
      return;
    target.reinit(dim);
    for (unsigned int d = 0; d < dim; ++d)
      target.block(d).reinit(mass.get_partitioner());
    target.collect_sizes();
  }



  template <int dim>
  void
  FieldSolver<dim>::lumped(NodalField<dim>                &field_set,
                           const ParticleUpdate::GridField field,
                           const GridVectorField          &q) const
  {
    MassMatrix::apply_lumped_inverse(field_set.mass,
                                     q,
                                     field_set.fields[field],
                                     mass_floor);
  }



  template <int dim>
  void
  FieldSolver<dim>::lumped_on_nodes(NodalField<dim>                 &field_set,
                                    const ParticleUpdate::GridField  field,
                                    const std::vector<unsigned int> &nodes,
                                    const double time_step) const
  {
    GridVectorField           &target  = field_set.fields[field];
    std::vector<unsigned int> &written = field_set.written_nodes[field];
    const double *const        m       = field_set.mass.begin();
    const double               inverse_time_step = 1. / time_step;
    for (unsigned int d = 0; d < dim; ++d)
      {
        double *const v = target.block(d).begin();
        for (const unsigned int i : written)
          v[i] = 0;
        const double *const p0 = field_set.momentum.block(d).begin();
        const double *const p1 = field_set.updated_momentum.block(d).begin();
        if (is_acceleration(field))
          // a = (p⁺ − p) / (m Δt), seed 004 Eqs. 32-34
          for (const unsigned int i : nodes)
            v[i] = ((p1[i] - p0[i]) * inverse_time_step) / m[i];
        else // v = p / m, v⁺ = p⁺ / m (seed 004 Eqs. 26, 31)
          {
            const double *const q = is_updated(field) ? p1 : p0;
            for (const unsigned int i : nodes)
              v[i] = q[i] / m[i];
          }
      }
    written = nodes;
    if (conditions)
      for (const auto &c : conditions->node_conditions())
        written.push_back(c.local_index);
  }



  template <int dim>
  void
  FieldSolver<dim>::finish(NodalField<dim>                &field_set,
                           const ParticleUpdate::GridField field,
                           const bool                      apply_conditions,
                           std::vector<double>            *corrections) const
  {
    GridVectorField &target = field_set.fields[field];
    if (apply_conditions && conditions)
      {
        if (is_acceleration(field))
          conditions->correct_accelerations(target, t_begin, t_end);
        else
          conditions->correct_velocities(target, time_of(field), corrections);
      }
    // Hanging nodes take the interpolation of their masters, in every
    // component (the constraints index one scalar block).
    if (has_hanging_nodes)
      for (unsigned int d = 0; d < dim; ++d)
        constraints->distribute(target.block(d));
    target.update_ghost_values();
    field_set.computed[field] = true;
  }



  namespace internal
  {
    void
    set_to_sum(GridScalar &total, const std::vector<const double *> &terms)
    {
      total.zero_out_ghost_values();
      const unsigned int n_local =
        total.locally_owned_size() + total.get_partitioner()->n_ghost_indices();
      double *const t = total.begin();
      if (terms.size() == 2)
        {
          const double *const a = terms[0];
          const double *const b = terms[1];
          for (unsigned int i = 0; i < n_local; ++i)
            t[i] = (0. + a[i]) + b[i];
          return;
        }
      for (unsigned int i = 0; i < n_local; ++i)
        t[i] = 0.;
      for (const double *const term : terms)
        for (unsigned int i = 0; i < n_local; ++i)
          t[i] += term[i];
    }
  } // namespace internal

  template struct NodalField<2>;
  template struct NodalField<3>;
  template struct FieldSolver<2>;
  template struct FieldSolver<3>;
} // namespace fmpm
