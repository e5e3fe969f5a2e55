// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_flip_midpoint_h
#define fmpm_particle_update_flip_midpoint_h

#include <fmpm/particle_update/interface.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief FLIP with the Lagrangian midpoint position update of seed 000
     * Eq. 2.33 (seed 003 Eq. 1.58, second form): V += a Δt, X += (V^(n) + a
     * Δt/2) Δt. Known to perform poorly; kept for stability studies.
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class FlipMidpoint : public Interface<dim>
    {
    public:
      std::vector<GridField>
      required_fields() const override;

      void
      update(Batch<dim> &batch) const override;
    };
  } // namespace ParticleUpdate
} // namespace fmpm

#endif
