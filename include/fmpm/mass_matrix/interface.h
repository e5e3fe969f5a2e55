// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_mass_matrix_interface_h
#define fmpm_mass_matrix_interface_h

#include <fmpm/grid_vectors.h>
#include <fmpm/mass_matrix/full_solve.h>
#include <fmpm/plugins.h>
#include <fmpm/simulator_access.h>
#include <fmpm/time_step_stability.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace fmpm
{
  /**
   * @defgroup MassMatrices Mass matrices
   * The maps from grid momenta to grid velocities, v = m̃ₖ⁻¹ p.
   */
  namespace MassMatrix
  {
    /**
     * @brief Interface of mass matrices: how grid velocities follow from grid
     * momenta (seed 000 Eqs. 1.5-1.6, 1.22-1.23).
     *
     * The Simulator calls setup() after every particle-to-grid pass (when the
     * lumped masses m = SᵀM, and m̃ = SᵀMS if requested, are known), then
     * solve() for each momentum-like grid field that must become a velocity
     * (p, p⁺, f). solve() writes locally owned entries only.
     *
     * @ingroup MassMatrices
     */
    template <int dim>
    class Interface : public Plugins::InterfaceBase, public SimulatorAccess<dim>
    {
    public:
      static void
      declare_parameters(ParameterHandler &)
      {}

      /** @brief Whether the particle-to-grid pass must assemble m̃ = SᵀMS. */
      virtual bool
      needs_full_mass_matrix() const
      {
        return false;
      }

      /** @brief Whether the solves read the known velocities of the grid
       * conditions (SimulatorAccess::get_known_velocity_mask()). */
      virtual bool
      reads_known_velocities() const
      {
        return false;
      }

      /**
       * @brief Whether m̃ may come as cell-wise local matrices
       * (CellwiseMatrix) instead of an assembled sparse matrix, when the
       * mesh allows it (no hanging nodes, classic shape functions).
       */
      virtual bool
      accepts_cellwise_full_mass_matrix() const
      {
        return false;
      }

      /** @brief The CG settings of an exact solve v = m̃⁻¹p (the
       * multimaterial exact solve uses them), or none. */
      using ExactSolveSettings = MassMatrix::ExactSolveSettings;
      virtual std::optional<ExactSolveSettings>
      exact_solve() const
      {
        return {};
      }

      /** @brief Called once per step after the masses are extrapolated. */
      virtual void
      setup()
      {}

      /** @brief v = m̃ₖ⁻¹ p for every component of @p momentum. */
      virtual void
      solve(const GridVectorField &momentum,
            GridVectorField       &velocity) const = 0;

      /**
       * @brief As solve(), but @p velocity holds on entry a guess of the
       * result (the same field one step earlier) that iterative solvers
       * start from, and their residual counts relative to
       * max(|momentum|, @p residual_scale) (for accelerations: momenta over
       * Δt, so that a Δt is as accurate as the velocities).
       */
      virtual void
      solve_from_guess(const GridVectorField &momentum,
                       GridVectorField       &velocity,
                       const double           residual_scale) const
      {
        (void)residual_scale;
        solve(momentum, velocity);
      }

      /**
       * @brief p = M v with the forward operator of this mass matrix (m for
       * lumped, m̃ for fmpm and full, the FE matrix for consistent), on
       * locally owned nodes; used by the unlumped #2 boundary-condition
       * method (seed 000 Eq. 2.56).
       */
      virtual void
      vmult(const GridVectorField &velocity, GridVectorField &momentum) const
      {
        const GridScalar &m = this->get_lumped_mass();
        for (unsigned int b = 0; b < velocity.n_blocks(); ++b)
          for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
            momentum.block(b).local_element(i) =
              m.local_element(i) * velocity.block(b).local_element(i);
      }

      /**
       * @brief Figures for summary.json (e.g. CG iteration counts), called
       * once at the end of a run.
       */
      virtual std::map<std::string, double>
      statistics() const
      {
        return {};
      }

      /**
       * @brief Extra history.csv columns of this mass matrix (e.g. the
       * order an adaptive series used), and their values over the steps
       * since the previous output (called once per output, on every rank).
       */
      virtual std::vector<std::string>
      history_columns() const
      {
        return {};
      }

      virtual std::vector<double>
      history_values()
      {
        return {};
      }

      /**
       * @brief Called at the start of every time step (step number before
       * the step, its start time and length): whether this step uses the
       * mass matrix's own inverse; false for the lumped steps between the
       * full-mass steps of a periodic FMPM(k). solve() and vmult() then act
       * as the lumped matrix.
       */
      virtual bool
      begin_step(const unsigned int /*step*/,
                 const double /*time*/,
                 const double /*time_step*/)
      {
        return true;
      }

      /** @brief Whether begin_step() can return false (periodic FMPM(k):
       * FLIP with the lumped matrix in the steps between). */
      virtual bool
      periodic() const
      {
        return false;
      }

      /** @brief The adaptive order's relative increment tolerance (0:
       * none, the series always has order() terms). */
      virtual double
      increment_tolerance() const
      {
        return 0;
      }

      /** @brief The order k of the approximation m̃ₖ (1 for lumped). */
      virtual unsigned int
      order() const
      {
        return 1;
      }

      /**
       * @brief The largest Courant number at which this mass matrix was
       * measured stable with the rest of @p method, and what that rests on
       * (Stability; called once the plugin has parsed its parameters).
       */
      virtual StabilityLimit
      stability_limit(const StabilityMethod &method) const
      {
        (void)method;
        StabilityLimit limit;
        limit.basis = "this mass matrix (not measured: no limit)";
        return limit;
      }

      /** @brief Whether multimaterial contact (Contact/Model name =
       * multimaterial) works with this mass matrix. */
      virtual bool
      supports_multimaterial_contact() const
      {
        return false;
      }
    };

    template <int dim>
    using Registry = Plugins::Registry<Interface<dim>>;

    /**
     * @brief v = m⁻¹p on locally owned nodes, zero where m is below
     * @p mass_floor (nodes no material point touches).
     */
    void
    apply_lumped_inverse(const GridScalar      &lumped_mass,
                         const GridVectorField &momentum,
                         GridVectorField       &velocity,
                         const double           mass_floor);

    /** @brief dst = m̃ src, component by component. */
    void
    apply_full_mass(const TrilinosWrappers::SparseMatrix &full_mass,
                    GridVectorField                      &dst,
                    const GridVectorField                &src);

    /**
     * @brief dst = m̃ src for all components in one pass over the cell
     * matrices.
     */
    void
    apply_full_mass(const CellwiseMatrix  &full_mass,
                    GridVectorField       &dst,
                    const GridVectorField &src);
  } // namespace MassMatrix
} // namespace fmpm

#define FMPM_REGISTER_MASS_MATRIX(CLASSNAME, NAME, DESCRIPTION) \
  FMPM_REGISTER_PLUGIN(::fmpm::MassMatrix::Interface,           \
                       CLASSNAME,                               \
                       NAME,                                    \
                       DESCRIPTION)

#endif
