// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_pic_midpoint_h
#define fmpm_particle_update_pic_midpoint_h

#include <fmpm/particle_update/interface.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief PIC velocity update with the Lagrangian midpoint position update
     * of seed 003 Eq. 1.67 (second form): V = v_p, X += (V^(n) + V^(n+1)) Δt/2.
     * With the lumped mass matrix this equals FMPM(1) (seed 000 Eq. 2.40).
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class PicMidpoint : public Interface<dim>
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
