// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/particle_update/pic.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    template <int dim>
    std::vector<GridField>
    Pic<dim>::required_fields() const
    {
      return {updated_velocity};
    }



    template <int dim>
    void
    Pic<dim>::update(Batch<dim> &batch) const
    {
      const double dt  = batch.time_step;
      const auto  &v_p = batch.grid[updated_velocity];
      for (unsigned int q = 0; q < batch.size(); ++q)
        {
          batch.velocity[q] = v_p[q];
          batch.position[q] += v_p[q] * dt;
        }
    }

    FMPM_REGISTER_PARTICLE_UPDATE(
      Pic,
      "pic",
      "PIC(Std) of [Nairn2023-FMPM] Table 2.1: V = v_p, X += v_p dt. Dissipative but "
      "robust.")
  } // namespace ParticleUpdate
} // namespace fmpm
