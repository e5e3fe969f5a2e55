// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_history_file_h
#define fmpm_postprocess_history_file_h

#include <fmpm/postprocess/history.h>
#include <fmpm/postprocess/interface.h>

#include <string>
#include <vector>

namespace fmpm
{
  namespace Postprocess
  {
    /**
     * @brief history.csv: one row per output with the global statistics,
     * the reactions, the materials' sums and contact's (2+ materials), the
     * mass matrix's columns, the tracked points (Output/Tracked points),
     * the volume change and the checkerboard indicator of J
     * (postprocess/checkerboard.h). A checkpoint keeps its rows; a resumed
     * run writes them again.
     */
    template <int dim>
    class HistoryFile : public Interface<dim>
    {
    public:
      /** The ids of Output/Tracked points: a position takes the point whose
       * initial position is nearest to it (the same at the start and on
       * resume). Throws, naming the entry, for a position outside every
       * body or an id no point has. Collective. */
      void
      find_tracked_points();

      /** Open history.csv and write its header (and the rows a checkpoint
       * restored). */
      void
      start() override;

      /** Add the row of the current step. Collective. */
      void
      execute(const GlobalStatistics<dim> &statistics) override;

      void
      save(std::map<std::string, std::string> &status_strings) const override;

      void
      load(const std::map<std::string, std::string> &status_strings) override;

      /** The rows written so far. */
      const std::vector<HistoryRow<dim>> &
      rows() const
      {
        return history.rows();
      }

    private:
      /** The extra columns: the materials', then the mass matrix's
       * (MassMatrix::Interface::history_columns()), then the tracked
       * points'. */
      std::vector<std::string>
      extra_columns() const;
      /** The columns of scenes with 2+ materials (per material, then
       * friction_work and contact_nodes). */
      std::vector<std::string>
      material_columns() const;
      /** The columns of the tracked points (trackN_ux, ...). */
      std::vector<std::string>
      tracked_point_columns() const;
      /** Displacement x - X, velocity and Cauchy stress of each tracked
       * point in the order of tracked_point_columns() (NaN for a point that
       * left the mesh), the same on every rank. Collective. */
      std::vector<double>
      tracked_point_values() const;
      /** Set the volume_change_rms and checkerboard_j of @p row (over all
       * ranks). */
      void
      compute_checkerboard(HistoryRow<dim> &row) const;
      /** Warn once when the checkerboard indicator of @p row passes its
       * threshold. */
      void
      warn_of_checkerboard(const HistoryRow<dim> &row);

      History<dim> history;
    };
  } // namespace Postprocess
} // namespace fmpm

#endif
