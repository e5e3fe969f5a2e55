// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// What a run leaves behind: VTU/PVTU/PVD files for ParaView, history.csv,
// summary.json, progress lines and the test-mode printout.

#include <fmpm/postprocess/checkerboard.h>
#include <fmpm/simulator.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/utilities.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/particles/data_out.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace fmpm
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
  Simulator<dim>::output_results(const GlobalStatistics<dim> &statistics)
  {
    TimerOutput::Scope timer(computing_timer, "output");

    // Accumulate the time-averaged reference errors over outputs.
    energy_balance.record_output(statistics);

    HistoryRow<dim> row;
    row.step              = control.step_number();
    row.time              = control.time();
    row.dt                = control.time_step();
    row.kinetic_energy    = statistics.kinetic_energy;
    row.strain_energy     = statistics.strain_energy;
    row.potential_energy  = statistics.potential_energy;
    row.total_energy      = statistics.total_energy();
    row.momentum          = statistics.momentum;
    row.mass              = statistics.mass;
    row.dissipated_energy = energy_balance.dissipated_energy;
    row.reactions         = reactions.forces;
    if (statistics.per_material.size() > 0)
      {
        // Per material: mass, centre-of-mass velocity, volume-averaged
        // Cauchy stress, kinetic and strain energy; then the contact sums.
        const unsigned int stride = GlobalStatistics<dim>::material_stride();
        for (unsigned int a = 0; a < parameters.size.n_materials; ++a)
          {
            const double *sums = &statistics.per_material[a * stride];
            const double  mass = sums[0], volume = sums[1 + dim];
            row.extra.push_back(mass);
            for (unsigned int d = 0; d < dim; ++d)
              row.extra.push_back(mass > 0 ? sums[1 + d] / mass : 0.);
            for (unsigned int c = 0; c < GlobalStatistics<dim>::n_stress; ++c)
              row.extra.push_back(volume > 0 ? sums[2 + dim + c] / volume : 0.);
            row.extra.push_back(sums[stride - 2]);
            row.extra.push_back(sums[stride - 1]);
          }
        const auto [friction_work, contact_nodes] =
          contact ? contact->history_values() : std::make_pair(0., 0.);
        row.extra.push_back(friction_work);
        row.extra.push_back(contact_nodes);
      }
    for (const double value : mass_matrix->history_values())
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
    if (row.checkerboard_j > Checkerboard::warning_threshold<dim> &&
        !history.checkerboard_warned)
      {
        history.checkerboard_warned = true;
        if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0 &&
            !parameters.test_mode)
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

    if (parameters.test_mode)
      {
        tout << std::scientific << std::setprecision(8) << "step "
             << control.step_number() << " t " << control.time() << " mass "
             << statistics.mass << " momentum " << statistics.momentum
             << " kinetic " << statistics.kinetic_energy << " strain "
             << statistics.strain_energy << std::endl;
      }

    control.output_written();
    // The postprocessors time themselves (no section inside another).
    timer.stop();
    postprocessors.execute(statistics);
    control.count_output();
  }



  template <int dim>
  void
  Simulator<dim>::print_progress(const GlobalStatistics<dim> &statistics,
                                 const bool)
  {
    TimerOutput::Scope timer(computing_timer, "progress");
    const double       wall     = MPI_Wtime() - counters.wall_start;
    counters.last_progress_wall = MPI_Wtime();
    const double fraction       = control.time() / parameters.time.end_time;
    const double eta = fraction > 0 ? wall * (1 - fraction) / fraction : 0.0;
    pcout << std::defaultfloat << std::setprecision(5) << "*** Step "
          << std::setw(6) << control.step_number() << "  t = " << std::setw(11)
          << control.time() << "  dt = " << std::setw(11) << control.time_step()
          << "  E = " << std::setw(11) << statistics.total_energy()
          << " (kinetic " << statistics.kinetic_energy << ", strain "
          << statistics.strain_energy << ")  " << std::setprecision(3)
          << 100 * fraction << "%  wall " << wall << " s, about " << eta
          << " s left" << std::endl;
  }



  template <int dim>
  void
  Simulator<dim>::compute_checkerboard(HistoryRow<dim> &row) const
  {
    using Index = PropertyIndex<dim>;
    // J per point in the store's (cell) order, then the sums cell by cell.
    std::vector<double> J(points.n_points());
    for (unsigned int k = 0; k < points.n_points(); ++k)
      J[k] =
        determinant(get_tensor3(points.record(k), Index::deformation_gradient));
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
    std::vector<double> global = {sums.residual, sums.volume_change, sums.mass};
    Utilities::MPI::sum(global, mpi_communicator, global);
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
  void
  Simulator<dim>::print_test_particles() const
  {
    if (!parameters.test_mode)
      return;
    using Index = PropertyIndex<dim>;
    // Gather (id, x, V) to rank 0 and print sorted by id.
    std::vector<std::pair<types::particle_index, std::vector<double>>> local;
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        std::vector<double> values;
        for (unsigned int d = 0; d < dim; ++d)
          values.push_back(points.position[k][d]);
        for (unsigned int d = 0; d < dim; ++d)
          values.push_back(points.column(Index::velocity + d)[k]);
        local.emplace_back(points.id[k], values);
      }
    const auto all = Utilities::MPI::gather(mpi_communicator, local, 0);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
      return;
    std::map<types::particle_index, std::vector<double>> sorted;
    for (const auto &rank : all)
      for (const auto &entry : rank)
        sorted[entry.first] = entry.second;
    tout << "points (id, position, velocity):" << std::endl;
    for (const auto &entry : sorted)
      {
        tout << entry.first;
        for (const double value : entry.second)
          tout << ' ' << std::scientific << std::setprecision(8) << value;
        tout << std::endl;
      }
  }



  template <int dim>
  void
  Simulator<dim>::write_summary(const std::string           &status,
                                const SimulationFailure     *failure,
                                const GlobalStatistics<dim> &statistics)
  {
    TimerOutput::Scope                  timer(computing_timer, "summary");
    const std::map<std::string, double> mass_matrix_statistics =
      mass_matrix->statistics();
    std::map<std::string, double> phases =
      computing_timer.get_summary_data(TimerOutput::total_wall_time);
    const double wall = MPI_Wtime() - counters.wall_start;
    // The share of the wall time inside the timer sections (they do not
    // nest, but for the point store's, which run within set-up, mesh
    // adaptation, checkpoints and the sort), on the slowest-covered rank.
    double covered = 0;
    for (const auto &phase : phases)
      if (phase.first.rfind("point store", 0) != 0)
        covered += phase.second;
    counters.timer_coverage =
      Utilities::MPI::min(wall > 0 ? covered / wall : 1., mpi_communicator);
    // Make the phase times the maximum over ranks.
    for (auto &phase : phases)
      phase.second = Utilities::MPI::max(phase.second, mpi_communicator);
    const double condition_error =
      Utilities::MPI::max(reactions.max_condition_error, mpi_communicator);
    // Load balance: the largest number of points on one rank against the
    // mean.
    const double local_points = static_cast<double>(points.n_points());
    const double max_rank_points =
      Utilities::MPI::max(local_points, mpi_communicator);
    const double mean_rank_points =
      Utilities::MPI::sum(local_points, mpi_communicator) /
      Utilities::MPI::n_mpi_processes(mpi_communicator);
    // Contact: the normal method's figures (LR: fits and NLLS iterations
    // on all ranks) and the exact solve's.
    const std::vector<std::pair<std::string, double>> contact_figures =
      contact ? contact->summary_entries() :
                std::vector<std::pair<std::string, double>>();
    // Memory: the resident-set high-water mark of every rank (VmHWM), and
    // the support cache's entries and bytes (doc/benchmarks.md).
    Utilities::System::MemoryStats memory_stats;
    Utilities::System::get_memory_stats(memory_stats);
    const double peak_resident_bytes =
      Utilities::MPI::sum(1024. * memory_stats.VmHWM, mpi_communicator);
    const double resident_bytes =
      Utilities::MPI::sum(1024. * memory_stats.VmRSS, mpi_communicator);
    const double support_entries =
      Utilities::MPI::sum(static_cast<double>(
                            supports.n_entries(GridTransfer<dim>::n_nodes)),
                          mpi_communicator);
    const double stored_entries =
      Utilities::MPI::sum(static_cast<double>(supports.n_stored),
                          mpi_communicator);
    const double cached_points =
      Utilities::MPI::sum(static_cast<double>(supports.n_points()),
                          mpi_communicator);
    const double support_cache_bytes =
      Utilities::MPI::sum(static_cast<double>(supports.memory_consumption()),
                          mpi_communicator);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
      return;

    std::ofstream out(parameters.output.directory + "/summary.json");
    out << "{\n";
    out << "  \"status\": " << quoted(status) << ",\n";
    if (!checkpoint_state.latest.empty())
      out << "  \"latest_checkpoint\": " << quoted(checkpoint_state.latest)
          << ",\n";
    out << "  \"dimension\": " << dim << ",\n";
    out << "  \"n_mpi_ranks\": "
        << Utilities::MPI::n_mpi_processes(mpi_communicator) << ",\n";
    out << "  \"n_particles\": " << counters.n_material_points << ",\n";
    out << "  \"n_cells\": " << triangulation.n_global_active_cells() << ",\n";
    out << "  \"point_imbalance\": "
        << number(mean_rank_points > 0 ? max_rank_points / mean_rank_points :
                                         1.)
        << ",\n";
    if (parameters.refinement.adaptive())
      {
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
            << std::max<unsigned long long>(
                 counters.max_cells, triangulation.n_global_active_cells())
            << ",\n";
        out << "  \"uniform_cells\": " << number(uniform_cells) << ",\n";
        out << "  \"cell_fraction\": " << number(mean_cells / uniform_cells)
            << ",\n";
      }
    out << "  \"n_dofs\": " << dof_handler.n_dofs() << ",\n";
    out << "  \"n_properties\": " << particle_properties.n_properties()
        << ",\n";
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
    write_summary_results(out,
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
    out << "  \"timer_coverage\": " << number(counters.timer_coverage)
        << "\n}\n";
  }



  template <int dim>
  void
  Simulator<dim>::write_summary_results(
    std::ostream                                      &out,
    const GlobalStatistics<dim>                       &statistics,
    const SimulationFailure                           *failure,
    const double                                       condition_error,
    const std::vector<std::pair<std::string, double>> &contact_figures,
    const std::map<std::string, double> &mass_matrix_statistics) const
  {
    out << "  \"final_kinetic_energy\": " << number(statistics.kinetic_energy)
        << ",\n";
    out << "  \"final_strain_energy\": " << number(statistics.strain_energy)
        << ",\n";
    out << "  \"final_total_energy\": " << number(statistics.total_energy())
        << ",\n";
    out << "  \"initial_total_energy\": "
        << number(energy_balance.initial_total_energy()) << ",\n";
    // The balance E - E0 - W, with W the work of walls and tractions, over
    // the largest energy the run held or moved (EnergyBalance::error_scale()).
    out << "  \"energy_error\": "
        << number(energy_balance.error(statistics,
                                       external_loads.work(),
                                       external_loads.work_scale()))
        << ",\n";
    out << "  \"energy_error_scale\": "
        << number(energy_balance.error_scale(statistics,
                                             external_loads.work_scale()))
        << ",\n";
    out << "  \"lost.points\": " << counters.total_lost_points << ",\n";
    {
      // The largest checkerboard indicator of the outputs, and its time.
      double max_checkerboard = 0, max_checkerboard_time = 0;
      for (const auto &row : history.rows())
        if (row.checkerboard_j > max_checkerboard)
          {
            max_checkerboard      = row.checkerboard_j;
            max_checkerboard_time = row.time;
          }
      out << "  \"max_checkerboard_j\": " << number(max_checkerboard) << ",\n";
      out << "  \"max_checkerboard_j_time\": " << number(max_checkerboard_time)
          << ",\n";
    }
    if (contact_active())
      {
        out << "  \"contact_normals\": "
            << quoted(parameters.contact.normals_name) << ",\n";
        for (const auto &[key, value] : contact_figures)
          out << "  " << quoted(key) << ": " << number(value) << ",\n";
      }
    if (!velocity_conditions.labels().empty())
      {
        out << "  \"boundary_condition_method\": "
            << quoted(parameters.boundary_conditions.method) << ",\n";
        out << "  \"velocity_condition_error\": " << number(condition_error)
            << ",\n";
        out << "  \"collection_fallbacks\": "
            << velocity_conditions.n_collection_fallbacks << ",\n";
      }
    if (external_loads.has_tractions() || !velocity_conditions.labels().empty())
      out << "  \"external_work\": " << number(external_loads.work()) << ",\n";
    out << "  \"mass_matrix_order\": " << mass_matrix->order() << ",\n";
    for (const auto &entry : mass_matrix_statistics)
      out << "  " << quoted(entry.first) << ": " << number(entry.second)
          << ",\n";
    if (parameters.output.track_dissipation)
      out << "  \"dissipated_energy\": "
          << number(energy_balance.dissipated_energy) << ",\n";
    if (parameters.reference.enable)
      {
        out << "  \"error_velocity_l2\": "
            << number(energy_balance.velocity_error()) << ",\n";
        out << "  \"error_displacement_l2\": "
            << number(energy_balance.displacement_error()) << ",\n";
      }
    if (failure != nullptr)
      {
        out << "  \"failure_step\": " << failure->step << ",\n";
        out << "  \"failure_time\": " << number(failure->time) << ",\n";
      }
  }

  template <int dim>
  std::vector<std::string>
  Simulator<dim>::history_extra_columns() const
  {
    std::vector<std::string> columns = material_history_columns();
    for (const auto &column : mass_matrix->history_columns())
      columns.push_back(column);
    for (const auto &column : tracked_point_columns())
      columns.push_back(column);
    return columns;
  }



  template <int dim>
  std::vector<std::string>
  Simulator<dim>::material_history_columns() const
  {
    std::vector<std::string> columns;
    if (parameters.size.n_materials < 2)
      return columns;
    const std::vector<std::string> stress =
      dim == 2 ? std::vector<std::string>{"xx", "yy", "xy"} :
                 std::vector<std::string>{"xx", "yy", "zz", "xy", "xz", "yz"};
    for (unsigned int a = 0; a < parameters.size.n_materials; ++a)
      {
        const std::string n = "_material_" + std::to_string(a);
        columns.push_back("mass" + n);
        for (unsigned int d = 0; d < dim; ++d)
          columns.push_back(std::string("velocity_") + "xyz"[d] + n);
        for (const auto &c : stress)
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
  Simulator<dim>::find_tracked_points()
  {
    using Index = PropertyIndex<dim>;
    history.tracked_point_ids.clear();
    const std::string &text  = parameters.output.tracked_points;
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
            AssertThrow(!field.empty() && *end == '\0' && std::isfinite(value),
                        ExcMessage(where + "<" + entry +
                                   "> is neither a point id nor " +
                                   std::to_string(dim) +
                                   " coordinates separated by ','."));
            numbers.push_back(value);
          }
        AssertThrow(numbers.size() == 1 || numbers.size() == dim,
                    ExcMessage(where + "<" + entry + "> has " +
                               std::to_string(numbers.size()) +
                               " numbers: give a point id (one integer) or a "
                               "position (" +
                               std::to_string(dim) + " coordinates)."));
        if (numbers.size() == 1)
          {
            AssertThrow(numbers[0] >= 0 && numbers[0] == std::floor(numbers[0]),
                        ExcMessage(where + "the point id <" + entry +
                                   "> is not an integer >= 0."));
            const auto id  = static_cast<types::particle_index>(numbers[0]);
            bool       has = false;
            for (unsigned int k = 0; k < points.n_points() && !has; ++k)
              has = points.id[k] == id;
            AssertThrow(Utilities::MPI::logical_or(has, mpi_communicator),
                        ExcMessage(where + "no material point has id " + entry +
                                   " (the scene has " +
                                   std::to_string(counters.n_material_points) +
                                   " points)."));
            history.tracked_point_ids.push_back(id);
            continue;
          }
        // The point whose initial position is nearest (the smallest id among
        // equally near ones); the position must lie in the box of a point's
        // initial domain, X ± l0.
        Point<dim> position;
        for (unsigned int d = 0; d < dim; ++d)
          position[d] = numbers[d];
        double                distance = std::numeric_limits<double>::max();
        types::particle_index nearest =
          std::numeric_limits<types::particle_index>::max();
        bool inside = false;
        for (unsigned int k = 0; k < points.n_points(); ++k)
          {
            const PointRecord    p = points.record(k);
            const Point<dim>     X(get_vector<dim>(p, Index::initial_position));
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
        const auto ids = Utilities::MPI::all_gather(mpi_communicator, nearest);
        distance       = std::numeric_limits<double>::max();
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
  Simulator<dim>::tracked_point_columns() const
  {
    const std::vector<std::string> stress =
      dim == 2 ? std::vector<std::string>{"xx", "yy", "xy"} :
                 std::vector<std::string>{"xx", "yy", "zz", "xy", "xz", "yz"};
    std::vector<std::string> columns;
    for (unsigned int n = 0; n < history.tracked_point_ids.size(); ++n)
      {
        const std::string prefix = "track" + std::to_string(n + 1) + "_";
        for (const char quantity : {'u', 'v'})
          for (unsigned int d = 0; d < dim; ++d)
            columns.push_back(prefix + quantity + "xyz"[d]);
        for (const auto &c : stress)
          columns.push_back(prefix + "s" + c);
      }
    return columns;
  }



  template <int dim>
  std::vector<double>
  Simulator<dim>::tracked_point_values() const
  {
    using Index                     = PropertyIndex<dim>;
    constexpr unsigned int n_stress = GlobalStatistics<dim>::n_stress;
    constexpr unsigned int n_values = 2 * dim + n_stress;
    // The stored stress slots of xx, yy, xy in 2D (xx, yy, zz, xy, xz, yz in
    // 3D), as in compute_statistics().
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
            const PointRecord    p = points.record(k);
            const Point<dim>     X(get_vector<dim>(p, Index::initial_position));
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
    Utilities::MPI::sum(values, mpi_communicator, values);
    for (unsigned int n = 0; n < n_tracked; ++n)
      if (values[n_tracked * n_values + n] == 0)
        std::fill(values.begin() + n * n_values,
                  values.begin() + (n + 1) * n_values,
                  std::numeric_limits<double>::quiet_NaN());
    values.resize(n_tracked * n_values);
    return values;
  }



  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
