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

    /**
     * @brief Solve ((1 − δ) K' + δ m) v = p with CG, preconditioned by the
     * lumped inverse m⁻¹. On nodes where @p known is 1, v keeps its input
     * value and the other rows see it as given (Dirichlet). On nodes where
     * @p weak is 1, K' is lumped: row and column become m_i, and their
     * couplings move onto the neighbours' diagonals, so K' keeps the column
     * sums m of K = m̃ and the extrapolated momentum Σ M S v stays Σ p.
     * Stops at |residual| <= tolerance |rhs|. On breakdown or no convergence,
     * v = m⁻¹p on the unknown nodes and converged = false.
     */
    FullMassSolve
    solve_full_mass_system(const TrilinosWrappers::SparseMatrix &K,
                           const GridScalar                     &m,
                           const GridScalar                     &known,
                           const GridScalar                     &weak,
                           const GridScalar                     &p,
                           GridScalar                           &v,
                           const double                          tolerance,
                           const unsigned int                    max_iterations,
                           const double                          delta,
                           const double                          mass_floor);

    /**
     * @brief The exact particle full mass matrix m̃ = SᵀMS (seed 000 Eq. 1.9):
     * v = m̃⁻¹p solved with CG, preconditioned by the lumped inverse m⁻¹, to a
     * relative tolerance.
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

      void
      solve(const GridVectorField &momentum,
            GridVectorField       &velocity) const override;

      /** p = K v with the assembled matrix (m̃, or the consistent one). */
      void
      vmult(const GridVectorField &velocity,
            GridVectorField       &momentum) const override
      {
        for (unsigned int b = 0; b < velocity.n_blocks(); ++b)
          matrix().vmult(momentum.block(b), velocity.block(b));
      }

      unsigned int
      order() const override
      {
        return 1000000;
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

    protected:
      /** The matrix to solve with (m̃ here, the FE mass in Consistent). */
      virtual const TrilinosWrappers::SparseMatrix &
      matrix() const
      {
        return this->get_full_mass_matrix();
      }

    private:
      mutable unsigned long long n_solves            = 0;
      mutable unsigned long long total_iterations    = 0;
      mutable unsigned int       max_iterations_used = 0;
      mutable unsigned long long n_lumped_fallbacks  = 0;
      /** 1 on weak nodes (owned entries), else 0. */
      GridScalar weak;
      /** Scratch: 1 on nodes whose velocity is known in the current solve. */
      mutable GridScalar known;
      unsigned long long n_weak_node_steps = 0;
      unsigned long long n_setups          = 0;
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

      void
      initialize() override;

      void
      setup() override;



    protected:
      const TrilinosWrappers::SparseMatrix &
      matrix() const override
      {
        return consistent_mass;
      }

    private:
      TrilinosWrappers::SparseMatrix consistent_mass;
      /** ∫_c NᵢNⱼ dx of each locally owned cell, by active cell index. */
      std::vector<FullMatrix<double>> cell_mass_integrals;
    };
  } // namespace MassMatrix
} // namespace fmpm

#endif
