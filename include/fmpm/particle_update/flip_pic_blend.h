// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_flip_pic_blend_h
#define fmpm_particle_update_flip_pic_blend_h

#include <fmpm/particle_update/interface.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief The FLIP/PIC blend of seed 000 §2.3.4 (Stomakhin et al.): V = α V
     * + S m̃ₖ⁻¹(p⁺ − α p), X += V^(n+1) Δt, with α the FLIP fraction. Its
     * position update is the known-bad one; kept for stability studies.
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class FlipPicBlend : public Interface<dim>
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm);

      void
      parse_parameters(ParameterHandler &prm) override;

      std::vector<GridField>
      required_fields() const override;

      void
      update(Batch<dim> &batch) const override;

      /** FLIP fraction α. */
      double alpha = 0.95;
    };
  } // namespace ParticleUpdate
} // namespace fmpm

#endif
