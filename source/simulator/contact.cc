// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Multimaterial contact (seed 004 §2-3): per-material fields, the contact
// corrections at nodes shared by materials, the material fields the
// stress and particle updates read.

#include <fmpm/contact.h>
#include <fmpm/simulator.h>

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>

namespace fmpm
{
  template <int dim>
  void
  Simulator<dim>::setup_contact()
  {
    const Contact::Parameters &contact = parameters.contact;
    material_fields.clear();
    contact_geometry_valid = false;
    if (!contact.multimaterial || parameters.size.n_materials < 2)
      return;
    using Method = Contact::NormalMethod;
    // Grid normals (Eq. 13) for all but 'specified' and LR; extrapolated
    // positions (Eq. 11) for the separation tests of AG, CP and DF.
    contact_needs_gradients = contact.normals != Method::specified &&
                              contact.normals != Method::logistic_regression;
    contact_needs_positions = contact.normals == Method::average_gradient ||
                              contact.normals == Method::contact_position ||
                              contact.normals == Method::d_fit;
    contact_needs_cell_size = contact.normals != Method::specified &&
                              contact.normals != Method::velocity_only;
    contact_needs_node_positions = contact.normals == Method::d_fit;

    // The exact solve: CG settings of the single-material one.
    const auto exact_solve = mass_matrix->exact_solve();
    material_exact_solve   = exact_solve.has_value();
    if (material_exact_solve)
      {
        material_solve_tolerance      = exact_solve->tolerance;
        material_solve_max_iterations = exact_solve->max_iterations;
        material_weak_threshold       = exact_solve->weak_node_threshold;
        AssertThrow(parameters.size.n_materials <= 32,
                    ExcMessage("'Mass matrix/Model name = full' with contact "
                               "supports up to 32 materials; this scene has " +
                               std::to_string(parameters.size.n_materials) +
                               "."));
      }

    const unsigned int n_materials = parameters.size.n_materials;
    increment_law = Contact::create_law<dim>(Contact::Law{"perfect", {}});
    contact_laws.clear();
    contact_laws.resize(n_materials * n_materials);
    contact_needs_interface = false;
    for (unsigned int a = 0; a < n_materials; ++a)
      for (unsigned int b = a + 1; b < n_materials; ++b)
        {
          contact_laws[a * n_materials + b] =
            Contact::create_law<dim>(contact.law(a, b));
          contact_needs_interface =
            contact_needs_interface ||
            contact_laws[a * n_materials + b]->interface_state();
        }
    // (The contact area of interface laws is measured in the local cell
    // size.)
    contact_needs_cell_size =
      contact_needs_cell_size || contact_needs_interface;

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
        if (mass_matrix->order() > 1)
          {
            reinit(material.series_product);
            if (contact.net_incremental)
              reinit(material.series_increment);
          }
        if (material_exact_solve)
          {
            reinit(material.series_residual);
            reinit(material.series_direction);
            reinit(material.series_free);
            material.weak_coupling.reinit(partitioner);
          }
        if (contact_needs_gradients)
          reinit(material.volume_gradient);
        if (contact_needs_positions)
          reinit(material.position_moment);
        if (contact_needs_interface)
          {
            reinit(material.displacement_moment);
            material.volume.reinit(partitioner);
          }
        for (auto &field : material.fields)
          reinit(field);
      }

    // DF: d(x) of each material from the half-length of its points (the
    // first body made of it; 2 points per cell if none).
    if (contact.normals == Method::d_fit)
      {
        edge_distance.clear();
        for (unsigned int a = 0; a < parameters.size.n_materials; ++a)
          {
            unsigned int points_per_cell = 2;
            for (const auto &body : parameters.bodies)
              if (body.material == a)
                {
                  points_per_cell = body.points_per_cell;
                  break;
                }
            edge_distance.emplace_back(shape_function, 0.5 / points_per_cell);
          }
      }

    // The local cell size at a node: the smallest vertex distance of the
    // cells around it (separations are measured in cells, also on adapted
    // and unstructured meshes); DF also needs the node positions.
    if (contact_needs_cell_size)
      {
        node_cell_size.reinit(partitioner);
        const double large = std::numeric_limits<double>::max();
        for (auto &value : node_cell_size)
          value = large;
        node_cell_size.update_ghost_values();
        if (contact_needs_node_positions)
          reinit(node_position);
        std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const double h = cell->minimum_vertex_distance();
              cell->get_dof_indices(dofs);
              for (unsigned int v = 0; v < dofs.size(); ++v)
                {
                  const unsigned int i = partitioner->global_to_local(dofs[v]);
                  double            &value = node_cell_size.local_element(i);
                  value                    = std::min(value, h);
                  if (contact_needs_node_positions) // FE_Q(1): dof v at vertex
                                                    // v
                    for (unsigned int d = 0; d < dim; ++d)
                      node_position.block(d).local_element(i) =
                        cell->vertex(v)[d];
                }
            }
        node_cell_size.compress(VectorOperation::min);
        if (contact_needs_node_positions)
          for (unsigned int d = 0; d < dim; ++d)
            node_position.block(d).compress(VectorOperation::insert);
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
    const GridScalar                           &m = material_fields[alpha].mass;
    typename VelocityConditions<dim>::Operators operators;
    operators.lumped_mass = &m;
    operators.mass_floor  = mass_floor_value;
    operators.solve = [&m, this](const GridVectorField &p, GridVectorField &v) {
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
  Simulator<dim>::gather_point_clouds()
  {
    TimerOutput::Scope timer(computing_timer, "contact: point clouds");
    using Index                    = PropertyIndex<dim>;
    const auto        &partitioner = *lumped_mass.get_partitioner();
    const unsigned int n_owned     = partitioner.locally_owned_size();
    const unsigned int n_local     = n_owned + partitioner.n_ghost_indices();
    const unsigned int n_materials = material_fields.size();
    const double       floor       = mass_floor_value;

    // Nodes (owned and ghost) that see 2+ materials: the ghost masses are
    // current after the extrapolation.
    std::vector<char> shared(n_local, 0);
    for (unsigned int i = 0; i < n_local; ++i)
      {
        unsigned int count = 0;
        for (unsigned int a = 0; a < n_materials; ++a)
          count += material_fields[a].mass.local_element(i) > floor;
        shared[i] = count > 1;
      }
    // The owner of each ghost node (ghosts are numbered rank by rank).
    std::vector<unsigned int> ghost_owner;
    ghost_owner.reserve(partitioner.n_ghost_indices());
    for (const auto &[rank, count] : partitioner.ghost_targets())
      ghost_owner.insert(ghost_owner.end(), count, rank);

    std::vector<CloudPoint>                         owned_points;
    std::map<unsigned int, std::vector<CloudPoint>> sent;
    for (unsigned int k = 0; k < supports.n_points(); ++k)
      {
        bool       filled = false;
        CloudPoint point{};
        for (unsigned int j = supports.support_begin[k];
             j < supports.support_begin[k + 1];
             ++j)
          {
            const unsigned int i = supports.node[j];
            if (!shared[i] || !(supports.S[j] > 0))
              continue;
            if (!filled)
              {
                const PointRecord P = points.record(k);
                const Point<dim> &X = points.position[k];
                Tensor<2, dim>    F;
                for (unsigned int a = 0; a < dim; ++a)
                  for (unsigned int b = 0; b < dim; ++b)
                    F[a][b] = P[Index::deformation_gradient + 3 * a + b];
                const Tensor<2, dim> F_inverse = invert(F);
                point.material                 = supports.material[k];
                for (unsigned int a = 0; a < dim; ++a)
                  {
                    point.position[a]      = X[a];
                    point.initial_radii[a] = P[Index::initial_half_length + a];
                    for (unsigned int b = 0; b < dim; ++b)
                      point.F_inverse[a * dim + b] = F_inverse[a][b];
                  }
                filled = true;
              }
            point.node = partitioner.local_to_global(i);
            if (i < n_owned)
              owned_points.push_back(point);
            else
              sent[ghost_owner[i - n_owned]].push_back(point);
          }
      }
    if (Utilities::MPI::n_mpi_processes(mpi_communicator) > 1)
      for (const auto &[rank, points] :
           Utilities::MPI::some_to_some(mpi_communicator, sent))
        owned_points.insert(owned_points.end(), points.begin(), points.end());

    // Sort into the clouds of the owned nodes (counting sort).
    cloud_begin.assign(n_owned + 1, 0);
    for (const auto &point : owned_points)
      ++cloud_begin[partitioner.global_to_local(point.node) + 1];
    for (unsigned int i = 0; i < n_owned; ++i)
      cloud_begin[i + 1] += cloud_begin[i];
    cloud.resize(owned_points.size());
    std::vector<unsigned int> next(cloud_begin.begin(), cloud_begin.end() - 1);
    for (const auto &point : owned_points)
      cloud[next[partitioner.global_to_local(point.node)]++] = point;
  }



  template <int dim>
  template <class Visit, class NodeDone>
  void
  Simulator<dim>::for_each_contact_pair(Visit &&visit, NodeDone &&node_done)
  {
    using ThreeOrMore                = Contact::Parameters::ThreeOrMore;
    const unsigned int n_materials   = material_fields.size();
    const unsigned int n_owned       = lumped_mass.locally_owned_size();
    const double       floor         = mass_floor_value;
    const ThreeOrMore  three_or_more = parameters.contact.three_or_more;
    std::vector<const double *> m(n_materials);
    for (unsigned int a = 0; a < n_materials; ++a)
      m[a] = material_fields[a].mass.begin();
    std::vector<unsigned int> present, alpha(1), beta;
    unsigned int              slot = 0;
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        present.clear();
        for (unsigned int a = 0; a < n_materials; ++a)
          if (m[a][i] > floor)
            present.push_back(a);
        if (present.size() < 2)
          continue;
        const bool three_plus = present.size() > 2;
        const bool explicit_node =
          three_plus && three_or_more == ThreeOrMore::explicit_pairs;
        if (!three_plus || three_or_more != ThreeOrMore::lumped)
          // Each pair in turn (one pair at most 3+ nodes apart).
          for (unsigned int x = 0; x < present.size(); ++x)
            for (unsigned int y = x + 1; y < present.size(); ++y)
              {
                alpha.assign(1, present[x]);
                beta.assign(1, present[y]);
                visit(ContactSlot{
                  i, slot++, false, explicit_node, x, alpha, beta, present[y]});
              }
        if (three_plus && three_or_more != ThreeOrMore::pairwise)
          // 3+ materials, lumped (Eq. 50): each against the sum of the
          // others, with the law of the heaviest other material.
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
              visit(ContactSlot{
                i, slot++, true, explicit_node, x, alpha, beta, heaviest});
            }
        node_done(i, present);
      }
  }



  template <int dim>
  void
  Simulator<dim>::compute_contact_geometry()
  {
    const Contact::Parameters &contact     = parameters.contact;
    const unsigned int         n_materials = material_fields.size();
    using Method                           = Contact::NormalMethod;
    const Method method                    = contact.normals;
    if (method == Method::logistic_regression)
      gather_point_clouds();
    TimerOutput::Scope timer(computing_timer, "contact: normals");

    // δc in cells: the user's (CP) or the linear d(x) fit's (Eq. 17).
    const double critical_separation =
      method == Method::contact_position ? contact.critical_separation :
      shape_function == ShapeFunction::Type::cpdi ? 0.96 :
                                                    0.92;
    Tensor<1, dim> specified_normal;
    for (unsigned int d = 0; d < dim; ++d)
      specified_normal[d] = contact.specified_normal[d];
    if (specified_normal.norm() > 0)
      specified_normal /= specified_normal.norm();

    std::vector<const double *> m(n_materials);
    std::vector<const double *> g(contact_needs_gradients ? n_materials * dim :
                                                            0);
    std::vector<const double *> xm(contact_needs_positions ? n_materials * dim :
                                                             0);
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        m[a] = material_fields[a].mass.begin();
        for (unsigned int d = 0; d < dim; ++d)
          {
            if (contact_needs_gradients)
              g[a * dim + d] =
                material_fields[a].volume_gradient.block(d).begin();
            if (contact_needs_positions)
              xm[a * dim + d] =
                material_fields[a].position_moment.block(d).begin();
          }
      }
    auto sum_over = [&](const std::vector<const double *> &v,
                        const std::vector<unsigned int>   &materials,
                        const unsigned int                 i) {
      Tensor<1, dim> sum;
      for (const unsigned int a : materials)
        for (unsigned int d = 0; d < dim; ++d)
          sum[d] += v[a * dim + d][i];
      return sum;
    };
    auto mass_of = [&](const std::vector<unsigned int> &materials,
                       const unsigned int               i) {
      double sum = 0;
      for (const unsigned int a : materials)
        sum += m[a][i];
      return sum;
    };

    // LR scratch: the cloud's positions and classes.
    std::vector<Tensor<1, dim>> cloud_x;
    std::vector<double>         cloud_c;
    std::vector<unsigned int>   cloud_k;
    unsigned long long          fits = 0, iterations = 0;

    // The geometry of α against β (β may be the sum of several materials,
    // Eq. 50) at node i.
    auto geometry = [&](const std::vector<unsigned int> &alpha,
                        const std::vector<unsigned int> &beta,
                        const unsigned int               i) {
      Contact::NodeGeometry<dim> node;
      auto in = [](const std::vector<unsigned int> &set, const unsigned int a) {
        return std::find(set.begin(), set.end(), a) != set.end();
      };
      if (method == Method::specified)
        {
          node.normal =
            (alpha.front() < beta.front() ? 1. : -1.) * specified_normal;
          return node;
        }
      // (velocity only has no cell size and returns before using it)
      const double h =
        contact_needs_cell_size ? node_cell_size.local_element(i) : 0.;
      if (method == Method::logistic_regression)
        {
          // Eqs. 19-21: the plane between the two classes of the cloud;
          // Eqs. 22-25: d_LR from the points nearest to it, R_p of their
          // deformed ellipsoids.
          cloud_x.clear();
          cloud_c.clear();
          cloud_k.clear();
          for (unsigned int k = cloud_begin[i]; k < cloud_begin[i + 1]; ++k)
            {
              const unsigned int a        = cloud[k].material;
              const bool         is_alpha = in(alpha, a);
              if (!is_alpha && !in(beta, a))
                continue;
              Tensor<1, dim> x;
              for (unsigned int d = 0; d < dim; ++d)
                x[d] = cloud[k].position[d];
              cloud_x.push_back(x);
              cloud_c.push_back(is_alpha ? -1. : 1.);
              cloud_k.push_back(k);
            }
          const auto fit = Contact::logistic_regression_normal<dim>(
            cloud_x.data(), cloud_c.data(), cloud_x.size(), h);
          ++fits;
          iterations += fit.iterations;
          if (!fit.valid)
            {
              node.touching = false;
              return node;
            }
          node.normal       = fit.normal;
          double alpha_edge = -std::numeric_limits<double>::max();
          double beta_edge  = std::numeric_limits<double>::max();
          for (unsigned int q = 0; q < cloud_k.size(); ++q)
            {
              const CloudPoint &point = cloud[cloud_k[q]];
              Tensor<2, dim>    F_inverse;
              Tensor<1, dim>    radii;
              for (unsigned int a = 0; a < dim; ++a)
                {
                  radii[a] = point.initial_radii[a];
                  for (unsigned int b = 0; b < dim; ++b)
                    F_inverse[a][b] = point.F_inverse[a * dim + b];
                }
              const double R =
                Contact::deformed_radius(F_inverse, radii, node.normal);
              const double s = cloud_x[q] * node.normal;
              if (cloud_c[q] < 0)
                alpha_edge = std::max(alpha_edge, s + R); // Eq. 22
              else
                beta_edge = std::min(beta_edge, s - R); // Eq. 23
            }
          const double d_LR = beta_edge - alpha_edge; // Eq. 24
          node.separation   = d_LR / h;
          node.touching     = d_LR < 0;
          return node;
        }
      // n̂ = (g^α − g^β)/|g^α − g^β| (Eq. 13)
      const Tensor<1, dim> difference =
        sum_over(g, alpha, i) - sum_over(g, beta, i);
      const double norm = difference.norm();
      if (!(norm > 0))
        {
          node.touching = false;
          return node;
        }
      node.normal = difference / norm;
      if (!contact_needs_positions)
        return node;
      const Tensor<1, dim> x_alpha = sum_over(xm, alpha, i) / mass_of(alpha, i);
      const Tensor<1, dim> x_beta  = sum_over(xm, beta, i) / mass_of(beta, i);
      if (method == Method::d_fit)
        {
          // Eq. 15: d((x^β − x_i)·n̂) − d((x^α − x_i)·n̂) < 0, in cells.
          Tensor<1, dim> x_i;
          for (unsigned int d = 0; d < dim; ++d)
            x_i[d] = node_position.block(d).local_element(i);
          const double gap =
            edge_distance[beta.front()].beta((x_beta - x_i) * node.normal / h) -
            edge_distance[alpha.front()].alpha((x_alpha - x_i) * node.normal /
                                               h);
          node.separation = gap;
          node.touching   = gap < 0;
          return node;
        }
      // (x^β − x^α)·n̂ < δc h (Eqs. 16-17)
      node.separation = (x_beta - x_alpha) * node.normal / h;
      node.touching   = node.separation < critical_separation;
      return node;
    };

    contact_geometry.clear();
    for_each_contact_pair(
      [&](const ContactSlot &s) {
        contact_geometry.push_back(geometry(s.alpha, s.beta, s.node));
      },
      [](const unsigned int, const std::vector<unsigned int> &) {});
    logistic_fits += fits;
    logistic_iterations += iterations;
    contact_state.assign(contact_geometry.size(), 0);
    if (contact_needs_interface)
      slot_interface_energy.assign(contact_geometry.size(), 0.);
    contact_geometry_valid = true;
  }



  template <int dim>
  void
  Simulator<dim>::apply_contact(const ContactStage stage)
  {
    if (!contact_geometry_valid)
      compute_contact_geometry();
    TimerOutput::Scope         timer(computing_timer, "contact");
    const Contact::Parameters &contact     = parameters.contact;
    const unsigned int         n_materials = material_fields.size();

    // Raw views: m^α, the momenta this stage corrects, Δv^α.
    std::vector<const double *> m(n_materials);
    std::vector<double *>       p(n_materials * dim);
    std::vector<double *>       dv(n_materials * dim);
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        MaterialField &field = material_fields[a];
        m[a]                 = field.mass.begin();
        GridVectorField &momenta =
          stage == ContactStage::updated   ? field.updated_momentum :
          stage == ContactStage::increment ? field.series_increment :
                                             field.momentum;
        for (unsigned int d = 0; d < dim; ++d)
          {
            p[a * dim + d]  = momenta.block(d).begin();
            dv[a * dim + d] = field.delta_velocity.block(d).begin();
          }
        // Δv^α of the correction of the extrapolated momenta (the first,
        // or the third before USL+/USAVG+ stresses).
        if (stage == ContactStage::extrapolated ||
            stage == ContactStage::re_extrapolated)
          field.delta_velocity = 0;
      }

    const bool measures_gap =
      contact.normals == Contact::NormalMethod::logistic_regression ||
      contact.normals == Contact::NormalMethod::d_fit;
    // The masses and momenta of α against β (β may be the sum of several
    // materials, Eq. 50), with the geometry found for them.
    auto node_pair = [&](const std::vector<unsigned int>  &alpha,
                         const std::vector<unsigned int>  &beta,
                         const unsigned int                i,
                         const Contact::NodeGeometry<dim> &geometry) {
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
      node.normal     = geometry.normal;
      node.touching   = geometry.touching;
      node.separation = geometry.separation;
      node.stage      = stage == ContactStage::updated ?
                          Contact::NodePair<dim>::Stage::updated :
                        stage == ContactStage::increment ?
                          Contact::NodePair<dim>::Stage::increment :
                          Contact::NodePair<dim>::Stage::extrapolated;
      node.time_step  = time_step;
      if (contact_needs_interface)
        {
          // u^β − u^α and A_c = sqrt(2 min(V^α, V^β)(V^α + V^β))/h, from
          // the sums of V and Σ S M u over each side's materials.
          auto sum_side = [&](const std::vector<unsigned int> &materials,
                              double                          &volume,
                              Tensor<1, dim>                  &moment) {
            for (const unsigned int a : materials)
              {
                volume += material_fields[a].volume.local_element(i);
                for (unsigned int d = 0; d < dim; ++d)
                  moment[d] += material_fields[a]
                                 .displacement_moment.block(d)
                                 .local_element(i);
              }
          };
          double         volume_alpha = 0, volume_beta = 0;
          Tensor<1, dim> moment_alpha, moment_beta;
          sum_side(alpha, volume_alpha, moment_alpha);
          sum_side(beta, volume_beta, moment_beta);
          if (node.mass_alpha > 0 && node.mass_beta > 0)
            node.displacement_jump =
              moment_beta / node.mass_beta - moment_alpha / node.mass_alpha;
          node.contact_area =
            std::sqrt(2 * std::min(volume_alpha, volume_beta) *
                      (volume_alpha + volume_beta)) /
            node_cell_size.local_element(i);
        }
      if (measures_gap && !node.touching && node.mass_alpha > 0 &&
          node.mass_beta > 0)
        {
          if (node.separation < contact.touching_tolerance)
            node.touching = true;
          else if (contact.gap_closing)
            {
              // d + (v^β − v^α)·n̂ Δt < 0: the gap closes within the step;
              // the laws leave the approach m_red d/Δt.
              const double m_red = node.mass_alpha * node.mass_beta /
                                   (node.mass_alpha + node.mass_beta);
              node.touching         = true;
              node.allowed_approach = m_red * node.separation *
                                      node_cell_size.local_element(i) /
                                      time_step;
            }
        }
      return node;
    };
    auto law = [&](const unsigned int a,
                   const unsigned int b) -> const Contact::LawInterface<dim> & {
      return *contact_laws[std::min(a, b) * n_materials + std::max(a, b)];
    };
    // 'XPIC contact term = series' keeps Δv^α = 0: the corrected momenta
    // then go through the whole series.
    const bool records_first_correction =
      (stage == ContactStage::extrapolated ||
       stage == ContactStage::re_extrapolated) &&
      contact.xpic_contact_term != Contact::XpicContactTerm::series;
    auto add_momentum = [&](const unsigned int    a,
                            const unsigned int    i,
                            const Tensor<1, dim> &dp) {
      for (unsigned int d = 0; d < dim; ++d)
        {
          p[a * dim + d][i] += dp[d];
          if (records_first_correction)
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
    auto record = [&](const unsigned int            i,
                      const Contact::NodePair<dim> &node) {
      for (unsigned int d = 0; d < dim; ++d)
        contact_normal.block(d).local_element(i) = node.normal[d];
      contact_separation.local_element(i) = node.separation;
    };

    // Net incremental contact: at the pairs in contact at the last
    // correction the increments of the series are made the same in both
    // materials (their centre of mass); slip and separation come from the
    // corrections of the momenta.
    const bool                  increments = stage == ContactStage::increment;
    std::vector<Tensor<1, dim>> changes(n_materials);
    unsigned int                n_slots       = 0;
    bool                        in_contact    = false;
    double                      work          = 0;
    unsigned long long          contact_nodes = 0;
    // One correction of α (one material) against β at node i, recorded.
    auto correct = [&](const unsigned int               a,
                       const std::vector<unsigned int> &alpha,
                       const std::vector<unsigned int> &beta,
                       const unsigned int               partner,
                       const unsigned int               i,
                       const unsigned int               slot) {
      const auto node = node_pair(alpha, beta, i, contact_geometry[slot]);
      // Increments: the same in both materials ('perfect'), or the
      // interface law's perfect directions.
      const Contact::LawInterface<dim> &pair_law = law(a, partner);
      const auto                        c =
        (increments && !pair_law.interface_state() ? *increment_law : pair_law)
          .correct(node);
      if (stage == ContactStage::updated && c.in_contact && !in_contact)
        record(i, node);
      if (stage == ContactStage::updated && contact_needs_interface)
        // (a lumped slot, α against the others, counts each pair twice)
        slot_interface_energy[slot] =
          (beta.size() > 1 ? 0.5 : 1.) * c.interface_energy;
      in_contact = in_contact || c.in_contact;
      return c;
    };

    // 'Three or more materials = explicit': the slots of a 3+ node, handled
    // when the node is done.
    struct PendingSlot
    {
      unsigned int              slot;
      bool                      lumped;
      unsigned int              x, a, partner;
      std::vector<unsigned int> beta;
    };
    std::vector<PendingSlot>  pending;
    std::vector<unsigned int> one_alpha(1), one_beta(1);
    // The pairs in contact (each pair's law on the momenta as they are;
    // for the series increments, the pairs in contact at the last
    // correction): none, one or two are corrected together, by turns
    // until neither pair's law changes the momenta (Eq. 49: both laws hold
    // and momentum is conserved); three or more lumped (Eq. 50).
    auto correct_explicit_node = [&](const unsigned int i) {
      std::vector<const PendingSlot *> pairs;
      bool                             lumped_at_last = false;
      for (const PendingSlot &pending_slot : pending)
        {
          if (pending_slot.lumped)
            {
              lumped_at_last = lumped_at_last ||
                               (increments && contact_state[pending_slot.slot]);
              continue;
            }
          bool touching = increments && contact_state[pending_slot.slot];
          if (!increments)
            {
              one_alpha[0] = pending_slot.a;
              one_beta[0]  = pending_slot.partner;
              touching =
                law(pending_slot.a, pending_slot.partner)
                  .correct(node_pair(one_alpha,
                                     one_beta,
                                     i,
                                     contact_geometry[pending_slot.slot]))
                  .in_contact;
            }
          if (touching)
            pairs.push_back(&pending_slot);
        }
      if (!increments)
        for (const PendingSlot &pending_slot : pending)
          contact_state[pending_slot.slot] = 0;

      if (pairs.size() >= 3 || lumped_at_last)
        {
          for (const PendingSlot &pending_slot : pending)
            if (pending_slot.lumped)
              {
                one_alpha[0] = pending_slot.a;
                const auto c = correct(pending_slot.a,
                                       one_alpha,
                                       pending_slot.beta,
                                       pending_slot.partner,
                                       i,
                                       pending_slot.slot);
                if (!increments)
                  contact_state[pending_slot.slot] = c.in_contact;
                changes[pending_slot.x] = c.delta_momentum;
                work += 0.5 * c.friction_work;
              }
          for (const PendingSlot &pending_slot : pending)
            if (pending_slot.lumped)
              add_momentum(pending_slot.a, i, changes[pending_slot.x]);
          return;
        }
      constexpr unsigned int max_turns = 100;
      for (unsigned int turn = 0; turn < max_turns && !pairs.empty(); ++turn)
        {
          double change = 0, scale = 0;
          for (const PendingSlot *pair : pairs)
            {
              one_alpha[0] = pair->a;
              one_beta[0]  = pair->partner;
              const auto c = correct(
                pair->a, one_alpha, one_beta, pair->partner, i, pair->slot);
              if (c.in_contact)
                {
                  if (!increments)
                    contact_state[pair->slot] = 1;
                  add_momentum(pair->a, i, c.delta_momentum);
                  add_momentum(pair->partner, i, -c.delta_momentum);
                }
              work += c.friction_work;
              change += c.delta_momentum.norm();
              for (unsigned int d = 0; d < dim; ++d)
                scale += std::abs(p[pair->a * dim + d][i]) +
                         std::abs(p[pair->partner * dim + d][i]);
            }
          if (pairs.size() == 1 || change <= 1e-14 * scale)
            break;
        }
    };

    for_each_contact_pair(
      [&](const ContactSlot &s) {
        ++n_slots;
        if (s.explicit_node)
          {
            pending.push_back(
              {s.slot, s.lumped, s.x, s.alpha.front(), s.partner, s.beta});
            return;
          }
        if (s.lumped)
          changes[s.x] = Tensor<1, dim>();
        if (increments && !contact_state[s.slot])
          return;
        const unsigned int a = s.alpha.front();
        const auto c = correct(a, s.alpha, s.beta, s.partner, s.node, s.slot);
        if (!increments)
          contact_state[s.slot] = c.in_contact;
        if (s.lumped) // the change goes to α only, after all of the node's
          changes[s.x] = c.delta_momentum;
        else // α gets Δp^α, β gets −Δp^α (Eq. 7)
          {
            add_momentum(a, s.node, c.delta_momentum);
            add_momentum(s.partner, s.node, -c.delta_momentum);
          }
        work += (s.lumped ? 0.5 : 1.) * c.friction_work;
      },
      [&](const unsigned int i, const std::vector<unsigned int> &present) {
        if (!pending.empty())
          {
            correct_explicit_node(i);
            pending.clear();
          }
        else if (present.size() > 2 &&
                 contact.three_or_more ==
                   Contact::Parameters::ThreeOrMore::lumped)
          for (unsigned int x = 0; x < present.size(); ++x)
            add_momentum(present[x], i, changes[x]);
        if (in_contact)
          ++contact_nodes;
        in_contact = false;
      });

    AssertDimension(n_slots, contact_geometry.size());
    if (stage == ContactStage::updated && contact_needs_interface)
      local_interface_energy = std::accumulate(slot_interface_energy.begin(),
                                               slot_interface_energy.end(),
                                               0.);
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
    if (stage == ContactStage::increment) // owned entries only, fields kept
      return;
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
              if (field == velocity &&
                  parameters.contact.xpic_contact_term ==
                    Contact::XpicContactTerm::uncorrected &&
                  mass_matrix->order() > 1)
                {
                  // v^α0 = v^α − Δv^α: the series of Eq. 37 without the
                  // contact term (Eq. 48).
                  target.add(-1., material.delta_velocity);
                }
              velocity_conditions.correct_velocities(target, t_begin, nullptr);
              break;
            case updated_velocity:
            case lumped_updated_velocity: // v^α+ = p^α+ / m^α (Eq. 31)
              MassMatrix::apply_lumped_inverse(material.mass,
                                               material.updated_momentum,
                                               target,
                                               mass_floor_value);
              if (field == updated_velocity &&
                  parameters.contact.xpic_contact_term ==
                    Contact::XpicContactTerm::uncorrected &&
                  mass_matrix->order() > 1)
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
    const unsigned int k = mass_matrix->order();
    if ((field != velocity && field != updated_velocity) || k < 2)
      return;
    const bool                     updated = field == updated_velocity;
    const double                   t_field = updated ? t_end : t_begin;
    std::vector<GridVectorField *> z, product;
    for (auto &material : material_fields)
      {
        z.push_back(&material.fields[field]);
        product.push_back(&material.series_product);
      }
    const unsigned int n_owned         = lumped_mass.locally_owned_size();
    const double       floor           = mass_floor_value;
    const bool         net_incremental = parameters.contact.net_incremental;
    for (unsigned int j = 1; j < k; ++j)
      {
        apply_material_full_mass(z, product);
        for (auto &material : material_fields)
          {
            GridVectorField       &target = material.fields[field];
            const GridVectorField &p =
              updated ? material.updated_momentum : material.momentum;
            // Net incremental contact: keep z_j, then the increment after
            // the velocity conditions becomes the momenta m^α δz^α that
            // the contact laws correct (below).
            if (net_incremental)
              material.series_increment = target;
            for (unsigned int d = 0; d < dim; ++d)
              {
                double *const       zd = target.block(d).begin();
                const double *const pd = p.block(d).begin();
                const double *const qd =
                  material.series_product.block(d).begin();
                const double *const dv =
                  material.delta_velocity.block(d).begin();
                const double *const m = material.mass.begin();
                for (unsigned int i = 0; i < n_owned; ++i)
                  if (m[i] > floor)
                    zd[i] += (pd[i] - m[i] * dv[i] - qd[i]) / m[i];
              }
            velocity_conditions.correct_velocities(target, t_field, nullptr);
            if (net_incremental)
              for (unsigned int d = 0; d < dim; ++d)
                {
                  double *const dp = material.series_increment.block(d).begin();
                  const double *const zd = target.block(d).begin();
                  const double *const m  = material.mass.begin();
                  for (unsigned int i = 0; i < n_owned;
                       ++i) // m^α (z_{j+1} − z_j)
                    dp[i] = m[i] * (zd[i] - dp[i]);
                }
          }
        if (net_incremental)
          {
            // The contact laws on the increments (Nairn 2026's net
            // incremental contact): z_{j+1} = z_j + (m^α)⁻¹(m^α δz^α + Δ^α).
            for (auto &material : material_fields)
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const double *const dp =
                    material.series_increment.block(d).begin();
                  double *const zd = material.fields[field].block(d).begin();
                  const double *const m = material.mass.begin();
                  for (unsigned int i = 0; i < n_owned; ++i)
                    if (m[i] > floor)
                      zd[i] -= dp[i] / m[i]; // back to z_j
                }
            apply_contact(ContactStage::increment);
            for (auto &material : material_fields)
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
        for (auto &material : material_fields)
          {
            GridVectorField &target = material.fields[field];
            if (has_hanging_nodes)
              for (unsigned int d = 0; d < dim; ++d)
                constraints.distribute(target.block(d));
            target.update_ghost_values();
          }
      }
  }



  template <int dim>
  void
  Simulator<dim>::solve_material_full_mass(
    const ParticleUpdate::GridField field)
  {
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
    using Index                    = PropertyIndex<dim>;
    const bool         updated     = field == updated_velocity;
    const double       t_field     = updated ? time + time_step : momentum_time;
    const unsigned int n_materials = material_fields.size();
    const unsigned int n_owned     = lumped_mass.locally_owned_size();
    const double       floor       = mass_floor_value;
    const double       tau         = material_weak_threshold;
    const bool         has_known   = velocity_conditions.uses_known_values();
    if (has_known)
      velocity_conditions.known_values(t_field,
                                       known_velocity_mask,
                                       known_velocity_value);

    // m̃^α_ii = Σ_{p∈α} M_p S_ip² (into series_free's first block).
    const double *const         mass_column = points.column(Index::mass);
    std::vector<double *>       diagonal(n_materials);
    std::vector<const double *> m(n_materials);
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        material_fields[a].series_free = 0;
        diagonal[a] = material_fields[a].series_free.block(0).begin();
        m[a]        = material_fields[a].mass.begin();
      }
    {
      const unsigned int *node = supports.node.data();
      const double       *S    = supports.S.data();
      for (unsigned int k = 0; k < supports.n_points(); ++k)
        {
          double *const d = diagonal[supports.material[k]];
          const double  M = mass_column[k];
          for (unsigned int j = supports.support_begin[k];
               j < supports.support_begin[k + 1];
               ++j)
            d[node[j]] += M * S[j] * S[j];
        }
      for (auto &material : material_fields)
        material.series_free.block(0).compress(VectorOperation::add);
    }

    // The materials in contact at each node (bit a: material a), from the
    // last correction's contact states.
    contact_groups.clear();
    for_each_contact_pair(
      [&](const ContactSlot &s) {
        if (!contact_state[s.slot])
          return;
        if (contact_groups.empty() || contact_groups.back().first != s.node)
          contact_groups.emplace_back(s.node, 0u);
        for (const unsigned int a : s.alpha)
          contact_groups.back().second |= 1u << a;
        for (const unsigned int b : s.beta)
          contact_groups.back().second |= 1u << b;
      },
      [](const unsigned int, const std::vector<unsigned int> &) {});

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
    for (auto &material : material_fields)
      {
        z.push_back(&material.fields[field]);
        direction.push_back(&material.series_direction);
        product.push_back(&material.series_product);
      }
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        GridVectorField &indicator = material_fields[a].series_direction;
        indicator                  = 0;
        for (unsigned int i = 0; i < n_owned; ++i)
          if (is_weak(a, i))
            for (unsigned int c = 0; c < dim; ++c)
              indicator.block(c).local_element(i) = 1;
        indicator.update_ghost_values();
      }
    apply_material_full_mass(direction, product);
    for (auto &material : material_fields)
      material.weak_coupling = material.series_product.block(0);

    // series_free: the inverse diagonal of Zᵀ diag(m̃ + c) Z on free
    // components, 0 on fixed ones.
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        const double *const coupling = material_fields[a].weak_coupling.begin();
        for (unsigned int i = 0; i < n_owned; ++i)
          if (group_of[i] & (1u << a))
            group_diagonal[i] += coupling[i];
      }
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        GridVectorField    &free     = material_fields[a].series_free;
        const double *const coupling = material_fields[a].weak_coupling.begin();
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
          for (auto &material : material_fields)
            {
              const double *const r = material.series_residual.block(c).begin();
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
                  sum +=
                    material_fields[a].series_residual.block(c).local_element(
                      i);
              for (unsigned int a = 0; a < n_materials; ++a)
                if (group & (1u << a))
                  material_fields[a].series_increment.block(c).local_element(
                    i) =
                    material_fields[a].series_free.block(c).local_element(i) *
                    sum;
              local[1] += sum * sum;
            }
          for (unsigned int a = 0; a < n_materials; ++a)
            {
              const MaterialField &material = material_fields[a];
              const double *const r = material.series_residual.block(c).begin();
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
        GridVectorField &coupled_start = material_fields[a].series_direction;
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
        MaterialField         &material = material_fields[a];
        const GridVectorField &p =
          updated ? material.updated_momentum : material.momentum;
        for (unsigned int c = 0; c < dim; ++c)
          {
            const double *const pd   = p.block(c).begin();
            const double *const dv   = material.delta_velocity.block(c).begin();
            const double *const mz   = material.series_product.block(c).begin();
            const double *const free = material.series_free.block(c).begin();
            const double *const ma   = material.mass.begin();
            const double *const cw   = material.weak_coupling.begin();
            const double *const z1   = material.fields[field].block(c).begin();
            double *const       r = material.series_residual.block(c).begin();
            for (unsigned int i = 0; i < n_owned; ++i)
              {
                const double q = pd[i] - ma[i] * dv[i];
                r[i]           = free[i] != 0 ? q - mz[i] - cw[i] * z1[i] : 0.;
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
    for (auto &material : material_fields)
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
        for (auto &material : material_fields)
          for (unsigned int c = 0; c < dim; ++c)
            {
              const double *const dd =
                material.series_direction.block(c).begin();
              const double *const cw = material.weak_coupling.begin();
              double *const       w  = material.series_product.block(c).begin();
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
        for (auto &material : material_fields)
          for (unsigned int c = 0; c < dim; ++c)
            {
              const double *const dd =
                material.series_direction.block(c).begin();
              const double *const w = material.series_product.block(c).begin();
              const double *const free = material.series_free.block(c).begin();
              double *const       x = material.fields[field].block(c).begin();
              double *const       r = material.series_residual.block(c).begin();
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
        for (auto &material : material_fields)
          {
            material.series_direction.sadd(beta, 1., material.series_increment);
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
            const MaterialField   &material = material_fields[a];
            const GridVectorField &p =
              updated ? material.updated_momentum : material.momentum;
            const double *const pd   = p.block(c).begin();
            const double *const dv   = material.delta_velocity.block(c).begin();
            const double *const zc   = material.fields[field].block(c).begin();
            const double *const free = material.series_free.block(c).begin();
            for (unsigned int i = 0; i < n_owned; ++i)
              {
                local[0] += pd[i] - m[a][i] * dv[i] - m[a][i] * zc[i];
                if (free[i] != 0)
                  local[1] += m[a][i];
                if (has_known && known_velocity_mask[c].local_element(i) != 0 &&
                    m[a][i] > floor)
                  local[2] = 1;
              }
          }
        Utilities::MPI::sum(local, comm, global);
        if (global[2] != 0 || global[1] == 0)
          continue;
        const double shift = global[0] / global[1];
        for (auto &material : material_fields)
          {
            const double *const free = material.series_free.block(c).begin();
            double *const       zc   = material.fields[field].block(c).begin();
            for (unsigned int i = 0; i < n_owned; ++i)
              if (free[i] != 0)
                zc[i] += shift;
          }
      }
    ++material_solves;
    material_solve_iterations += iteration;
    material_solve_failures += converged ? 0 : 1;

    for (auto &material : material_fields)
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
  Simulator<dim>::apply_material_full_mass(
    const std::vector<GridVectorField *> &in,
    const std::vector<GridVectorField *> &out)
  {
    using Index                             = PropertyIndex<dim>;
    const unsigned int          n_materials = in.size();
    std::vector<const double *> x(n_materials * dim);
    std::vector<double *>       y(n_materials * dim);
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        *out[a] = 0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            x[a * dim + d] = in[a]->block(d).begin();
            y[a * dim + d] = out[a]->block(d).begin();
          }
      }
    const double *const mass_column = points.column(Index::mass);
    const unsigned int *node        = supports.node.data();
    const double       *S           = supports.S.data();
    for (unsigned int k = 0; k < supports.n_points(); ++k)
      {
        const unsigned int   a      = supports.material[k];
        const unsigned int   begin  = supports.support_begin[k];
        const unsigned int   end    = supports.support_begin[k + 1];
        const double         M      = mass_column[k];
        const double *const *xa     = &x[a * dim];
        double *const       *ya     = &y[a * dim];
        double               s[dim] = {};
        for (unsigned int j = begin; j < end; ++j) // (S z)(x_p)
          for (unsigned int d = 0; d < dim; ++d)
            s[d] += S[j] * xa[d][node[j]];
        for (unsigned int j = begin; j < end; ++j)
          for (unsigned int d = 0; d < dim; ++d)
            ya[d][node[j]] += M * S[j] * s[d];
      }
    for (auto *field : out)
      field->compress(VectorOperation::add);
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
