// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The fmpm executable: read the scene, check it, run Simulator<dim>.

#include <fmpm/parameters.h>
#include <fmpm/simulator.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <unistd.h>

namespace
{
  /**
   * A run started without mpirun is an Open MPI singleton: by default its
   * MPI_Init starts a runtime daemon (orted) and probes the UCX network
   * layer, about 0.35 s before the first line of a serial run. One process
   * needs neither: ask for an isolated singleton that talks to itself only.
   * Isolated singletons all have job id 0, so by default they share one
   * run-time folder (<tmp>/ompi.<host>.<uid>/jf.0/1/0): one run's
   * MPI_Finalize removes it while another run's MPI_Init creates it, and
   * that MPI_Init fails ("A call to mkdir was unable to create the desired
   * directory"). Each run gets its own run-time folder, which Open MPI
   * creates and removes. In that shared folder the shared-memory component
   * of MPI-IO's shared file pointer (sharedfp sm) also kept its files; the
   * other components keep a lock file beside the data file. Settings the
   * user made win; runs under a launcher are untouched; other MPI
   * libraries ignore the names.
   */
  void
  prefer_quick_singleton_start()
  {
    for (const char *launched_by : {"OMPI_COMM_WORLD_SIZE",
                                    "OMPI_COMM_WORLD_RANK",
                                    "PMIX_RANK",
                                    "PMI_RANK",
                                    "PMI_SIZE",
                                    "SLURM_PROCID"})
      if (std::getenv(launched_by) != nullptr)
        return;
    setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
    setenv("OMPI_MCA_pml", "ob1", 0);
    setenv("OMPI_MCA_btl", "self", 0);
    setenv("OMPI_MCA_sharedfp", "^sm", 0);
    const char       *tmp = std::getenv("TMPDIR");
    const std::string run_time_folder =
      std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") +
      "/fmpm-mpi." + std::to_string(getpid());
    setenv("OMPI_MCA_orte_top_session_dir", run_time_folder.c_str(), 0);
  }

  const char *usage =
    "Usage: fmpm [options] [scene.prm ...]\n"
    "\n"
    "Runs a material point method scene described by deal.II parameter\n"
    "files. Several files are read in order; later 'set' lines override\n"
    "earlier ones. '-' reads the scene from standard input. Without a file,\n"
    "fmpm runs its built-in default scene: two elastic disks colliding.\n"
    "\n"
    "Options:\n"
    "  -h, --help                 show this text\n"
    "  --version                  print the version and the git commit\n"
    "  --validate                 check the scene and exit without running\n"
    "  --print-parameters[=json]  print every parameter with its default,\n"
    "                             allowed values and description; with\n"
    "                             scene files, those of the scene (its\n"
    "                             Body N, Material N, Moving wall N, ...)\n"
    "                             with the scene's values\n"
    "  --print-default-scene      print the built-in default scene\n"
    "  --resume                   continue the scene from the newest complete\n"
    "                             checkpoint in <Output/Directory>/checkpoint/\n"
    "                             (see 'subsection Checkpoint')\n"
    "\n"
    "Results (VTU/PVD, history.csv, summary.json, parameters.prm) go to the\n"
    "directory set by 'subsection Output / set Directory'.\n"
    "\n"
    "Exit codes: 0 completed, 1 bad input, 2 numerical failure, 3 stopped by\n"
    "SIGTERM/SIGINT after writing a checkpoint.\n";

  /** The files and folders a run writes into Output/Directory. */
  bool
  is_run_output(const std::filesystem::path &path)
  {
    const std::string name = path.filename().string();
    for (const char *file : {"parameters.prm",
                             "parameters.json",
                             "history.csv",
                             "summary.json",
                             "particles.pvd",
                             "grid.pvd",
                             "checkpoint"})
      if (name == file)
        return true;
    // particles_NNNNN.pvtu/.vtu/.csv, particles_NNNNN.R.vtu, grid_NNNNN...
    for (const std::string prefix : {"particles_", "grid_"})
      if (name.rfind(prefix, 0) == 0 && name.size() > prefix.size() + 6 &&
          name.find_first_not_of("0123456789", prefix.size()) ==
            prefix.size() + 5 &&
          name[prefix.size() + 5] == '.')
        return true;
    return false;
  }

  /**
   * A fresh run must not leave the files of an earlier run in its output
   * directory (ParaView would group an old particles_00042.vtu with the new
   * series, --resume would find the old checkpoints): they are moved into
   * <directory>/previous_run/, which replaces an older one.
   */
  void
  set_aside_earlier_run(const std::string &directory, const bool quiet)
  {
    namespace fs = std::filesystem;
    if (!fs::is_directory(directory))
      return;
    std::vector<fs::path> earlier;
    for (const auto &entry : fs::directory_iterator(directory))
      if (is_run_output(entry.path()))
        earlier.push_back(entry.path());
    if (earlier.empty())
      return;
    const fs::path previous = fs::path(directory) / "previous_run";
    fs::remove_all(previous);
    fs::create_directory(previous);
    for (const auto &path : earlier)
      fs::rename(path, previous / path.filename());
    if (!quiet)
      std::cout << "fmpm: moved the " << earlier.size()
                << " files of an earlier run in <" << directory << "> to <"
                << previous.string() << ">" << std::endl;
  }

  /** The scene as read, in both of deal.II's listings, beside the output. */
  void
  write_scene_listing(const std::string              &directory,
                      const dealii::ParameterHandler &prm)
  {
    std::filesystem::create_directories(directory);
    std::ofstream prm_out(directory + "/parameters.prm");
    prm.print_parameters(prm_out, dealii::ParameterHandler::ShortPRM);
    std::ofstream json_out(directory + "/parameters.json");
    prm.print_parameters(json_out, dealii::ParameterHandler::JSON);
  }

  template <int dim>
  int
  run(const fmpm::Parameters   &parameters,
      dealii::ParameterHandler &prm,
      const bool                resume)
  {
    // Set-up first: a scene refused there leaves an earlier run's files
    // where they are.
    fmpm::Simulator<dim> simulator(parameters, prm, MPI_COMM_WORLD, resume);
    if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
      {
        if (!resume)
          set_aside_earlier_run(parameters.output.directory,
                                parameters.test_mode);
        write_scene_listing(parameters.output.directory, prm);
      }
    // No rank writes into the directory before the earlier run is set aside.
    MPI_Barrier(MPI_COMM_WORLD);
    try
      {
        simulator.run();
      }
    catch (const fmpm::SimulationFailure &)
      {
        return 2;
      }
    return simulator.stopped_by_signal() ? 3 : 0;
  }

  /** The scene set up (mesh, plugins, points), not run: its point count. */
  template <int dim>
  unsigned long long
  set_up_only(const fmpm::Parameters &parameters, dealii::ParameterHandler &prm)
  {
    fmpm::Simulator<dim> simulator(parameters, prm, MPI_COMM_WORLD, false);
    simulator.disable_timing_summary();
    return simulator.n_material_points();
  }

  /** Output/Directory must be a directory that can be made or written. */
  void
  check_output_directory(const std::string &directory)
  {
    namespace fs      = std::filesystem;
    fs::path existing = fs::absolute(directory);
    while (!fs::exists(existing) && existing.has_parent_path() &&
           existing != existing.parent_path())
      existing = existing.parent_path();
    AssertThrow(fs::is_directory(existing),
                dealii::ExcMessage(
                  "Output/Directory = <" + directory + ">: <" +
                  existing.string() +
                  "> is a file, not a directory. Choose another "
                  "'subsection Output / set Directory'."));
    AssertThrow(access(existing.c_str(), W_OK | X_OK) == 0,
                dealii::ExcMessage(
                  "Output/Directory = <" + directory + ">: the directory <" +
                  existing.string() +
                  "> is not writable. Choose another 'subsection Output / "
                  "set Directory'."));
  }

  /**
   * deal.II's PRM listing with an 'Allowed:' comment line above every
   * 'set' line (the pattern of the entry, from the JSON listing).
   */
  void
  print_parameters_with_allowed_values(const dealii::ParameterHandler &prm,
                                       std::ostream                   &out)
  {
    using Tree = boost::property_tree::ptree;
    std::stringstream json, text;
    prm.print_parameters(json, dealii::ParameterHandler::JSON);
    prm.print_parameters(text, dealii::ParameterHandler::PRM);
    Tree tree;
    boost::property_tree::read_json(json, tree);
    const char               separator = '\x1f';
    std::vector<std::string> path;
    std::string              line;
    while (std::getline(text, line))
      {
        const std::string trimmed = dealii::Utilities::trim(line);
        if (trimmed.rfind("subsection ", 0) == 0)
          path.push_back(dealii::Utilities::trim(trimmed.substr(11)));
        else if (trimmed == "end" && !path.empty())
          path.pop_back();
        else if (trimmed.rfind("set ", 0) == 0)
          {
            std::string key;
            for (const auto &name : path)
              key += name + separator;
            key +=
              dealii::Utilities::trim(trimmed.substr(4, trimmed.find('=') - 4));
            const auto pattern = tree.get_optional<std::string>(
              Tree::path_type(key + separator + "pattern_description",
                              separator));
            if (pattern)
              {
                std::string allowed = *pattern;
                if (allowed.size() > 1 && allowed.front() == '[' &&
                    allowed.back() == ']')
                  allowed = allowed.substr(1, allowed.size() - 2);
                out << line.substr(0, line.find("set "))
                    << "# Allowed: " << dealii::Utilities::trim(allowed)
                    << '\n';
              }
          }
        out << line << '\n';
      }
  }

  /**
   * --print-parameters: every parameter, declared for the scene given by
   * @p files (its dimension and its numbers of bodies, materials, moving
   * walls and tractions, each with its numbered subsection) and set to the
   * scene's values, or for the default sizes without files.
   */
  int
  print_scene_parameters(const std::vector<std::string>             &files,
                         const dealii::ParameterHandler::OutputStyle format,
                         const bool                                  is_root)
  {
    using namespace dealii;
    if (!is_root)
      return 0;
    ParameterHandler prm;
    try
      {
        if (files.empty())
          fmpm::Parameters::declare_parameters(prm, fmpm::SceneSize());
        else
          {
            const auto sources = fmpm::load_scene_sources(files);
            fmpm::Parameters::declare_parameters(
              prm, fmpm::read_scene_size(sources));
            for (const auto &source : sources)
              {
                std::istringstream in(source.second);
                prm.parse_input(in, source.first, "", false);
              }
          }
      }
    catch (const std::exception &e)
      {
        std::cerr << "fmpm: " << fmpm::error_message(e) << std::endl;
        return 1;
      }
    if (format == ParameterHandler::PRM)
      print_parameters_with_allowed_values(prm, std::cout);
    else
      prm.print_parameters(std::cout, format);
    return 0;
  }
} // namespace



int
main(int argc, char **argv)
{
  using namespace dealii;
  prefer_quick_singleton_start();
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const bool is_root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;

  std::vector<std::string>      files;
  bool                          validate_only    = false;
  bool                          resume           = false;
  bool                          print_parameters = false;
  ParameterHandler::OutputStyle print_format     = ParameterHandler::PRM;
  for (int i = 1; i < argc; ++i)
    {
      const std::string arg = argv[i];
      if (arg == "-h" || arg == "--help")
        {
          if (is_root)
            std::cout << usage;
          return 0;
        }
      else if (arg == "--version")
        {
          if (is_root)
            std::cout << fmpm::version_text() << '\n';
          return 0;
        }
      else if (arg == "--validate")
        validate_only = true;
      else if (arg == "--resume")
        resume = true;
      else if (arg == "--print-parameters" ||
               arg == "--print-parameters=json" ||
               arg == "--print-parameters=prm")
        {
          // Printed after all arguments are read: the scene files decide
          // which numbered subsections exist.
          print_parameters = true;
          print_format     = arg == "--print-parameters=json" ?
                               ParameterHandler::JSON :
                               ParameterHandler::PRM;
        }
      else if (arg == "--print-default-scene")
        {
          if (is_root)
            std::cout << fmpm::default_scene();
          return 0;
        }
      else if (arg.size() > 1 && arg[0] == '-' && arg != "-")
        {
          if (is_root)
            std::cerr << "fmpm: unknown option <" << arg << ">.\n\n" << usage;
          return 1;
        }
      else
        files.push_back(arg);
    }

  if (print_parameters)
    return print_scene_parameters(files, print_format, is_root);

  // Read and check the scene on rank 0 first, so that an error is reported
  // once; the other ranks then read the same text.
  std::vector<std::pair<std::string, std::string>> sources;
  ParameterHandler                                 prm;
  fmpm::Parameters                                 parameters;
  std::string                                      error;
  if (is_root)
    {
      try
        {
          sources = fmpm::load_scene_sources(files);
          fmpm::read_scene(sources, prm, parameters);
          check_output_directory(parameters.output.directory);
        }
      catch (const std::exception &e)
        {
          error = fmpm::error_message(e);
        }
    }
  error = Utilities::MPI::broadcast(MPI_COMM_WORLD, error, 0);
  if (!error.empty())
    {
      if (is_root)
        std::cerr << "fmpm: " << error << std::endl;
      return 1;
    }
  sources = Utilities::MPI::broadcast(MPI_COMM_WORLD, sources, 0);
  if (!is_root)
    fmpm::read_scene(sources, prm, parameters);

  if (validate_only)
    {
      // The checks that need the mesh and the points (a body outside the
      // mesh or without points, a mesh file, ...): set the scene up, run
      // nothing, write nothing.
      try
        {
          const auto n_points = parameters.size.dimension == 2 ?
                                  set_up_only<2>(parameters, prm) :
                                  set_up_only<3>(parameters, prm);
          if (is_root)
            std::cout << "fmpm: the scene is valid ("
                      << parameters.size.dimension << "D, "
                      << parameters.size.n_bodies << " bodies, "
                      << parameters.size.n_materials << " materials, "
                      << n_points << " material points)." << std::endl;
          return 0;
        }
      catch (const std::exception &e)
        {
          if (is_root)
            std::cerr << "fmpm: " << fmpm::error_message(e) << std::endl;
          return 1;
        }
    }

  try
    {
      if (parameters.size.dimension == 2)
        return run<2>(parameters, prm, resume);
      else
        return run<3>(parameters, prm, resume);
    }
  catch (const std::exception &e)
    {
      if (is_root)
        std::cerr << "fmpm: " << fmpm::error_message(e) << std::endl;
      return 1;
    }
}
