// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/particle_update/flip_end_velocity.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    template <int dim>
    std::vector<GridField>
    FlipEndVelocity<dim>::required_fields() const
    {
      return {acceleration};
    }



    template <int dim>
    void
    FlipEndVelocity<dim>::update(Batch<dim> &batch) const
    {
      const double dt = batch.time_step;
      const auto  &a  = batch.grid[acceleration];
      for (unsigned int q = 0; q < batch.size(); ++q)
        {
          batch.velocity[q] += a[q] * dt;
          batch.position[q] += batch.velocity[q] * dt;
        }
    }

    FMPM_REGISTER_PARTICLE_UPDATE(
      FlipEndVelocity,
      "flip end velocity",
      "Modified FLIP #2 of [Nairn2018-extrap] Eqs. 1.63-1.64: V += a dt, X += V(n+1) dt. Known to fail; for stability studies. (Modified FLIP #1 of [Nairn2018-extrap] is 'flip' with psi = 0.)")
  } // namespace ParticleUpdate
} // namespace fmpm
