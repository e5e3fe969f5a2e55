// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/parameter_entries.h>
#include <fmpm/particle_update/flip.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    template <int dim>
    void
    Flip<dim>::declare_parameters(ParameterHandler &prm)
    {
      const Flip<dim> defaults;
      prm.declare_entry(
        "Position update psi",
        format_number(defaults.psi),
        Patterns::Double(0, 1),
        "psi of [Nairn2023-FMPM] Eq. 2.28: 1 (default) the second-order "
        "position update X += (v_p - a dt/2) dt, which moves the points with "
        "the grid velocity averaged over the step, as USAVG+ strains them; 0 "
        "the common first-order update X += v_p dt, which lets a checkerboard "
        "of J grow in large-deflection dynamics at Courant numbers above 0.2 "
        "(doc/studies/cantilever.md). Units: none.");
    }



    template <int dim>
    void
    Flip<dim>::parse_parameters(ParameterHandler &prm)
    {
      psi = prm.get_double("Position update psi");
    }



    template <int dim>
    std::vector<GridField>
    Flip<dim>::required_fields() const
    {
      return {updated_velocity, acceleration};
    }



    template <int dim>
    void
    Flip<dim>::update(Batch<dim> &batch) const
    {
      const double dt  = batch.time_step;
      const auto  &v_p = batch.grid[updated_velocity];
      const auto  &a   = batch.grid[acceleration];
      for (unsigned int q = 0; q < batch.size(); ++q)
        {
          batch.velocity[q] += a[q] * dt;
          batch.position[q] += (v_p[q] - 0.5 * psi * dt * a[q]) * dt;
        }
    }

    FMPM_REGISTER_PARTICLE_UPDATE(
      Flip,
      "flip",
      "FLIP(Std) of [Nairn2023-FMPM] Table 2.1 / Eqs. 2.27-2.28: V += a dt, "
      "X += (v_p - psi/2 a dt) dt.")

    FMPM_REGISTER_PARTICLE_UPDATE(
      Fmpm0,
      "fmpm0",
      "FMPM(0) = XPIC(0) of [Nairn2023-FMPM] Table 2.1: V += a dt, X += (v_p - a "
      "dt/2) dt (FLIP with psi = 1).")
  } // namespace ParticleUpdate
} // namespace fmpm
