// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/interface.h>
#include <fmpm/postprocess/checkerboard.h>
#include <fmpm/postprocess/energy_balance.h>
#include <fmpm/postprocess/history_file.h>
#include <fmpm/simulation_control.h>
#include <fmpm/simulator.h>
#include <fmpm/velocity_conditions.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <sstream>

#include <boost/archive/binary_iarchive.hpp>
#include <boost/archive/binary_oarchive.hpp>

namespace fmpm
{
  namespace Postprocess
  {
    namespace
    {
      /** The names of the Cauchy stress components of the columns. */
      template <int dim>
      std::vector<std::string>
      stress_names()
      {
        return dim == 2 ?
                 std::vector<std::string>{"xx", "yy", "xy"} :
                 std::vector<std::string>{"xx", "yy", "zz", "xy", "xz", "yz"};
      }
    } // namespace



    template <int dim>
    void
    HistoryFile<dim>::start()
    {
      const Parameters &parameters = this->get_parameters();
      if (parameters.axisymmetric)
        history.preamble =
          "Geometry = axisymmetric (x = r, y = z): mass, momentum, energies "
          "and reactions per radian";
      history.open(parameters.output.directory + "/history.csv",
                   Utilities::MPI::this_mpi_process(
                     this->get_mpi_communicator()) == 0,
                   parameters.reference.enable,
                   parameters.output.track_dissipation,
                   this->get_velocity_conditions().labels(),
                   extra_columns());
    }



    template <int dim>
    void
    HistoryFile<dim>::execute(const GlobalStatistics<dim> &statistics)
    {
      TimerOutput::Scope       timer(this->get_computing_timer(), "output");
      const SimulationControl &control = this->get_simulation_control();
      HistoryRow<dim>          row;
      row.step              = control.step_number();
      row.time              = control.time();
      row.dt                = control.time_step();
      row.kinetic_energy    = statistics.kinetic_energy;
      row.strain_energy     = statistics.strain_energy;
      row.potential_energy  = statistics.potential_energy;
      row.total_energy      = statistics.total_energy();
      row.momentum          = statistics.momentum;
      row.mass              = statistics.mass;
      row.dissipated_energy = this->get_energy_balance().dissipated_energy;
      row.reactions         = this->get_reactions().forces;
      if (statistics.per_material.size() > 0)
        {
          // Per material: mass, centre-of-mass velocity, volume-averaged
          // Cauchy stress, kinetic and strain energy; then the contact sums.
          const unsigned int stride = GlobalStatistics<dim>::material_stride();
          for (unsigned int a = 0; a < this->get_parameters().size.n_materials;
               ++a)
            {
              const double *sums = &statistics.per_material[a * stride];
              const double  mass = sums[0], volume = sums[1 + dim];
              row.extra.push_back(mass);
              for (unsigned int d = 0; d < dim; ++d)
                row.extra.push_back(mass > 0 ? sums[1 + d] / mass : 0.);
              for (unsigned int c = 0; c < GlobalStatistics<dim>::n_stress; ++c)
                row.extra.push_back(volume > 0 ? sums[2 + dim + c] / volume :
                                                 0.);
              row.extra.push_back(sums[stride - 2]);
              row.extra.push_back(sums[stride - 1]);
            }
          const auto [friction_work, contact_nodes] =
            this->get_contact() ? this->contact_history_values() :
                                  std::make_pair(0., 0.);
          row.extra.push_back(friction_work);
          row.extra.push_back(contact_nodes);
        }
      for (const double value : this->mass_matrix_history_values())
        row.extra.push_back(value);
      for (const double value : tracked_point_values())
        row.extra.push_back(value);
      row.error_velocity_l2 =
        statistics.velocity_reference_squared > 0 ?
          std::sqrt(statistics.velocity_error_squared /
                    statistics.velocity_reference_squared) :
          std::sqrt(statistics.velocity_error_squared / statistics.mass);
      row.error_displacement_l2 =
        statistics.displacement_reference_squared > 0 ?
          std::sqrt(statistics.displacement_error_squared /
                    statistics.displacement_reference_squared) :
          std::sqrt(statistics.displacement_error_squared / statistics.mass);
      compute_checkerboard(row);
      history.add(row);
      warn_of_checkerboard(row);
    }



    template <int dim>
    void
    HistoryFile<dim>::warn_of_checkerboard(const HistoryRow<dim> &row)
    {
      if (row.checkerboard_j <= Checkerboard::warning_threshold<dim> ||
          history.checkerboard_warned)
        return;
      history.checkerboard_warned = true;
      if (Utilities::MPI::this_mpi_process(this->get_mpi_communicator()) == 0 &&
          !this->get_parameters().test_mode)
        std::cerr
          << "fmpm: warning: the checkerboard indicator of J "
             "(history.csv column checkerboard_j) is "
          << format_number(row.checkerboard_j, 3)
          << " at t = " << format_number(row.time, 6) << ", above "
          << format_number(Checkerboard::warning_threshold<dim>)
          << ": neighbouring points have J alternating by more than the "
             "deformation the grid resolves, and the results are "
             "unreliable from here on (doc/studies/cantilever.md). Use "
             "a position update that matches the strain update "
             "('Particle update/Flip/Position update psi = auto', the "
             "default), a smaller Time/Courant number, or psi = 0 where the "
             "forces follow the positions (contact, interface springs; "
             "doc/choosing_a_method.md)."
          << std::endl;
    }



    template <int dim>
    void
    HistoryFile<dim>::compute_checkerboard(HistoryRow<dim> &row) const
    {
      using Index                       = PropertyIndex<dim>;
      const MaterialPoints<dim> &points = this->get_material_points();
      // J per point in the store's (cell) order, then the sums cell by cell.
      std::vector<double> J(points.n_points());
      for (unsigned int k = 0; k < points.n_points(); ++k)
        J[k] = determinant(
          get_tensor3(points.record(k), Index::deformation_gradient));
      const double      *mass = points.column(Index::mass);
      Checkerboard::Sums sums;
      for (unsigned int c = 0; c < points.n_cells(); ++c)
        {
          const unsigned int begin = points.cell_point_begin[c],
                             n     = points.cell_point_begin[c + 1] - begin;
          sums += Checkerboard::cell_sums<dim>(
            ArrayView<const Point<dim>>(points.position.data() + begin, n),
            ArrayView<const double>(mass + begin, n),
            ArrayView<const double>(J.data() + begin, n));
        }
      std::vector<double> global = {sums.residual,
                                    sums.volume_change,
                                    sums.mass};
      Utilities::MPI::sum(global, this->get_mpi_communicator(), global);
      sums.residual         = global[0];
      sums.volume_change    = global[1];
      sums.mass             = global[2];
      row.volume_change_rms = sums.volume_change_rms();
      double largest_rms    = row.volume_change_rms;
      for (const auto &earlier : history.rows())
        largest_rms = std::max(largest_rms, earlier.volume_change_rms);
      row.checkerboard_j =
        Checkerboard::indicator(sums.residual_rms(), largest_rms);
    }



    template <int dim>
    std::vector<std::string>
    HistoryFile<dim>::extra_columns() const
    {
      std::vector<std::string> columns = material_columns();
      for (const auto &column : this->get_mass_matrix().history_columns())
        columns.push_back(column);
      for (const auto &column : tracked_point_columns())
        columns.push_back(column);
      return columns;
    }



    template <int dim>
    std::vector<std::string>
    HistoryFile<dim>::material_columns() const
    {
      std::vector<std::string> columns;
      const unsigned int n_materials = this->get_parameters().size.n_materials;
      if (n_materials < 2)
        return columns;
      for (unsigned int a = 0; a < n_materials; ++a)
        {
          const std::string n = "_material_" + std::to_string(a);
          columns.push_back("mass" + n);
          for (unsigned int d = 0; d < dim; ++d)
            columns.push_back(std::string("velocity_") + "xyz"[d] + n);
          for (const auto &c : stress_names<dim>())
            columns.push_back("stress_" + c + n);
          columns.push_back("kinetic_energy" + n);
          columns.push_back("strain_energy" + n);
        }
      columns.push_back("friction_work");
      columns.push_back("contact_nodes");
      return columns;
    }



    template <int dim>
    void
    HistoryFile<dim>::find_tracked_points()
    {
      using Index                       = PropertyIndex<dim>;
      const MaterialPoints<dim> &points = this->get_material_points();
      const MPI_Comm mpi_communicator   = this->get_mpi_communicator();
      history.tracked_point_ids.clear();
      const std::string &text  = this->get_parameters().output.tracked_points;
      const std::string  where = "Output/Tracked points = <" + text + ">: ";
      for (const auto &entry : Utilities::split_string_list(text, ';'))
        {
          if (entry.empty())
            continue;
          const auto          fields = Utilities::split_string_list(entry, ',');
          std::vector<double> numbers;
          for (const auto &field : fields)
            {
              char        *end   = nullptr;
              const double value = std::strtod(field.c_str(), &end);
              AssertThrow(!field.empty() && *end == '\0' &&
                            std::isfinite(value),
                          ExcMessage(where + "<" + entry +
                                     "> is neither a point id nor " +
                                     std::to_string(dim) +
                                     " coordinates separated by ','."));
              numbers.push_back(value);
            }
          AssertThrow(numbers.size() == 1 || numbers.size() == dim,
                      ExcMessage(where + "<" + entry + "> has " +
                                 std::to_string(numbers.size()) +
                                 " numbers: give a point id (one integer) or "
                                 "a position (" +
                                 std::to_string(dim) + " coordinates)."));
          if (numbers.size() == 1)
            {
              AssertThrow(numbers[0] >= 0 &&
                            numbers[0] == std::floor(numbers[0]),
                          ExcMessage(where + "the point id <" + entry +
                                     "> is not an integer >= 0."));
              const auto id  = static_cast<types::particle_index>(numbers[0]);
              bool       has = false;
              for (unsigned int k = 0; k < points.n_points() && !has; ++k)
                has = points.id[k] == id;
              AssertThrow(Utilities::MPI::logical_or(has, mpi_communicator),
                          ExcMessage(
                            where + "no material point has id " + entry +
                            " (the scene has " +
                            std::to_string(
                              this->get_simulator().n_material_points()) +
                            " points)."));
              history.tracked_point_ids.push_back(id);
              continue;
            }
          // The point whose initial position is nearest (the smallest id
          // among equally near ones); the position must lie in the box of a
          // point's initial domain, X ± l0.
          Point<dim> position;
          for (unsigned int d = 0; d < dim; ++d)
            position[d] = numbers[d];
          double                distance = std::numeric_limits<double>::max();
          types::particle_index nearest =
            std::numeric_limits<types::particle_index>::max();
          bool inside = false;
          for (unsigned int k = 0; k < points.n_points(); ++k)
            {
              const PointRecord p = points.record(k);
              const Point<dim>  X(get_vector<dim>(p, Index::initial_position));
              const Tensor<1, dim> l0 =
                get_vector<dim>(p, Index::initial_half_length);
              bool in_domain = true;
              for (unsigned int d = 0; d < dim; ++d)
                in_domain = in_domain &&
                            std::abs(position[d] - X[d]) <= l0[d] * (1 + 1e-12);
              inside         = inside || in_domain;
              const double r = position.distance(X);
              if (r < distance || (r == distance && points.id[k] < nearest))
                {
                  distance = r;
                  nearest  = points.id[k];
                }
            }
          const auto distances =
            Utilities::MPI::all_gather(mpi_communicator, distance);
          const auto ids =
            Utilities::MPI::all_gather(mpi_communicator, nearest);
          distance = std::numeric_limits<double>::max();
          for (unsigned int r = 0; r < ids.size(); ++r)
            if (distances[r] < distance ||
                (distances[r] == distance && ids[r] < nearest))
              {
                distance = distances[r];
                nearest  = ids[r];
              }
          std::ostringstream place;
          place << "(" << position << ")";
          AssertThrow(Utilities::MPI::logical_or(inside, mpi_communicator),
                      ExcMessage(where + "the position " + place.str() +
                                 " lies outside every body (the nearest "
                                 "material point, id " +
                                 std::to_string(nearest) + ", started " +
                                 format_number(distance, 6) + " m from it)."));
          history.tracked_point_ids.push_back(nearest);
        }
    }



    template <int dim>
    std::vector<std::string>
    HistoryFile<dim>::tracked_point_columns() const
    {
      std::vector<std::string> columns;
      for (unsigned int n = 0; n < history.tracked_point_ids.size(); ++n)
        {
          const std::string prefix = "track" + std::to_string(n + 1) + "_";
          for (const char quantity : {'u', 'v'})
            for (unsigned int d = 0; d < dim; ++d)
              columns.push_back(prefix + quantity + "xyz"[d]);
          for (const auto &c : stress_names<dim>())
            columns.push_back(prefix + "s" + c);
        }
      return columns;
    }



    template <int dim>
    std::vector<double>
    HistoryFile<dim>::tracked_point_values() const
    {
      using Index                         = PropertyIndex<dim>;
      const MaterialPoints<dim> &points   = this->get_material_points();
      constexpr unsigned int     n_stress = GlobalStatistics<dim>::n_stress;
      constexpr unsigned int     n_values = 2 * dim + n_stress;
      // The stored stress slots of xx, yy, xy in 2D (xx, yy, zz, xy, xz, yz
      // in 3D), as in compute_statistics().
      constexpr unsigned int stress_slots[6] = {0, 1, 3, 2, 4, 5};
      const unsigned int     n_tracked       = history.tracked_point_ids.size();
      // Each value from the one rank that owns the point, zeros from the
      // others (the sums are exact), and the count of owners.
      std::vector<double> values(n_tracked * (n_values + 1), 0.);
      if (n_tracked == 0)
        return values;
      for (unsigned int k = 0; k < points.n_points(); ++k)
        for (unsigned int n = 0; n < n_tracked; ++n)
          if (points.id[k] == history.tracked_point_ids[n])
            {
              const PointRecord p = points.record(k);
              const Point<dim>  X(get_vector<dim>(p, Index::initial_position));
              const Tensor<1, dim> u   = points.position[k] - X;
              const Tensor<1, dim> V   = get_vector<dim>(p, Index::velocity);
              double *const        row = &values[n * n_values];
              for (unsigned int d = 0; d < dim; ++d)
                {
                  row[d]       = u[d];
                  row[dim + d] = V[d];
                }
              for (unsigned int c = 0; c < n_stress; ++c)
                row[2 * dim + c] =
                  p[Index::stress + (dim == 2 ? stress_slots[c] : c)];
              values[n_tracked * n_values + n] = 1;
            }
      Utilities::MPI::sum(values, this->get_mpi_communicator(), values);
      for (unsigned int n = 0; n < n_tracked; ++n)
        if (values[n_tracked * n_values + n] == 0)
          std::fill(values.begin() + n * n_values,
                    values.begin() + (n + 1) * n_values,
                    std::numeric_limits<double>::quiet_NaN());
      values.resize(n_tracked * n_values);
      return values;
    }



    template <int dim>
    void
    HistoryFile<dim>::save(
      std::map<std::string, std::string> &status_strings) const
    {
      std::ostringstream out;
      {
        boost::archive::binary_oarchive archive(out);
        archive << history;
      }
      status_strings["History"] = out.str();
    }



    template <int dim>
    void
    HistoryFile<dim>::load(
      const std::map<std::string, std::string> &status_strings)
    {
      const auto saved = status_strings.find("History");
      if (saved == status_strings.end())
        return;
      std::istringstream              in(saved->second);
      boost::archive::binary_iarchive archive(in);
      archive >> history;
    }



    template class HistoryFile<2>;
    template class HistoryFile<3>;
  } // namespace Postprocess
} // namespace fmpm
