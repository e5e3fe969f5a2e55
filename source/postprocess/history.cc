// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/postprocess/history.h>

#include <deal.II/base/exceptions.h>

#include <iomanip>

namespace fmpm
{
  template <int dim>
  void
  History<dim>::open(const std::string              &file_name,
                     const bool                      is_root,
                     const bool                      errors,
                     const bool                      dissipation,
                     const std::vector<std::string> &reaction_labels,
                     const std::vector<std::string> &extra_columns)
  {
    n_reactions      = reaction_labels.size();
    n_extra          = extra_columns.size();
    with_errors      = errors;
    with_dissipation = dissipation;
    std::vector<HistoryRow<dim>> restored;
    restored.swap(all_rows);
    if (is_root)
      write_header(file_name, reaction_labels, extra_columns);
    for (const auto &row : restored)
      add(row);
  }



  template <int dim>
  void
  History<dim>::write_header(const std::string              &file_name,
                             const std::vector<std::string> &reaction_labels,
                             const std::vector<std::string> &extra_columns)
  {
    file = std::make_unique<std::ofstream>(file_name);
    AssertThrow(*file,
                ExcMessage("Cannot write <" + file_name +
                           ">: check that the output directory is writable."));
    if (!preamble.empty())
      *file << "# " << preamble << '\n';
    *file << "step,time,dt,kinetic_energy,strain_energy,potential_energy,"
             "total_energy,momentum_x,momentum_y";
    if (dim == 3)
      *file << ",momentum_z";
    *file << ",mass";
    if (with_errors)
      *file << ",error_velocity_l2,error_displacement_l2";
    if (with_dissipation)
      *file << ",dissipated_energy";
    for (const auto &label : reaction_labels)
      for (unsigned int d = 0; d < dim; ++d)
        *file << ",reaction_" << label << '_' << "xyz"[d];
    for (const auto &column : extra_columns)
      *file << ',' << column;
    *file << ",volume_change_rms,checkerboard_j\n";
    file->flush();
  }



  template <int dim>
  void
  History<dim>::add(const HistoryRow<dim> &row)
  {
    all_rows.push_back(row);
    if (!file)
      return;
    *file << row.step << std::setprecision(12) << ',' << row.time << ','
          << row.dt << ',' << row.kinetic_energy << ',' << row.strain_energy
          << ',' << row.potential_energy << ',' << row.total_energy;
    for (unsigned int d = 0; d < dim; ++d)
      *file << ',' << row.momentum[d];
    *file << ',' << row.mass;
    if (with_errors)
      *file << ',' << row.error_velocity_l2 << ',' << row.error_displacement_l2;
    if (with_dissipation)
      *file << ',' << row.dissipated_energy;
    for (unsigned int r = 0; r < n_reactions; ++r)
      for (unsigned int d = 0; d < dim; ++d)
        *file << ',' << (r < row.reactions.size() ? row.reactions[r][d] : 0.);
    for (unsigned int c = 0; c < n_extra; ++c)
      *file << ',' << (c < row.extra.size() ? row.extra[c] : 0.);
    *file << ',' << row.volume_change_rms << ',' << row.checkerboard_j << '\n';
    file->flush();
  }

  template class History<2>;
  template class History<3>;
} // namespace fmpm
