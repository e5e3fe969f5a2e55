// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_history_h
#define fmpm_postprocess_history_h

#include <deal.II/base/tensor.h>
#include <deal.II/particles/property_pool.h>

#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <boost/serialization/vector.hpp>

namespace fmpm
{
  using namespace dealii;

  /** @brief One row of history.csv. */
  template <int dim>
  struct HistoryRow
  {
    unsigned int   step             = 0;
    double         time             = 0;
    double         dt               = 0;
    double         kinetic_energy   = 0;
    double         strain_energy    = 0;
    double         potential_energy = 0;
    double         total_energy     = 0;
    Tensor<1, dim> momentum;
    double         mass = 0;
    /** Relative L2 errors against the reference solution (or NaN). */
    double error_velocity_l2     = 0;
    double error_displacement_l2 = 0;
    /** Energy dissipated by the particle updates since the start. */
    double dissipated_energy = 0;
    /** The RMS of J − 1 over the points. */
    double volume_change_rms = 0;
    /** The checkerboard indicator of J (postprocess/checkerboard.h). */
    double checkerboard_j = 0;
    /** Force each reaction label's boundary exerts on the material in the
     * last step (reaction_<label>_x, ...). Units: N (N/m in 2D). */
    std::vector<Tensor<1, dim>> reactions;
    /** The values of open()'s extra columns (per-material sums, contact). */
    std::vector<double> extra;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &step &time &dt &kinetic_energy &strain_energy &potential_energy
        &total_energy &momentum &mass &error_velocity_l2 &error_displacement_l2
          &dissipated_energy &reactions &extra &volume_change_rms
            &checkerboard_j;
    }
  };

  /**
   * @brief The time history of a run: kept in memory and written row by row
   * (flushed) to history.csv on rank 0, so that a failed run keeps every row
   * written before the failure.
   */
  template <int dim>
  class History
  {
  public:
    /** @brief Open @p file_name (rank 0 only) and write the header, then
     * the rows a checkpoint restored (serialize()), so that history.csv of
     * a resumed run holds exactly the rows up to the checkpoint followed by
     * the new ones. */
    void
    open(const std::string              &file_name,
         const bool                      is_root,
         const bool                      with_errors,
         const bool                      with_dissipation,
         const std::vector<std::string> &reaction_labels = {},
         const std::vector<std::string> &extra_columns   = {});

    void
    add(const HistoryRow<dim> &row);

    const std::vector<HistoryRow<dim>> &
    rows() const
    {
      return all_rows;
    }

    /** Ids of the points of Output/Tracked points, in its order (their
     * columns trackN_ux, ...). */
    std::vector<types::particle_index> tracked_point_ids;
    /** Whether the run has warned that the checkerboard indicator passed
     * its threshold. */
    bool checkerboard_warned = false;

    /** A comment line written above the header (without '# '), empty for
     * none: axisymmetric runs say that their sums are per radian. */
    std::string preamble;

    /** What a checkpoint keeps: the rows so far. */
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &all_rows;
    }

  private:
    /** Open @p file_name and write the header of the columns. */
    void
    write_header(const std::string              &file_name,
                 const std::vector<std::string> &reaction_labels,
                 const std::vector<std::string> &extra_columns);

    std::vector<HistoryRow<dim>>   all_rows;
    std::unique_ptr<std::ofstream> file;
    bool                           with_errors      = false;
    bool                           with_dissipation = false;
    unsigned int                   n_reactions      = 0;
    unsigned int                   n_extra          = 0;
  };
} // namespace fmpm

#endif
