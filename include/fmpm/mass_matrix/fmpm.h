// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_mass_matrix_fmpm_h
#define fmpm_mass_matrix_fmpm_h

#include <fmpm/mass_matrix/interface.h>
#include <fmpm/mass_matrix/series.h>

#include <deal.II/lac/trilinos_sparse_matrix.h>


namespace fmpm
{
  namespace MassMatrix
  {
    /**
     * @brief FMPM(k): the approximate full-mass-matrix inverse m̃ₖ⁻¹.
     *
     * @ingroup MassMatrices
     */
    template <int dim>
    class Fmpm : public Interface<dim>
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm);

      void
      parse_parameters(ParameterHandler &prm) override;

      /** m̃ is assembled in the steps that use the series only. */
      bool
      needs_full_mass_matrix() const override
      {
        return k > 1 && series_this_step;
      }

      bool
      reads_known_velocities() const override
      {
        return true;
      }

      bool
      begin_step(const unsigned int step,
                 const double       time,
                 const double       time_step) override;

      bool
      periodic() const override
      {
        return period > 1 || period_time > 0;
      }

      bool
      accepts_cellwise_full_mass_matrix() const override
      {
        return true;
      }

      void
      solve(const GridVectorField &momentum,
            GridVectorField       &velocity) const override;

      /** p = m̃ v (the assembled m̃ for m̃_k; m v for k = 1). */
      void
      vmult(const GridVectorField &velocity,
            GridVectorField       &momentum) const override;

      unsigned int
      order() const override
      {
        return k;
      }

      double
      increment_tolerance() const override
      {
        return tolerance;
      }

      /** The bar's limits for k <= 10, falling as 1/k (1/sqrt(k) with
       * smooth shape functions) above; capped when periodic. */
      StabilityLimit
      stability_limit(const StabilityMethod &method) const override;

      /** Multimaterial XPIC(k)/FMPM(k). */
      bool
      supports_multimaterial_contact() const override
      {
        return true;
      }

      std::vector<std::string>
      history_columns() const override;

      std::vector<double>
      history_values() override;

      std::map<std::string, double>
      statistics() const override;

      /** The order k >= 1. */
      unsigned int k = 2;
      /** Adaptive order: the relative increment that ends the series
       * early ('Increment tolerance'); 0: always k. */
      double tolerance = 0;
      /** Periodic FMPM(k): the series every 'Period' steps, or once in
       * every 'Period time' interval when that is positive; lumped steps in
       * between. */
      unsigned int period      = 1;
      double       period_time = 0;

    private:
      /** Whether the current step uses the series (begin_step()). */
      bool               series_this_step = true;
      unsigned long long series_steps     = 0;
      /** Orders used by solve() since the last output and in the run. */
      mutable unsigned long long solves_since_output = 0,
                                 orders_since_output = 0, solves = 0,
                                 orders           = 0;
      mutable unsigned int max_order_since_output = 0, max_order = 0;

      void
      count(const unsigned int order_used) const;
    };
  } // namespace MassMatrix
} // namespace fmpm

#endif
