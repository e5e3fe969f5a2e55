// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The strain update (G: to points): per batch of points, the velocity
// gradients gathered from the grid, F^{n+1} and J (transfer/kinematics.h),
// the constitutive models' call per material group, the new state into the
// store, and with forces the force sink over the batch's points in store
// order (f = −Σ V σ G + Σ S M b, Eq. 2.11).

#include <fmpm/simulator.h>
#include <fmpm/simulator.templates.h>
#include <fmpm/transfer/kinematics.h>
#include <fmpm/transfer/sinks.h>
#include <fmpm/transfer/stress_update_forces.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace fmpm
{
  namespace
  {
    /** Points per batch of the strain update (constitutive model calls). */
    constexpr unsigned int stress_batch_size =
      ConstitutiveModel::StressUpdateInputs::capacity;

    /**
     * The store's columns the strain update reads and writes: F (row
     * major), σ, W, V and V0. In 2D (plane strain) only the 2x2 block and
     * F_33 of F, and σ_xx, σ_yy, σ_zz, σ_xy are stored: the other entries
     * are zero and are not written.
     */
    template <int dim>
    struct StressColumns
    {
      static constexpr unsigned int n_stress_entries = dim == 3 ? 6 : 4;

      explicit StressColumns(MaterialPoints<dim> &points)
      {
        using Index = PropertyIndex<dim>;
        for (unsigned int c = 0; c < 9; ++c)
          F[c] = points.column(Index::deformation_gradient + c);
        for (unsigned int c = 0; c < 6; ++c)
          stress[c] = points.column(Index::stress + c);
        energy         = points.column(Index::strain_energy_density);
        volume         = points.column(Index::volume);
        initial_volume = points.column(Index::initial_volume);
      }

      double       *F[9];
      double       *stress[6];
      double       *energy;
      double       *volume;
      const double *initial_volume;
    };

    /** The points of one material in a batch (store indices), stored one
     * after another (contiguous) when the batch has one material. */
    struct MaterialGroup
    {
      const unsigned int *point;
      unsigned int        n;
      unsigned int        k0;
      bool                contiguous;
    };

    /**
     * S and G of the batch's points: read from the support cache, or for
     * implicit classic supports computed once for L and the forces and
     * kept by place in the batch.
     */
    template <int dim>
    class BatchSupports
    {
    public:
      static constexpr unsigned int n_nodes = GridTransfer<dim>::n_nodes;

      BatchSupports(const SupportCache<dim> &supports,
                    const GridTransfer<dim> &transfer,
                    const unsigned int      *point_cell,
                    const Point<dim>        *points_position)
        : supports(supports)
        , transfer(transfer)
        , point_cell(point_cell)
        , points_position(points_position)
        , support_of(supports, transfer, point_cell)
      {}

      /** L = ∇v = Σ_i v_i ⊗ G_pi (Eqs. 2.7, 2.18) of the group's points
       * from the nodal velocities @p v, plane strain in 2D; with @p hoop
       * (axisymmetric, stored supports) also L_33 = Σ_i v_r,i T_pi. */
      template <bool hoop = false>
      void
      velocity_gradients(const MaterialGroup      &group,
                         const unsigned int        batch_begin,
                         const double *const       v[dim],
                         Kinematics::BatchEntries &L)
      {
        for (unsigned int q = 0; q < group.n; ++q)
          {
            const unsigned int k = group.point[q];
            if (supports.implicit_classic)
              {
                const unsigned int b    = k - batch_begin;
                const auto        &cell = transfer.cell_data(point_cell[k]);
                support_of.compute(k, cell, true, S[b], G[b]);
                node[b] = cell.local_index.data();
                Kinematics::velocity_gradient<dim>(
                  node[b],
                  G[b].data(),
                  0,
                  std::integral_constant<unsigned int, n_nodes>(),
                  v,
                  L,
                  q);
                if constexpr (hoop)
                  {
                    // Classic: T = S/r_p (the bits the builder stores).
                    const double inverse_r = 1 / points_position[k][0];
                    std::array<double, n_nodes> T;
                    for (unsigned int i = 0; i < n_nodes; ++i)
                      T[i] = S[b][i] * inverse_r;
                    Kinematics::hoop_rate(
                      node[b],
                      T.data(),
                      0,
                      std::integral_constant<unsigned int, n_nodes>(),
                      v[0],
                      L,
                      q);
                  }
              }
            else
              support_of.visit(k,
                               true,
                               [&](const unsigned int *const   node,
                                   const double *const         S,
                                   const Tensor<1, dim> *const G,
                                   const auto                  n_entries) {
                                 Kinematics::velocity_gradient<dim>(
                                   node, G, 0, n_entries, v, L, q);
                                 if constexpr (hoop)
                                   Kinematics::hoop_rate(node,
                                                         supports.T.data() +
                                                           (S -
                                                            supports.S.data()),
                                                         0,
                                                         n_entries,
                                                         v[0],
                                                         L,
                                                         q);
                               });
          }
      }

      /** velocity_gradients() with L_33 (axisymmetric), out of line. */
      [[gnu::noinline]] void
      hoop_velocity_gradients(const MaterialGroup      &group,
                              const unsigned int        batch_begin,
                              const double *const       v[dim],
                              Kinematics::BatchEntries &L)
      {
        velocity_gradients<true>(group, batch_begin, v, L);
      }

      /** L of @p group: hoop_velocity_gradients() if @p axisymmetric, else
       * velocity_gradients(). */
      void
      group_velocity_gradients(const bool                axisymmetric,
                               const MaterialGroup      &group,
                               const unsigned int        batch_begin,
                               const double *const       v[dim],
                               Kinematics::BatchEntries &L)
      {
        if (axisymmetric)
          hoop_velocity_gradients(group, batch_begin, v, L);
        else
          velocity_gradients(group, batch_begin, v, L);
      }

      /** add_points() of the hoop force sink, out of line. */
      template <typename Sink>
      [[gnu::noinline]] void
      add_points_out_of_line(const unsigned int batch_begin,
                             const unsigned int batch_end,
                             const Sink        &sink) const
      {
        add_points(batch_begin, batch_end, sink);
      }

      /** The points [batch_begin, batch_end) into @p sink in the store's
       * order, with the entries velocity_gradients() read. */
      template <typename Sink>
      void
      add_points(const unsigned int batch_begin,
                 const unsigned int batch_end,
                 const Sink        &sink) const
      {
        for (unsigned int k = batch_begin; k < batch_end; ++k)
          if (supports.implicit_classic)
            {
              const unsigned int b = k - batch_begin;
              sink.point(k,
                         node[b],
                         S[b].data(),
                         G[b].data(),
                         std::integral_constant<unsigned int, n_nodes>());
            }
          else
            support_of.visit(k,
                             true,
                             [&](const unsigned int *const   node,
                                 const double *const         S,
                                 const Tensor<1, dim> *const G,
                                 const auto n_entries) DEAL_II_ALWAYS_INLINE {
                               sink.point(k, node, S, G, n_entries);
                             });
      }

    private:
      const SupportCache<dim>  &supports;
      const GridTransfer<dim>  &transfer;
      const unsigned int *const point_cell;
      /** The points' positions (r_p of axisymmetric classic supports). */
      const Point<dim> *const             points_position;
      const SupportReader<dim>            support_of;
      std::array<double, n_nodes>         S[stress_batch_size];
      std::array<Tensor<1, dim>, n_nodes> G[stress_batch_size];
      const unsigned int                 *node[stress_batch_size];
    };

    /** What the group's model reads besides L: Δx of the points' cells,
     * σ^n, W^n and the points' records (history slots), V^n/V0. */
    template <int dim>
    void
    gather_model_inputs(const ConstitutiveModel::Interface<dim> &model,
                        const MaterialGroup                     &group,
                        const StressColumns<dim>                &columns,
                        const MaterialPoints<dim>               &points,
                        const std::vector<double> &cell_size_by_index,
                        ConstitutiveModel::StressUpdateInputs &inputs)
    {
      constexpr unsigned int n_entries = StressColumns<dim>::n_stress_entries;
      if (model.needs_cell_size())
        for (unsigned int q = 0; q < group.n; ++q)
          inputs.cell_size[q] = cell_size_by_index[points.cell[group.point[q]]];
      if (model.reads_old_state())
        {
          if (group.contiguous)
            {
              const unsigned int k0 = group.k0;
              for (unsigned int c = 0; c < n_entries; ++c)
                std::copy(columns.stress[c] + k0,
                          columns.stress[c] + k0 + group.n,
                          inputs.old_stress[c]);
              std::copy(columns.energy + k0,
                        columns.energy + k0 + group.n,
                        inputs.old_strain_energy_density);
            }
          else
            for (unsigned int q = 0; q < group.n; ++q)
              {
                const unsigned int k = group.point[q];
                for (unsigned int c = 0; c < n_entries; ++c)
                  inputs.old_stress[c][q] = columns.stress[c][k];
                inputs.old_strain_energy_density[q] = columns.energy[k];
              }
          for (unsigned int q = 0; q < group.n; ++q)
            inputs.properties[q] = points.record(group.point[q]);
        }
      if (model.needs_old_volume_ratio())
        for (unsigned int q = 0; q < group.n; ++q)
          inputs.old_volume_ratio[q] = columns.volume[group.point[q]] /
                                       columns.initial_volume[group.point[q]];
    }

    /**
     * F^{n+1} = ΔF F^n and J = det F^{n+1} (the operations of deal.II's
     * Tensor product and determinant()) for the increments @p dF; in 2D on
     * the 2x2 block, F_33 kept (plane strain).
     */
    template <int dim>
    void
    apply_increments(const MaterialGroup            &group,
                     const StressColumns<dim>       &columns,
                     const Kinematics::BatchEntries &dF,
                     Kinematics::BatchEntries       &F,
                     double                         *J,
                     const bool                      axisymmetric)
    {
      double *const *const F_n = columns.F;
      for (unsigned int q = 0; q < group.n; ++q)
        {
          const unsigned int k = group.point[q];
          if constexpr (dim == 2)
            {
              const double a = F_n[0][k], b = F_n[1][k], c = F_n[3][k],
                           e = F_n[4][k];
              F[0][q]        = dF[0][q] * a + dF[1][q] * c;
              F[1][q]        = dF[0][q] * b + dF[1][q] * e;
              F[3][q]        = dF[3][q] * a + dF[4][q] * c;
              F[4][q]        = dF[3][q] * b + dF[4][q] * e;
              F[8][q]        = F_n[8][k];
            }
          else
            for (unsigned int a = 0; a < 3; ++a)
              for (unsigned int b = 0; b < 3; ++b)
                F[3 * a + b][q] = dF[3 * a][q] * F_n[b][k] +
                                  dF[3 * a + 1][q] * F_n[3 + b][k] +
                                  dF[3 * a + 2][q] * F_n[6 + b][k];
        }
      // Axisymmetric: the hoop stretch F_33^{n+1} = ΔF_33 F_33^n.
      if (dim == 2 && axisymmetric)
        for (unsigned int q = 0; q < group.n; ++q)
          F[8][q] = dF[8][q] * F_n[8][group.point[q]];
      for (unsigned int q = 0; q < group.n; ++q)
        if constexpr (dim == 2)
          // The same value without the plane-strain zeros' products.
          J[q] = F[0][q] * (F[4][q] * F[8][q]) - F[1][q] * (F[3][q] * F[8][q]);
        else
          {
            const double C0 = F[4][q] * F[8][q] - F[5][q] * F[7][q];
            const double C1 = F[5][q] * F[6][q] - F[3][q] * F[8][q];
            const double C2 = F[3][q] * F[7][q] - F[4][q] * F[6][q];
            J[q]            = F[0][q] * C0 + F[1][q] * C1 + F[2][q] * C2;
          }
    }

    /** F^n of the group: the store's columns, or gathered into
     * @p F_gathered for a group spread over the batch (several materials). */
    template <int dim>
    inline std::array<const double *, 9>
    old_deformation_gradients(const MaterialGroup      &group,
                              const StressColumns<dim> &columns,
                              Kinematics::BatchEntries &F_gathered)
    {
      std::array<const double *, 9> F_old;
      for (unsigned int c = 0; c < 9; ++c)
        if (group.contiguous)
          F_old[c] = columns.F[c] + group.k0;
        else
          {
            for (unsigned int q = 0; q < group.n; ++q)
              F_gathered[c][q] = columns.F[c][group.point[q]];
            F_old[c] = F_gathered[c];
          }
      return F_old;
    }

    /** F^{n+1} and J of the group into @p inputs from its velocity
     * gradients, by the method's F update (seed 001). */
    template <int dim>
    void
    update_deformation_gradients(const MaterialGroup      &group,
                                 const StressColumns<dim> &columns,
                                 const MethodParameters   &method,
                                 const double              dt,
                                 Kinematics::BatchEntries &dF,
                                 Kinematics::BatchEntries &F_gathered,
                                 ConstitutiveModel::StressUpdateInputs &inputs)
    {
      const DeformationGradientUpdate F_update =
        method.deformation_gradient_update;
      if (F_update == DeformationGradientUpdate::cayley)
        {
          const auto F_old =
            old_deformation_gradients(group, columns, F_gathered);
          Kinematics::cayley_update<dim>(group.n,
                                         dt,
                                         inputs.velocity_gradient,
                                         F_old,
                                         inputs.deformation_gradient,
                                         inputs.volume_ratio);
        }
      else
        {
          Kinematics::increments<dim>(
            F_update, method, inputs.velocity_gradient, dt, group.n, dF);
          apply_increments<dim>(group,
                                columns,
                                dF,
                                inputs.deformation_gradient,
                                inputs.volume_ratio,
                                false);
        }
    }

    /** update_deformation_gradients() of an axisymmetric group (2D): the
     * hoop stretch F_33 with L_33 (kept out of line, so that the plane
     * strain path stays as it was). */
    template <int dim>
    [[gnu::noinline]] void
    axisymmetric_deformation_gradients(
      const MaterialGroup                   &group,
      const StressColumns<dim>              &columns,
      const MethodParameters                &method,
      const double                           dt,
      Kinematics::BatchEntries              &dF,
      Kinematics::BatchEntries              &F_gathered,
      ConstitutiveModel::StressUpdateInputs &inputs)
    {
      const DeformationGradientUpdate F_update =
        method.deformation_gradient_update;
      if (F_update == DeformationGradientUpdate::cayley)
        {
          const auto F_old =
            old_deformation_gradients(group, columns, F_gathered);
          Kinematics::axisymmetric_cayley_update(group.n,
                                                 dt,
                                                 inputs.velocity_gradient,
                                                 F_old,
                                                 inputs.deformation_gradient,
                                                 inputs.volume_ratio);
        }
      else
        {
          Kinematics::axisymmetric_increments(
            F_update, method, inputs.velocity_gradient, dt, group.n, dF);
          apply_increments<dim>(group,
                                columns,
                                dF,
                                inputs.deformation_gradient,
                                inputs.volume_ratio,
                                true);
        }
    }

    /** F, σ, W and V = J V0 of the group into the store (in 2D the
     * plane-strain zero entries are not stored; F_33 is unchanged), and
     * each point's J for the wave speed (1 for inverted points, which are
     * reported and give no speed). */
    template <int dim>
    void
    store_group(const MaterialGroup                          &group,
                const StressColumns<dim>                     &columns,
                const ConstitutiveModel::StressUpdateInputs  &inputs,
                const ConstitutiveModel::StressUpdateOutputs &outputs,
                double                                       *J_of_group,
                const bool                                    axisymmetric)
    {
      constexpr unsigned int n_entries = StressColumns<dim>::n_stress_entries;
      const auto            &F         = inputs.deformation_gradient;
      const auto            &J         = inputs.volume_ratio;
      // Axisymmetric: the hoop stretch F_33 too.
      if (dim == 2 && axisymmetric)
        for (unsigned int q = 0; q < group.n; ++q)
          columns.F[8][group.point[q]] = F[8][q];
      if (group.contiguous)
        {
          const unsigned int k0 = group.k0;
          for (unsigned int c = 0; c < 9; ++c)
            if (dim == 3 || c == 0 || c == 1 || c == 3 || c == 4)
              std::copy(F[c], F[c] + group.n, columns.F[c] + k0);
          for (unsigned int c = 0; c < n_entries; ++c)
            std::copy(outputs.cauchy_stress[c],
                      outputs.cauchy_stress[c] + group.n,
                      columns.stress[c] + k0);
          std::copy(outputs.strain_energy_density,
                    outputs.strain_energy_density + group.n,
                    columns.energy + k0);
          for (unsigned int q = 0; q < group.n; ++q)
            {
              columns.volume[k0 + q] = J[q] * columns.initial_volume[k0 + q];
              J_of_group[q]          = J[q] > 0 ? J[q] : 1;
            }
        }
      else
        for (unsigned int q = 0; q < group.n; ++q)
          {
            const unsigned int k = group.point[q];
            for (unsigned int c = 0; c < 9; ++c)
              if (dim == 3 || c == 0 || c == 1 || c == 3 || c == 4)
                columns.F[c][k] = F[c][q];
            for (unsigned int c = 0; c < n_entries; ++c)
              columns.stress[c][k] = outputs.cauchy_stress[c][q];
            columns.energy[k] = outputs.strain_energy_density[q];
            columns.volume[k] = J[q] * columns.initial_volume[k];
            J_of_group[q]     = J[q] > 0 ? J[q] : 1;
          }
    }

    /** The points of the batch [batch_begin, batch_end) by their
     * @p material into @p by_material (only with two or more materials). */
    inline void
    sort_by_material(const unsigned int                      batch_begin,
                     const unsigned int                      batch_end,
                     const unsigned char *const              material,
                     std::vector<std::vector<unsigned int>> &by_material)
    {
      if (by_material.size() <= 1)
        return;
      for (auto &points_of_material : by_material)
        points_of_material.clear();
      for (unsigned int k = batch_begin; k < batch_end; ++k)
        by_material[material[k]].push_back(k);
    }

    /** The group of material @p m in the batch [batch_begin, batch_end)
     * into @p group_points: the whole batch for one material, else the
     * batch's points of @p m. */
    inline MaterialGroup
    material_group(const unsigned int                            m,
                   const unsigned int                            batch_begin,
                   const unsigned int                            batch_end,
                   const std::vector<std::vector<unsigned int>> &by_material,
                   unsigned int                                 *group_points)
    {
      MaterialGroup group;
      group.point             = group_points;
      const bool one_material = by_material.size() == 1;
      group.n  = one_material ? batch_end - batch_begin : by_material[m].size();
      group.k0 = batch_begin;
      group.contiguous = true;
      if (group.n == 0)
        return group;
      if (one_material)
        std::iota(group_points, group_points + group.n, batch_begin);
      else
        std::copy(by_material[m].begin(), by_material[m].end(), group_points);
      group.k0         = group_points[0];
      group.contiguous = group_points[group.n - 1] == group.k0 + group.n - 1;
      return group;
    }

    /** The cell sizes Δx (Eq. 52) by active cell index of the cells with
     * points, only when a model reads them. */
    template <int dim, typename Models>
    void
    compute_cell_sizes(const MaterialPoints<dim> &points,
                       const unsigned int         n_active_cells,
                       const Models              &models,
                       std::vector<double>       &cell_size_by_index)
    {
      bool needs_cell_size = false;
      for (const auto &model : models)
        needs_cell_size = needs_cell_size || model->needs_cell_size();
      if (!needs_cell_size)
        return;
      cell_size_by_index.resize(n_active_cells);
      for (unsigned int c = 0; c < points.n_cells(); ++c)
        cell_size_by_index[points.cell_index[c]] =
          points.cell_iterator(c)->minimum_vertex_distance();
    }

    /** The larger of @p wave_speed and the group's wave speeds: the
     * model's per point, else its bound for the group's J. */
    template <int dim>
    double
    max_wave_speed(const double                                  wave_speed,
                   const ConstitutiveModel::Interface<dim>      &model,
                   const double                                  density,
                   const MaterialGroup                          &group,
                   const ConstitutiveModel::StressUpdateOutputs &outputs,
                   const double                                 *J_of_group)
    {
      double speed = wave_speed;
      if (model.computes_wave_speed())
        for (unsigned int q = 0; q < group.n; ++q)
          speed = std::max(speed, outputs.wave_speed[q]);
      else
        speed =
          std::max(speed,
                   model.max_wave_speed(
                     density, ArrayView<const double>(J_of_group, group.n)));
      return speed;
    }

  } // namespace



  template <int dim>
  void
  Simulator<dim>::update_stresses(const ParticleUpdate::GridField field,
                                  const double                    dt,
                                  const bool                      with_forces)
  {
    // The velocities of the centre of mass, or with contact of the group's
    // material (Eq. 28).
    const bool contact = contact_active();
    if (contact)
      this->contact->compute_field(field);
    else
      compute_field(field);
    const unsigned int n_materials = constitutive_models.size();
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
    BatchSupports<dim>       batch_supports(supports,
                                      transfer,
                                      points.cell.data(),
                                      points.position.data());
    const StressColumns<dim> columns(points);

    // USF/USAVG: f (and with contact f^α0, Eq. 29) from the new stresses
    // in this sweep, each batch's points in the store's order once their
    // stresses are updated.
    const bool axisymmetric = parameters.axisymmetric;
    const Transfer::StressUpdateForces<dim> forces(points,
                                                   external_loads,
                                                   supports,
                                                   centre_of_mass.force,
                                                   contact ?
                                                     this->contact.get() :
                                                     nullptr,
                                                   with_forces,
                                                   axisymmetric);

    compute_cell_sizes(points,
                       triangulation.n_active_cells(),
                       constitutive_models,
                       cell_size_by_index);

    // Points of a batch grouped by material for the model call (one group
    // when the scene has one material).
    std::vector<std::vector<unsigned int>> by_material(n_materials);
    for (auto &group : by_material)
      group.reserve(stress_batch_size);
    unsigned int group_points[stress_batch_size];
    double       J_of_group[stress_batch_size];

    for (unsigned int batch_begin = 0; batch_begin < supports.n_points();
         batch_begin += stress_batch_size)
      {
        const unsigned int batch_end =
          std::min(batch_begin + stress_batch_size, supports.n_points());
        sort_by_material(batch_begin,
                         batch_end,
                         supports.material.data(),
                         by_material);

        for (unsigned int m = 0; m < n_materials; ++m)
          {
            const MaterialGroup group = material_group(
              m, batch_begin, batch_end, by_material, group_points);
            if (group.n == 0)
              continue;
            const ConstitutiveModel::Interface<dim> &model =
              *constitutive_models[m];
            if (contact)
              view_velocities(
                this->contact->material_fields()[m].fields[field]);
            inputs.resize(group.n);
            inputs.reference_density = parameters.materials[m].density;
            // L, and what else the model reads.
            batch_supports.group_velocity_gradients(
              axisymmetric, group, batch_begin, v_a, inputs.velocity_gradient);
            gather_model_inputs(
              model, group, columns, points, cell_size_by_index, inputs);
            if (axisymmetric)
              axisymmetric_deformation_gradients(
                group, columns, parameters.method, dt, dF, F_gathered, inputs);
            else
              update_deformation_gradients(
                group, columns, parameters.method, dt, dF, F_gathered, inputs);
            const double *const J = inputs.volume_ratio;
            for (unsigned int q = 0; q < group.n; ++q)
              if (!(J[q] > 0))
                report_point_failure(group_points[q],
                                     FailedPoint::Cause::inverted,
                                     "has an inverted deformation gradient, "
                                     "J = ",
                                     J[q]);

            outputs.failed_point = -1;
            model.update_stress(inputs, outputs);
            if (outputs.failed_point >= 0)
              report_point_failure(group_points[outputs.failed_point],
                                   FailedPoint::Cause::model_failure,
                                   outputs.failure);

            store_group(
              group, columns, inputs, outputs, J_of_group, axisymmetric);
            for (unsigned int q = 0; q < group.n; ++q)
              if (!std::isfinite(outputs.strain_energy_density[q]))
                report_point_failure(group_points[q],
                                     FailedPoint::Cause::stress_not_finite,
                                     "is not finite (NaN or Inf)");
            wave_speed = max_wave_speed(wave_speed,
                                        model,
                                        parameters.materials[m].density,
                                        group,
                                        outputs,
                                        J_of_group);
          }
        forces.add(batch_supports, batch_begin, batch_end);
      }
    local_max_wave_speed = wave_speed;
    if (with_forces)
      {
        add_face_traction_forces(contact);
        if (contact) // f = Σ_α f^α0
          this->contact->finish_forces(centre_of_mass);
        centre_of_mass.force.compress(VectorOperation::add);
      }
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
