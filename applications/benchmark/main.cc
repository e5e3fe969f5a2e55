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
// k = 1, 2, 5, and the exact solve, with one velocity field and with LR
// contact (net incremental and once per step), and prints the cost of
// contact per order.
//
// With --sizes, benchmark_2d.prm at about 1e4, 1e5, 1e6 and 1e7 points (the
// mesh refined with the points per cell kept), and prints the time per
// particle-step and the peak resident memory per point of each size.
//
// Every run prints each phase's time per point-step and an estimate of
// the memory bandwidth the step uses: the bytes the passes move per
// point-step (counted from the per-point data each pass reads and writes,
// see bytes_per_point_step()) times the point-steps per second, against
// this machine's bandwidth measured by a STREAM triad. The default run
// (benchmark_2d, benchmark_gimp_2d, benchmark_3d) ends with the one-core
// one-core targets beside the measured figures.

#include <fmpm/parameters.h>
#include <fmpm/simulator.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
#include <stdexcept>

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
  /** Wall seconds per step (phases but set-up, output, those once per run
   * and the sub-sections, which run within another phase) of a summary. */
  double
  seconds_per_step(const boost::property_tree::ptree &summary)
  {
    double seconds = 0;
    for (const auto &phase : summary.get_child("phase_wall_seconds"))
      if (phase.first != "setup" && phase.first != "output" &&
          phase.first != "run start" && phase.first != "summary" &&
          !fmpm::is_timer_subsection(phase.first))
        seconds += phase.second.get_value<double>();
    return seconds / summary.get<double>("n_steps");
  }

  /**
   * This machine's memory bandwidth in bytes per second: the best of 5
   * STREAM triads a = b + s c over arrays of 2^25 doubles (STREAM counts
   * 24 bytes per element; the write-allocate is not counted).
   */
  double
  stream_bandwidth()
  {
    const std::size_t   n = std::size_t(1) << 25;
    std::vector<double> a(n, 0.), b(n, 1.), c(n, 2.);
    double              best = 1e300;
    for (unsigned int round = 0; round < 5; ++round)
      {
        const auto start = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i < n; ++i)
          a[i] = b[i] + 0.5 * c[i];
        const std::chrono::duration<double> elapsed =
          std::chrono::steady_clock::now() - start;
        best = std::min(best, elapsed.count());
      }
    // Keep the triad from being optimised away.
    if (a[n / 2] != 2.)
      std::cerr << "stream triad: unexpected value\n";
    return 24. * n / best;
  }

  /**
   * Bytes the passes of one FLIP-type step move per point: the columns of
   * the point store each pass reads and writes (8 bytes per value; Q
   * property columns, of which 6 are not stored in 2D: plane strain), and
   * s support entries per point of 4 + 8 + 8 dim bytes (node, S, G), stored
   * for a fraction s_stored/s of them; the others are computed from ξ (read
   * in each pass, copied once). Grid vectors (a few per cent of the points'
   * bytes) are left out.
   *   supports:          read x or ξ (8 dim), write the entries and 4
   *   particles to grid: read the entries, M, V, the volume and σ
   *   stress update:     read node and G, read and write F, write σ, e, V
   *                      (read V₀)
   *   particle update:   read node and S, read and write V, x and ξ
   *   sort (rebin):      every column read and written once (a step in
   *                      which the points move everywhere), and the
   *                      permutation
   */
  double
  bytes_per_point_step(const boost::property_tree::ptree &summary)
  {
    const double dim = summary.get<double>("dimension");
    const double Q   = summary.get<double>("n_properties", 0.);
    const double s   = summary.get<double>("support_entries_per_point", 0.);
    const double s_stored =
      summary.get<double>("support_entries_stored_per_point", s);
    const double stored_fraction = s > 0 ? s_stored / s : 1.;
    const double computed        = 1 - stored_fraction;
    const double entry           = 4 + 8 + 8 * dim;
    const double x               = 8. * dim;
    const double n_F             = dim == 2 ? 5 : 9;
    const double n_sigma         = dim == 2 ? 4 : 6;
    const double stored          = Q - (dim == 2 ? 6 : 0);
    const double support =
      stored_fraction * (x + s * entry + 4.) + computed * 2 * x;
    const double p2g =
      stored_fraction * s * entry + computed * x + 8 * (2 + dim + n_sigma);
    const double stress = stored_fraction * s * (4 + 8 * dim) + computed * x +
                          8 * (2 * n_F + n_sigma + 3);
    const double update =
      stored_fraction * s * (4 + 8) + computed * x + 2 * 3 * x;
    const double sort = 2 * (8 * stored + 2 * x + 8 + 4) + 4;
    return support + p2g + stress + update + sort;
  }

  /** Prints the phases of @p summary per step and per point-step, and the
   * bandwidth estimate against @p bandwidth (bytes/s). */
  void
  print_phases(const boost::property_tree::ptree &summary,
               const double                       bandwidth)
  {
    const double n_steps  = summary.get<double>("n_steps");
    const double n_points = summary.get<double>("n_particles");
    std::cout << "    time per step and phase:      ms/step   ns/point-step\n";
    for (const auto &phase : summary.get_child("phase_wall_seconds"))
      {
        const double seconds = phase.second.get_value<double>();
        std::cout << "      " << std::left << std::setw(26) << phase.first
                  << std::right << std::fixed << std::setprecision(3)
                  << std::setw(10)
                  << (phase.first == "setup" ? seconds * 1000 :
                                               seconds * 1000 / n_steps);
        if (phase.first == "setup")
          std::cout << "  (once)";
        else
          std::cout << std::setw(12) << std::setprecision(1)
                    << 1e9 * seconds / (n_steps * n_points);
        std::cout << "\n";
      }
    const double rate  = n_points / seconds_per_step(summary);
    const double bytes = bytes_per_point_step(summary);
    std::cout << std::setprecision(0) << "    bytes moved per point-step "
              << "(estimate): " << bytes << "; at " << std::scientific
              << std::setprecision(3) << rate << " point-steps/s that is "
              << std::fixed << std::setprecision(2) << bytes * rate / 1e9
              << " GB/s = " << std::setprecision(1)
              << 100 * bytes * rate / bandwidth
              << " % of the measured bandwidth (" << std::setprecision(2)
              << bandwidth / 1e9 << " GB/s)\n";
    const double resident = summary.get<double>("resident_bytes", 0.);
    if (resident > 0)
      std::cout << std::setprecision(0)
                << "    resident memory at the end of the run: "
                << resident / 1048576. << " MiB, " << resident / n_points
                << " bytes per point (support cache "
                << summary.get<double>("support_cache_bytes", 0.) / n_points
                << "); peak of the process so far: "
                << summary.get<double>("peak_resident_bytes", 0.) / n_points
                << " bytes per point\n";
    std::cout << std::scientific;
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
                  << " | " << std::setprecision(1) << 1000 * grid_solve << " | "
                  << (cg > 0 ? std::to_string(static_cast<int>(cg + 0.5)) :
                               std::string("-"))
                  << " |\n";
      }
    std::cout << std::flush;
  }

  /** The --contact mode: one velocity field against contact with every
   * normal method. */
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
      return 1000 * summary.get<double>("phase_wall_seconds." + phase, 0.) /
             summary.get<double>("n_steps");
    };
    std::cout << "\n=== contact on " << scene << " (" << n_particles
              << " points; each phase's fastest of " << rounds << " rounds)\n"
              << "| normals | particle-steps/s | cost / one field | contact "
                 "ms/step | normals ms/step | point clouds ms/step | LR "
                 "fits/step | NLLS iterations (mean) |\n"
              << "|---|---|---|---|---|---|---|---|\n";
    for (unsigned int k = 0; k < variants.size(); ++k)
      {
        const auto  &summary = summaries[k];
        const double seconds = seconds_per_step(summary);
        const double fits = summary.get<double>("logistic_regression_fits", 0.);
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
   * XPIC(k) per order, against the single-field run of the same method. */
  void
  compare_contact_orders(const std::string              &scene,
                         const std::vector<std::string> &overrides,
                         const unsigned int              rounds)
  {
    std::vector<Variant>     variants;
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
    // The exact solve (the limit of net incremental contact; once per step
    // has no limit and is refused).
    const std::string exact =
      "subsection Particle update\n  set Model name = fmpm\nend\n"
      "subsection Mass matrix\n  set Model name = full\nend\n";
    variants.push_back(
      {"exact solve, one field",
       exact + "subsection Contact\n  set Model name = none\nend\n"});
    variants.push_back({"exact solve, LR, net incremental",
                        exact + "subsection Contact\n  set Model name = "
                                "multimaterial\n  set Contact in mass-matrix "
                                "iterations = net incremental\nend\n"});
    const auto summaries =
      run_variants(scene, overrides, variants, rounds, "--contact-orders");
    if (summaries.empty())
      return;
    const double n_particles = summaries[0].get<double>("n_particles");
    std::cout << "\n=== contact per order on " << scene << " (" << n_particles
              << " points; each phase's fastest of " << rounds << " rounds)\n"
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
    const double one = seconds_per_step(summaries[3 * methods.size()]);
    const double net = seconds_per_step(summaries[3 * methods.size() + 1]);
    std::cout << "| exact solve | " << std::scientific << std::setprecision(2)
              << n_particles / one << " | " << std::fixed
              << std::setprecision(2) << net / one << " | refused |\n";
    std::cout << std::flush;
  }

  /** The --sizes mode: time per particle-step and memory per point from
   * about 1e4 to 1e7 points. */
  void
  compare_sizes(const std::string              &scene,
                const std::vector<std::string> &overrides)
  {
    const bool is_root =
      dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    // benchmark_2d: 2.545 n^2 points on n x n cells, with n = subdivisions
    // x 2^refinement (a coarse cell per p4est tree: 1e7 points on 31 x 31
    // coarse cells refined 6 times); steps for about 1e7 point-steps, at
    // least 5.
    struct Size
    {
      unsigned int subdivisions, refinement, steps;
    };
    const std::vector<Size>                  sizes = {{63, 0, 400},
                                                      {200, 0, 100},
                                                      {627, 0, 15},
                                                      {31, 6, 5}};
    std::vector<boost::property_tree::ptree> summaries;
    for (const auto &size : sizes)
      {
        std::vector<std::string> files = {scene};
        files.insert(files.end(), overrides.begin(), overrides.end());
        auto              sources = fmpm::load_scene_sources(files);
        const std::string n       = std::to_string(size.subdivisions);
        const std::string cells =
          std::to_string(size.subdivisions << size.refinement);
        sources.emplace_back(
          "--sizes",
          "subsection Mesh\n  set Subdivisions = " + n + ", " + n +
            "\n  set Initial global refinement = " +
            std::to_string(size.refinement) +
            "\nend\nsubsection Time\n  set Maximum number of steps = " +
            std::to_string(size.steps) +
            "\nend\nsubsection Output\n  set Directory = output-sizes-" +
            cells + "\nend\n");
        if (is_root)
          std::cout << "\n=== " << cells << " x " << cells << " cells"
                    << std::endl;
        summaries.push_back(run_scene(sources));
      }
    if (!is_root)
      return;
    // After the runs: its arrays would set their resident-memory peak.
    const double bandwidth = stream_bandwidth();
    std::cout << "\n=== sizes on " << scene << "\n"
              << "| points | steps | particle-steps/s | ns per point-step | "
                 "/ 1e5-point figure | peak resident bytes per point "
                 "(process, sizes in increasing order) | "
                 "bandwidth used |\n|---|---|---|---|---|---|---|\n";
    const double reference =
      seconds_per_step(summaries[1]) / summaries[1].get<double>("n_particles");
    for (const auto &summary : summaries)
      {
        const double points = summary.get<double>("n_particles");
        const double per    = seconds_per_step(summary) / points;
        const double bytes  = bytes_per_point_step(summary);
        std::cout << "| " << std::fixed << std::setprecision(0) << points
                  << " | " << summary.get<double>("n_steps") << " | "
                  << std::scientific << std::setprecision(2) << 1 / per << " | "
                  << std::fixed << std::setprecision(0) << 1e9 * per << " | "
                  << std::setprecision(2) << per / reference << " | "
                  << std::setprecision(0)
                  << summary.get<double>("peak_resident_bytes", 0.) / points
                  << " | " << std::setprecision(1)
                  << 100 * bytes / per / bandwidth << " % |\n";
      }
    std::cout << std::flush;
  }
} // namespace

namespace
{
  const char usage[] =
    "Usage: fmpm-benchmark [mode] [scene.prm ...] [-- overrides.prm ...]\n"
    "\n"
    "Runs benchmark scenes and prints particle-steps per second, the time\n"
    "per phase and point-step, the memory bandwidth used and the resident\n"
    "memory per point. A benchmark, not a test: it asserts nothing.\n"
    "Without a scene: benchmark_2d, benchmark_gimp_2d and benchmark_3d\n"
    "from parameters/, then the one-core targets beside the\n"
    "measured figures.\n"
    "Files after '--' are read after every scene (later 'set' lines win).\n"
    "\n"
    "Modes (one scene, or the default named in brackets):\n"
    "  -h, --help                 show this text\n"
    "  --methods [rounds]         every particle update and mass matrix,\n"
    "                             cost relative to FLIP, lumped mass\n"
    "                             [benchmark_2d]\n"
    "  --contact [rounds]         one velocity field against contact with\n"
    "                             each normal method [benchmark_contact_2d]\n"
    "  --contact-orders [rounds]  FMPM(k)/XPIC(k), k = 1, 2, 5, and the\n"
    "                             exact solve, with and without contact\n"
    "                             [benchmark_contact_2d]\n"
    "  --sizes                    about 1e4, 1e5, 1e6 and 1e7 points: time per\n"
    "                             point-step and memory per point\n"
    "                             [benchmark_2d]\n";

  int
  benchmark_main(int argc, char **argv);
} // namespace



int
main(int argc, char **argv)
{
  using namespace dealii;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  // Bad input (a missing scene, an unknown parameter) stops every rank
  // with the message, not an abort.
  try
    {
      return benchmark_main(argc, argv);
    }
  catch (const std::exception &e)
    {
      if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
        std::cerr << "fmpm-benchmark: " << fmpm::error_message(e) << std::endl;
      return 1;
    }
}



namespace
{
  int
  benchmark_main(int argc, char **argv)
  {
    using namespace dealii;
    const bool is_root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;

    std::vector<std::string> scenes, overrides;
    bool                     after_separator = false;
    unsigned int             method_rounds   = 0;
    bool                     contact_mode    = false;
    bool                     orders_mode     = false;
    bool                     sizes_mode      = false;
    for (int i = 1; i < argc; ++i)
      {
        const std::string arg = argv[i];
        if (arg == "--")
          after_separator = true;
        else if ((arg == "-h" || arg == "--help") && !after_separator)
          {
            if (is_root)
              std::cout << usage;
            return 0;
          }
        else if (arg == "--sizes" && !after_separator)
          sizes_mode = true;
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
        else if (arg.size() > 1 && arg[0] == '-' && !after_separator)
          throw std::invalid_argument(
            "unknown option " + arg +
            " (allowed: --help, --methods, --contact, --contact-orders, "
            "--sizes, --)");
        else
          (after_separator ? overrides : scenes).push_back(arg);
      }
    // The modes run one scene: the first given, else their default.
    const auto scene_or = [&scenes](const std::string &default_scene) {
      return scenes.empty() ?
               std::string(FMPM_SOURCE_DIR "/parameters/") + default_scene :
               scenes.front();
    };
    if (sizes_mode)
      {
        compare_sizes(scene_or("benchmark_2d.prm"), overrides);
        return 0;
      }
    if (orders_mode)
      {
        compare_contact_orders(scene_or("benchmark_contact_2d.prm"),
                               overrides,
                               method_rounds);
        return 0;
      }
    if (contact_mode)
      {
        compare_contact(scene_or("benchmark_contact_2d.prm"),
                        overrides,
                        method_rounds);
        return 0;
      }
    if (method_rounds > 0)
      {
        compare_methods(scene_or("benchmark_2d.prm"), overrides, method_rounds);
        return 0;
      }
    const bool default_scenes = scenes.empty();
    if (default_scenes)
      scenes = {FMPM_SOURCE_DIR "/parameters/benchmark_2d.prm",
                FMPM_SOURCE_DIR "/parameters/benchmark_gimp_2d.prm",
                FMPM_SOURCE_DIR "/parameters/benchmark_3d.prm"};
    std::vector<double> rates;

    // The scenes first, then the bandwidth (its arrays would otherwise set
    // the runs' resident-memory high-water mark), then the report.
    std::vector<boost::property_tree::ptree> summaries;
    for (const auto &scene : scenes)
      {
        std::vector<std::string> files = {scene};
        files.insert(files.end(), overrides.begin(), overrides.end());
        summaries.push_back(run_scene(fmpm::load_scene_sources(files)));
      }
    const double bandwidth = is_root ? stream_bandwidth() : 0.;
    for (unsigned int s = 0; s < scenes.size() && is_root; ++s)
      {
        const auto  &scene   = scenes[s];
        const auto  &summary = summaries[s];
        const double n_steps = summary.get<double>("n_steps");
        std::cout << "\n=== benchmark " << scene << "\n"
                  << "    " << summary.get<std::string>("status") << ", "
                  << summary.get<int>("dimension") << "D, "
                  << summary.get<int>("n_mpi_ranks") << " rank(s), "
                  << summary.get<long>("n_particles") << " points, "
                  << summary.get<long>("n_cells") << " cells, "
                  << static_cast<long>(n_steps) << " steps\n"
                  << "    particle-steps per second (whole run): "
                  << std::scientific << std::setprecision(3)
                  << summary.get<double>("particle_steps_per_second") << "\n";
        const double rate =
          summary.get<long>("n_particles") / seconds_per_step(summary);
        rates.push_back(rate);
        std::cout << "    particle-steps per second (time steps only): " << rate
                  << "\n";
        print_phases(summary, bandwidth);
      }
    if (default_scenes && is_root)
      {
        // The one-core targets beside the measured figures.
        const char  *labels[3]  = {"2D classic FLIP (benchmark_2d)",
                                   "2D uGIMP FLIP USAVG+ (benchmark_gimp_2d)",
                                   "3D classic (benchmark_3d)"};
        const double targets[3] = {1e7, 6e6, 4e6};
        std::cout << "\n=== targets (one core)\n"
                  << "| scene | target particle-steps/s | measured | "
                     "measured / target |\n|---|---|---|---|\n";
        for (unsigned int k = 0; k < 3; ++k)
          std::cout << "| " << labels[k] << " | " << std::scientific
                    << std::setprecision(1) << targets[k] << " | "
                    << std::setprecision(2) << rates[k] << " | " << std::fixed
                    << std::setprecision(2) << rates[k] / targets[k] << " |\n";
        std::cout << std::flush;
      }
    return 0;
  }
} // namespace
