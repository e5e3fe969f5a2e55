// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_periodic_updates_h
#define fmpm_particle_update_periodic_updates_h

#include <fmpm/particle_update/interface.h>

#include <memory>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief The scene's particle update, and FLIP for the lumped steps of a
     * periodic FMPM(k) (MassMatrix::Interface::periodic()): which of the two
     * the current step uses.
     */
    template <int dim>
    struct PeriodicUpdates
    {
      /** Method/Particle update. */
      std::unique_ptr<Interface<dim>> configured;
      /** FLIP for the lumped steps (null unless the mass matrix is
       * periodic). */
      std::unique_ptr<Interface<dim>> lumped_step;
      /** Whether the current step uses the mass matrix's series
       * (MassMatrix::Interface::begin_step()). */
      bool series_step = true;

      /** Whether the current step uses @ref configured. */
      bool
      configured_active() const
      {
        return series_step || !lumped_step;
      }

      /** The update of the current step. */
      Interface<dim> &
      active() const
      {
        return configured_active() ? *configured : *lumped_step;
      }
    };
  } // namespace ParticleUpdate
} // namespace fmpm

#endif
