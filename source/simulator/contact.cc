// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Multimaterial contact (seed 004 §2-3): per-material fields, the contact
// corrections at nodes shared by materials, the material fields the
// stress and particle updates read.

#include <fmpm/contact.h>
#include <fmpm/simulator.h>

#include <algorithm>
#include <limits>

namespace fmpm
{
  template <int dim>
  void
  Simulator<dim>::setup_contact()
  {
    const Contact::Parameters &contact = parameters.contact;
    material_fields.clear();
    if (!contact.multimaterial || parameters.size.n_materials < 2)
      return;
    using Method = Contact::NormalMethod;
    contact_needs_gradients = contact.normals != Method::specified;
    contact_needs_positions = contact.normals == Method::average_gradient ||
                              contact.normals == Method::contact_position;

    const auto partitioner = lumped_mass.get_partitioner();
    auto       reinit      = [&](GridVectorField &field) {
      field.reinit(dim);
      for (unsigned int d = 0; d < dim; ++d)
        field.block(d).reinit(partitioner);
      field.collect_sizes();
    };
    reinit(contact_normal);
    contact_separation.reinit(partitioner);
    material_fields.resize(parameters.size.n_materials);
    for (auto &material : material_fields)
      {
        material.mass.reinit(partitioner);
        reinit(material.momentum);
        reinit(material.force);
        reinit(material.updated_momentum);
        reinit(material.delta_velocity);
        if (contact_needs_gradients)
          reinit(material.volume_gradient);
        if (contact_needs_positions)
          reinit(material.position_moment);
        for (auto &field : material.fields)
          reinit(field);
      }

    // The local cell size at a node: the smallest vertex distance of the
    // cells around it (separations are measured in cells, also on adapted
    // and unstructured meshes).
    if (contact_needs_positions)
      {
        node_cell_size.reinit(partitioner);
        const double large = std::numeric_limits<double>::max();
        for (auto &value : node_cell_size)
          value = large;
        node_cell_size.update_ghost_values();
        std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const double h = cell->minimum_vertex_distance();
              cell->get_dof_indices(dofs);
              for (const auto dof : dofs)
                {
                  double &value =
                    node_cell_size.local_element(partitioner->global_to_local(dof));
                  value = std::min(value, h);
                }
            }
        node_cell_size.compress(VectorOperation::min);
      }
  }



  template <int dim>
  void
  Simulator<dim>::impose_material_conditions(const unsigned int alpha,
                                             GridVectorField   &q,
                                             const double       t)
  {
    // The conditions act on every material field with that material's
    // lumped masses (contact requires the lumped mass matrix).
    const GridScalar &m = material_fields[alpha].mass;
    typename VelocityConditions<dim>::Operators operators;
    operators.lumped_mass = &m;
    operators.mass_floor  = mass_floor_value;
    operators.solve       = [&m, this](const GridVectorField &p,
                                 GridVectorField       &v) {
      MassMatrix::apply_lumped_inverse(m, p, v, mass_floor_value);
    };
    operators.forward = [&m](const GridVectorField &v, GridVectorField &p) {
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
          p.block(d).local_element(i) =
            m.local_element(i) * v.block(d).local_element(i);
    };
    operators.full_mass = operators.forward;
    velocity_conditions.impose_on_momenta(q, t, operators, nullptr);
  }



  template <int dim>
  void
  Simulator<dim>::apply_contact(const ContactStage stage)
  {
    TimerOutput::Scope         timer(computing_timer, "contact");
    const Contact::Parameters &contact     = parameters.contact;
    const unsigned int         n_materials = material_fields.size();
    const unsigned int         n_owned     = lumped_mass.locally_owned_size();
    const double               floor       = mass_floor_value;
    using Method                           = Contact::NormalMethod;

    // δc in cells: the user's (CP) or the linear d(x) fit's (Eq. 17).
    const double critical_separation =
      contact.normals == Method::contact_position ? contact.critical_separation :
      shape_function == ShapeFunction::Type::cpdi ? 0.96 :
                                                    0.92;
    Tensor<1, dim> specified_normal;
    for (unsigned int d = 0; d < dim; ++d)
      specified_normal[d] = contact.specified_normal[d];
    if (specified_normal.norm() > 0)
      specified_normal /= specified_normal.norm();

    // Raw views: m^α, the momenta this stage corrects, g^α, Σ S M X.
    std::vector<const double *> m(n_materials);
    std::vector<double *>       p(n_materials * dim);
    std::vector<const double *> g(contact_needs_gradients ? n_materials * dim :
                                                            0);
    std::vector<const double *> xm(contact_needs_positions ? n_materials * dim :
                                                             0);
    std::vector<double *>       dv(n_materials * dim);
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        MaterialField &field = material_fields[a];
        m[a]                 = field.mass.begin();
        GridVectorField &momenta =
          stage == ContactStage::updated ? field.updated_momentum :
                                           field.momentum;
        for (unsigned int d = 0; d < dim; ++d)
          {
            p[a * dim + d]  = momenta.block(d).begin();
            dv[a * dim + d] = field.delta_velocity.block(d).begin();
            if (contact_needs_gradients)
              g[a * dim + d] = field.volume_gradient.block(d).begin();
            if (contact_needs_positions)
              xm[a * dim + d] = field.position_moment.block(d).begin();
          }
        if (stage == ContactStage::extrapolated)
          field.delta_velocity = 0;
      }

    // The state of a node seen by material α against β, where β may be the
    // sum of several materials (Eq. 50).
    auto sum_over = [&](const std::vector<const double *> &v,
                        const std::vector<unsigned int>    &materials,
                        const unsigned int                  i) {
      Tensor<1, dim> sum;
      for (const unsigned int a : materials)
        for (unsigned int d = 0; d < dim; ++d)
          sum[d] += v[a * dim + d][i];
      return sum;
    };
    auto node_pair = [&](const std::vector<unsigned int> &alpha,
                         const std::vector<unsigned int> &beta,
                         const unsigned int               i) {
      Contact::NodePair<dim> node;
      for (const unsigned int a : alpha)
        {
          node.mass_alpha += m[a][i];
          for (unsigned int d = 0; d < dim; ++d)
            node.momentum_alpha[d] += p[a * dim + d][i];
        }
      for (const unsigned int b : beta)
        {
          node.mass_beta += m[b][i];
          for (unsigned int d = 0; d < dim; ++d)
            node.momentum_beta[d] += p[b * dim + d][i];
        }
      if (contact.normals == Method::specified)
        node.normal = (alpha.front() < beta.front() ? 1. : -1.) *
                      specified_normal;
      else
        {
          // n̂ = (g^α − g^β)/|g^α − g^β| (Eq. 13)
          const Tensor<1, dim> difference =
            sum_over(g, alpha, i) - sum_over(g, beta, i);
          const double norm = difference.norm();
          if (norm > 0)
            node.normal = difference / norm;
          else
            node.touching = false;
        }
      if (contact_needs_positions && node.touching)
        {
          // (x^β − x^α)·n̂ < δc h (Eqs. 16-17)
          const Tensor<1, dim> x_alpha =
            sum_over(xm, alpha, i) / node.mass_alpha;
          const Tensor<1, dim> x_beta = sum_over(xm, beta, i) / node.mass_beta;
          node.separation = (x_beta - x_alpha) * node.normal /
                            node_cell_size.local_element(i);
          node.touching = node.separation < critical_separation;
        }
      return node;
    };
    auto add_momentum = [&](const unsigned int    a,
                            const unsigned int    i,
                            const Tensor<1, dim> &dp) {
      for (unsigned int d = 0; d < dim; ++d)
        {
          p[a * dim + d][i] += dp[d];
          if (stage == ContactStage::extrapolated)
            dv[a * dim + d][i] += dp[d] / m[a][i];
        }
    };

    // The grid output's contact normal and separation: of the first pair
    // in contact at a node after the momentum update, else zero.
    if (stage == ContactStage::updated)
      {
        contact_normal     = 0;
        contact_separation = 0;
      }
    auto record = [&](const unsigned int i, const Contact::NodePair<dim> &node) {
      for (unsigned int d = 0; d < dim; ++d)
        contact_normal.block(d).local_element(i) = node.normal[d];
      contact_separation.local_element(i) = node.separation;
    };

    std::vector<unsigned int>   present, alpha(1), beta;
    std::vector<Tensor<1, dim>> changes;
    double                      work          = 0;
    unsigned long long          contact_nodes = 0;
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        present.clear();
        for (unsigned int a = 0; a < n_materials; ++a)
          if (m[a][i] > floor)
            present.push_back(a);
        if (present.size() < 2)
          continue;
        bool in_contact = false;
        if (present.size() == 2 || !contact.lumped_three_or_more)
          {
            // Each pair in turn (one pair at most 3+ nodes apart): α gets
            // Δp^α, β gets −Δp^α (Eq. 7).
            for (unsigned int x = 0; x < present.size(); ++x)
              for (unsigned int y = x + 1; y < present.size(); ++y)
                {
                  alpha.assign(1, present[x]);
                  beta.assign(1, present[y]);
                  const auto node = node_pair(alpha, beta, i);
                  const auto c =
                    Contact::correct(contact.law(present[x], present[y]), node);
                  add_momentum(present[x], i, c.delta_momentum);
                  add_momentum(present[y], i, -c.delta_momentum);
                  if (stage == ContactStage::updated && c.in_contact &&
                      !in_contact)
                    record(i, node);
                  in_contact = in_contact || c.in_contact;
                  work += c.friction_work;
                }
          }
        else
          {
            // 3+ materials, lumped (Eq. 50): each against the sum of the
            // others, with the law of the heaviest other material; the
            // change goes to that material only.
            changes.assign(present.size(), Tensor<1, dim>());
            for (unsigned int x = 0; x < present.size(); ++x)
              {
                alpha.assign(1, present[x]);
                beta.clear();
                unsigned int heaviest = present[x == 0 ? 1 : 0];
                for (const unsigned int b : present)
                  if (b != present[x])
                    {
                      beta.push_back(b);
                      if (m[b][i] > m[heaviest][i])
                        heaviest = b;
                    }
                const auto node = node_pair(alpha, beta, i);
                const auto c =
                  Contact::correct(contact.law(present[x], heaviest), node);
                changes[x] = c.delta_momentum;
                if (stage == ContactStage::updated && c.in_contact &&
                    !in_contact)
                  record(i, node);
                in_contact = in_contact || c.in_contact;
                work += 0.5 * c.friction_work;
              }
            for (unsigned int x = 0; x < present.size(); ++x)
              add_momentum(present[x], i, changes[x]);
          }
        if (in_contact)
          ++contact_nodes;
      }

    if (stage == ContactStage::updated)
      {
        local_friction_work += work;
        local_contact_nodes = contact_nodes;
      }
    if (stage == ContactStage::updated)
      {
        contact_normal.update_ghost_values();
        contact_separation.update_ghost_values();
      }
    for (auto &field : material_fields)
      {
        GridVectorField &momenta = stage == ContactStage::updated ?
                                     field.updated_momentum :
                                     field.momentum;
        momenta.update_ghost_values();
        field.computed.fill(false);
      }
  }



  template <int dim>
  void
  Simulator<dim>::compute_material_field(const ParticleUpdate::GridField field)
  {
    using namespace ParticleUpdate;
    TimerOutput::Scope timer(computing_timer, "grid solve");
    const double       t_begin = momentum_time, t_end = time + time_step;
    for (auto &material : material_fields)
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
                                               mass_floor_value);
              velocity_conditions.correct_velocities(target, t_begin, nullptr);
              break;
            case updated_velocity:
            case lumped_updated_velocity: // v^α+ = p^α+ / m^α (Eq. 31)
              MassMatrix::apply_lumped_inverse(material.mass,
                                               material.updated_momentum,
                                               target,
                                               mass_floor_value);
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
                difference = material.updated_momentum;
                difference.add(-1., material.momentum);
                difference *= 1. / time_step;
                MassMatrix::apply_lumped_inverse(material.mass,
                                                 difference,
                                                 target,
                                                 mass_floor_value);
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
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
