// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/particle_update/fmpm.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    template <int dim>
    std::vector<GridField>
    Fmpm<dim>::required_fields() const
    {
      return {updated_velocity};
    }



    template <int dim>
    void
    Fmpm<dim>::update(Batch<dim> &batch) const
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
      Fmpm,
      "fmpm",
      "FMPM(k) of seed 000 Table 2.1 / Eq. 2.26: V = v_p, X += (V + v_p) dt/2 with v_p = S m~_k^-1 p+; k is the order of the mass matrix (lumped: FMPM(1), Eq. 2.40).")
  } // namespace ParticleUpdate
} // namespace fmpm
