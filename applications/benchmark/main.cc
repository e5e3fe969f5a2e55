// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// fmpm-benchmark: runs benchmark scenes (by default parameters/benchmark_2d
// and benchmark_3d.prm) and prints particle-steps per second and the wall
// time per phase. A benchmark, not a test: it asserts nothing.
//
//   fmpm-benchmark [scene.prm ...] [-- overrides.prm ...]

#include <fmpm/parameters.h>
#include <fmpm/simulator.h>

#include <deal.II/base/mpi.h>

#include <iomanip>
#include <iostream>

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
} // namespace

int
main(int argc, char **argv)
{
  using namespace dealii;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const bool is_root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;

  std::vector<std::string> scenes, overrides;
  bool                     after_separator = false;
  for (int i = 1; i < argc; ++i)
    {
      const std::string arg = argv[i];
      if (arg == "--")
        after_separator = true;
      else
        (after_separator ? overrides : scenes).push_back(arg);
    }
  if (scenes.empty())
    scenes = {FMPM_SOURCE_DIR "/parameters/benchmark_2d.prm",
              FMPM_SOURCE_DIR "/parameters/benchmark_3d.prm"};

  for (const auto &scene : scenes)
    {
      std::vector<std::string> files = {scene};
      files.insert(files.end(), overrides.begin(), overrides.end());
      ParameterHandler prm;
      fmpm::Parameters parameters;
      fmpm::read_scene(fmpm::load_scene_sources(files), prm, parameters);
      if (parameters.size.dimension == 2)
        run<2>(parameters, prm);
      else
        run<3>(parameters, prm);

      if (!is_root)
        continue;
      boost::property_tree::ptree summary;
      boost::property_tree::read_json(parameters.output.directory +
                                        "/summary.json",
                                      summary);
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
      double step_seconds = 0;
      for (const auto &phase : summary.get_child("phase_wall_seconds"))
        if (phase.first != "setup" && phase.first != "output")
          step_seconds += phase.second.get_value<double>();
      std::cout << "    particle-steps per second (time steps only): "
                << summary.get<long>("n_particles") * n_steps / step_seconds
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
