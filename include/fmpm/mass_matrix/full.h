// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_mass_matrix_full_h
#define fmpm_mass_matrix_full_h

#include <fmpm/mass_matrix/interface.h>

#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <map>
#include <string>

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

    /**
     * @brief The exact particle full mass matrix m̃ = SᵀMS (seed 000 Eq. 1.9):
     * v = m̃⁻¹p solved with CG, preconditioned by the diagonal of m̃ (Jacobi),
     * to a relative tolerance, all components at once. m̃ is kept as cell
     * matrices (CellwiseMatrix) where the mesh allows (no hanging nodes,
     * classic shape functions), else as a Trilinos sparse matrix. Each field
     * starts from its value of the last step (solve_from_guess()).
     *
     * m̃ is singular or nearly so where few points support a node (few points
     * per cell, a point that just entered a cell at a body edge): there
     * m̃ᵢᵢ/mᵢ = Σ M S²/Σ M S is small and the exact solve returns huge nodal
     * velocities. Remedies the scene chooses, all reported in summary.json:
     * - weak nodes: nodes with m̃ᵢᵢ < τ mᵢ are lumped: their row and
     *   column of m̃ become mᵢ and their couplings move onto the
     *   neighbours' diagonals, which keeps the column sums and so momentum
     *   (τ = 'Weak node threshold', 0 switches it off);
     * - a lumped fraction δ solves ((1 − δ) m̃ + δ m) v = p, SPD for δ > 0;
     * - when CG breaks down or does not converge, the field falls back to
     *   the lumped matrix.
     *
     * @ingroup MassMatrices
     */
    template <int dim>
    class Full : public Interface<dim>
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm);

      void
      parse_parameters(ParameterHandler &prm) override;

      bool
      needs_full_mass_matrix() const override
      {
        return true;
      }

      bool
      reads_known_velocities() const override
      {
        return true;
      }

      bool
      accepts_cellwise_full_mass_matrix() const override
      {
        return true;
      }

      std::optional<typename Interface<dim>::ExactSolveSettings>
      exact_solve() const override
      {
        return typename Interface<dim>::ExactSolveSettings{tolerance,
                                                           max_iterations,
                                                           weak_node_threshold};
      }

      void
      solve(const GridVectorField &momentum,
            GridVectorField       &velocity) const override;

      void
      solve_from_guess(const GridVectorField &momentum,
                       GridVectorField       &velocity,
                       const double           residual_scale) const override;

      /** p = K v with the matrix solved with (m̃, or the consistent one). */
      void
      vmult(const GridVectorField &velocity,
            GridVectorField       &momentum) const override
      {
        if (const CellwiseMatrix *cellwise = cellwise_matrix())
          apply_full_mass(*cellwise, momentum, velocity);
        else
          apply_full_mass(matrix(), momentum, velocity);
      }

      unsigned int
      order() const override
      {
        return 1000000;
      }

      /** The rigid rotation's limit; FLIP-type updates are warned of. */
      StabilityLimit
      stability_limit(const StabilityMethod &method) const override;

      /** The k -> infinity limit of multimaterial FMPM(k). */
      bool
      supports_multimaterial_contact() const override
      {
        return true;
      }

      std::map<std::string, double>
      statistics() const override;

      /** Relative residual tolerance of CG. */
      double tolerance = 1e-10;
      /** Maximum number of CG iterations. */
      unsigned int max_iterations = 1000;
      /** δ of the remedy ((1 − δ) m̃ + δ m) v = p. */
      double lumped_fraction = 0;
      /** τ: nodes with m̃ᵢᵢ < τ mᵢ are weak and take lumped velocities. */
      double weak_node_threshold = 0.1;

      void
      setup() override;

      /** The solve counters of summary.json, summed over ranks. */
      void
      save(std::map<std::string, std::string> &status) const override;

      /** Counters of save() (rank 0 takes the sums, the others zero). */
      void
      load(const std::map<std::string, std::string> &status) override;

    protected:
      /** Whether the columns of matrix() sum to the lumped masses m. */
      virtual bool
      columns_sum_to_lumped_mass() const
      {
        return true;
      }

      /** The matrix to solve with (m̃ here, the FE mass in Consistent). */
      virtual const TrilinosWrappers::SparseMatrix &
      matrix() const
      {
        return this->get_full_mass_matrix();
      }

      /** m̃ as cell matrices when the simulator keeps it so, else nullptr. */
      virtual const CellwiseMatrix *
      cellwise_matrix() const;

    private:
      /** v = K⁻¹p, from v (warm start) or from m⁻¹p. */
      void
      solve_system(const GridVectorField &p,
                   GridVectorField       &v,
                   const bool             start_from_v,
                   const double           residual_scale) const;

      mutable unsigned long long n_solves            = 0;
      mutable unsigned long long total_iterations    = 0;
      mutable unsigned int       max_iterations_used = 0;
      mutable unsigned long long n_lumped_fallbacks  = 0;
      /** 1 on weak nodes (owned entries), else 0. */
      GridScalar weak;
      /** The diagonal K_ii of the matrix solved with (owned entries). */
      GridScalar                diagonal;
      mutable FullMassWorkspace workspace;
      unsigned long long        n_weak_node_steps = 0;
      unsigned long long        n_setups          = 0;
    };



    /**
     * @brief The consistent finite element mass matrix ∫ρ NᵢNⱼ dx (seed 001,
     * "MPM discretization", M_gh), with the density of each cell carried from
     * its material points (ρ_c = Σ_p M_p / |c|), solved like Full.
     *
     * @ingroup MassMatrices
     */
    template <int dim>
    class Consistent : public Full<dim>
    {
    public:
      bool
      needs_full_mass_matrix() const override
      {
        return false;
      }

      /** (Solves the FE mass matrix, not m̃.) */
      std::optional<typename Interface<dim>::ExactSolveSettings>
      exact_solve() const override
      {
        return {};
      }

      void
      initialize() override;

      void
      setup() override;

      /** Unstable at free surfaces once points move: always warned of. */
      StabilityLimit
      stability_limit(const StabilityMethod &method) const override;

      bool
      supports_multimaterial_contact() const override
      {
        return false;
      }

    protected:
      const TrilinosWrappers::SparseMatrix &
      matrix() const override
      {
        return consistent_mass;
      }

      const CellwiseMatrix *
      cellwise_matrix() const override
      {
        return nullptr;
      }

      bool
      columns_sum_to_lumped_mass() const override
      {
        return false;
      }

    private:
      TrilinosWrappers::SparseMatrix consistent_mass;
      /** ∫_c NᵢNⱼ dx of each locally owned cell, by active cell index. */
      std::vector<FullMatrix<double>> cell_mass_integrals;
    };
  } // namespace MassMatrix
} // namespace fmpm

#endif
