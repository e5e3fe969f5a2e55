// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/contact/manager.h>
#include <fmpm/external_loads.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/parameters.h>
#include <fmpm/postprocess/energy_balance.h>
#include <fmpm/postprocess/history_file.h>
#include <fmpm/postprocess/summary_file.h>
#include <fmpm/simulation_control.h>
#include <fmpm/simulator.h>
#include <fmpm/timer_output.h>
#include <fmpm/velocity_conditions.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace fmpm
{
  namespace Postprocess
  {
    namespace
    {
      /** JSON string literal. */
      std::string
      quoted(const std::string &text)
      {
        std::string result = "\"";
        for (const char c : text)
          {
            if (c == '"' || c == '\\')
              result += '\\';
            if (c == '\n')
              {
                result += "\\n";
                continue;
              }
            result += c;
          }
        return result + "\"";
      }

      /** JSON number (null for NaN/Inf, which JSON cannot represent). */
      std::string
      number(const double value)
      {
        if (!std::isfinite(value))
          return "null";
        std::ostringstream out;
        out << std::setprecision(12) << value;
        return out.str();
      }

    } // namespace



    template <int dim>
    void
    SummaryFile<dim>::stopping(const std::string &status)
    {
      write(status, nullptr);
    }



    template <int dim>
    void
    SummaryFile<dim>::end_of_run(const std::string       &status,
                                 const SimulationFailure *failure)
    {
      write(status, failure);
      if (failure == nullptr)
        this->get_pcout() << "      timer sections cover " << std::fixed
                          << std::setprecision(1) << 100 * timer_coverage
                          << " % of the wall time" << std::defaultfloat
                          << std::endl;
    }



    template <int dim>
    void
    SummaryFile<dim>::write(const std::string       &status,
                            const SimulationFailure *failure)
    {
      const GlobalStatistics<dim> statistics     = this->current_statistics();
      const RunCounters          &counters       = this->get_run_counters();
      const Contact::Manager<dim> *const contact = this->get_contact();
      const MPI_Comm                     comm    = this->get_mpi_communicator();
      const Parameters                  &parameters = this->get_parameters();
      const SimulationControl &control       = this->get_simulation_control();
      const SupportCache<dim> &supports      = this->get_support_cache();
      const auto              &triangulation = this->get_triangulation();
      TimerOutput::Scope       timer(this->get_computing_timer(), "summary");
      const std::map<std::string, double> mass_matrix_statistics =
        this->get_mass_matrix().statistics();
      std::map<std::string, double> phases =
        this->get_computing_timer().get_summary_data(
          TimerOutput::total_wall_time);
      const double wall = MPI_Wtime() - counters.wall_start;
      // The share of the wall time inside the timer sections, on the
      // slowest-covered rank. Sections do not nest, but for the sub-sections
      // "<part>: <detail>" (point store, contact), which run within
      // another section and are not counted twice.
      double covered = 0;
      for (const auto &phase : phases)
        if (!is_timer_subsection(phase.first))
          covered += phase.second;
      timer_coverage =
        Utilities::MPI::min(wall > 0 ? covered / wall : 1., comm);
      // Make the phase times the maximum over ranks.
      for (auto &phase : phases)
        phase.second = Utilities::MPI::max(phase.second, comm);
      const double condition_error =
        Utilities::MPI::max(this->get_reactions().max_condition_error, comm);
      // Load balance: the largest number of points on one rank against the
      // mean.
      const double local_points =
        static_cast<double>(this->get_material_points().n_points());
      const double max_rank_points  = Utilities::MPI::max(local_points, comm);
      const double mean_rank_points = Utilities::MPI::sum(local_points, comm) /
                                      Utilities::MPI::n_mpi_processes(comm);
      // Contact: the normal method's figures (LR: fits and NLLS iterations
      // on all ranks) and the exact solve's.
      const std::vector<std::pair<std::string, double>> contact_figures =
        contact != nullptr ? contact->summary_entries() :
                             std::vector<std::pair<std::string, double>>();
      // Memory: the resident-set high-water mark of every rank (VmHWM), and
      // the support cache's entries and bytes (doc/benchmarks.md).
      Utilities::System::MemoryStats memory_stats;
      Utilities::System::get_memory_stats(memory_stats);
      const double peak_resident_bytes =
        Utilities::MPI::sum(1024. * memory_stats.VmHWM, comm);
      const double resident_bytes =
        Utilities::MPI::sum(1024. * memory_stats.VmRSS, comm);
      const double support_entries =
        Utilities::MPI::sum(static_cast<double>(
                              supports.n_entries(GridTransfer<dim>::n_nodes)),
                            comm);
      const double stored_entries =
        Utilities::MPI::sum(static_cast<double>(supports.n_stored), comm);
      const double cached_points =
        Utilities::MPI::sum(static_cast<double>(supports.n_points()), comm);
      const double support_cache_bytes =
        Utilities::MPI::sum(static_cast<double>(supports.memory_consumption()),
                            comm);
      if (Utilities::MPI::this_mpi_process(comm) != 0)
        return;

      std::ofstream out(parameters.output.directory + "/summary.json");
      out << "{\n";
      out << "  \"status\": " << quoted(status) << ",\n";
      if (!this->latest_checkpoint().empty())
        out << "  \"latest_checkpoint\": " << quoted(this->latest_checkpoint())
            << ",\n";
      out << "  \"dimension\": " << dim << ",\n";
      out << "  \"n_mpi_ranks\": " << Utilities::MPI::n_mpi_processes(comm)
          << ",\n";
      out << "  \"n_particles\": " << counters.n_material_points << ",\n";
      out << "  \"n_cells\": " << triangulation.n_global_active_cells()
          << ",\n";
      out << "  \"point_imbalance\": "
          << number(mean_rank_points > 0 ? max_rank_points / mean_rank_points :
                                           1.)
          << ",\n";
      if (parameters.refinement.adaptive())
        write_adaptation(out);
      out << "  \"n_dofs\": " << this->get_dof_handler().n_dofs() << ",\n";
      out << "  \"n_properties\": "
          << this->get_particle_properties().n_properties() << ",\n";
      out << "  \"support_entries_per_point\": "
          << number(cached_points > 0 ? support_entries / cached_points : 0.)
          << ",\n";
      out << "  \"support_entries_stored_per_point\": "
          << number(cached_points > 0 ? stored_entries / cached_points : 0.)
          << ",\n";
      out << "  \"support_cache_bytes\": " << number(support_cache_bytes)
          << ",\n";
      out << "  \"peak_resident_bytes\": " << number(peak_resident_bytes)
          << ",\n";
      out << "  \"resident_bytes\": " << number(resident_bytes) << ",\n";
      out << "  \"n_steps\": " << control.step_number() << ",\n";
      out << "  \"end_time\": " << number(control.time()) << ",\n";
      out << "  \"wall_seconds\": " << number(wall) << ",\n";
      out << "  \"particle_steps_per_second\": "
          << number(wall > 0 ? counters.particle_steps / wall : 0.) << ",\n";
      out << "  \"particle_update\": "
          << quoted(parameters.method.particle_update) << ",\n";
      out << "  \"mass_matrix\": " << quoted(parameters.method.mass_matrix)
          << ",\n";
      out << "  \"strain_update\": " << quoted(parameters.method.strain_update)
          << ",\n";
      write_results(out,
                    statistics,
                    failure,
                    condition_error,
                    contact_figures,
                    mass_matrix_statistics);
      out << "  \"phase_wall_seconds\": {";
      bool first = true;
      for (const auto &phase : phases)
        {
          out << (first ? "\n" : ",\n") << "    " << quoted(phase.first) << ": "
              << number(phase.second);
          first = false;
        }
      out << "\n  },\n";
      // The share of the wall time the sections above cover.
      out << "  \"timer_coverage\": " << number(timer_coverage) << "\n}\n";
    }



    template <int dim>
    void
    SummaryFile<dim>::write_adaptation(std::ostream &out) const
    {
      const RunCounters       &counters      = this->get_run_counters();
      const Parameters        &parameters    = this->get_parameters();
      const SimulationControl &control       = this->get_simulation_control();
      const auto              &triangulation = this->get_triangulation();
      // The uniform mesh at the finest level the scene allows: what an
      // unadapted run with the same smallest cells would need.
      const double uniform_cells =
        static_cast<double>(triangulation.n_global_coarse_cells()) *
        std::pow(2.0, dim * parameters.refinement.maximum_level);
      const double mean_cells =
        control.step_number() > 0 ?
          static_cast<double>(counters.cell_steps) / control.step_number() :
          static_cast<double>(triangulation.n_global_active_cells());
      out << "  \"mesh_adaptations\": " << counters.mesh_adaptations << ",\n";
      out << "  \"mean_cells\": " << number(mean_cells) << ",\n";
      out << "  \"max_cells\": "
          << std::max<unsigned long long>(counters.max_cells,
                                          triangulation.n_global_active_cells())
          << ",\n";
      out << "  \"uniform_cells\": " << number(uniform_cells) << ",\n";
      out << "  \"cell_fraction\": " << number(mean_cells / uniform_cells)
          << ",\n";
    }



    template <int dim>
    void
    SummaryFile<dim>::write_results(
      std::ostream                                      &out,
      const GlobalStatistics<dim>                       &statistics,
      const SimulationFailure                           *failure,
      const double                                       condition_error,
      const std::vector<std::pair<std::string, double>> &contact_figures,
      const std::map<std::string, double> &mass_matrix_statistics) const
    {
      const RunCounters &counters = this->get_run_counters();
      out << "  \"final_kinetic_energy\": " << number(statistics.kinetic_energy)
          << ",\n";
      out << "  \"final_strain_energy\": " << number(statistics.strain_energy)
          << ",\n";
      out << "  \"final_total_energy\": " << number(statistics.total_energy())
          << ",\n";
      out << "  \"initial_total_energy\": "
          << number(this->get_energy_balance().initial_total_energy()) << ",\n";
      // The balance E - E0 - W, with W the work of walls and tractions, over
      // the largest energy the run held or moved
      // (EnergyBalance::error_scale()).
      out << "  \"energy_error\": "
          << number(this->get_energy_balance().error(
               statistics,
               this->get_external_loads().work(),
               this->get_external_loads().work_scale()))
          << ",\n";
      out << "  \"energy_error_scale\": "
          << number(this->get_energy_balance().error_scale(
               statistics, this->get_external_loads().work_scale()))
          << ",\n";
      out << "  \"lost.points\": " << counters.total_lost_points << ",\n";
      {
        // The largest checkerboard indicator of the outputs, and its time.
        double max_checkerboard = 0, max_checkerboard_time = 0;
        for (const auto &row : this->get_postprocess_manager()
                                 .template find<Postprocess::HistoryFile<dim>>()
                                 ->rows())
          if (row.checkerboard_j > max_checkerboard)
            {
              max_checkerboard      = row.checkerboard_j;
              max_checkerboard_time = row.time;
            }
        out << "  \"max_checkerboard_j\": " << number(max_checkerboard)
            << ",\n";
        out << "  \"max_checkerboard_j_time\": "
            << number(max_checkerboard_time) << ",\n";
      }
      if (this->get_contact() != nullptr)
        {
          out << "  \"contact_normals\": "
              << quoted(this->get_parameters().contact.normals_name) << ",\n";
          for (const auto &[key, value] : contact_figures)
            out << "  " << quoted(key) << ": " << number(value) << ",\n";
        }
      if (!this->get_velocity_conditions().labels().empty())
        {
          out << "  \"boundary_condition_method\": "
              << quoted(this->get_parameters().boundary_conditions.method)
              << ",\n";
          out << "  \"velocity_condition_error\": " << number(condition_error)
              << ",\n";
          out << "  \"collection_fallbacks\": "
              << this->get_velocity_conditions().n_collection_fallbacks
              << ",\n";
        }
      if (this->get_external_loads().has_tractions() ||
          !this->get_velocity_conditions().labels().empty())
        out << "  \"external_work\": "
            << number(this->get_external_loads().work()) << ",\n";
      out << "  \"mass_matrix_order\": " << this->get_mass_matrix().order()
          << ",\n";
      for (const auto &entry : mass_matrix_statistics)
        out << "  " << quoted(entry.first) << ": " << number(entry.second)
            << ",\n";
      if (this->get_parameters().output.track_dissipation)
        out << "  \"dissipated_energy\": "
            << number(this->get_energy_balance().dissipated_energy) << ",\n";
      if (this->get_parameters().reference.enable)
        {
          out << "  \"error_velocity_l2\": "
              << number(this->get_energy_balance().velocity_error()) << ",\n";
          out << "  \"error_displacement_l2\": "
              << number(this->get_energy_balance().displacement_error())
              << ",\n";
        }
      if (failure != nullptr)
        {
          out << "  \"failure_step\": " << failure->step << ",\n";
          out << "  \"failure_time\": " << number(failure->time) << ",\n";
        }
    }

    template class SummaryFile<2>;
    template class SummaryFile<3>;
  } // namespace Postprocess
} // namespace fmpm
