// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_pic_h
#define fmpm_particle_update_pic_h

#include <fmpm/particle_update/interface.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief PIC(Std), seed 000 Table 2.1: V = v_p, X += v_p Δt with
     * v_p = S m̃ₖ⁻¹ p⁺.
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class Pic : public Interface<dim>
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
