// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// fmpm-benchmark: runs benchmark scenes (by default parameters/benchmark_2d
// and benchmark_3d.prm) and prints particle-steps per second and the wall
// time per phase. A benchmark, not a test: it asserts nothing.
//
//   fmpm-benchmark [scene.prm ...] [-- overrides.prm ...]
//
// With --methods [rounds], it runs one scene (default benchmark_2d.prm) with
// every particle update and mass matrix of the cost table in
// doc/benchmarks.md, interleaved over 'rounds' rounds (default 3; each
// phase's fastest round counts, which filters out other load), and
// prints the cost per step relative to FLIP with the lumped mass matrix.

#include <fmpm/parameters.h>
#include <fmpm/simulator.h>

#include <deal.II/base/mpi.h>

#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

namespace
{
  template <int dim>
  void
  run(const fmpm::Parameters &parameters, dealii::ParameterHandler &prm)
  {
    fmpm::Simulator<dim> simulator(parameters, prm, MPI_COMM_WORLD);
    simulator.run();
  }

  /**
   * Runs the scene read from @p sources; returns its summary.json on rank 0
   * (empty on the others).
   */
  boost::property_tree::ptree
  run_scene(const std::vector<std::pair<std::string, std::string>> &sources)
  {
    dealii::ParameterHandler prm;
    fmpm::Parameters         parameters;
    fmpm::read_scene(sources, prm, parameters);
    if (parameters.size.dimension == 2)
      run<2>(parameters, prm);
    else
      run<3>(parameters, prm);
    boost::property_tree::ptree summary;
    if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
      boost::property_tree::read_json(parameters.output.directory +
                                        "/summary.json",
                                      summary);
    return summary;
  }
} // namespace

namespace
{
  /** One row of the --methods table. */
  struct Method
  {
    std::string label, particle_update, mass_matrix;
    unsigned int order;
  };

  /** Wall seconds per step (phases but set-up and output) of a summary. */
  double
  seconds_per_step(const boost::property_tree::ptree &summary)
  {
    double seconds = 0;
    for (const auto &phase : summary.get_child("phase_wall_seconds"))
      if (phase.first != "setup" && phase.first != "output")
        seconds += phase.second.get_value<double>();
    return seconds / summary.get<double>("n_steps");
  }

  /** The --methods mode: every update and mass matrix on one scene. */
  void
  compare_methods(const std::string              &scene,
                  const std::vector<std::string> &overrides,
                  const unsigned int              rounds)
  {
    using namespace dealii;
    const bool is_root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    const std::vector<Method> methods = {
      {"FLIP, lumped", "flip", "lumped", 1},
      {"PIC, lumped", "pic", "lumped", 1},
      {"FMPM(1), lumped", "fmpm", "lumped", 1},
      {"FLIP, FMPM(2)", "flip", "fmpm", 2},
      {"FMPM(2)", "fmpm", "fmpm", 2},
      {"FMPM(3)", "fmpm", "fmpm", 3},
      {"FMPM(5)", "fmpm", "fmpm", 5},
      {"XPIC(5)", "xpic", "fmpm", 5},
      {"FLIP, full", "flip", "full", 1},
      {"FMPM, full", "fmpm", "full", 1}};
    std::vector<double> best(methods.size(),
                             std::numeric_limits<double>::max());
    std::vector<boost::property_tree::ptree> summaries(methods.size());
    for (unsigned int round = 0; round < rounds; ++round)
      for (unsigned int k = 0; k < methods.size(); ++k)
        {
          const Method &method = methods[k];
          std::vector<std::string> files = {scene};
          files.insert(files.end(), overrides.begin(), overrides.end());
          auto sources = fmpm::load_scene_sources(files);
          const std::string directory =
            "output-methods-" + std::to_string(k);
          sources.emplace_back(
            "--methods",
            "subsection Particle update\n  set Model name = " +
              method.particle_update +
              "\nend\nsubsection Mass matrix\n  set Model name = " +
              method.mass_matrix +
              "\n  subsection Fmpm\n    set Order = " +
              std::to_string(method.order) +
              "\n  end\nend\nsubsection Time\n  set Strain update mass "
              "matrix = lumped\nend\nsubsection Output\n  set Directory = " +
              directory + "\nend\n");
          if (is_root)
            std::cout << "\n=== round " << round + 1 << "/" << rounds << ", "
                      << method.label << std::endl;
          const boost::property_tree::ptree summary = run_scene(sources);
          if (!is_root)
            continue;
          // Each phase's fastest round.
          if (round == 0)
            summaries[k] = summary;
          else
            for (auto &phase : summaries[k].get_child("phase_wall_seconds"))
              phase.second.put_value(std::min(
                phase.second.get_value<double>(),
                summary.get<double>("phase_wall_seconds." + phase.first)));
          best[k] = seconds_per_step(summaries[k]);
        }
    if (!is_root)
      return;
    const double n_particles = summaries[0].get<double>("n_particles");
    std::cout << "\n=== methods on " << scene << " (" << n_particles
              << " points; each phase's fastest of " << rounds
              << " rounds; strain velocities lumped)\n"
              << "| method | particle-steps/s | cost / FLIP lumped | "
                 "grid solve ms/step | CG iterations (mean) |\n"
              << "|---|---|---|---|---|\n";
    for (unsigned int k = 0; k < methods.size(); ++k)
      {
        const auto  &summary = summaries[k];
        const double grid_solve =
          summary.get<double>("phase_wall_seconds.grid solve", 0.) /
          summary.get<double>("n_steps");
        const double cg = summary.get<double>("cg_iterations_mean", 0.);
        std::cout << "| " << methods[k].label << " | " << std::scientific
                  << std::setprecision(2) << n_particles / best[k] << " | "
                  << std::fixed << std::setprecision(2) << best[k] / best[0]
                  << " | " << std::setprecision(1) << 1000 * grid_solve
                  << " | "
                  << (cg > 0 ? std::to_string(static_cast<int>(cg + 0.5)) :
                               std::string("-"))
                  << " |\n";
      }
    std::cout << std::flush;
  }
} // namespace

int
main(int argc, char **argv)
{
  using namespace dealii;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const bool is_root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;

  std::vector<std::string> scenes, overrides;
  bool                     after_separator = false;
  unsigned int             method_rounds   = 0;
  for (int i = 1; i < argc; ++i)
    {
      const std::string arg = argv[i];
      if (arg == "--")
        after_separator = true;
      else if (arg == "--methods" && !after_separator)
        {
          method_rounds = 3;
          if (i + 1 < argc &&
              std::string(argv[i + 1]).find_first_not_of("0123456789") ==
                std::string::npos)
            method_rounds = std::max(1, std::atoi(argv[++i]));
        }
      else
        (after_separator ? overrides : scenes).push_back(arg);
    }
  if (method_rounds > 0)
    {
      compare_methods(scenes.empty() ?
                        FMPM_SOURCE_DIR "/parameters/benchmark_2d.prm" :
                        scenes.front(),
                      overrides,
                      method_rounds);
      return 0;
    }
  if (scenes.empty())
    scenes = {FMPM_SOURCE_DIR "/parameters/benchmark_2d.prm",
              FMPM_SOURCE_DIR "/parameters/benchmark_3d.prm"};

  for (const auto &scene : scenes)
    {
      std::vector<std::string> files = {scene};
      files.insert(files.end(), overrides.begin(), overrides.end());
      const boost::property_tree::ptree summary =
        run_scene(fmpm::load_scene_sources(files));
      if (!is_root)
        continue;
      const double n_steps = summary.get<double>("n_steps");
      std::cout << "\n=== benchmark " << scene << "\n"
                << "    " << summary.get<std::string>("status") << ", "
                << summary.get<int>("dimension") << "D, "
                << summary.get<int>("n_mpi_ranks") << " rank(s), "
                << summary.get<long>("n_particles") << " points, "
                << summary.get<long>("n_cells") << " cells, " << n_steps
                << " steps\n"
                << "    particle-steps per second (whole run): "
                << std::scientific << std::setprecision(3)
                << summary.get<double>("particle_steps_per_second") << "\n";
      std::cout << "    particle-steps per second (time steps only): "
                << summary.get<long>("n_particles") / seconds_per_step(summary)
                << "\n    time per step and phase (ms):\n";
      for (const auto &phase : summary.get_child("phase_wall_seconds"))
        std::cout << "      " << std::left << std::setw(26) << phase.first
                  << std::right << std::fixed << std::setprecision(3)
                  << std::setw(10)
                  << (phase.first == "setup" ?
                        phase.second.get_value<double>() * 1000 :
                        phase.second.get_value<double>() * 1000 / n_steps)
                  << (phase.first == "setup" ? "  (once)" : "") << "\n";
      std::cout << std::scientific;
    }
}
