// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_visualization_h
#define fmpm_postprocess_visualization_h

#include <fmpm/postprocess/interface.h>

#include <future>
#include <string>
#include <utility>
#include <vector>

namespace fmpm
{
  namespace Postprocess
  {
    /**
     * @brief The VTU files of an output (Output/Write vtu): the points
     * (particles_NNNNN.R.vtu) and the grid (grid_NNNNN.R.vtu) of every
     * rank, their .pvtu records and particles.pvd and grid.pvd (deal.II
     * step-70), which a checkpoint keeps so that they continue after a
     * restart (Lethe's PVDHandler). The pieces are compressed and written
     * in a background thread while the run continues (ASPECT's 'Write in
     * background thread').
     */
    template <int dim>
    class Visualization : public Interface<dim>
    {
    public:
      ~Visualization() override;

      void
      execute(const GlobalStatistics<dim> &statistics) override;

      void
      finish() override;

      void
      save(std::map<std::string, std::string> &status_strings) const override;

      /** Restore the records and write the .pvd files as they were at the
       * checkpoint (outputs written after it by the run that stopped are
       * written again). */
      void
      load(const std::map<std::string, std::string> &status_strings) override;

    private:
      /** (time, .pvtu name) of every output so far. */
      std::vector<std::pair<double, std::string>> particle_pvd_records;
      std::vector<std::pair<double, std::string>> grid_pvd_records;
      /** The writer of the last output's pieces (no MPI there). */
      std::future<void> writer;

      /** Write particles.pvd and grid.pvd (rank 0). */
      void
      write_pvd_records() const;
    };
  } // namespace Postprocess
} // namespace fmpm

#endif
