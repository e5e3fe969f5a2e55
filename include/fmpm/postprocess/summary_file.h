// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_summary_file_h
#define fmpm_postprocess_summary_file_h

#include <fmpm/postprocess/interface.h>

#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace fmpm
{
  namespace Postprocess
  {
    /**
     * @brief summary.json: the run's status, sizes, wall time and its
     * phases (the timer sections), memory, the final energies and errors,
     * the figures of the mass matrix, contact and velocity conditions;
     * written when the run ends (also on a failure) and when it stops on a
     * signal. Closes a run that did not fail with the share of the wall
     * time the timer sections cover.
     */
    template <int dim>
    class SummaryFile : public Interface<dim>
    {
    public:
      /** Nothing at an output. */
      void
      execute(const GlobalStatistics<dim> &) override
      {}

      void
      stopping(const std::string &status) override;

      void
      end_of_run(const std::string       &status,
                 const SimulationFailure *failure) override;

    private:
      /** Write summary.json with @p status and @p failure or nullptr
       * (collective). */
      void
      write(const std::string &status, const SimulationFailure *failure);

      /** The entries of a run with adaptive refinement: adaptations, the
       * mean and largest cell counts against the uniform finest mesh. */
      void
      write_adaptation(std::ostream &out) const;

      /** The entries of the results: energies, errors, contact, conditions,
       * mass matrix. */
      void
      write_results(
        std::ostream                                      &out,
        const GlobalStatistics<dim>                       &statistics,
        const SimulationFailure                           *failure,
        const double                                       condition_error,
        const std::vector<std::pair<std::string, double>> &contact_figures,
        const std::map<std::string, double> &mass_matrix_statistics) const;

      /** The share of the wall time inside the timer sections (the last
       * summary's). */
      double timer_coverage = 0;
    };
  } // namespace Postprocess
} // namespace fmpm

#endif
