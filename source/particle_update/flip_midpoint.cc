// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/particle_update/flip_midpoint.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    template <int dim>
    std::vector<GridField>
    FlipMidpoint<dim>::required_fields() const
    {
      return {acceleration};
    }



    template <int dim>
    void
    FlipMidpoint<dim>::update(Batch<dim> &batch) const
    {
      const double dt = batch.time_step;
      const auto  &a  = batch.grid[acceleration];
      for (unsigned int q = 0; q < batch.size(); ++q)
        {
          batch.position[q] += (batch.velocity[q] + 0.5 * dt * a[q]) * dt;
          batch.velocity[q] += a[q] * dt;
        }
    }

    FMPM_REGISTER_PARTICLE_UPDATE(
      FlipMidpoint,
      "flip midpoint",
      "FLIP velocity update with the midpoint position update of [Nairn2023-FMPM] Eq. 2.33 ([Nairn2018-extrap] Eq. 1.58, second form): X += (V + a dt/2) dt. Known to fail; for stability studies.")
  } // namespace ParticleUpdate
} // namespace fmpm
