// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/particle_update/pic_midpoint.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    template <int dim>
    std::vector<GridField>
    PicMidpoint<dim>::required_fields() const
    {
      return {updated_velocity};
    }



    template <int dim>
    void
    PicMidpoint<dim>::update(Batch<dim> &batch) const
    {
      const double ht  = 0.5 * batch.time_step;
      const auto  &v_p = batch.grid[updated_velocity];
      for (unsigned int q = 0; q < batch.size(); ++q)
        {
          batch.position[q] += (batch.velocity[q] + v_p[q]) * ht;
          batch.velocity[q] = v_p[q];
        }
    }

    FMPM_REGISTER_PARTICLE_UPDATE(
      PicMidpoint,
      "pic midpoint",
      "PIC with the midpoint position update of seed 003 Eq. 1.67 (second form): V = v_p, X += (V(n) + V(n+1)) dt/2. (Modified PIC #1 of seed 003, Eqs. 1.73-1.74, is 'pic'.)")
  } // namespace ParticleUpdate
} // namespace fmpm
