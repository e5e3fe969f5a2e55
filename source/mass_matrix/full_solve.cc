// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The CG solve of full-mass systems K v = p (seed 000 Eq. 1.9): one
// material's m̃, or the per-material m̃^α of materials in contact (seed 004).

#include <fmpm/mass_matrix/full_solve.h>
#include <fmpm/mass_matrix/interface.h>

#include <deal.II/base/mpi.h>

#include <algorithm>

namespace fmpm
{
  namespace MassMatrix
  {
    namespace
    {
      /**
       * The SPD operator of the correction solve on free nodes F:
       * (1 − δ) (K_FF + diag(c)) + δ m, where c = K 1_W lumps the couplings
       * to weak nodes W onto the diagonal (so the column sums stay m and
       * momentum is conserved). It acts on fields that vanish on the fixed
       * (known, weak, empty) nodes and returns zero there.
       */
      template <typename MatrixType>
      struct BlendedMass
      {
        const MatrixType *K = nullptr;
        /** 1 − δ */
        double K_factor = 1;
        /** Nodes i with e_i = (1 − δ) c_i + δ m_i != 0, and e_i. */
        std::vector<std::pair<unsigned int, double>> diagonal_terms;
        /** Per component, the fixed nodes that K may couple to free ones. */
        std::vector<std::vector<unsigned int>> fixed_rows;

        /** dst = A src. */
        void
        vmult(GridVectorField &dst, const GridVectorField &src) const
        {
          apply_full_mass(*K, dst, src);
          for (unsigned int b = 0; b < src.n_blocks(); ++b)
            {
              if (K_factor != 1)
                dst.block(b) *= K_factor;
              double       *y = dst.block(b).begin();
              const double *x = src.block(b).begin();
              for (const auto &[i, e] : diagonal_terms)
                y[i] += e * x[i];
              for (const unsigned int i : fixed_rows[b])
                y[i] = 0;
            }
        }
      };

      /** Runs [begin, end) of locally owned nodes the CG passes visit. */
      using NodeRanges = std::vector<std::pair<unsigned int, unsigned int>>;

      /**
       * The ranges of nodes where @p inverse_diagonal is non-zero in some
       * component (the free nodes), without the nodes of @p excluded
       * (sorted); gaps shorter than 16 nodes are bridged.
       */
      NodeRanges
      free_node_ranges(const GridVectorField           &inverse_diagonal,
                       const std::vector<unsigned int> &excluded)
      {
        const unsigned int n = inverse_diagonal.block(0).locally_owned_size();
        const unsigned int n_blocks = inverse_diagonal.n_blocks();
        const double      *inverse[3];
        for (unsigned int b = 0; b < n_blocks; ++b)
          inverse[b] = inverse_diagonal.block(b).begin();
        NodeRanges ranges;
        auto       next_excluded = excluded.begin();
        bool       may_bridge    = false;
        for (unsigned int i = 0; i < n; ++i)
          {
            if (next_excluded != excluded.end() && *next_excluded == i)
              {
                ++next_excluded;
                may_bridge = false;
                continue;
              }
            bool is_free = false;
            for (unsigned int b = 0; b < n_blocks; ++b)
              is_free |= inverse[b][i] != 0;
            if (!is_free)
              continue;
            if (may_bridge && i < ranges.back().second + 16)
              ranges.back().second = i + 1;
            else
              ranges.emplace_back(i, i + 1);
            may_bridge = true;
          }
        return ranges;
      }

      /** One system of the CG: its operator and its fields. */
      template <typename MatrixType>
      struct CgSystem
      {
        BlendedMass<MatrixType> A;
        /** D⁻¹, zero on fixed nodes (at shared nodes: the group's). */
        const GridVectorField *inverse_diagonal;
        NodeRanges             ranges;
        GridVectorField       *x, *r, *direction, *q;
      };

      /** The CG steps at shared nodes, which the fused passes skip. */
      enum class SharedStep
      {
        start,     // p = z
        product,   // p·q
        update,    // x += α p, r −= α q
        direction, // p = z + β p
      };

      /**
       * One step of the CG at the shared nodes, component @p b: there the
       * preconditioned residual is z_a = D⁻¹_a Σ r (one unknown per group),
       * and the residual that counts is Σ r. Adds the nodes' terms to r·z
       * and r·r (start, update) or to p·q (product).
       */
      template <typename MatrixType>
      void
      shared_step(std::vector<CgSystem<MatrixType>> &systems,
                  const SharedNodes                 &shared,
                  const SharedStep                   step,
                  const unsigned int                 b,
                  const double                       alpha_or_beta,
                  double                            &r_dot_z_or_p_dot_q,
                  double                            &r_dot_r)
      {
        for (const auto &[i, group] : shared)
          {
            double sum = 0, d_r = 0;
            for (unsigned int a = 0; a < systems.size(); ++a)
              if (group & (1u << a))
                {
                  CgSystem<MatrixType> &system = systems[a];
                  const double          d_a =
                    system.inverse_diagonal->block(b).local_element(i);
                  double &p_a = system.direction->block(b).local_element(i);
                  double &r_a = system.r->block(b).local_element(i);
                  const double q_a = system.q->block(b).local_element(i);
                  if (step == SharedStep::product)
                    r_dot_z_or_p_dot_q += p_a * q_a;
                  else if (step == SharedStep::update && d_a != 0)
                    {
                      system.x->block(b).local_element(i) +=
                        alpha_or_beta * p_a;
                      r_a -= alpha_or_beta * q_a;
                    }
                  sum += r_a;
                  d_r += d_a * r_a;
                }
            if (step == SharedStep::start || step == SharedStep::update)
              {
                r_dot_z_or_p_dot_q += sum * d_r;
                r_dot_r += sum * sum;
              }
            if (step == SharedStep::start || step == SharedStep::direction)
              for (unsigned int a = 0; a < systems.size(); ++a)
                if (group & (1u << a))
                  {
                    const double d_a =
                      systems[a].inverse_diagonal->block(b).local_element(i);
                    double &p_a =
                      systems[a].direction->block(b).local_element(i);
                    p_a = d_a * sum + (step == SharedStep::direction ?
                                         alpha_or_beta * p_a :
                                         0.);
                  }
          }
      }

      /** x += α p, r −= α q on the free nodes of component @p b of every
       * system, adding the new r·D⁻¹r and r·r to @p r_dot_z and @p r_dot_r
       * (two interleaved sums, then the odd node, then their halves). */
      template <typename MatrixType>
      void
      update_component(std::vector<CgSystem<MatrixType>> &systems,
                       const unsigned int                 b,
                       const double                       alpha,
                       double                            &r_dot_z,
                       double                            &r_dot_r)
      {
        for (auto &system : systems)
          {
            const double *d  = system.inverse_diagonal->block(b).begin();
            const double *pb = system.direction->block(b).begin();
            const double *qb = system.q->block(b).begin();
            double       *xb = system.x->block(b).begin();
            double       *rb = system.r->block(b).begin();
            DoublePair    rz = 0., rr = 0.;
            for (const auto &[begin, end] : system.ranges)
              {
                unsigned int i = begin;
                for (; i + 2 <= end; i += 2)
                  {
                    store_pair(xb + i,
                               load_pair(xb + i) + alpha * load_pair(pb + i));
                    const DoublePair r_i =
                      load_pair(rb + i) - alpha * load_pair(qb + i);
                    store_pair(rb + i, r_i);
                    rz += r_i * load_pair(d + i) * r_i;
                    rr += r_i * r_i;
                  }
                if (i < end)
                  {
                    xb[i] += alpha * pb[i];
                    rb[i] -= alpha * qb[i];
                    r_dot_z += rb[i] * d[i] * rb[i];
                    r_dot_r += rb[i] * rb[i];
                  }
              }
            r_dot_z += rz[0] + rz[1];
            r_dot_r += rr[0] + rr[1];
          }
      }



      /** p = D⁻¹r + β p on the free nodes of component @p b of every
       * system. */
      template <typename MatrixType>
      void
      new_direction(std::vector<CgSystem<MatrixType>> &systems,
                    const unsigned int                 b,
                    const double                       beta)
      {
        for (auto &system : systems)
          {
            const double *d  = system.inverse_diagonal->block(b).begin();
            const double *rb = system.r->block(b).begin();
            double       *pb = system.direction->block(b).begin();
            for (const auto &[begin, end] : system.ranges)
              {
                unsigned int i = begin;
                for (; i + 2 <= end; i += 2)
                  store_pair(pb + i,
                             load_pair(d + i) * load_pair(rb + i) +
                               beta * load_pair(pb + i));
                if (i < end)
                  pb[i] = d[i] * rb[i] + beta * pb[i];
              }
          }
      }



      /**
       * Preconditioned CG on all systems and components at once, each
       * component with its own step lengths α_b, β_b (one Krylov space per
       * component, as if solved one by one) but one matrix pass per system
       * for all of them. The solve is bound by memory traffic and latency,
       * so the vector work is fused into three passes per iteration over the
       * free nodes only (shared nodes apart: shared_step()), z = D⁻¹r is
       * never stored, and the sums run in interleaved parts, two
       * doubles at a time. D⁻¹ is zero on fixed nodes, so directions,
       * products and residuals vanish there. Starts from x = 0 with
       * residuals r (zero off the free nodes); stops when |r| <=
       * @p threshold. Returns the iterations, or throws on breakdown or no
       * convergence.
       */
      template <typename MatrixType>
      unsigned int
      solve_cg(std::vector<CgSystem<MatrixType>> &systems,
               const SharedNodes                 &shared,
               const double                       threshold,
               const unsigned int                 max_iterations)
      {
        const MPI_Comm comm =
          systems[0].x->block(0).get_partitioner()->get_mpi_communicator();
        const unsigned int n_blocks = systems[0].x->n_blocks();
        // A component whose residual falls below this stops moving.
        const double component_threshold =
          threshold / std::sqrt(static_cast<double>(n_blocks));

        // Per component: r·D⁻¹r, then r·r.
        double local[2 * 3] = {}, global[2 * 3] = {};
        for (auto &system : systems)
          {
            *system.x         = 0;
            *system.direction = 0;
          }
        for (unsigned int b = 0; b < n_blocks; ++b)
          {
            for (auto &system : systems)
              {
                const double *d  = system.inverse_diagonal->block(b).begin();
                const double *rb = system.r->block(b).begin();
                double       *pb = system.direction->block(b).begin();
                for (const auto &[begin, end] : system.ranges)
                  for (unsigned int i = begin; i < end; ++i)
                    {
                      pb[i] = d[i] * rb[i];
                      local[b] += rb[i] * pb[i];
                      local[3 + b] += rb[i] * rb[i];
                    }
              }
            shared_step(systems,
                        shared,
                        SharedStep::start,
                        b,
                        0.,
                        local[b],
                        local[3 + b]);
          }
        Utilities::MPI::sum(local, comm, global);
        double r_dot_z[3], r_dot_r[3];
        for (unsigned int b = 0; b < n_blocks; ++b)
          {
            r_dot_z[b] = global[b];
            r_dot_r[b] = global[3 + b];
          }

        for (unsigned int iteration = 0;; ++iteration)
          {
            double residual_squared = 0;
            bool   active[3];
            for (unsigned int b = 0; b < n_blocks; ++b)
              {
                residual_squared += r_dot_r[b];
                active[b] = std::sqrt(r_dot_r[b]) > component_threshold;
              }
            if (std::sqrt(residual_squared) <= threshold)
              return iteration;
            AssertThrow(iteration < max_iterations,
                        ExcMessage("CG did not converge"));

            // q = A p, α_b = (r·z)_b / (p·q)_b
            double p_dot_q_local[3] = {}, p_dot_q[3] = {};
            for (auto &system : systems)
              {
                system.A.vmult(*system.q, *system.direction);
                for (unsigned int b = 0; b < n_blocks; ++b)
                  {
                    const double *pb  = system.direction->block(b).begin();
                    const double *qb  = system.q->block(b).begin();
                    DoublePair    sum = 0.;
                    for (const auto &[begin, end] : system.ranges)
                      {
                        unsigned int i = begin;
                        for (; i + 2 <= end; i += 2)
                          sum += load_pair(pb + i) * load_pair(qb + i);
                        if (i < end)
                          p_dot_q_local[b] += pb[i] * qb[i];
                      }
                    p_dot_q_local[b] += sum[0] + sum[1];
                  }
              }
            for (unsigned int b = 0; b < n_blocks; ++b)
              shared_step(systems,
                          shared,
                          SharedStep::product,
                          b,
                          0.,
                          p_dot_q_local[b],
                          p_dot_q_local[b]);
            Utilities::MPI::sum(p_dot_q_local, comm, p_dot_q);

            // x += α p, r −= α q, and the new r·D⁻¹r, r·r
            for (unsigned int b = 0; b < 2 * 3; ++b)
              local[b] = 0;
            for (unsigned int b = 0; b < n_blocks; ++b)
              {
                if (!active[b])
                  continue;
                AssertThrow(p_dot_q[b] > 0, ExcMessage("CG breakdown"));
                const double alpha = r_dot_z[b] / p_dot_q[b];
                update_component(systems, b, alpha, local[b], local[3 + b]);
                shared_step(systems,
                            shared,
                            SharedStep::update,
                            b,
                            alpha,
                            local[b],
                            local[3 + b]);
              }
            Utilities::MPI::sum(local, comm, global);

            // p = D⁻¹r + β p
            for (unsigned int b = 0; b < n_blocks; ++b)
              {
                if (!active[b])
                  continue;
                const double beta = global[b] / r_dot_z[b];
                r_dot_z[b]        = global[b];
                r_dot_r[b]        = global[3 + b];
                new_direction(systems, b, beta);
                double unused[2];
                shared_step(systems,
                            shared,
                            SharedStep::direction,
                            b,
                            beta,
                            unused[0],
                            unused[1]);
              }
          }
      }



      /**
       * Σ_a Σ_j m_j v_j = Σ_a Σ_i p_i holds for the exact solution (the
       * columns of m̃ sum to m, Eq. 1.9, lumping weak nodes keeps the sums,
       * and forces between shared nodes cancel); CG leaves it off by the sum
       * of its residual. In each component without known nodes that carry
       * mass, a uniform shift c of the free nodes' velocities,
       * c = (Σ p − Σ m v) / Σ_free m, restores it to round-off.
       */
      template <typename MatrixType>
      void
      restore_momentum(const std::vector<FullMassSystem<MatrixType>> &systems,
                       const double                   mass_floor,
                       const std::vector<GridScalar> *known_mask)
      {
        const GridScalar  &m0   = *systems[0].m;
        const MPI_Comm     comm = m0.get_partitioner()->get_mpi_communicator();
        const unsigned int n    = m0.locally_owned_size();
        for (unsigned int b = 0; b < systems[0].p->n_blocks(); ++b)
          {
            // Known nodes that carry mass exchange momentum with the walls.
            bool has_known_mass = false;
            if (known_mask)
              for (const auto &system : systems)
                for (unsigned int i = 0; i < n; ++i)
                  has_known_mass |= (*known_mask)[b].local_element(i) != 0 &&
                                    system.m->local_element(i) > mass_floor;
            if (Utilities::MPI::logical_or(has_known_mass, comm))
              continue;
            double local[2] = {}, global[2];
            for (const auto &system : systems)
              {
                const GridVectorField &inverse_diagonal =
                  system.workspace->inverse_diagonal;
                for (unsigned int i = 0; i < n; ++i)
                  {
                    const double m_i = system.m->local_element(i);
                    local[0] += system.p->block(b).local_element(i) -
                                m_i * system.v->block(b).local_element(i);
                    if (inverse_diagonal.block(b).local_element(i) != 0)
                      local[1] += m_i;
                  }
              }
            Utilities::MPI::sum(local, comm, global);
            if (global[1] == 0)
              continue;
            const double shift = global[0] / global[1];
            for (const auto &system : systems)
              for (unsigned int i = 0; i < n; ++i)
                if (system.workspace->inverse_diagonal.block(b).local_element(
                      i) != 0)
                  system.v->block(b).local_element(i) += shift;
          }
      }



      /**
       * The fixed nodes of @p system (known, weak, empty), the start of the
       * iteration in its workspace (v on known nodes, m⁻¹p on weak ones, 0
       * on empty ones; FullMassStart::given: v on all three; on free nodes
       * m⁻¹p or the given v), 1 on its free nodes in the inverse diagonal,
       * and its operator @p A with the diagonal of A.
       */
      template <typename MatrixType>
      void
      set_up_system(const FullMassSystem<MatrixType> &system,
                    const FullMassStart               start,
                    const std::vector<GridScalar>    *known_mask,
                    const FullMassSolveSettings      &settings,
                    BlendedMass<MatrixType>          &A)
      {
        const unsigned int     n        = system.m->locally_owned_size();
        const double           delta    = settings.lumped_fraction;
        const double           floor    = settings.mass_floor;
        const unsigned int     n_blocks = system.p->n_blocks();
        const GridScalar      &m        = *system.m;
        const GridScalar      &weak     = *system.weak;
        const GridVectorField &p        = *system.p;
        GridVectorField       &v        = *system.v;
        FullMassWorkspace     &w        = *system.workspace;
        w.reinit(p);
        v.zero_out_ghost_values();
        A.K        = system.K;
        A.K_factor = 1 - delta;
        A.fixed_rows.assign(n_blocks, {});

        // Fixed nodes (known, weak, empty) and the start of the
        // iteration: v on known nodes, m⁻¹p on weak ones, 0 on empty ones
        // (FullMassStart::given: v on all three), and on free nodes m⁻¹p
        // or the given v.
        const bool    given  = start == FullMassStart::given;
        const double *m_data = m.begin(), *weak_data = weak.begin();
        for (unsigned int b = 0; b < n_blocks; ++b)
          {
            const double *p_b = p.block(b).begin();
            const double *known_b =
              known_mask ? (*known_mask)[b].begin() : nullptr;
            double *v_b       = v.block(b).begin();
            double *start_b   = w.lumped_start.block(b).begin();
            double *inverse_b = w.inverse_diagonal.block(b).begin();
            for (unsigned int i = 0; i < n; ++i)
              {
                const double m_i      = m_data[i];
                const bool   is_known = known_b && known_b[i] != 0;
                const bool   is_weak  = weak_data[i] != 0;
                const bool   is_empty = !(m_i > floor);
                const bool   is_fixed = is_known || is_weak || is_empty;
                if (!given)
                  {
                    if (is_empty)
                      v_b[i] = 0;
                    else if (is_weak)
                      v_b[i] = p_b[i] / m_i;
                  }
                start_b[i] = is_fixed || given ? v_b[i] : p_b[i] / m_i;
                // 1 marks free nodes here; their inverse diagonal below.
                inverse_b[i] = is_fixed ? 0 : 1;
                if (is_known || is_weak || (is_empty && m_i != 0))
                  A.fixed_rows[b].push_back(i);
              }
          }

        // c = K 1_W: the couplings of each node to weak nodes, the
        // diagonal terms e = (1 − δ) c + δ m of A, and A's diagonal.
        w.weak_coupling = 0;
        if (weak.linfty_norm() > 0) // (over all ranks)
          {
            for (unsigned int b = 0; b < n_blocks; ++b)
              w.direction.block(b) = weak;
            apply_full_mass(*system.K, w.product, w.direction);
            w.weak_coupling = w.product.block(0);
          }
        A.diagonal_terms.clear();
        for (unsigned int i = 0; i < n; ++i)
          {
            const double c_i = w.weak_coupling.local_element(i);
            const double m_i = m.local_element(i);
            const double e   = (1 - delta) * c_i + delta * m_i;
            if (e != 0)
              A.diagonal_terms.emplace_back(i, e);
            w.diagonal.local_element(i) =
              (1 - delta) * (system.K_diagonal->local_element(i) + c_i) +
              delta * m_i;
          }
      }



      /**
       * r0 = p − A x0 on the free rows of @p system: the known values of x0
       * enter through (1 − δ) K_FK v_K, weak and empty nodes not at all.
       */
      template <typename MatrixType>
      void
      initial_residual(const FullMassSystem<MatrixType> &system,
                       const FullMassSolveSettings      &settings,
                       const GridVectorField            &x0,
                       GridVectorField                  &r0)
      {
        const unsigned int n          = system.m->locally_owned_size();
        const double       delta      = settings.lumped_fraction;
        const double       floor      = settings.mass_floor;
        const unsigned int n_blocks   = system.p->n_blocks();
        const GridScalar  &m          = *system.m;
        FullMassWorkspace &w          = *system.workspace;
        GridVectorField   &x0_coupled = w.coupled_start;
        x0_coupled                    = x0;
        const double *const m_data    = m.begin();
        const double *const weak_data = system.weak->begin();
        const double *const coupling  = w.weak_coupling.begin();
        for (unsigned int b = 0; b < n_blocks; ++b)
          {
            double *const x_b = x0_coupled.block(b).begin();
            for (unsigned int i = 0; i < n; ++i)
              if (weak_data[i] != 0 || !(m_data[i] > floor))
                x_b[i] = 0;
          }
        apply_full_mass(*system.K, r0, x0_coupled);
        for (unsigned int b = 0; b < n_blocks; ++b)
          {
            const double *const x_b       = x0.block(b).begin();
            const double *const p_b       = system.p->block(b).begin();
            const double *const inverse_b = w.inverse_diagonal.block(b).begin();
            double *const       r_b       = r0.block(b).begin();
            for (unsigned int i = 0; i < n; ++i)
              r_b[i] = inverse_b[i] == 0 ?
                         0. :
                         p_b[i] -
                           (1 - delta) * (r_b[i] + coupling[i] * x_b[i]) -
                           delta * m_data[i] * x_b[i];
          }
      }
    } // namespace



    template <typename MatrixType>
    FullMassSolve
    solve_full_mass_systems(
      const std::vector<FullMassSystem<MatrixType>> &systems,
      const SharedNodes                             &shared,
      const std::vector<GridScalar>                 *known_mask,
      const FullMassStart                            start,
      const FullMassSolveSettings                   &settings)
    {
      Assert(!systems.empty(), ExcInternalError());
      Assert(systems.size() <= 32, ExcInternalError());
      const unsigned int n_systems = systems.size();
      const GridScalar  &m0        = *systems[0].m;
      const unsigned int n         = m0.locally_owned_size();
      const double       floor     = settings.mass_floor;
      const unsigned int n_blocks  = systems[0].p->n_blocks();
      FullMassSolve      result;

      std::vector<CgSystem<MatrixType>> cg(n_systems);
      for (unsigned int a = 0; a < n_systems; ++a)
        set_up_system(systems[a], start, known_mask, settings, cg[a].A);
      // Shared nodes: the diagonal of Zᵀ diag Z, the sum over the group;
      // each system's shared nodes, which its fused CG passes skip.
      std::vector<std::vector<unsigned int>> shared_of(n_systems);
      for (const auto &[i, group] : shared)
        {
          double sum = 0;
          for (unsigned int a = 0; a < n_systems; ++a)
            if (group & (1u << a))
              sum += systems[a].workspace->diagonal.local_element(i);
          for (unsigned int a = 0; a < n_systems; ++a)
            if (group & (1u << a))
              {
                systems[a].workspace->diagonal.local_element(i) = sum;
                shared_of[a].push_back(i);
              }
        }
      for (auto &nodes : shared_of)
        std::sort(nodes.begin(), nodes.end());
      for (unsigned int a = 0; a < n_systems; ++a)
        {
          FullMassWorkspace  &w        = *systems[a].workspace;
          const double *const diagonal = w.diagonal.begin();
          for (unsigned int b = 0; b < n_blocks; ++b)
            {
              double *const inverse = w.inverse_diagonal.block(b).begin();
              for (unsigned int i = 0; i < n; ++i)
                inverse[i] =
                  inverse[i] != 0 && diagonal[i] > 0 ? 1. / diagonal[i] : 0.;
            }
        }

      // FullMassStart::better_of_given_and_lumped: from v only where it is
      // the better start (it is not, e.g., in the first step or after the
      // mesh changed).
      const bool compare_starts =
        start == FullMassStart::better_of_given_and_lumped;
      double lumped_norm = 0, given_norm = 0;
      for (const auto &system : systems)
        {
          FullMassWorkspace &w = *system.workspace;
          initial_residual(system, settings, w.lumped_start, w.residual);
          if (compare_starts)
            {
              lumped_norm += w.residual.norm_sqr();
              initial_residual(system, settings, *system.v, w.correction);
              given_norm += w.correction.norm_sqr();
            }
        }
      const bool from_given     = compare_starts && given_norm < lumped_norm;
      double     p_norm_squared = 0;
      for (unsigned int a = 0; a < n_systems; ++a)
        {
          const FullMassSystem<MatrixType> &system = systems[a];
          FullMassWorkspace                &w      = *system.workspace;
          if (from_given)
            w.residual.swap(w.correction);
          else if (start != FullMassStart::given) // (given: v is its start)
            *system.v = w.lumped_start;
          p_norm_squared += system.p->norm_sqr();
          cg[a].inverse_diagonal = &w.inverse_diagonal;
          cg[a].ranges    = free_node_ranges(w.inverse_diagonal, shared_of[a]);
          cg[a].x         = &w.correction;
          cg[a].r         = &w.residual;
          cg[a].direction = &w.direction;
          cg[a].q         = &w.product;
        }

      // The residual that counts as converged: relative to |p|, or to a
      // larger scale the caller gives (accelerations: momenta over Δt).
      const double norm =
        std::max(std::sqrt(p_norm_squared), settings.residual_scale);
      if (norm == 0)
        return result;

      try
        {
          result.iterations = solve_cg(cg,
                                       shared,
                                       settings.tolerance * norm,
                                       settings.max_iterations);
          if (result.iterations > 0)
            for (const auto &system : systems)
              *system.v += system.workspace->correction;
          if (settings.conserve_momentum)
            restore_momentum(systems, floor, known_mask);
        }
      catch (const std::exception &)
        {
          result.converged  = false;
          result.iterations = settings.max_iterations;
          // Breakdown or stagnation: the lumped start (m⁻¹p on free nodes).
          for (const auto &system : systems)
            *system.v = system.workspace->lumped_start;
        }
      return result;
    }



    template <typename MatrixType>
    FullMassSolve
    solve_full_mass_system(const MatrixType              &K,
                           const GridScalar              &K_diagonal,
                           const GridScalar              &m,
                           const std::vector<GridScalar> *known_mask,
                           const GridScalar              &weak,
                           const GridVectorField         &p,
                           GridVectorField               &v,
                           const bool                     start_from_v,
                           const FullMassSolveSettings   &settings,
                           FullMassWorkspace             *workspace)
    {
      FullMassWorkspace local_workspace;
      return solve_full_mass_systems<MatrixType>(
        {{&K,
          &K_diagonal,
          &m,
          &weak,
          &p,
          &v,
          workspace ? workspace : &local_workspace}},
        {},
        known_mask,
        start_from_v ? FullMassStart::better_of_given_and_lumped :
                       FullMassStart::lumped,
        settings);
    }

#define FMPM_INSTANTIATE(MatrixType)                 \
  template FullMassSolve solve_full_mass_systems(    \
    const std::vector<FullMassSystem<MatrixType>> &, \
    const SharedNodes &,                             \
    const std::vector<GridScalar> *,                 \
    const FullMassStart,                             \
    const FullMassSolveSettings &);                  \
  template FullMassSolve solve_full_mass_system(     \
    const MatrixType &,                              \
    const GridScalar &,                              \
    const GridScalar &,                              \
    const std::vector<GridScalar> *,                 \
    const GridScalar &,                              \
    const GridVectorField &,                         \
    GridVectorField &,                               \
    const bool,                                      \
    const FullMassSolveSettings &,                   \
    FullMassWorkspace *);
    FMPM_INSTANTIATE(TrilinosWrappers::SparseMatrix)
    FMPM_INSTANTIATE(CellwiseMatrix)
#undef FMPM_INSTANTIATE



    void
    FullMassWorkspace::reinit(const GridVectorField &like)
    {
      for (GridVectorField *field : {&lumped_start,
                                     &inverse_diagonal,
                                     &residual,
                                     &correction,
                                     &direction,
                                     &product,
                                     &coupled_start})
        if (field->n_blocks() != like.n_blocks() ||
            field->block(0).get_partitioner() !=
              like.block(0).get_partitioner())
          field->reinit(like, true);
      for (GridScalar *scalar : {&weak_coupling, &diagonal})
        if (scalar->get_partitioner() != like.block(0).get_partitioner())
          scalar->reinit(like.block(0).get_partitioner());
    }
  } // namespace MassMatrix
} // namespace fmpm
