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
//
// With --contact [rounds], it runs one scene (default
// benchmark_contact_2d.prm) with one velocity field and with contact and
// every normal method, and prints the cost of contact, the time in the
// normals (LR: the fits) and point clouds, and the LR iterations.
//
// With --contact-orders [rounds], the same scene with FMPM(k) and XPIC(k),
// k = 1, 2, 5, with one velocity field and with LR contact (net incremental
// and once per step), and prints the cost of contact per order.

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

  /** A variant of a scene: a label and the parameters it overrides. */
  struct Variant
  {
    std::string label, settings;
  };

  /**
   * Runs @p scene (with @p overrides) once per variant, interleaved over
   * @p rounds rounds; each phase's fastest round counts, which filters out
   * other load. Returns the summaries on rank 0 (empty on the others).
   */
  std::vector<boost::property_tree::ptree>
  run_variants(const std::string              &scene,
               const std::vector<std::string> &overrides,
               const std::vector<Variant>     &variants,
               const unsigned int              rounds,
               const std::string              &mode)
  {
    using namespace dealii;
    const bool is_root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    std::vector<boost::property_tree::ptree> summaries(variants.size());
    for (unsigned int round = 0; round < rounds; ++round)
      for (unsigned int k = 0; k < variants.size(); ++k)
        {
          std::vector<std::string> files = {scene};
          files.insert(files.end(), overrides.begin(), overrides.end());
          auto sources = fmpm::load_scene_sources(files);
          sources.emplace_back(mode,
                               variants[k].settings +
                                 "subsection Output\n  set Directory = "
                                 "output" +
                                 mode.substr(1) + "-" + std::to_string(k) +
                                 "\nend\n");
          if (is_root)
            std::cout << "\n=== round " << round + 1 << "/" << rounds << ", "
                      << variants[k].label << std::endl;
          const boost::property_tree::ptree summary = run_scene(sources);
          if (!is_root)
            continue;
          if (round == 0)
            summaries[k] = summary;
          else
            for (auto &phase : summaries[k].get_child("phase_wall_seconds"))
              phase.second.put_value(std::min(
                phase.second.get_value<double>(),
                summary.get<double>("phase_wall_seconds." + phase.first)));
        }
    if (!is_root)
      summaries.clear();
    return summaries;
  }

  /** The --methods mode: every update and mass matrix on one scene. */
  void
  compare_methods(const std::string              &scene,
                  const std::vector<std::string> &overrides,
                  const unsigned int              rounds)
  {
    struct Method
    {
      std::string  label, particle_update, mass_matrix;
      unsigned int order;
    };
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
    std::vector<Variant> variants;
    for (const auto &method : methods)
      variants.push_back(
        {method.label,
         "subsection Particle update\n  set Model name = " +
           method.particle_update +
           "\nend\nsubsection Mass matrix\n  set Model name = " +
           method.mass_matrix + "\n  subsection Fmpm\n    set Order = " +
           std::to_string(method.order) +
           "\n  end\nend\nsubsection Time\n  set Strain update mass "
           "matrix = lumped\nend\n"});
    const auto summaries =
      run_variants(scene, overrides, variants, rounds, "--methods");
    if (summaries.empty())
      return;
    const double n_particles = summaries[0].get<double>("n_particles");
    const double reference   = seconds_per_step(summaries[0]);
    std::cout << "\n=== methods on " << scene << " (" << n_particles
              << " points; each phase's fastest of " << rounds
              << " rounds; strain velocities lumped)\n"
              << "| method | particle-steps/s | cost / FLIP lumped | "
                 "grid solve ms/step | CG iterations (mean) |\n"
              << "|---|---|---|---|---|\n";
    for (unsigned int k = 0; k < methods.size(); ++k)
      {
        const auto  &summary = summaries[k];
        const double seconds = seconds_per_step(summary);
        const double grid_solve =
          summary.get<double>("phase_wall_seconds.grid solve", 0.) /
          summary.get<double>("n_steps");
        const double cg = summary.get<double>("cg_iterations_mean", 0.);
        std::cout << "| " << methods[k].label << " | " << std::scientific
                  << std::setprecision(2) << n_particles / seconds << " | "
                  << std::fixed << std::setprecision(2) << seconds / reference
                  << " | " << std::setprecision(1) << 1000 * grid_solve
                  << " | "
                  << (cg > 0 ? std::to_string(static_cast<int>(cg + 0.5)) :
                               std::string("-"))
                  << " |\n";
      }
    std::cout << std::flush;
  }

  /** The --contact mode: one velocity field against contact with every
   * normal method (issue 13's benchmark). */
  void
  compare_contact(const std::string              &scene,
                  const std::vector<std::string> &overrides,
                  const unsigned int              rounds)
  {
    std::vector<Variant> variants = {
      {"one velocity field",
       "subsection Contact\n  set Model name = none\nend\n"}};
    for (const std::string normals : {"velocity only",
                                      "average gradient",
                                      "contact position",
                                      "d fit",
                                      "logistic regression"})
      variants.push_back({normals,
                          "subsection Contact\n  set Model name = "
                          "multimaterial\n  set Normals = " +
                            normals + "\nend\n"});
    const auto summaries =
      run_variants(scene, overrides, variants, rounds, "--contact");
    if (summaries.empty())
      return;
    const double n_particles = summaries[0].get<double>("n_particles");
    const double reference   = seconds_per_step(summaries[0]);
    auto         ms_per_step = [](const boost::property_tree::ptree &summary,
                          const std::string                 &phase) {
      return 1000 *
             summary.get<double>("phase_wall_seconds." + phase, 0.) /
             summary.get<double>("n_steps");
    };
    std::cout << "\n=== contact on " << scene << " (" << n_particles
              << " points; each phase's fastest of " << rounds
              << " rounds)\n"
              << "| normals | particle-steps/s | cost / one field | contact "
                 "ms/step | normals ms/step | point clouds ms/step | LR "
                 "fits/step | NLLS iterations (mean) |\n"
              << "|---|---|---|---|---|---|---|---|\n";
    for (unsigned int k = 0; k < variants.size(); ++k)
      {
        const auto  &summary = summaries[k];
        const double seconds = seconds_per_step(summary);
        const double fits =
          summary.get<double>("logistic_regression_fits", 0.);
        std::cout << "| " << variants[k].label << " | " << std::scientific
                  << std::setprecision(2) << n_particles / seconds << " | "
                  << std::fixed << std::setprecision(2) << seconds / reference
                  << " | " << std::setprecision(2)
                  << ms_per_step(summary, "contact") << " | "
                  << ms_per_step(summary, "contact: normals") << " | "
                  << ms_per_step(summary, "contact: point clouds") << " | "
                  << std::setprecision(0)
                  << fits / summary.get<double>("n_steps") << " | "
                  << std::setprecision(2)
                  << summary.get<double>("logistic_regression_iterations_mean",
                                         0.)
                  << " |\n";
      }
    std::cout << std::flush;
  }

  /** The --contact-orders mode: the cost of contact inside FMPM(k) and
   * XPIC(k) per order, against the single-field run of the same method
   * (issue 14's benchmark). */
  void
  compare_contact_orders(const std::string              &scene,
                         const std::vector<std::string> &overrides,
                         const unsigned int              rounds)
  {
    std::vector<Variant> variants;
    std::vector<std::string> methods;
    for (const std::string update : {"fmpm", "xpic"})
      for (const unsigned int k : {1u, 2u, 5u})
        {
          const std::string label =
            (update == "fmpm" ? "FMPM(" : "XPIC(") + std::to_string(k) + ")";
          const std::string method =
            "subsection Particle update\n  set Model name = " + update +
            "\nend\nsubsection Mass matrix\n  set Model name = " +
            (k == 1 ? std::string("lumped") : std::string("fmpm")) +
            "\n  subsection Fmpm\n    set Order = " + std::to_string(k) +
            "\n  end\nend\n";
          methods.push_back(label);
          variants.push_back(
            {label + ", one field",
             method + "subsection Contact\n  set Model name = none\nend\n"});
          variants.push_back(
            {label + ", LR, net incremental",
             method + "subsection Contact\n  set Model name = "
                      "multimaterial\n  set Contact in mass-matrix iterations "
                      "= net incremental\nend\n"});
          variants.push_back(
            {label + ", LR, once per step",
             method + "subsection Contact\n  set Model name = "
                      "multimaterial\n  set Contact in mass-matrix iterations "
                      "= once per step\nend\n"});
        }
    const auto summaries =
      run_variants(scene, overrides, variants, rounds, "--contact-orders");
    if (summaries.empty())
      return;
    const double n_particles = summaries[0].get<double>("n_particles");
    std::cout << "\n=== contact per order on " << scene << " (" << n_particles
              << " points; each phase's fastest of " << rounds
              << " rounds)\n"
              << "| method | one field particle-steps/s | contact, net "
                 "incremental / one field | contact, once per step / one "
                 "field |\n"
              << "|---|---|---|---|\n";
    for (unsigned int m = 0; m < methods.size(); ++m)
      {
        const double one  = seconds_per_step(summaries[3 * m]);
        const double net  = seconds_per_step(summaries[3 * m + 1]);
        const double once = seconds_per_step(summaries[3 * m + 2]);
        std::cout << "| " << methods[m] << " | " << std::scientific
                  << std::setprecision(2) << n_particles / one << " | "
                  << std::fixed << std::setprecision(2) << net / one << " | "
                  << once / one << " |\n";
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
  bool                     contact_mode    = false;
  bool                     orders_mode     = false;
  for (int i = 1; i < argc; ++i)
    {
      const std::string arg = argv[i];
      if (arg == "--")
        after_separator = true;
      else if ((arg == "--methods" || arg == "--contact" ||
                arg == "--contact-orders") &&
               !after_separator)
        {
          method_rounds = 3;
          contact_mode  = arg == "--contact";
          orders_mode   = arg == "--contact-orders";
          if (i + 1 < argc &&
              std::string(argv[i + 1]).find_first_not_of("0123456789") ==
                std::string::npos)
            method_rounds = std::max(1, std::atoi(argv[++i]));
        }
      else
        (after_separator ? overrides : scenes).push_back(arg);
    }
  if (orders_mode)
    {
      compare_contact_orders(
        scenes.empty() ? FMPM_SOURCE_DIR "/parameters/benchmark_contact_2d.prm" :
                         scenes.front(),
        overrides,
        method_rounds);
      return 0;
    }
  if (contact_mode)
    {
      compare_contact(scenes.empty() ?
                        FMPM_SOURCE_DIR "/parameters/benchmark_contact_2d.prm" :
                        scenes.front(),
                      overrides,
                      method_rounds);
      return 0;
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
