// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The contact corrections (seed 004 §2-3): the pairs at each node, their
// geometry from the normal method, the laws applied at each stage.

#include <fmpm/contact/manager.h>
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



    /**
     * One contact correction of a stage over the owned nodes with 2+
     * materials (Manager::apply()): raw views of m^α, of the momenta the
     * stage corrects and of Δv^α, the pair in contact at each node, and what
     * the correction adds up (friction work, contact nodes).
     */
    template <int dim>
    class Manager<dim>::CorrectionSweep
    {
    public:
      CorrectionSweep(Manager<dim> &manager, const Stage stage);

      /** The pair of one slot (Slot of for_each_pair()). */
      void
      visit(const Slot &s);

      /** Node @p i is done: its pending or lumped corrections. */
      void
      node_done(const unsigned int i, const std::vector<unsigned int> &present);

      unsigned int       n_slots       = 0;
      double             work          = 0;
      unsigned long long contact_nodes = 0;

    private:
      /** 'Three or more materials = explicit': the slots of a 3+ node,
       * handled when the node is done. */
      struct PendingSlot
      {
        unsigned int              slot;
        bool                      lumped;
        unsigned int              x, a, partner;
        std::vector<unsigned int> beta;
      };

      /** The masses and momenta of α against β (β may be the sum of several
       * materials, Eq. 50), with the geometry found for them. */
      NodePair<dim>
      node_pair(const std::vector<unsigned int> &alpha,
                const std::vector<unsigned int> &beta,
                const unsigned int               i,
                const NodeGeometry<dim>         &slot_geometry) const;

      const LawInterface<dim> &
      law(const unsigned int a, const unsigned int b) const
      {
        return *manager.laws[std::min(a, b) * n_materials + std::max(a, b)];
      }

      void
      add_momentum(const unsigned int    a,
                   const unsigned int    i,
                   const Tensor<1, dim> &dp);

      /** The grid output's contact normal and separation at node @p i. */
      void
      record(const unsigned int i, const NodePair<dim> &node);

      /** One correction of α (one material) against β at node i,
       * recorded. */
      Correction<dim>
      correct(const unsigned int               a,
              const std::vector<unsigned int> &alpha,
              const std::vector<unsigned int> &beta,
              const unsigned int               partner,
              const unsigned int               i,
              const unsigned int               slot);

      /** The pending slots of node @p i (explicit 3+ nodes). */
      void
      correct_explicit_node(const unsigned int i);

      Manager<dim>               &manager;
      const Stage                 stage;
      const double                time_step;
      const Contact::Parameters  &contact;
      const unsigned int          n_materials;
      std::vector<const double *> m;
      std::vector<double *>       p, dv;
      const bool                  measures_gap;
      /** 'XPIC contact term = series' keeps Δv^α = 0: the corrected
       * momenta then go through the whole series. */
      const bool records_first_correction;
      /** Net incremental contact: at the pairs in contact at the last
       * correction the increments of the series are made the same in both
       * materials (their centre of mass); slip and separation come from the
       * corrections of the momenta. */
      const bool                  increments;
      std::vector<Tensor<1, dim>> changes;
      bool                        in_contact = false;
      std::vector<PendingSlot>    pending;
      std::vector<unsigned int>   one_alpha, one_beta;
    };



    template <int dim>
    Manager<dim>::CorrectionSweep::CorrectionSweep(Manager<dim> &manager,
                                                   const Stage   stage)
      : manager(manager)
      , stage(stage)
      , time_step(manager.get_timestep())
      , contact(manager.get_parameters().contact)
      , n_materials(manager.fields.size())
      , m(n_materials)
      , p(n_materials * dim)
      , dv(n_materials * dim)
      , measures_gap(manager.needs.measures_gap)
      , records_first_correction(
          (stage == Stage::extrapolated || stage == Stage::re_extrapolated) &&
          contact.xpic_contact_term != Contact::XpicContactTerm::series)
      , increments(stage == Stage::increment)
      , changes(n_materials)
      , one_alpha(1)
      , one_beta(1)
    {
      // Raw views: m^α, the momenta this stage corrects, Δv^α.
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          MaterialField<dim> &field = manager.fields[a];
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
          for (const unsigned int i : manager.delta_velocity_nodes)
            for (unsigned int a = 0; a < n_materials * dim; ++a)
              dv[a][i] = 0;
          manager.delta_velocity_nodes = manager.multimaterial_nodes;
        }
      // The grid output's contact normal and separation: of the first pair
      // in contact at a node after the momentum update, else zero.
      if (stage == Stage::updated)
        {
          for (const unsigned int i : manager.recorded_nodes)
            {
              for (unsigned int d = 0; d < dim; ++d)
                manager.contact_normal.block(d).local_element(i) = 0;
              manager.contact_separation.local_element(i) = 0;
            }
          manager.recorded_nodes.clear();
        }
    }



    template <int dim>
    NodePair<dim>
    Manager<dim>::CorrectionSweep::node_pair(
      const std::vector<unsigned int> &alpha,
      const std::vector<unsigned int> &beta,
      const unsigned int               i,
      const NodeGeometry<dim>         &slot_geometry) const
    {
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
      node.stage =
        stage == Stage::updated   ? Contact::NodePair<dim>::Stage::updated :
        stage == Stage::increment ? Contact::NodePair<dim>::Stage::increment :
                                    Contact::NodePair<dim>::Stage::extrapolated;
      node.time_step = time_step;
      if (manager.needs_interface)
        {
          // u^β − u^α and A_c = sqrt(2 min(V^α, V^β)(V^α + V^β))/h, from
          // the sums of V and Σ S M u over each side's materials.
          auto sum_side = [&](const std::vector<unsigned int> &materials,
                              double                          &volume,
                              Tensor<1, dim>                  &moment) {
            for (const unsigned int a : materials)
              {
                volume += manager.fields[a].volume.local_element(i);
                for (unsigned int d = 0; d < dim; ++d)
                  moment[d] += manager.fields[a]
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
            manager.node_cell_size.local_element(i);
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
                                      manager.node_cell_size.local_element(i) /
                                      time_step;
            }
        }
      return node;
    }



    template <int dim>
    void
    Manager<dim>::CorrectionSweep::add_momentum(const unsigned int    a,
                                                const unsigned int    i,
                                                const Tensor<1, dim> &dp)
    {
      for (unsigned int d = 0; d < dim; ++d)
        {
          p[a * dim + d][i] += dp[d];
          if (records_first_correction)
            dv[a * dim + d][i] += dp[d] / m[a][i];
        }
    }



    template <int dim>
    void
    Manager<dim>::CorrectionSweep::record(const unsigned int   i,
                                          const NodePair<dim> &node)
    {
      manager.recorded_nodes.push_back(i);
      for (unsigned int d = 0; d < dim; ++d)
        manager.contact_normal.block(d).local_element(i) = node.normal[d];
      manager.contact_separation.local_element(i) = node.separation;
    }



    template <int dim>
    Correction<dim>
    Manager<dim>::CorrectionSweep::correct(
      const unsigned int               a,
      const std::vector<unsigned int> &alpha,
      const std::vector<unsigned int> &beta,
      const unsigned int               partner,
      const unsigned int               i,
      const unsigned int               slot)
    {
      const auto node = node_pair(alpha, beta, i, manager.geometry[slot]);
      // Increments: the same in both materials ('perfect'), or the
      // interface law's perfect directions.
      const Contact::LawInterface<dim> &pair_law = law(a, partner);
      const auto                        c =
        (increments && !pair_law.interface_state() ? *manager.increment_law :
                                                     pair_law)
          .correct(node);
      if (stage == Stage::updated && c.in_contact && !in_contact)
        record(i, node);
      if (stage == Stage::updated && manager.needs_interface)
        // (a lumped slot, α against the others, counts each pair twice)
        manager.slot_interface_energy[slot] =
          (beta.size() > 1 ? 0.5 : 1.) * c.interface_energy;
      in_contact = in_contact || c.in_contact;
      return c;
    }



    template <int dim>
    void
    Manager<dim>::CorrectionSweep::correct_explicit_node(const unsigned int i)
    {
      // The pairs in contact (each pair's law on the momenta as they are;
      // for the series increments, the pairs in contact at the last
      // correction): none, one or two are corrected together, by turns
      // until neither pair's law changes the momenta (Eq. 49: both laws hold
      // and momentum is conserved); three or more lumped (Eq. 50).
      std::vector<char>               &state = manager.state;
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
              touching =
                law(pending_slot.a, pending_slot.partner)
                  .correct(node_pair(one_alpha,
                                     one_beta,
                                     i,
                                     manager.geometry[pending_slot.slot]))
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
    }



    template <int dim>
    void
    Manager<dim>::CorrectionSweep::visit(const Slot &s)
    {
      ++n_slots;
      if (s.explicit_node)
        {
          pending.push_back(
            {s.slot, s.lumped, s.x, s.alpha.front(), s.partner, s.beta});
          return;
        }
      if (s.lumped)
        changes[s.x] = Tensor<1, dim>();
      if (increments && !manager.state[s.slot])
        return;
      const unsigned int a = s.alpha.front();
      const auto c = correct(a, s.alpha, s.beta, s.partner, s.node, s.slot);
      if (!increments)
        manager.state[s.slot] = c.in_contact;
      if (s.lumped) // the change goes to α only, after all of the node's
        changes[s.x] = c.delta_momentum;
      else // α gets Δp^α, β gets −Δp^α (Eq. 7)
        {
          add_momentum(a, s.node, c.delta_momentum);
          add_momentum(s.partner, s.node, -c.delta_momentum);
        }
      work += (s.lumped ? 0.5 : 1.) * c.friction_work;
    }



    template <int dim>
    void
    Manager<dim>::CorrectionSweep::node_done(
      const unsigned int               i,
      const std::vector<unsigned int> &present)
    {
      if (!pending.empty())
        {
          correct_explicit_node(i);
          pending.clear();
        }
      else if (present.size() > 2 && contact.three_or_more ==
                                       Contact::Parameters::ThreeOrMore::lumped)
        for (unsigned int x = 0; x < present.size(); ++x)
          add_momentum(present[x], i, changes[x]);
      if (in_contact)
        ++contact_nodes;
      in_contact = false;
    }



    template <int dim>
    void
    Manager<dim>::apply(const Stage stage)
    {
      if (!geometry_valid)
        compute_geometry();
      if (!multimaterial_nodes_valid)
        find_multimaterial_nodes();
      TimerOutput::Scope timer(this->get_computing_timer(),
                               "contact: corrections");
      CorrectionSweep    sweep(*this, stage);
      for_each_pair([&](const Slot &s) { sweep.visit(s); },
                    [&](const unsigned int               i,
                        const std::vector<unsigned int> &present) {
                      sweep.node_done(i, present);
                    });

      AssertDimension(sweep.n_slots, geometry.size());
      if (stage == Stage::updated && needs_interface)
        interface_energy = std::accumulate(slot_interface_energy.begin(),
                                           slot_interface_energy.end(),
                                           0.);
      if (stage == Stage::updated)
        {
          local_friction_work += sweep.work;
          local_contact_nodes = sweep.contact_nodes;
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
