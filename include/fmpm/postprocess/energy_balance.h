// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_energy_balance_h
#define fmpm_postprocess_energy_balance_h

#include <fmpm/postprocess/global_statistics.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <boost/serialization/split_member.hpp>
#include <mpi.h>

namespace fmpm
{
  namespace Postprocess
  {
    /**
     * @brief The energy balance of a run and its time-averaged errors
     * against the reference solution: the initial energies, the largest
     * energy exchanged at the outputs so far, the energy the particle
     * updates dissipated (seed 003 Eq. 1.46) and Σ over outputs of the
     * squared reference errors and norms. Checkpoints serialize it whole.
     * Units: J.
     */
    template <int dim>
    class EnergyBalance
    {
    public:
      /** The state at the start, and the scale of the energy-growth bound
       * (initial kinetic + strain energy, or the work gravity can do across
       * the mesh). */
      void
      start(const GlobalStatistics<dim> &statistics, const double scale)
      {
        initial_total   = statistics.total_energy();
        initial_kinetic = statistics.kinetic_energy;
        initial_strain  = statistics.strain_energy;
        initial_scale   = scale;
      }

      double
      initial_total_energy() const
      {
        return initial_total;
      }

      double
      growth_scale() const
      {
        return initial_scale;
      }

      /** An output at @p statistics: the errors are summed, the energy
       * exchanged so far grows. */
      void
      record_output(const GlobalStatistics<dim> &statistics)
      {
        error_sums[0] += statistics.velocity_error_squared;
        error_sums[1] += statistics.velocity_reference_squared;
        error_sums[2] += statistics.displacement_error_squared;
        error_sums[3] += statistics.displacement_reference_squared;
        max_exchanged = exchanged(statistics);
      }

      /** The largest change of the kinetic, the strain or the potential
       * energy from its initial value, at the outputs so far and in
       * @p statistics. The potential energy is measured from the initial
       * configuration, so its change is its value. */
      double
      exchanged(const GlobalStatistics<dim> &statistics) const
      {
        return std::max({max_exchanged,
                         std::abs(statistics.kinetic_energy - initial_kinetic),
                         std::abs(statistics.strain_energy - initial_strain),
                         std::abs(statistics.potential_energy)});
      }

      /** The scale of error(): the largest of KE0 + SE0, exchanged() and
       * Σ|dW| of the external work (@p external_work_scale). */
      double
      error_scale(const GlobalStatistics<dim> &statistics,
                  const double                 external_work_scale) const
      {
        return std::max({initial_kinetic + initial_strain,
                         exchanged(statistics),
                         external_work_scale,
                         std::numeric_limits<double>::min()});
      }

      /** (E - E0 - W) / error_scale() (summary.json energy_error). */
      double
      error(const GlobalStatistics<dim> &statistics,
            const double                 external_work,
            const double                 external_work_scale) const
      {
        return (statistics.total_energy() - initial_total - external_work) /
               error_scale(statistics, external_work_scale);
      }

      /** The time-averaged relative L2 errors of velocity and
       * displacement over the outputs. */
      double
      velocity_error() const
      {
        return std::sqrt(error_sums[0] / std::max(error_sums[1], 1e-300));
      }

      double
      displacement_error() const
      {
        return std::sqrt(error_sums[2] / std::max(error_sums[3], 1e-300));
      }

      /** The energy the particle updates dissipated since the start. */
      double dissipated_energy = 0;
      /** The diagonal of the mesh's bounding box: the distance over which
       * gravity and the tractions can do work (scales of the bounds).
       * Units: m. */
      double mesh_diameter = 0;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &initial_total &initial_scale &initial_kinetic &initial_strain
          &max_exchanged &dissipated_energy &error_sums &mesh_diameter;
      }

    private:
      double                initial_total   = 0;
      double                initial_kinetic = 0;
      double                initial_strain  = 0;
      double                initial_scale   = 0;
      double                max_exchanged   = 0;
      std::array<double, 4> error_sums{{0, 0, 0, 0}};
    };



    /**
     * @brief Counts of a run for summary.json: material-point steps, cell
     * steps and the most cells, mesh adaptations, lost points; and the
     * wall clocks of the run and of its last progress line.
     */
    struct RunCounters
    {
      unsigned long long particle_steps    = 0;
      unsigned long long cell_steps        = 0;
      unsigned long long max_cells         = 0;
      unsigned long long total_lost_points = 0;
      /** The number of material points on all ranks (set when the store
       * is filled). */
      unsigned long long n_material_points = 0;
      /** Mesh adaptations during the run (after the initial one). */
      unsigned int mesh_adaptations = 0;
      /** MPI_Wtime() at the start (shifted back by the time before a
       * checkpoint on resume). */
      double wall_start = 0;

      /** What a checkpoint keeps: the counts and the wall time elapsed
       * (a resumed run's wall clock starts that much earlier). */
      template <class Archive>
      void
      save(Archive &archive, const unsigned int) const
      {
        const double wall_seconds = MPI_Wtime() - wall_start;
        archive &particle_steps &mesh_adaptations &cell_steps &max_cells
          &total_lost_points &wall_seconds;
      }

      template <class Archive>
      void
      load(Archive &archive, const unsigned int)
      {
        double wall_seconds = 0;
        archive &particle_steps &mesh_adaptations &cell_steps &max_cells
          &total_lost_points &wall_seconds;
        wall_start = MPI_Wtime() - wall_seconds;
      }

      BOOST_SERIALIZATION_SPLIT_MEMBER()
    };
  } // namespace Postprocess
} // namespace fmpm

#endif
