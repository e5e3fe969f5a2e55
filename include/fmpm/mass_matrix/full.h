// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_mass_matrix_full_h
#define fmpm_mass_matrix_full_h

#include <fmpm/mass_matrix/full_solve.h>
#include <fmpm/mass_matrix/interface.h>

#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <map>
#include <string>

namespace fmpm
{
  namespace MassMatrix
  {
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
      /** Padding layer: the solves of the mirror iteration, and their cap. */
      mutable unsigned long long    n_mirror_sweeps   = 0;
      static constexpr unsigned int max_mirror_sweeps = 100;
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
