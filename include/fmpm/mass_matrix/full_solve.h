// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_mass_matrix_full_solve_h
#define fmpm_mass_matrix_full_solve_h

#include <fmpm/grid_vectors.h>

#include <utility>
#include <vector>

/**
 * The CG solve of full-mass systems K v = p (seed 000 Eq. 1.9), used by the
 * exact mass matrix and by the per-material fields of contact (seed 004).
 */
namespace fmpm
{
  namespace MassMatrix
  {
    /** @brief Outcome of one full-mass solve. */
    struct FullMassSolve
    {
      unsigned int iterations = 0;
      bool         converged  = true;
    };

    /** @brief The CG settings of an exact solve v = m̃⁻¹p, which a mass
     * matrix gives the multimaterial exact solve of contact; no defaults
     * here: they are the mass matrix's parameters. */
    struct ExactSolveSettings
    {
      double       tolerance;
      unsigned int max_iterations;
      double       weak_node_threshold;
    };

    /** @brief How solve_full_mass_system() solves. */
    struct FullMassSolveSettings
    {
      /**
       * CG stops at |p − A v| <= tolerance max(|p|, residual_scale), over
       * all components.
       */
      double tolerance = 1e-10;
      /** A scale of the residual larger than |p| (0: none). */
      double residual_scale = 0;
      /** CG iterations before the solve counts as failed. */
      unsigned int max_iterations = 1000;
      /** δ of ((1 − δ) K' + δ m) v = p. */
      double lumped_fraction = 0;
      /** Nodes with m_i <= mass_floor are empty: v_i = 0. */
      double mass_floor = 0;
      /**
       * Whether the columns of K sum to m (m̃ does, the consistent FE matrix
       * does not): then, in components without known nodes, v is shifted
       * uniformly on the free nodes so that Σ m v = Σ p to round-off, as
       * the exact solution has it, instead of to the CG tolerance.
       */
      bool conserve_momentum = true;
    };

    /** @brief Scratch fields of one system of solve_full_mass_systems(),
     * kept between solves so that a solve allocates nothing. */
    struct FullMassWorkspace
    {
      GridVectorField lumped_start, inverse_diagonal, residual, correction,
        direction, product, coupled_start;
      /** c = K 1_W, and the diagonal of the operator at each node. */
      GridScalar weak_coupling, diagonal;

      /** Give every field the layout of @p like (kept if it has it). */
      void
      reinit(const GridVectorField &like);
    };

    /** @brief Where solve_full_mass_systems() starts CG. */
    enum class FullMassStart
    {
      /** m⁻¹p on free nodes; v = 0 on empty nodes, m⁻¹p on weak ones */
      lumped,
      /** as lumped, or from the given v on free nodes where that leaves
       * the smaller residual (a warm start) */
      better_of_given_and_lumped,
      /** from the given v on every node; fixed nodes keep it */
      given
    };

    /** @brief One system K v = p of solve_full_mass_systems(). */
    template <typename MatrixType>
    struct FullMassSystem
    {
      /** K (m̃, or a material's m̃^α) and its diagonal K_ii (owned) */
      const MatrixType *K;
      const GridScalar *K_diagonal;
      /** the lumped masses (the column sums of K) */
      const GridScalar *m;
      /** 1 on weak nodes (owned), else 0 */
      const GridScalar      *weak;
      const GridVectorField *p;
      GridVectorField       *v;
      FullMassWorkspace     *workspace;
    };

    /**
     * @brief Owned nodes (local index) at which systems share one unknown
     * correction, with the systems that share it (bit a: system a).
     */
    using SharedNodes = std::vector<std::pair<unsigned int, unsigned int>>;

    /**
     * @brief Solve K_a v_a = p_a for several systems a with one CG per
     * component, each as solve_full_mass_system() describes (known, weak
     * and empty nodes, δ, Jacobi, momentum restored over all systems).
     *
     * At @p shared nodes the systems take the same correction (so they keep
     * equal velocities there if they start from equal ones) and only the
     * sum of their residuals has to vanish (materials in contact: the equal
     * and opposite contact forces remain). The preconditioner is there
     * D Z (Zᵀ diag Z)⁻¹ Zᵀ D (Z: the shared unknown, D: free components),
     * symmetric positive semi-definite, whose range is the subspace of equal
     * corrections; the residual norm counts their sums. Without shared
     * nodes the systems are independent.
     *
     * On breakdown or no convergence every v_a takes its lumped start (with
     * FullMassStart::given: its input) and converged = false.
     */
    template <typename MatrixType>
    FullMassSolve
    solve_full_mass_systems(
      const std::vector<FullMassSystem<MatrixType>> &systems,
      const SharedNodes                             &shared,
      const std::vector<GridScalar>                 *known_mask,
      const FullMassStart                            start,
      const FullMassSolveSettings                   &settings);

    /**
     * @brief Solve ((1 − δ) K' + δ m) v = p for all components at once with
     * CG, preconditioned by the inverse diagonal (Jacobi).
     *
     * - Known nodes (@p known_mask of the component is 1, or nullptr for
     *   none): v keeps its input value and the other rows see it as given
     *   (Dirichlet).
     * - Weak nodes (@p weak is 1): K' is lumped there: row and column
     *   become m_i, and their couplings move onto the neighbours' diagonals,
     *   so K' keeps the column sums m of K = m̃ and the extrapolated momentum
     *   Σ M S v stays Σ p.
     * - Empty nodes (m_i <= mass floor): v_i = 0.
     * - The other nodes start from v if @p start_from_v (a warm start, e.g.
     *   the last step's field), else from m⁻¹p.
     *
     * CG runs on the correction from that start, whose search directions
     * vanish on known, weak and empty nodes. On breakdown or no
     * convergence, v = m⁻¹p on the unknown nodes and converged = false.
     *
     * @param K m̃ as a sparse matrix or as cell matrices
     * @param K_diagonal the diagonal K_ii (locally owned)
     */
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
                           FullMassWorkspace             *workspace = nullptr);
  } // namespace MassMatrix
} // namespace fmpm

#endif
