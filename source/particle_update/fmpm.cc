// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/parameter_entries.h>
#include <fmpm/particle_update/fmpm.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    template <int dim>
    void
    Fmpm<dim>::declare_parameters(ParameterHandler &prm)
    {
      const Fmpm<dim> defaults;
      prm.declare_entry(
        "Position update psi",
        format_number(defaults.psi),
        Patterns::Double(0, 1),
        "psi of [Nairn2023-FMPM] Eq. 2.28 with the FMPM acceleration A dt = v_p - V "
        "(Eq. 2.41): X += (v_p - psi (v_p - V)/2) dt. 1 is Table 2.1's "
        "X += (V + v_p) dt/2; 0 moves the points with the grid velocity "
        "v_p = S m~_k^-1 p+ that also updates their deformation gradient "
        "(USL+/USAVG+), which keeps FMPM(k >= 3) stable under large "
        "compression at the automatic time step (doc/studies/stability.md). "
        "Units: none.");
    }



    template <int dim>
    void
    Fmpm<dim>::parse_parameters(ParameterHandler &prm)
    {
      psi = prm.get_double("Position update psi");
    }



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
      // Eq. 2.28 with A dt = v_p - V: X += ((1 - psi/2) v_p + psi/2 V) dt;
      // psi = 1 is (V + v_p) dt/2 (bitwise: the weights are exact halves).
      const double dt    = batch.time_step;
      const double w_old = 0.5 * psi;
      const double w_new = 1. - w_old;
      const auto  &v_p   = batch.grid[updated_velocity];
      for (unsigned int q = 0; q < batch.size(); ++q)
        {
          batch.position[q] +=
            (w_new * v_p[q] + w_old * batch.velocity[q]) * dt;
          batch.velocity[q] = v_p[q];
        }
    }

    FMPM_REGISTER_PARTICLE_UPDATE(
      Fmpm,
      "fmpm",
      "FMPM(k) of [Nairn2023-FMPM] Table 2.1 / Eq. 2.26: V = v_p, X += (V + v_p) dt/2 with v_p = S m~_k^-1 p+ ('Position update psi' = 1; 0: X += v_p dt); k is the order of the mass matrix (lumped: FMPM(1), Eq. 2.40).")
  } // namespace ParticleUpdate
} // namespace fmpm
