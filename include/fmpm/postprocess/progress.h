// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_progress_h
#define fmpm_postprocess_progress_h

#include <fmpm/postprocess/interface.h>

namespace fmpm
{
  namespace Postprocess
  {
    /**
     * @brief The progress lines of a run on standard output ("*** Step
     * ..."): step, t, Δt, the energies, the share of the end time done,
     * the wall time and an estimate of what is left; at the start, every
     * Output/Progress seconds and at the end.
     */
    template <int dim>
    class Progress : public Interface<dim>
    {
    public:
      /** Nothing at an output. */
      void
      execute(const GlobalStatistics<dim> &) override
      {}

      /** Whether Output/Progress seconds have passed since the last line
       * (rank 0's answer counts). */
      bool
      progress_due() const override;

      /** Print the line of @p statistics. */
      void
      progress(const GlobalStatistics<dim> &statistics) override;

    private:
      /** MPI_Wtime() at the last line. */
      double last_line_wall = -1e30;
    };
  } // namespace Postprocess
} // namespace fmpm

#endif
