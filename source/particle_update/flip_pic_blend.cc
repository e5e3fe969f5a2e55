// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/parameter_entries.h>
#include <fmpm/particle_update/flip_pic_blend.h>

namespace fmpm
{
  namespace ParticleUpdate
  {

    template <int dim>
    void
    FlipPicBlend<dim>::declare_parameters(ParameterHandler &prm)
    {
      const FlipPicBlend<dim> defaults;
      prm.declare_entry("FLIP fraction",
                        format_number(defaults.alpha),
                        Patterns::Double(0, 1),
                        "Fraction alpha of FLIP in the blend (1: FLIP velocity "
                        "update, 0: PIC). Units: none.");
    }



    template <int dim>
    void
    FlipPicBlend<dim>::parse_parameters(ParameterHandler &prm)
    {
      alpha = prm.get_double("FLIP fraction");
    }



    template <int dim>
    std::vector<GridField>
    FlipPicBlend<dim>::required_fields() const
    {
      return {updated_velocity, velocity};
    }



    template <int dim>
    void
    FlipPicBlend<dim>::update(Batch<dim> &batch) const
    {
      const double dt  = batch.time_step;
      const auto  &v_p = batch.grid[updated_velocity]; // S m̃ₖ⁻¹ p⁺
      const auto  &v   = batch.grid[velocity];         // S m̃ₖ⁻¹ p
      for (unsigned int q = 0; q < batch.size(); ++q)
        {
          batch.velocity[q] = alpha * batch.velocity[q] + v_p[q] - alpha * v[q];
          batch.position[q] += batch.velocity[q] * dt;
        }
    }

    FMPM_REGISTER_PARTICLE_UPDATE(
      FlipPicBlend,
      "flip pic blend",
      "The FLIP/PIC blend of [Nairn2023-FMPM] section 2.3.4: V = alpha V + S m~_k^-1 (p+ - alpha p), X += V(n+1) dt, alpha = FLIP fraction. Known to fail for alpha near 1; for stability studies.")
  } // namespace ParticleUpdate
} // namespace fmpm
