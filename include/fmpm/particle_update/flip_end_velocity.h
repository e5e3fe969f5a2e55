// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_flip_end_velocity_h
#define fmpm_particle_update_flip_end_velocity_h

#include <fmpm/particle_update/interface.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief Modified FLIP update #2 of seed 003 Eqs. 1.63-1.64: V += a Δt, X
     * += V^(n+1) Δt. Known to perform poorly; kept for stability studies.
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class FlipEndVelocity : public Interface<dim>
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
