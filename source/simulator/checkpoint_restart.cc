// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checkpoints and resuming from them (the order of deal.II step-83 and
// ASPECT's checkpoint_restart.cc):
//  1. rank 0 Boost-serializes the scalar state (time, step, time-step
//     state, history rows, PVD records, energies, counters, plugin state);
//  2. the points (ParticleHandler::prepare_for_serialization) and the
//     grid fields the iterative solves start from (SolutionTransfer) are
//     attached to the mesh, which p4est saves;
//  3. everything goes into step-NNNNNN.tmp/, renamed to step-NNNNNN/ only
//     when complete: a run killed while writing leaves the previous
//     checkpoint as the newest complete one.
// A resumed run builds the coarse mesh, loads the refined one, then the
// points, sets up the DoFs and reads the grid fields back.

#include <fmpm/simulator.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/distributed/cell_data_transfer.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/lac/vector.h>

#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <boost/archive/binary_iarchive.hpp>
#include <boost/archive/binary_oarchive.hpp>
#include <boost/serialization/map.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>


namespace fmpm
{
  namespace
  {
    /** Set by SIGTERM/SIGINT/SIGUSR1; read once per step. */
    volatile std::sig_atomic_t checkpoint_signal_received = 0;

    extern "C" void
    request_checkpoint_and_stop(int)
    {
      checkpoint_signal_received = 1;
    }

    /** First line of every state file, and its format version. */
    const std::string  state_magic   = "fmpm checkpoint";
    const unsigned int state_version = 4;

    namespace fs = std::filesystem;

    /** "step-000120" */
    std::string
    checkpoint_name(const unsigned int step)
    {
      std::ostringstream name;
      name << "step-" << std::setw(6) << std::setfill('0') << step;
      return name.str();
    }

    /** The step of a complete checkpoint directory name, or -1. */
    long long
    checkpoint_step(const std::string &name)
    {
      if (name.size() < 6 || name.compare(0, 5, "step-") != 0 ||
          name.find_first_not_of("0123456789", 5) != std::string::npos)
        return -1;
      return std::stoll(name.substr(5));
    }

    /** Complete checkpoints in @p directory, oldest first. */
    std::vector<std::pair<long long, fs::path>>
    complete_checkpoints(const fs::path &directory)
    {
      std::vector<std::pair<long long, fs::path>> found;
      std::error_code                             error;
      if (!fs::is_directory(directory, error))
        return found;
      for (const auto &entry : fs::directory_iterator(directory, error))
        {
          const long long step =
            checkpoint_step(entry.path().filename().string());
          if (step >= 0 && entry.is_directory())
            found.emplace_back(step, entry.path());
        }
      std::sort(found.begin(), found.end());
      return found;
    }

    /** The files deal.II's Triangulation::save() writes for @p mesh. */
    std::vector<std::string>
    mesh_files(const std::string &mesh)
    {
      return {mesh, mesh + ".info", mesh + "_fixed.data"};
    }

    /** The newest complete checkpoint in @p directory and the bytes of its
     * state file: rank 0 finds and reads them, the others get them (or the
     * error) from it. Collective. */
    std::pair<std::string, std::string>
    newest_checkpoint(const fs::path &directory, const MPI_Comm comm)
    {
      const bool is_root = Utilities::MPI::this_mpi_process(comm) == 0;
      // Rank 0 finds the newest complete checkpoint and reads its state; the
      // others get the bytes (or the error) from it.
      std::string error, state, checkpoint;
      if (is_root)
        {
          const auto checkpoints = complete_checkpoints(directory);
          if (checkpoints.empty())
            error = "Cannot resume: there is no complete checkpoint in <" +
                    directory.string() +
                    "> (a directory step-NNNNNN written by a run of this "
                    "scene with 'subsection Checkpoint / set Step interval' "
                    "or 'Wall time interval', or stopped by SIGTERM/SIGINT).";
          else
            {
              checkpoint = checkpoints.back().second.string();
              std::vector<std::string> missing;
              for (const auto &file : mesh_files(checkpoint + "/mesh"))
                if (!fs::exists(file))
                  missing.push_back(file);
              const std::string state_file = checkpoint + "/state.bin";
              std::ifstream     in(state_file, std::ios::binary);
              if (!in)
                missing.insert(missing.begin(), state_file);
              if (!missing.empty())
                {
                  error = "Cannot resume from the checkpoint <" + checkpoint +
                          ">: it is incomplete, missing";
                  for (const auto &file : missing)
                    error += " <" + file + ">";
                  error += ". Delete it to resume from an older one.";
                }
              else
                state.assign(std::istreambuf_iterator<char>(in),
                             std::istreambuf_iterator<char>());
            }
        }
      error = Utilities::MPI::broadcast(comm, error, 0);
      AssertThrow(error.empty(), ExcMessage(error));
      state      = Utilities::MPI::broadcast(comm, state, 0);
      checkpoint = Utilities::MPI::broadcast(comm, checkpoint, 0);
      return {checkpoint, state};
    }
  } // namespace



  template <int dim>
  template <class Archive>
  void
  Simulator<dim>::serialize_scalar_state(Archive &archive)
  {
    // Everything run() changes besides the mesh, the points and the grid
    // fields, by owner (the postprocessors' and the plugins' state go in
    // their save() maps). The values are the same on every rank (sums and
    // maxima were reduced), so rank 0's copy serves any number of ranks on
    // resume.
    archive &control &energy_balance &counters;
    if (contact)
      archive &*contact;
    velocity_conditions.serialize_state(archive);
    archive &centre_of_mass &external_loads &reactions;
  }



  template <int dim>
  void
  Simulator<dim>::install_signal_handlers()
  {
    checkpoint_signal_received = 0;
    std::signal(SIGTERM, request_checkpoint_and_stop);
    std::signal(SIGINT, request_checkpoint_and_stop);
    // Open MPI's mpirun forwards SIGUSR1 to every rank and returns their
    // exit code; on SIGINT/SIGTERM it kills the ranks a second later.
    std::signal(SIGUSR1, request_checkpoint_and_stop);
  }



  template <int dim>
  int
  Simulator<dim>::local_checkpoint_request() const
  {
    // Tests raise the signal on the last rank only at a given step (a
    // signal may reach only some ranks).
    static const char *test_signal_step =
      std::getenv("FMPM_TEST_SIGNAL_AT_STEP");
    if (test_signal_step != nullptr &&
        control.step_number() == std::strtoul(test_signal_step, nullptr, 10) &&
        Utilities::MPI::this_mpi_process(mpi_communicator) ==
          Utilities::MPI::n_mpi_processes(mpi_communicator) - 1)
      std::raise(SIGTERM);

    return checkpoint_signal_received != 0               ? 2 :
           control.checkpoint_wall_time_due(MPI_Wtime()) ? 1 :
                                                           0;
  }



  template <int dim>
  bool
  Simulator<dim>::checkpoint_due()
  {
    // The maximum over the ranks came with the step's failure flags (no
    // reduction of its own): every rank checkpoints (and stops) together.
    const int request        = checkpoint_state.request;
    checkpoint_state.request = 0;
    if (request == 2)
      checkpoint_state.stop_requested = true;
    return request > 0 || control.checkpoint_step_due();
  }



  template <int dim>
  void
  Simulator<dim>::write_checkpoint()
  {
    TimerOutput::Scope timer(computing_timer, "checkpoint");
    const double       wall_begin = MPI_Wtime();
    const bool         is_root =
      Utilities::MPI::this_mpi_process(mpi_communicator) == 0;
    const fs::path directory =
      fs::path(parameters.output.directory) / "checkpoint";
    const std::string name      = checkpoint_name(control.step_number());
    const fs::path    temporary = directory / (name + ".tmp");
    const fs::path    complete  = directory / name;

    if (is_root)
      {
        fs::remove_all(temporary);
        fs::create_directories(temporary);
      }
    // The other ranks write into the directory only after rank 0 made it.
    MPI_Barrier(mpi_communicator);

    // 1. The scalar state, with per-rank figures reduced first (collective).
    reactions.max_condition_error =
      Utilities::MPI::max(reactions.max_condition_error, mpi_communicator);
    std::map<std::string, std::map<std::string, std::string>> plugin_state;
    mass_matrix->save(plugin_state["mass matrix"]);
    particle_updates.configured->save(plugin_state["particle update"]);
    for (unsigned int m = 0; m < constitutive_models.size(); ++m)
      constitutive_models[m]->save(
        plugin_state[numbered_subsection("Material", m)]);
    postprocessors.save(plugin_state["postprocess"]);
    if (is_root)
      {
        const fs::path state_file = temporary / "state.bin";
        std::ofstream  out(state_file, std::ios::binary);
        {
          boost::archive::binary_oarchive archive(out);
          std::string                     magic     = state_magic;
          unsigned int                    version   = state_version;
          unsigned int                    dimension = dim;
          unsigned int n_properties   = particle_properties.n_properties();
          unsigned int n_coarse_cells = triangulation.n_global_coarse_cells();
          unsigned int n_ranks =
            Utilities::MPI::n_mpi_processes(mpi_communicator);
          archive &magic &version &dimension &n_properties &n_coarse_cells
            &n_ranks;
          serialize_scalar_state(archive);
          archive &plugin_state;
        }
        out.close();
        AssertThrow(out,
                    ExcMessage("Cannot write the checkpoint file <" +
                               state_file.string() + ">: is the disk full?"));
      }

    // 2. The partition, the points and the warm-start grid fields ride on
    //    the mesh (deal.II step-83): the order of attaching is the order of
    //    reading back.
    //    deal.II's load() partitions the cells evenly, but a run balanced by
    //    its points (Mesh refinement/Point weight) has another partition,
    //    and the order of the sums follows it. Each rank's cells get weights
    //    summing to the same total (1 each, the first cell the rest), so
    //    that p4est's weighted partition cuts a loaded mesh where this one
    //    is cut (load_checkpoint()).
    const unsigned int n_owned_cells =
      triangulation.n_locally_owned_active_cells();
    const unsigned int most_owned_cells =
      Utilities::MPI::max(n_owned_cells, mpi_communicator);
    Vector<double> partition_weights(triangulation.n_active_cells());
    bool           first_cell = true;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          partition_weights[cell->active_cell_index()] =
            first_cell ? most_owned_cells - n_owned_cells + 1 : 1;
          first_cell = false;
        }
    parallel::distributed::CellDataTransfer<dim, dim, Vector<double>>
      partition_transfer(triangulation);
    partition_transfer.prepare_for_serialization(partition_weights);
    points_to_handler();
    particle_handler.prepare_for_serialization();
    std::vector<GridScalar> ghosted;
    // A field not allocated is zero.
    for (const auto &field : centre_of_mass.fields)
      for (unsigned int d = 0; d < dim; ++d)
        {
          if (field.n_blocks() == dim)
            ghosted.push_back(field.block(d));
          else
            {
              ghosted.push_back(centre_of_mass.mass);
              ghosted.back() = 0.;
            }
          ghosted.back().update_ghost_values();
        }
    std::vector<const GridScalar *> fields;
    for (const auto &field : ghosted)
      fields.push_back(&field);
    parallel::distributed::SolutionTransfer<dim, GridScalar> field_transfer(
      dof_handler);
    field_transfer.prepare_for_serialization(fields);
    triangulation.save((temporary / "mesh").string());
    // The store keeps the points.
    particle_handler.clear_particles();
    particle_handler.update_cached_numbers();

    // Tests stop here in the checkpoint of a given step, after the
    // temporary files, as a run killed while writing would.
    static const char *test_stop_step =
      std::getenv("FMPM_TEST_STOP_DURING_CHECKPOINT");
    if (test_stop_step != nullptr &&
        control.step_number() == std::strtoul(test_stop_step, nullptr, 10))
      {
        MPI_Barrier(mpi_communicator);
        std::_Exit(3);
      }

    // 3. Complete: rename, then keep the newest 'Keep' checkpoints.
    MPI_Barrier(mpi_communicator);
    std::uintmax_t bytes = 0;
    if (is_root)
      {
        fs::remove_all(complete);
        fs::rename(temporary, complete);
        for (const auto &entry : fs::directory_iterator(complete))
          bytes += entry.file_size();
        const auto checkpoints = complete_checkpoints(directory);
        for (unsigned int i = 0;
             i + parameters.checkpoint.keep < checkpoints.size();
             ++i)
          fs::remove_all(checkpoints[i].second);
      }
    const double wall_end = MPI_Wtime();
    control.checkpoint_written(wall_end);
    checkpoint_state.latest = complete.string();
    pcout << "*** Checkpoint " << complete.string() << " ("
          << std::setprecision(3) << bytes / 1e6 << " MB, "
          << wall_end - wall_begin << " s)" << std::endl;
  }



  template <int dim>
  void
  Simulator<dim>::load_checkpoint()
  {
    const auto [checkpoint, state] =
      newest_checkpoint(fs::path(parameters.output.directory) / "checkpoint",
                        mpi_communicator);
    checkpoint_state.resumed_from = checkpoint;
    checkpoint_state.latest       = checkpoint;
    const std::string state_file  = checkpoint + "/state.bin";

    // 1. The scalar state: check that it is fmpm's and fits this scene.
    std::map<std::string, std::map<std::string, std::string>> plugin_state;
    unsigned int                                              saved_n_ranks = 0;
    try
      {
        std::istringstream              in(state);
        boost::archive::binary_iarchive archive(in);
        std::string                     magic;
        unsigned int version = 0, dimension = 0, n_properties = 0,
                     n_coarse_cells = 0;
        archive &magic &version &dimension &n_properties &n_coarse_cells
          &saved_n_ranks;
        AssertThrow(magic == state_magic && version == state_version,
                    ExcMessage("The file <" + state_file +
                               "> is not an fmpm checkpoint of this "
                               "version."));
        AssertThrow(dimension == dim,
                    ExcMessage(
                      "The checkpoint <" + state_file + "> was written by a " +
                      std::to_string(dimension) + "D run, but the scene is " +
                      std::to_string(dim) + "D."));
        AssertThrow(
          n_properties == particle_properties.n_properties() &&
            n_coarse_cells == triangulation.n_global_coarse_cells(),
          ExcMessage(
            "The checkpoint <" + state_file +
            "> was written by another scene: it has " +
            std::to_string(n_coarse_cells) + " coarse cells and " +
            std::to_string(n_properties) + " values per point, this scene " +
            std::to_string(triangulation.n_global_coarse_cells()) + " and " +
            std::to_string(particle_properties.n_properties()) + "."));
        serialize_scalar_state(archive);
        archive &plugin_state;
      }
    catch (const boost::archive::archive_exception &e)
      {
        AssertThrow(false,
                    ExcMessage("The checkpoint file <" + state_file +
                               "> is corrupt or truncated (" + e.what() +
                               "). Delete its directory to resume from an "
                               "older checkpoint."));
      }
    mass_matrix->load(plugin_state["mass matrix"]);
    particle_updates.configured->load(plugin_state["particle update"]);
    for (unsigned int m = 0; m < constitutive_models.size(); ++m)
      constitutive_models[m]->load(
        plugin_state[numbered_subsection("Material", m)]);
    // (Visualization writes the PVD records as they were at the checkpoint:
    // the outputs written after it by the run that stopped are written
    // again.)
    postprocessors.load(plugin_state["postprocess"]);

    // 2. The mesh, then (in the order they were attached) the partition
    //    weights, the points, the DoFs and the grid fields.
    triangulation.load(checkpoint + "/mesh");
    Vector<double> partition_weights(triangulation.n_active_cells());
    {
      parallel::distributed::CellDataTransfer<dim, dim, Vector<double>>
        partition_transfer(triangulation);
      partition_transfer.deserialize(partition_weights);
    }
    initialize_particle_handler();
    particle_handler.deserialize();
    setup_dofs();
    mass_matrix->initialize();
    std::vector<GridScalar> loaded(ParticleUpdate::n_grid_fields * dim,
                                   centre_of_mass.mass);
    {
      std::vector<GridScalar *> fields;
      for (auto &field : loaded)
        fields.push_back(&field);
      parallel::distributed::SolutionTransfer<dim, GridScalar> field_transfer(
        dof_handler);
      field_transfer.deserialize(fields);
    }
    // On the same number of ranks, restore the saved partition (see
    // write_checkpoint()); on another, balance the points (Point weight).
    // The points and the grid fields move along.
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(mpi_communicator);
    const bool same_ranks = saved_n_ranks == n_ranks;
    if ((same_ranks || parameters.refinement.point_weight > 0) && n_ranks > 1)
      {
        auto restore = triangulation.signals.weight.connect(
          [&](const typename parallel::distributed::Triangulation<
                dim>::cell_iterator                        &cell,
              const typename Triangulation<dim>::CellStatus status) {
            return same_ranks ?
                     static_cast<unsigned int>(
                       partition_weights[cell->active_cell_index()]) :
                     cell_weight(cell, status);
          });
        std::vector<GridScalar>         ghosted(loaded);
        std::vector<const GridScalar *> fields;
        for (auto &field : ghosted)
          {
            field.update_ghost_values();
            fields.push_back(&field);
          }
        parallel::distributed::SolutionTransfer<dim, GridScalar> field_transfer(
          dof_handler);
        particle_handler.prepare_for_coarsening_and_refinement();
        field_transfer.prepare_for_coarsening_and_refinement(fields);
        triangulation.repartition();
        restore.disconnect();
        particle_handler.unpack_after_coarsening_and_refinement();
        setup_dofs();
        mass_matrix->initialize();
        std::vector<GridScalar *> new_fields;
        for (auto &field : loaded)
          {
            field.reinit(centre_of_mass.mass);
            new_fields.push_back(&field);
          }
        field_transfer.interpolate(new_fields);
      }
    // A zero field stays unallocated unless a step reads it.
    for (unsigned int f = 0; f < ParticleUpdate::n_grid_fields; ++f)
      {
        bool zero = true;
        for (unsigned int d = 0; d < dim; ++d)
          zero = zero && loaded[f * dim + d].linfty_norm() == 0;
        if (zero && centre_of_mass.fields[f].n_blocks() != dim)
          continue;
        centre_of_mass.allocate(static_cast<ParticleUpdate::GridField>(f));
        for (unsigned int d = 0; d < dim; ++d)
          {
            centre_of_mass.fields[f].block(d) = loaded[f * dim + d];
            centre_of_mass.fields[f].block(d).update_ghost_values();
          }
      }
    points_from_handler();
    // The node conditions at the restored wall positions and time.
    setup_boundary_conditions();
    connect_cell_weights();
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
