// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Helpers of the whole-run unit tests: build a Simulator from scene files
// and override text, and silence its output.

#ifndef fmpm_tests_scene_helpers_h
#define fmpm_tests_scene_helpers_h

#include <fmpm/parameters.h>
#include <fmpm/simulator.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace fmpm_tests
{
  using namespace dealii;

  /** parameters/ of the source tree. */
  inline const std::string parameter_dir = FMPM_SOURCE_DIR "/parameters/";

  /**
   * A Simulator from parameter files plus @p overrides (later settings
   * win); with no files the overrides are the whole scene (not the
   * built-in default scene).
   */
  template <int dim>
  std::unique_ptr<fmpm::Simulator<dim>>
  make_simulator(const std::vector<std::string> &files,
                 const std::string              &overrides,
                 ParameterHandler               &prm)
  {
    std::vector<std::pair<std::string, std::string>> sources;
    if (!files.empty())
      sources = fmpm::load_scene_sources(files);
    sources.emplace_back("overrides", overrides);
    fmpm::Parameters parameters;
    fmpm::read_scene(sources, prm, parameters);
    return std::make_unique<fmpm::Simulator<dim>>(parameters,
                                                  prm,
                                                  MPI_COMM_WORLD);
  }

  /** Output to @p directory, no VTU, no timer summary. */
  inline std::string
  output_overrides(const std::string &directory)
  {
    return "subsection Output\n set Directory = " + directory +
           "\n set Write vtu = false\nend\nsubsection Timer\n set Type = "
           "none\nend\n";
  }
} // namespace fmpm_tests

#endif
