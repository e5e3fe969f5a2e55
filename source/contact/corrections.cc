// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The contact corrections (seed 004 §2-3): the pairs at each node, their
// geometry from the normal method, the laws applied at each stage.

#include <fmpm/contact/manager.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/material_points.h>
#include <fmpm/neighbour_exchange.h>
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
    Manager<dim>::gather_point_clouds()
    {
      const GridScalar          &lumped_mass = this->get_lumped_mass();
      const SupportCache<dim>   &supports    = this->get_support_cache();
      const MaterialPoints<dim> &points      = this->get_material_points();
      const double               mass_floor  = this->get_mass_floor();
      const MPI_Comm     mpi_communicator    = this->get_mpi_communicator();
      TimerOutput::Scope timer(this->get_computing_timer(),
                               "contact: point clouds");
      using Index                    = PropertyIndex<dim>;
      const auto        &partitioner = *lumped_mass.get_partitioner();
      const unsigned int n_owned     = partitioner.locally_owned_size();
      const unsigned int n_local     = n_owned + partitioner.n_ghost_indices();
      const unsigned int n_materials = fields.size();
      const double       floor       = mass_floor;

      // Nodes (owned and ghost) that see 2+ materials: the ghost masses are
      // current after the extrapolation.
      if (!multimaterial_nodes_valid)
        find_multimaterial_nodes();
      std::vector<char> shared(n_local, 0);
      for (const unsigned int i : multimaterial_nodes)
        shared[i] = 1;
      for (unsigned int i = n_owned; i < n_local; ++i)
        {
          unsigned int count = 0;
          for (unsigned int a = 0; a < n_materials; ++a)
            count += fields[a].mass.local_element(i) > floor;
          shared[i] = count > 1;
        }
      // The owner of each ghost node (ghosts are numbered rank by rank).
      std::vector<unsigned int> ghost_owner;
      ghost_owner.reserve(partitioner.n_ghost_indices());
      for (const auto &[rank, count] : partitioner.ghost_targets())
        ghost_owner.insert(ghost_owner.end(), count, rank);

      std::vector<CloudPoint<dim>>                         owned_points;
      std::map<unsigned int, std::vector<CloudPoint<dim>>> sent;
      const GridTransfer<dim> &transfer = this->get_grid_transfer();
      const SupportReader<dim> support_of(supports,
                                          transfer,
                                          points.cell.data());
      for (unsigned int c = 0; c < points.n_cells(); ++c)
        {
          // Computed supports are the cell's nodes: a cell without a
          // shared node has no point in a cloud.
          if (supports.implicit_classic)
            {
              bool any_shared = false;
              for (const unsigned int i :
                   transfer.cell_data(points.cell_index[c]).local_index)
                any_shared = any_shared || shared[i];
              if (!any_shared)
                continue;
            }
          for (unsigned int k = points.cell_point_begin[c];
               k < points.cell_point_begin[c + 1];
               ++k)
            support_of.visit(
              k,
              false,
              [&](const unsigned int *const node,
                  const double *const       S,
                  const Tensor<1, dim> *,
                  const auto n_entries) {
                bool            filled = false;
                CloudPoint<dim> point{};
                for (unsigned int j = 0; j < n_entries; ++j)
                  {
                    const unsigned int i = node[j];
                    if (!shared[i] || !(S[j] > 0))
                      continue;
                    if (!filled)
                      {
                        const PointRecord P = points.record(k);
                        const Point<dim> &X = points.position[k];
                        Tensor<2, dim>    F;
                        for (unsigned int a = 0; a < dim; ++a)
                          for (unsigned int b = 0; b < dim; ++b)
                            F[a][b] =
                              P[Index::deformation_gradient + 3 * a + b];
                        const Tensor<2, dim> F_inverse = invert(F);
                        point.id                       = points.id[k];
                        point.material                 = supports.material[k];
                        for (unsigned int a = 0; a < dim; ++a)
                          {
                            point.position[a] = X[a];
                            point.initial_radii[a] =
                              P[Index::initial_half_length + a];
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
              });
        }
      // Each rank sends to the owners of its ghost nodes and receives from
      // the ranks that have its nodes as ghosts (the partitioner's import
      // targets): one message each way, possibly empty, no collective.
      std::vector<unsigned int> send_to, receive_from;
      for (const auto &[rank, count] : partitioner.ghost_targets())
        send_to.push_back(rank);
      for (const auto &[rank, count] : partitioner.import_targets())
        receive_from.push_back(rank);
      for (const auto &[rank, points] :
           neighbour_exchange(mpi_communicator,
                              send_to,
                              receive_from,
                              sent,
                              MPITags::contact_point_clouds))
        owned_points.insert(owned_points.end(), points.begin(), points.end());

      // Sort into the clouds of the owned nodes (counting sort).
      cloud_begin.assign(n_owned + 1, 0);
      for (const auto &point : owned_points)
        ++cloud_begin[partitioner.global_to_local(point.node) + 1];
      for (unsigned int i = 0; i < n_owned; ++i)
        cloud_begin[i + 1] += cloud_begin[i];
      cloud.resize(owned_points.size());
      std::vector<unsigned int> next(cloud_begin.begin(),
                                     cloud_begin.end() - 1);
      for (const auto &point : owned_points)
        cloud[next[partitioner.global_to_local(point.node)]++] = point;
      // The points of other ranks came after the rank's own: the clouds in
      // id order, the same on every number of ranks.
      for (unsigned int i = 0; i < n_owned; ++i)
        std::sort(cloud.begin() + cloud_begin[i],
                  cloud.begin() + cloud_begin[i + 1],
                  [](const CloudPoint<dim> &a, const CloudPoint<dim> &b) {
                    return a.id < b.id;
                  });
    }



    template <int dim>
    void
    Manager<dim>::find_multimaterial_nodes()
    {
      const unsigned int n_owned = this->get_lumped_mass().locally_owned_size();
      const unsigned int n_materials = fields.size();
      const double       floor       = this->get_mass_floor();
      std::vector<const double *> m(n_materials);
      for (unsigned int a = 0; a < n_materials; ++a)
        m[a] = fields[a].mass.begin();
      multimaterial_nodes.clear();
      multimaterial_begin.assign(1, 0);
      multimaterial_materials.clear();
      material_nodes.resize(n_materials);
      for (auto &nodes : material_nodes)
        nodes.clear();
      for (unsigned int i = 0; i < n_owned; ++i)
        {
          unsigned int count = 0;
          for (unsigned int a = 0; a < n_materials; ++a)
            if (m[a][i] > floor)
              {
                material_nodes[a].push_back(i);
                ++count;
              }
          if (count < 2)
            continue;
          multimaterial_nodes.push_back(i);
          for (unsigned int a = 0; a < n_materials; ++a)
            if (m[a][i] > floor)
              multimaterial_materials.push_back(a);
          multimaterial_begin.push_back(multimaterial_materials.size());
        }
      multimaterial_nodes_valid = true;
    }



    template <int dim>
    template <class Visit, class NodeDone>
    void
    Manager<dim>::for_each_pair(Visit &&visit, NodeDone &&node_done)
    {
      const ::fmpm::Parameters &parameters = this->get_parameters();
      using ThreeOrMore                    = Contact::Parameters::ThreeOrMore;
      const ThreeOrMore three_or_more      = parameters.contact.three_or_more;
      if (!multimaterial_nodes_valid)
        find_multimaterial_nodes();
      std::vector<const double *> m(fields.size());
      for (unsigned int a = 0; a < fields.size(); ++a)
        m[a] = fields[a].mass.begin();
      std::vector<unsigned int> present, alpha(1), beta;
      unsigned int              slot = 0;
      for (unsigned int n = 0; n < multimaterial_nodes.size(); ++n)
        {
          const unsigned int i = multimaterial_nodes[n];
          present.assign(multimaterial_materials.begin() +
                           multimaterial_begin[n],
                         multimaterial_materials.begin() +
                           multimaterial_begin[n + 1]);
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
                  visit(Slot{i,
                             slot++,
                             false,
                             explicit_node,
                             x,
                             alpha,
                             beta,
                             present[y]});
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
                visit(Slot{
                  i, slot++, true, explicit_node, x, alpha, beta, heaviest});
              }
          node_done(i, present);
        }
    }



    template <int dim>
    void
    Manager<dim>::compute_geometry()
    {
      const unsigned int n_materials = fields.size();
      if (needs.point_clouds)
        gather_point_clouds();
      TimerOutput::Scope timer(this->get_computing_timer(), "contact: normals");

      // The sums over each side of what the normal method reads.
      std::vector<const double *> m(n_materials);
      std::vector<const double *> g(needs.volume_gradients ? n_materials * dim :
                                                             0);
      std::vector<const double *> xm(needs.positions ? n_materials * dim : 0);
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          m[a] = fields[a].mass.begin();
          for (unsigned int d = 0; d < dim; ++d)
            {
              if (needs.volume_gradients)
                g[a * dim + d] = fields[a].volume_gradient.block(d).begin();
              if (needs.positions)
                xm[a * dim + d] = fields[a].position_moment.block(d).begin();
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
      std::vector<int> side_of_material(n_materials, 0);

      geometry.clear();
      for_each_pair(
        [&](const Slot &s) {
          const unsigned int i = s.node;
          NormalInputs<dim>  node;
          node.first_alpha = s.alpha.front();
          node.first_beta  = s.beta.front();
          for (const unsigned int a : s.alpha)
            node.mass_alpha += m[a][i];
          for (const unsigned int b : s.beta)
            node.mass_beta += m[b][i];
          if (needs.volume_gradients)
            {
              node.volume_gradient_alpha = sum_over(g, s.alpha, i);
              node.volume_gradient_beta  = sum_over(g, s.beta, i);
            }
          if (needs.positions)
            {
              node.position_moment_alpha = sum_over(xm, s.alpha, i);
              node.position_moment_beta  = sum_over(xm, s.beta, i);
            }
          if (needs.node_positions)
            for (unsigned int d = 0; d < dim; ++d)
              node.node_position[d] = node_position.block(d).local_element(i);
          if (needs.cell_size)
            node.cell_size = node_cell_size.local_element(i);
          if (needs.point_clouds)
            {
              std::fill(side_of_material.begin(), side_of_material.end(), 0);
              for (const unsigned int a : s.alpha)
                side_of_material[a] = -1;
              for (const unsigned int b : s.beta)
                side_of_material[b] = 1;
              node.cloud = make_array_view(cloud.data() + cloud_begin[i],
                                           cloud.data() + cloud_begin[i + 1]);
              node.side_of_material = make_array_view(side_of_material);
            }
          geometry.push_back(normal_method->geometry(node));
        },
        [](const unsigned int, const std::vector<unsigned int> &) {});
      state.assign(geometry.size(), 0);
      if (needs_interface)
        slot_interface_energy.assign(geometry.size(), 0.);
      geometry_valid = true;
    }



    template <int dim>
    void
    Manager<dim>::apply(const Stage stage)
    {
      const ::fmpm::Parameters &parameters = this->get_parameters();
      const double              time_step  = this->get_timestep();
      if (!geometry_valid)
        compute_geometry();
      if (!multimaterial_nodes_valid)
        find_multimaterial_nodes();
      TimerOutput::Scope         timer(this->get_computing_timer(), "contact");
      const Contact::Parameters &contact     = parameters.contact;
      const unsigned int         n_materials = fields.size();

      // Raw views: m^α, the momenta this stage corrects, Δv^α.
      std::vector<const double *> m(n_materials);
      std::vector<double *>       p(n_materials * dim);
      std::vector<double *>       dv(n_materials * dim);
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          MaterialField<dim> &field = fields[a];
          m[a]                      = field.mass.begin();
          GridVectorField &momenta =
            stage == Stage::updated   ? field.updated_momentum :
            stage == Stage::increment ? field.series_increment :
                                        field.momentum;
          for (unsigned int d = 0; d < dim; ++d)
            {
              p[a * dim + d]  = momenta.block(d).begin();
              dv[a * dim + d] = field.delta_velocity.block(d).begin();
            }
        }
      // Δv^α of the correction of the extrapolated momenta (the first, or
      // the third before USL+/USAVG+ stresses): zero but where a correction
      // may have set it.
      if (stage == Stage::extrapolated || stage == Stage::re_extrapolated)
        {
          for (const unsigned int i : delta_velocity_nodes)
            for (unsigned int a = 0; a < n_materials * dim; ++a)
              dv[a][i] = 0;
          delta_velocity_nodes = multimaterial_nodes;
        }

      const bool measures_gap = needs.measures_gap;
      // The masses and momenta of α against β (β may be the sum of several
      // materials, Eq. 50), with the geometry found for them.
      auto node_pair = [&](const std::vector<unsigned int> &alpha,
                           const std::vector<unsigned int> &beta,
                           const unsigned int               i,
                           const NodeGeometry<dim>         &slot_geometry) {
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
        node.normal     = slot_geometry.normal;
        node.touching   = slot_geometry.touching;
        node.separation = slot_geometry.separation;
        node.stage      = stage == Stage::updated ?
                            Contact::NodePair<dim>::Stage::updated :
                          stage == Stage::increment ?
                            Contact::NodePair<dim>::Stage::increment :
                            Contact::NodePair<dim>::Stage::extrapolated;
        node.time_step  = time_step;
        if (needs_interface)
          {
            // u^β − u^α and A_c = sqrt(2 min(V^α, V^β)(V^α + V^β))/h, from
            // the sums of V and Σ S M u over each side's materials.
            auto sum_side = [&](const std::vector<unsigned int> &materials,
                                double                          &volume,
                                Tensor<1, dim>                  &moment) {
              for (const unsigned int a : materials)
                {
                  volume += fields[a].volume.local_element(i);
                  for (unsigned int d = 0; d < dim; ++d)
                    moment[d] +=
                      fields[a].displacement_moment.block(d).local_element(i);
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
      auto law =
        [&](const unsigned int a,
            const unsigned int b) -> const Contact::LawInterface<dim> & {
        return *laws[std::min(a, b) * n_materials + std::max(a, b)];
      };
      // 'XPIC contact term = series' keeps Δv^α = 0: the corrected momenta
      // then go through the whole series.
      const bool records_first_correction =
        (stage == Stage::extrapolated || stage == Stage::re_extrapolated) &&
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
      if (stage == Stage::updated)
        {
          for (const unsigned int i : recorded_nodes)
            {
              for (unsigned int d = 0; d < dim; ++d)
                contact_normal.block(d).local_element(i) = 0;
              contact_separation.local_element(i) = 0;
            }
          recorded_nodes.clear();
        }
      auto record = [&](const unsigned int            i,
                        const Contact::NodePair<dim> &node) {
        recorded_nodes.push_back(i);
        for (unsigned int d = 0; d < dim; ++d)
          contact_normal.block(d).local_element(i) = node.normal[d];
        contact_separation.local_element(i) = node.separation;
      };

      // Net incremental contact: at the pairs in contact at the last
      // correction the increments of the series are made the same in both
      // materials (their centre of mass); slip and separation come from the
      // corrections of the momenta.
      const bool                  increments = stage == Stage::increment;
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
        const auto node = node_pair(alpha, beta, i, geometry[slot]);
        // Increments: the same in both materials ('perfect'), or the
        // interface law's perfect directions.
        const Contact::LawInterface<dim> &pair_law = law(a, partner);
        const auto                        c =
          (increments && !pair_law.interface_state() ? *increment_law :
                                                       pair_law)
            .correct(node);
        if (stage == Stage::updated && c.in_contact && !in_contact)
          record(i, node);
        if (stage == Stage::updated && needs_interface)
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
                lumped_at_last =
                  lumped_at_last || (increments && state[pending_slot.slot]);
                continue;
              }
            bool touching = increments && state[pending_slot.slot];
            if (!increments)
              {
                one_alpha[0] = pending_slot.a;
                one_beta[0]  = pending_slot.partner;
                touching     = law(pending_slot.a, pending_slot.partner)
                             .correct(node_pair(one_alpha,
                                                one_beta,
                                                i,
                                                geometry[pending_slot.slot]))
                             .in_contact;
              }
            if (touching)
              pairs.push_back(&pending_slot);
          }
        if (!increments)
          for (const PendingSlot &pending_slot : pending)
            state[pending_slot.slot] = 0;

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
                    state[pending_slot.slot] = c.in_contact;
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
                      state[pair->slot] = 1;
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

      for_each_pair(
        [&](const Slot &s) {
          ++n_slots;
          if (s.explicit_node)
            {
              pending.push_back(
                {s.slot, s.lumped, s.x, s.alpha.front(), s.partner, s.beta});
              return;
            }
          if (s.lumped)
            changes[s.x] = Tensor<1, dim>();
          if (increments && !state[s.slot])
            return;
          const unsigned int a = s.alpha.front();
          const auto c = correct(a, s.alpha, s.beta, s.partner, s.node, s.slot);
          if (!increments)
            state[s.slot] = c.in_contact;
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

      AssertDimension(n_slots, geometry.size());
      if (stage == Stage::updated && needs_interface)
        interface_energy = std::accumulate(slot_interface_energy.begin(),
                                           slot_interface_energy.end(),
                                           0.);
      if (stage == Stage::updated)
        {
          local_friction_work += work;
          local_contact_nodes = contact_nodes;
        }
      if (stage == Stage::updated)
        {
          contact_normal.update_ghost_values();
          contact_separation.update_ghost_values();
        }
      if (stage == Stage::increment) // owned entries only, fields kept
        return;
      for (auto &field : fields)
        {
          GridVectorField &momenta =
            stage == Stage::updated ? field.updated_momentum : field.momentum;
          momenta.update_ghost_values();
          field.computed.fill(false);
        }
    }



    template <int dim>
    void
    Manager<dim>::find_contact_groups()
    {
      contact_groups.clear();
      for_each_pair(
        [&](const Slot &s) {
          if (!state[s.slot])
            return;
          if (contact_groups.empty() || contact_groups.back().first != s.node)
            contact_groups.emplace_back(s.node, 0u);
          for (const unsigned int a : s.alpha)
            contact_groups.back().second |= 1u << a;
          for (const unsigned int b : s.beta)
            contact_groups.back().second |= 1u << b;
        },
        [](const unsigned int, const std::vector<unsigned int> &) {});
    }



    template class Manager<2>;
    template class Manager<3>;
  } // namespace Contact
} // namespace fmpm
