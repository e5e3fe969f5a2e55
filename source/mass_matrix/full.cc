// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/full.h>
#include <fmpm/simulator.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <cstring>

namespace fmpm
{
  namespace MassMatrix
  {
    namespace
    {
      /** Two doubles as one SIMD value (GCC/Clang vector extension). */
      typedef double Pair __attribute__((vector_size(16)));

      inline Pair
      load(const double *x)
      {
        Pair v;
        std::memcpy(&v, x, sizeof(Pair));
        return v;
      }

      inline void
      store(double *x, const Pair v)
      {
        std::memcpy(x, &v, sizeof(Pair));
      }

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
        const MatrixType &K;
        /** 1 − δ */
        double K_factor;
        /** Nodes i with e_i = (1 − δ) c_i + δ m_i != 0, and e_i. */
        std::vector<std::pair<unsigned int, double>> diagonal_terms;
        /** Per component, the fixed nodes that K may couple to free ones. */
        std::vector<std::vector<unsigned int>> fixed_rows;

        /** dst = A src. */
        void
        vmult(GridVectorField &dst, const GridVectorField &src) const
        {
          apply_full_mass(K, dst, src);
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
       * component (the free nodes); gaps shorter than 16 nodes are bridged.
       */
      NodeRanges
      free_node_ranges(const GridVectorField &inverse_diagonal)
      {
        const unsigned int n = inverse_diagonal.block(0).locally_owned_size();
        NodeRanges         ranges;
        for (unsigned int i = 0; i < n; ++i)
          {
            bool is_free = false;
            for (unsigned int b = 0; b < inverse_diagonal.n_blocks(); ++b)
              is_free |= inverse_diagonal.block(b).local_element(i) != 0;
            if (!is_free)
              continue;
            if (!ranges.empty() && i < ranges.back().second + 16)
              ranges.back().second = i + 1;
            else
              ranges.emplace_back(i, i + 1);
          }
        return ranges;
      }

      /**
       * Preconditioned CG (Jacobi) on all components at once, each with its
       * own step lengths α_b, β_b (one Krylov space per component, as if
       * solved one by one) but one matrix pass for all of them. The solve is
       * bound by memory traffic and latency, so the vector work is fused
       * into three passes per iteration over the free nodes only, z = D⁻¹r
       * is never stored, and the sums run in interleaved parts, two doubles
       * at a time. The inverse diagonal D⁻¹ is zero on fixed nodes, so
       * directions, products and residuals vanish there. Starts from x = 0
       * with residual @p r (zero off the free nodes); stops when
       * |r| <= @p threshold. Returns the iterations, or throws on breakdown
       * or no convergence.
       */
      template <typename MatrixType>
      unsigned int
      solve_cg(const BlendedMass<MatrixType> &A,
               const GridVectorField         &inverse_diagonal,
               const NodeRanges              &ranges,
               GridVectorField               &x,
               GridVectorField               &r,
               GridVectorField               &direction,
               GridVectorField               &q,
               const double                   threshold,
               const unsigned int             max_iterations)
      {
        const MPI_Comm comm =
          x.block(0).get_partitioner()->get_mpi_communicator();
        const unsigned int n_blocks = x.n_blocks();
        // A component whose residual falls below this stops moving.
        const double component_threshold =
          threshold / std::sqrt(static_cast<double>(n_blocks));

        // Per component: r·D⁻¹r, then r·r.
        double local[2 * 3] = {}, global[2 * 3] = {};
        x         = 0;
        direction = 0;
        for (unsigned int b = 0; b < n_blocks; ++b)
          {
            const double *d  = inverse_diagonal.block(b).begin();
            const double *rb = r.block(b).begin();
            double       *pb = direction.block(b).begin();
            for (const auto &[begin, end] : ranges)
              for (unsigned int i = begin; i < end; ++i)
                {
                  pb[i] = d[i] * rb[i];
                  local[b] += rb[i] * pb[i];
                  local[3 + b] += rb[i] * rb[i];
                }
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
            A.vmult(q, direction);
            double p_dot_q_local[3] = {}, p_dot_q[3] = {};
            for (unsigned int b = 0; b < n_blocks; ++b)
              {
                const double *pb  = direction.block(b).begin();
                const double *qb  = q.block(b).begin();
                Pair          sum = {};
                for (const auto &[begin, end] : ranges)
                  {
                    unsigned int i = begin;
                    for (; i + 2 <= end; i += 2)
                      sum += load(pb + i) * load(qb + i);
                    if (i < end)
                      p_dot_q_local[b] += pb[i] * qb[i];
                  }
                p_dot_q_local[b] += sum[0] + sum[1];
              }
            Utilities::MPI::sum(p_dot_q_local, comm, p_dot_q);

            // x += α p, r −= α q, and the new r·D⁻¹r, r·r
            for (unsigned int b = 0; b < 2 * 3; ++b)
              local[b] = 0;
            for (unsigned int b = 0; b < n_blocks; ++b)
              {
                if (!active[b])
                  continue;
                AssertThrow(p_dot_q[b] > 0, ExcMessage("CG breakdown"));
                const double  alpha = r_dot_z[b] / p_dot_q[b];
                const double *d     = inverse_diagonal.block(b).begin();
                const double *pb    = direction.block(b).begin();
                const double *qb    = q.block(b).begin();
                double       *xb    = x.block(b).begin();
                double       *rb    = r.block(b).begin();
                Pair          rz = {}, rr = {};
                for (const auto &[begin, end] : ranges)
                  {
                    unsigned int i = begin;
                    for (; i + 2 <= end; i += 2)
                      {
                        store(xb + i, load(xb + i) + alpha * load(pb + i));
                        const Pair r_i = load(rb + i) - alpha * load(qb + i);
                        store(rb + i, r_i);
                        rz += r_i * load(d + i) * r_i;
                        rr += r_i * r_i;
                      }
                    if (i < end)
                      {
                        xb[i] += alpha * pb[i];
                        rb[i] -= alpha * qb[i];
                        local[b] += rb[i] * d[i] * rb[i];
                        local[3 + b] += rb[i] * rb[i];
                      }
                  }
                local[b] += rz[0] + rz[1];
                local[3 + b] += rr[0] + rr[1];
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
                const double *d   = inverse_diagonal.block(b).begin();
                const double *rb  = r.block(b).begin();
                double       *pb  = direction.block(b).begin();
                for (const auto &[begin, end] : ranges)
                  {
                    unsigned int i = begin;
                    for (; i + 2 <= end; i += 2)
                      store(pb + i,
                            load(d + i) * load(rb + i) + beta * load(pb + i));
                    if (i < end)
                      pb[i] = d[i] * rb[i] + beta * pb[i];
                  }
              }
          }
      }
    } // namespace



    template <int dim>
    void
    Full<dim>::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Tolerance",
                        "1e-10",
                        Patterns::Double(0, 1),
                        "Relative residual |p - m~ v| / |p| at which CG stops "
                        "(all components together; for accelerations "
                        "|f - m~ a| dt / (|p| + |f| dt), so that a dt is as "
                        "accurate as the velocities). Units: none.");
      prm.declare_entry("Maximum iterations",
                        "1000",
                        Patterns::Integer(1),
                        "CG iterations after which the solve counts as "
                        "failed and the step falls back to the lumped mass "
                        "matrix. Units: none.");
      prm.declare_entry("Weak node threshold",
                        "0.1",
                        Patterns::Double(0, 1),
                        "Remedy for a nearly singular full mass matrix: nodes "
                        "whose diagonal m~_ii is below this fraction of the "
                        "lumped mass m_i (a node barely touched by points) "
                        "take the lumped velocity p_i/m_i; the other nodes "
                        "solve the full system with these velocities known. "
                        "0 solves the exact full system everywhere. "
                        "Units: none.");
      prm.declare_entry("Lumped fraction",
                        "0",
                        Patterns::Double(0, 1),
                        "Remedy for a nearly singular full mass matrix (few "
                        "points per cell, body edges): solve ((1 - delta) m~ "
                        "+ delta m) v = p with this delta. 0 is the exact full "
                        "mass matrix, 1 the lumped one. Units: none.");
    }



    template <int dim>
    void
    Full<dim>::parse_parameters(ParameterHandler &prm)
    {
      tolerance           = prm.get_double("Tolerance");
      max_iterations      = prm.get_integer("Maximum iterations");
      lumped_fraction     = prm.get_double("Lumped fraction");
      weak_node_threshold = prm.get_double("Weak node threshold");
    }



    namespace
    {
      /**
       * Σ_j m_j v_j = Σ_i p_i holds for the exact solution (the columns of
       * m̃ sum to m, Eq. 1.9, and lumping weak nodes keeps the sums); CG
       * leaves it off by the sum of its residual. In each component without
       * known nodes that carry mass, a uniform shift c of the free nodes'
       * velocities,
       * c = (Σ p − Σ m v) / Σ_free m, restores it to round-off.
       */
      void
      restore_momentum(const GridScalar              &m,
                       const double                   mass_floor,
                       const std::vector<GridScalar> *known_mask,
                       const GridVectorField         &inverse_diagonal,
                       const GridVectorField         &p,
                       GridVectorField               &v)
      {
        const MPI_Comm     comm = m.get_partitioner()->get_mpi_communicator();
        const unsigned int n    = m.locally_owned_size();
        for (unsigned int b = 0; b < p.n_blocks(); ++b)
          {
            // Known nodes that carry mass exchange momentum with the walls.
            bool has_known_mass = false;
            if (known_mask)
              for (unsigned int i = 0; i < n; ++i)
                has_known_mass |= (*known_mask)[b].local_element(i) != 0 &&
                                  m.local_element(i) > mass_floor;
            if (Utilities::MPI::logical_or(has_known_mass, comm))
              continue;
            double local[2] = {}, global[2];
            for (unsigned int i = 0; i < n; ++i)
              {
                const double m_i = m.local_element(i);
                local[0] += p.block(b).local_element(i) -
                            m_i * v.block(b).local_element(i);
                if (inverse_diagonal.block(b).local_element(i) != 0)
                  local[1] += m_i;
              }
            Utilities::MPI::sum(local, comm, global);
            if (global[1] == 0)
              continue;
            const double shift = global[0] / global[1];
            for (unsigned int i = 0; i < n; ++i)
              if (inverse_diagonal.block(b).local_element(i) != 0)
                v.block(b).local_element(i) += shift;
          }
      }
    } // namespace



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
      FullMassWorkspace  local_workspace;
      FullMassWorkspace &w = workspace ? *workspace : local_workspace;
      w.reinit(p);
      const MPI_Comm     comm  = m.get_partitioner()->get_mpi_communicator();
      const unsigned int n     = m.locally_owned_size();
      const double       delta = settings.lumped_fraction;
      const double       floor = settings.mass_floor;
      FullMassSolve      result;
      v.zero_out_ghost_values();

      // Fixed nodes (known, weak, empty) and two starts of the iteration:
      // v on known nodes, m⁻¹p on weak ones, 0 on empty ones, and on free
      // nodes m⁻¹p (lumped start) or the given v (warm start).
      const unsigned int      n_blocks         = p.n_blocks();
      GridVectorField        &lumped_start     = w.lumped_start;
      GridVectorField        &inverse_diagonal = w.inverse_diagonal;
      BlendedMass<MatrixType> A{K, 1 - delta, {}, {}};
      A.fixed_rows.resize(n_blocks);
      const auto is_uncoupled = [&](const unsigned int i) {
        return weak.local_element(i) != 0 || !(m.local_element(i) > floor);
      };
      for (unsigned int b = 0; b < n_blocks; ++b)
        for (unsigned int i = 0; i < n; ++i)
          {
            const double m_i = m.local_element(i);
            const bool   is_known =
              known_mask && (*known_mask)[b].local_element(i) != 0;
            const bool is_weak  = weak.local_element(i) != 0;
            const bool is_empty = !(m_i > floor);
            double    &v_i      = v.block(b).local_element(i);
            if (is_empty)
              v_i = 0;
            else if (is_weak)
              v_i = p.block(b).local_element(i) / m_i;
            lumped_start.block(b).local_element(i) =
              is_known || is_weak || is_empty ?
                v_i :
                p.block(b).local_element(i) / m_i;
            // 1 marks free nodes here; their inverse diagonal comes below.
            inverse_diagonal.block(b).local_element(i) = 0;
            if (is_known || is_weak || (is_empty && m_i != 0))
              A.fixed_rows[b].push_back(i);
            else if (!is_empty)
              inverse_diagonal.block(b).local_element(i) = 1;
          }

      // c = K 1_W: the couplings of each node to weak nodes, and the
      // diagonal terms e = (1 − δ) c + δ m of A.
      GridScalar weak_coupling(m);
      weak_coupling = 0;
      if (Utilities::MPI::max(weak.linfty_norm(), comm) > 0)
        {
          GridVectorField ones(p), coupling(p);
          for (unsigned int b = 0; b < n_blocks; ++b)
            ones.block(b) = weak;
          apply_full_mass(K, coupling, ones);
          weak_coupling = coupling.block(0);
        }
      for (unsigned int i = 0; i < n; ++i)
        {
          const double e = (1 - delta) * weak_coupling.local_element(i) +
                           delta * m.local_element(i);
          if (e != 0)
            A.diagonal_terms.emplace_back(i, e);
        }
      for (unsigned int b = 0; b < n_blocks; ++b)
        for (unsigned int i = 0; i < n; ++i)
          {
            double      &inverse = inverse_diagonal.block(b).local_element(i);
            const double diagonal =
              (1 - delta) *
                (K_diagonal.local_element(i) + weak_coupling.local_element(i)) +
              delta * m.local_element(i);
            inverse = inverse != 0 && diagonal > 0 ? 1. / diagonal : 0.;
          }

      // r0 = p − A x0 on free rows: the known values of x0 enter through
      // (1 − δ) K_FK v_K, weak and empty nodes not at all.
      const auto initial_residual = [&](const GridVectorField &x0,
                                        GridVectorField       &r0) {
        GridVectorField &x0_coupled = w.coupled_start;
        x0_coupled                  = x0;
        for (unsigned int b = 0; b < n_blocks; ++b)
          for (unsigned int i = 0; i < n; ++i)
            if (is_uncoupled(i))
              x0_coupled.block(b).local_element(i) = 0;
        apply_full_mass(K, r0, x0_coupled);
        for (unsigned int b = 0; b < n_blocks; ++b)
          for (unsigned int i = 0; i < n; ++i)
            {
              const double x_i = x0.block(b).local_element(i);
              double      &r_i = r0.block(b).local_element(i);
              r_i =
                inverse_diagonal.block(b).local_element(i) == 0 ?
                  0. :
                  p.block(b).local_element(i) -
                    (1 - delta) * (r_i + weak_coupling.local_element(i) * x_i) -
                    delta * m.local_element(i) * x_i;
            }
      };
      // Start from v only where it is the better start (it is not, e.g.,
      // in the first step or after the mesh changed).
      GridVectorField &residual = w.residual, &correction = w.correction;
      initial_residual(lumped_start, residual);
      if (start_from_v)
        {
          initial_residual(v, correction);
          if (correction.l2_norm() < residual.l2_norm())
            residual.swap(correction);
          else
            v = lumped_start;
        }
      else
        v = lumped_start;
      correction = 0;

      // The residual that counts as converged: relative to |p|, or to a
      // larger scale the caller gives (accelerations: momenta over Δt).
      const double norm = std::max(p.l2_norm(), settings.residual_scale);
      if (norm == 0)
        return result;

      try
        {
          result.iterations = solve_cg(A,
                                       inverse_diagonal,
                                       free_node_ranges(inverse_diagonal),
                                       correction,
                                       residual,
                                       w.direction,
                                       w.product,
                                       settings.tolerance * norm,
                                       settings.max_iterations);
          v += correction;
          if (settings.conserve_momentum)
            restore_momentum(m, floor, known_mask, inverse_diagonal, p, v);
        }
      catch (const std::exception &)
        {
          result.converged  = false;
          result.iterations = settings.max_iterations;
          // Breakdown or stagnation: lumped velocities on the unknown nodes.
          for (unsigned int b = 0; b < p.n_blocks(); ++b)
            for (unsigned int i = 0; i < n; ++i)
              if (!(known_mask && (*known_mask)[b].local_element(i) != 0))
                {
                  const double m_i = m.local_element(i);
                  v.block(b).local_element(i) =
                    m_i > floor ? p.block(b).local_element(i) / m_i : 0.;
                }
        }
      return result;
    }

#define FMPM_INSTANTIATE(MatrixType)             \
  template FullMassSolve solve_full_mass_system( \
    const MatrixType &,                          \
    const GridScalar &,                          \
    const GridScalar &,                          \
    const std::vector<GridScalar> *,             \
    const GridScalar &,                          \
    const GridVectorField &,                     \
    GridVectorField &,                           \
    const bool,                                  \
    const FullMassSolveSettings &,               \
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
    }



    template <int dim>
    const CellwiseMatrix *
    Full<dim>::cellwise_matrix() const
    {
      return this->get_simulator().get_cellwise_full_mass_matrix();
    }



    template <int dim>
    void
    Full<dim>::solve(const GridVectorField &p, GridVectorField &v) const
    {
      solve_system(p, v, false, 0);
    }



    template <int dim>
    void
    Full<dim>::solve_from_guess(const GridVectorField &p,
                                GridVectorField       &v,
                                const double           residual_scale) const
    {
      solve_system(p, v, true, residual_scale);
    }



    template <int dim>
    void
    Full<dim>::solve_system(const GridVectorField &p,
                            GridVectorField       &v,
                            const bool             start_from_v,
                            const double           residual_scale) const
    {
      const auto        &mask   = this->get_known_velocity_mask();
      const auto        &values = this->get_known_velocity_values();
      const unsigned int n      = this->get_lumped_mass().locally_owned_size();
      // Known nodes: components held by a grid condition.
      for (unsigned int b = 0; b < p.n_blocks(); ++b)
        for (unsigned int i = 0; i < n; ++i)
          if (mask[b].local_element(i) != 0)
            v.block(b).local_element(i) = values[b].local_element(i);
      FullMassSolveSettings settings;
      settings.tolerance         = tolerance;
      settings.residual_scale    = residual_scale;
      settings.max_iterations    = max_iterations;
      settings.lumped_fraction   = lumped_fraction;
      settings.mass_floor        = this->get_simulator().mass_floor();
      settings.conserve_momentum = columns_sum_to_lumped_mass();
      const GridScalar   &m      = this->get_lumped_mass();
      const FullMassSolve result = cellwise_matrix() ?
                                     solve_full_mass_system(*cellwise_matrix(),
                                                            diagonal,
                                                            m,
                                                            &mask,
                                                            weak,
                                                            p,
                                                            v,
                                                            start_from_v,
                                                            settings,
                                                            &workspace) :
                                     solve_full_mass_system(matrix(),
                                                            diagonal,
                                                            m,
                                                            &mask,
                                                            weak,
                                                            p,
                                                            v,
                                                            start_from_v,
                                                            settings,
                                                            &workspace);
      ++n_solves;
      total_iterations += result.iterations;
      max_iterations_used = std::max(max_iterations_used, result.iterations);
      n_lumped_fallbacks += result.converged ? 0 : 1;
    }



    template <int dim>
    void
    Full<dim>::setup()
    {
      const GridScalar &m = this->get_lumped_mass();
      for (GridScalar *vector : {&weak, &diagonal})
        if (vector->size() != m.size() ||
            !vector->get_partitioner()->is_compatible(*m.get_partitioner()))
          vector->reinit(m.get_partitioner());
      if (const CellwiseMatrix *cellwise = cellwise_matrix())
        cellwise->diagonal(diagonal);
      else
        {
          const auto &range = m.get_partitioner()->locally_owned_range();
          for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
            diagonal.local_element(i) =
              matrix().diag_element(range.nth_index_in_set(i));
        }
      weak = 0;
      if (weak_node_threshold <= 0)
        return;
      const double       floor  = this->get_simulator().mass_floor();
      unsigned long long n_weak = 0;
      for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
        {
          // A node barely touched by points: m̃ᵢᵢ/mᵢ = Σ M S² / Σ M S < τ.
          const double m_i     = m.local_element(i);
          const bool   is_weak = m_i > floor && diagonal.local_element(i) <
                                                weak_node_threshold * m_i;
          weak.local_element(i) = is_weak ? 1. : 0.;
          n_weak += is_weak;
        }
      n_weak_node_steps += n_weak;
      ++n_setups;
    }



    template <int dim>
    void
    Full<dim>::save(std::map<std::string, std::string> &status) const
    {
      // The counters are the same on every rank (CG is global) except the
      // weak nodes, which each rank counts on its own nodes: their sum is
      // kept, so that a run resumed on another number of ranks reports the
      // same figures.
      const MPI_Comm comm                = this->get_mpi_communicator();
      status["full.n_solves"]            = std::to_string(n_solves);
      status["full.total_iterations"]    = std::to_string(total_iterations);
      status["full.max_iterations_used"] = std::to_string(max_iterations_used);
      status["full.n_lumped_fallbacks"] =
        std::to_string(Utilities::MPI::max(n_lumped_fallbacks, comm));
      status["full.n_weak_node_steps"] =
        std::to_string(Utilities::MPI::sum(n_weak_node_steps, comm));
      status["full.n_setups"] = std::to_string(n_setups);
    }



    template <int dim>
    void
    Full<dim>::load(const std::map<std::string, std::string> &status)
    {
      const auto value = [&status](const std::string &key) {
        const auto entry = status.find(key);
        return entry == status.end() ? 0ULL : std::stoull(entry->second);
      };
      const bool is_root =
        Utilities::MPI::this_mpi_process(this->get_mpi_communicator()) == 0;
      n_solves            = value("full.n_solves");
      total_iterations    = value("full.total_iterations");
      max_iterations_used = value("full.max_iterations_used");
      n_lumped_fallbacks  = value("full.n_lumped_fallbacks");
      n_weak_node_steps   = is_root ? value("full.n_weak_node_steps") : 0;
      n_setups            = value("full.n_setups");
    }



    template <int dim>
    std::map<std::string, double>
    Full<dim>::statistics() const
    {
      const MPI_Comm comm = this->get_mpi_communicator();
      return {
        {"weak_nodes_per_step",
         n_setups ?
           Utilities::MPI::sum(static_cast<double>(n_weak_node_steps), comm) /
             n_setups :
           0.},
        {"cg_solves", static_cast<double>(n_solves)},
        {"cg_iterations_mean",
         n_solves ? static_cast<double>(total_iterations) / n_solves : 0.},
        {"cg_iterations_max", static_cast<double>(max_iterations_used)},
        {"lumped_fallbacks",
         Utilities::MPI::max(static_cast<double>(n_lumped_fallbacks), comm)}};
    }



    template <int dim>
    void
    Consistent<dim>::initialize()
    {
      const DoFHandler<dim> &dof_handler = this->get_dof_handler();
      const MPI_Comm         comm        = this->get_mpi_communicator();
      IndexSet               relevant;
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      TrilinosWrappers::SparsityPattern sparsity(
        dof_handler.locally_owned_dofs(),
        dof_handler.locally_owned_dofs(),
        relevant,
        comm);
      DoFTools::make_sparsity_pattern(dof_handler,
                                      sparsity,
                                      this->get_constraints(),
                                      false,
                                      Utilities::MPI::this_mpi_process(comm));
      sparsity.compress();
      consistent_mass.reinit(sparsity);

      // ∫ NᵢNⱼ dx per cell, exact for the (bi/tri)linear map with Gauss(3).
      const FiniteElement<dim> &fe = dof_handler.get_fe();
      FEValues<dim>             fe_values(fe,
                              QGauss<dim>(3),
                              update_values | update_JxW_values);
      cell_mass_integrals.assign(
        dof_handler.get_triangulation().n_active_cells(), FullMatrix<double>());
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            FullMatrix<double> &local =
              cell_mass_integrals[cell->active_cell_index()];
            local.reinit(fe.dofs_per_cell, fe.dofs_per_cell);
            for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q)
              for (unsigned int i = 0; i < fe.dofs_per_cell; ++i)
                for (unsigned int j = 0; j < fe.dofs_per_cell; ++j)
                  local(i, j) += fe_values.shape_value(i, q) *
                                 fe_values.shape_value(j, q) * fe_values.JxW(q);
          }
    }



    template <int dim>
    void
    Consistent<dim>::setup()
    {
      // Σ M_p of each cell, by active cell index.
      const MaterialPoints<dim> &points = this->get_material_points();
      const double *const mass   = points.column(PropertyIndex<dim>::mass);
      std::vector<double> mass_of_cell(
        this->get_triangulation().n_active_cells(), 0.);
      for (unsigned int c = 0; c < points.n_cells(); ++c)
        for (unsigned int k = points.cell_point_begin[c];
             k < points.cell_point_begin[c + 1];
             ++k)
          mass_of_cell[points.cell_index[c]] += mass[k];
      consistent_mass = 0;
      std::vector<types::global_dof_index> dofs(
        this->get_dof_handler().get_fe().dofs_per_cell);
      FullMatrix<double> local;
      for (const auto &cell : this->get_dof_handler().active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const double cell_mass = mass_of_cell[cell->active_cell_index()];
            if (cell_mass == 0)
              continue;
            // ρ_c = Σ M_p / |c|
            local = cell_mass_integrals[cell->active_cell_index()];
            local *= cell_mass / cell->measure();
            cell->get_dof_indices(dofs);
            this->get_constraints().distribute_local_to_global(local,
                                                               dofs,
                                                               consistent_mass);
          }
      consistent_mass.compress(VectorOperation::add);
      Full<dim>::setup();
    }

    template <int dim>
    StabilityLimit
    Full<dim>::stability_limit(const StabilityMethod &method) const
    {
      const std::string name = "full mass matrix";
      StabilityLimit    limit;
      limit.max_courant = Stability::full_limit;
      limit.basis       = name + ", " + Stability::strain_update_text(method) +
                    ": the rigid rotation is stable at C = 0.12, "
                    "unstable at 0.15";
      Stability::limit_full_mass_method(limit, method, name, order(), true);
      return limit;
    }



    template <int dim>
    StabilityLimit
    Consistent<dim>::stability_limit(const StabilityMethod &method) const
    {
      StabilityLimit limit;
      limit.max_courant = Stability::consistent_limit;
      limit.basis       = "consistent mass matrix, " +
                    Stability::strain_update_text(method) +
                    ": FLIP on the vibrating bar stable up to C = 0.4";
      limit.warning =
        "the consistent finite element mass matrix amplifies a mode at "
        "free surfaces once material points move relative to the cells, "
        "at any time step (with " +
        Stability::update_text(method) + " and strain update '" +
        method.strain_update.name() +
        "' the vibrating bar of doc/studies/stability.md is unstable at " +
        (method.flip_type && method.strain_update.average ?
           "Courant numbers above 0.45 and " :
           "every Courant number and ") +
        "at large displacements); use it for small-displacement studies "
        "only, or choose 'Mass matrix/Model name = full' with the fmpm "
        "update or 'fmpm' (FMPM(k)).";
      return limit;
    }

    FMPM_REGISTER_MASS_MATRIX(
      Full,
      "full",
      "The exact particle full mass matrix m~ = S^T M S of [Nairn2023-FMPM] Eq. 1.9, "
      "solved with CG (Jacobi preconditioner) to 'Tolerance'; CG "
      "iteration counts go to summary.json.")
    FMPM_REGISTER_MASS_MATRIX(
      Consistent,
      "consistent",
      "The consistent finite element mass matrix int rho N_i N_j dx with the "
      "cell densities carried from the material points, solved like 'full'.")
  } // namespace MassMatrix
} // namespace fmpm
