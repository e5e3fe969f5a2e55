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
        defaults.psi_from_strain_update ? std::string("auto") :
                                          format_number(defaults.psi),
        Patterns::Anything(),
        "psi of [Nairn2023-FMPM] Eq. 2.28 in X += (v_p - psi a dt/2) dt, a "
        "number from 0 to 1 or 'auto'. 1 moves a point by the grid velocity "
        "averaged over the step, (v + v_p)/2 dt, as USAVG and USAVG+ strain "
        "it; 0 by the end-of-step grid velocity v_p dt, as USL- and USL+ "
        "strain it. 'auto' (default) takes the one that matches "
        "'Time/Strain update': 0 for usl and usl+, 1 for the others. A "
        "position update that does not match the strain update moves the "
        "points away from their deformation by (v(t) - v(0)) dt/2, a "
        "first-order error in the displacement, and with USAVG+ and psi = 0 "
        "lets a checkerboard of J grow in large-deflection dynamics at "
        "Courant numbers above 0.2 (doc/studies/cantilever.md). Units: "
        "none.");
    }



    template <int dim>
    void
    Flip<dim>::parse_parameters(ParameterHandler &prm)
    {
      const std::string value = prm.get("Position update psi");
      psi_from_strain_update  = (value == "auto");
      if (psi_from_strain_update)
        return;
      std::size_t end = 0;
      try
        {
          psi = std::stod(value, &end);
        }
      catch (const std::exception &)
        {
          end = 0;
        }
      AssertThrow(end > 0 && end == value.size() && psi >= 0 && psi <= 1,
                  ExcMessage("'Particle update/Flip/Position update psi' is <" +
                             value +
                             ">; allowed: a number from 0 to 1, or 'auto'."));
    }



    template <int dim>
    void
    Flip<dim>::set_strain_update(const std::string &name)
    {
      if (psi_from_strain_update)
        psi = (name == "usl" || name == "usl+") ? 0. : 1.;
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
