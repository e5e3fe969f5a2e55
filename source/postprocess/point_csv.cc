// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/postprocess/point_csv.h>
#include <fmpm/simulation_control.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <utility>
#include <vector>

namespace fmpm
{
  namespace Postprocess
  {
    template <int dim>
    void
    PointCsv<dim>::execute(const GlobalStatistics<dim> &)
    {
      TimerOutput::Scope timer(this->get_computing_timer(), "output");
      using Index = PropertyIndex<dim>;
      const ParticleProperties<dim> &particle_properties =
        this->get_particle_properties();
      const MaterialPoints<dim> &points = this->get_material_points();
      const MPI_Comm mpi_communicator   = this->get_mpi_communicator();
      // Optional per-point state of the constitutive models (0 otherwise).
      const bool has_energy = particle_properties.has("internal_energy");
      const bool has_plastic_strain = particle_properties.has("plastic_strain");
      const unsigned int energy_slot =
        has_energy ? particle_properties.offset("internal_energy") : 0;
      const unsigned int plastic_slot =
        has_plastic_strain ? particle_properties.offset("plastic_strain") : 0;
      // Stored stress order xx, yy, zz, xy, xz, yz; 2D writes xx, yy, xy,
      // axisymmetric also the hoop stress zz (column stress_hoop).
      const bool axisymmetric = this->get_parameters().axisymmetric;
      const std::vector<unsigned int> stress_slots =
        dim == 2 ? (axisymmetric ? std::vector<unsigned int>{0, 1, 3, 2} :
                                   std::vector<unsigned int>{0, 1, 3}) :
                   std::vector<unsigned int>{0, 1, 2, 3, 4, 5};
      const unsigned int n_columns = 2 + 2 * dim + stress_slots.size() + 4;

      std::vector<std::pair<types::particle_index, std::vector<double>>> local;
      local.reserve(points.n_points());
      for (unsigned int k = 0; k < points.n_points(); ++k)
        {
          const PointRecord   p = points.record(k);
          std::vector<double> row;
          row.reserve(n_columns);
          row.push_back(p[Index::body_id]);
          row.push_back(p[Index::material_id]);
          for (unsigned int d = 0; d < dim; ++d)
            row.push_back(points.position[k][d]);
          for (unsigned int d = 0; d < dim; ++d)
            row.push_back(p[Index::velocity + d]);
          for (const unsigned int c : stress_slots)
            row.push_back(p[Index::stress + c]);
          row.push_back(
            -(p[Index::stress] + p[Index::stress + 1] + p[Index::stress + 2]) /
            3.);
          row.push_back(
            determinant(get_tensor3(p, Index::deformation_gradient)));
          row.push_back(has_energy ? p[energy_slot] : 0.);
          row.push_back(has_plastic_strain ? p[plastic_slot] : 0.);
          local.emplace_back(points.id[k], std::move(row));
        }
      const auto all = Utilities::MPI::gather(mpi_communicator, local, 0);
      if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
        return;
      std::vector<std::pair<types::particle_index, std::vector<double>>> rows;
      for (const auto &rank : all)
        rows.insert(rows.end(), rank.begin(), rank.end());
      std::sort(rows.begin(), rows.end(), [](const auto &a, const auto &b) {
        return a.first < b.first;
      });

      const char        *axes = "xyz";
      std::ostringstream name;
      name << this->get_parameters().output.directory << "/particles_"
           << std::setw(5) << std::setfill('0')
           << this->get_simulation_control().output_number() << ".csv";
      std::ofstream out(name.str());
      AssertThrow(out, ExcMessage("Cannot write <" + name.str() + ">."));
      out << "id,body,material";
      for (unsigned int d = 0; d < dim; ++d)
        out << ',' << axes[d];
      for (unsigned int d = 0; d < dim; ++d)
        out << ",v" << axes[d];
      for (const unsigned int c : stress_slots)
        if (dim == 2 && c == 2)
          out << ",stress_hoop";
        else
          out << ",stress_" << axes[stress_component_i[c]]
              << axes[stress_component_j[c]];
      out << ",pressure,J,internal_energy,plastic_strain\n";
      out << std::setprecision(12);
      for (const auto &row : rows)
        {
          out << row.first << ',' << static_cast<int>(row.second[0]) << ','
              << static_cast<int>(row.second[1]);
          for (unsigned int c = 2; c < row.second.size(); ++c)
            out << ',' << row.second[c];
          out << '\n';
        }
    }

    template class PointCsv<2>;
    template class PointCsv<3>;
  } // namespace Postprocess
} // namespace fmpm
