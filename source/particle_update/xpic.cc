// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/particle_update/xpic.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    template <int dim>
    std::vector<GridField>
    Xpic<dim>::required_fields() const
    {
      return {velocity, lumped_velocity, lumped_acceleration};
    }



    template <int dim>
    void
    Xpic<dim>::update(Batch<dim> &batch) const
    {
      const double dt  = batch.time_step;
      const auto  &v_k = batch.grid[velocity];            // S m̃ₖ⁻¹ p
      const auto  &v_m = batch.grid[lumped_velocity];     // S m⁻¹ p
      const auto  &a   = batch.grid[lumped_acceleration]; // S m⁻¹ f
      for (unsigned int q = 0; q < batch.size(); ++q)
        {
          const Tensor<1, dim> V_new = v_k[q] + a[q] * dt;
          batch.position[q] +=
            (v_m[q] + 0.5 * (V_new - batch.velocity[q])) * dt;
          batch.velocity[q] = V_new;
        }
    }

    FMPM_REGISTER_PARTICLE_UPDATE(
      Xpic,
      "xpic",
      "XPIC(k) of seed 000 Eqs. 2.34-2.35 / Table 2.1: V = S m~_k^-1 p + S m^-1 f dt, X += [S m^-1 p + (V(n+1) - V(n))/2] dt; k is the order of the mass matrix (lumped: XPIC(1), Eq. 2.38).")
  } // namespace ParticleUpdate
} // namespace fmpm
