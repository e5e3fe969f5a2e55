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

  /** Read access to a Simulator's state for the tests (SimulatorAccess
   * with its accessors public). */
  template <int dim>
  class Inspector : public fmpm::SimulatorAccess<dim>
  {
  public:
    explicit Inspector(const fmpm::Simulator<dim> &simulator)
    {
      this->initialize_simulator(simulator);
    }

    using fmpm::SimulatorAccess<dim>::compute_statistics;
    using fmpm::SimulatorAccess<dim>::get_cellwise_full_mass_matrix;
    using fmpm::SimulatorAccess<dim>::get_dof_handler;
    using fmpm::SimulatorAccess<dim>::get_grid_field;
    using fmpm::SimulatorAccess<dim>::get_history;
    using fmpm::SimulatorAccess<dim>::get_material_points;
    using fmpm::SimulatorAccess<dim>::get_reaction_forces;
    using fmpm::SimulatorAccess<dim>::get_triangulation;
    using fmpm::SimulatorAccess<dim>::get_velocity_conditions;
    using fmpm::SimulatorAccess<dim>::n_mesh_adaptations;
  };

  /** An Inspector of @p simulator. */
  template <int dim>
  Inspector<dim>
  inspect(const fmpm::Simulator<dim> &simulator)
  {
    return Inspector<dim>(simulator);
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
