// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/parameter_entries.h>
#include <fmpm/particle_update/xpic.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    template <int dim>
    void
    Xpic<dim>::declare_parameters(ParameterHandler &prm)
    {
      const Xpic<dim> defaults;
      prm.declare_entry(
        "Position update psi",
        format_number(defaults.psi),
        Patterns::Double(0, 1),
        "X += (v_m + (1 - psi) a dt + psi dV/2) dt with dV = V(n+1) - V(n): "
        "1 is Table 2.1's XPIC(k) position update, 0 moves the points with "
        "the lumped grid velocity S m^-1 p+ that also updates their "
        "deformation gradient (FLIP's), which keeps XPIC(k >= 3) stable "
        "under large compression (doc/studies/stability.md). Units: none.");
    }



    template <int dim>
    void
    Xpic<dim>::parse_parameters(ParameterHandler &prm)
    {
      psi = prm.get_double("Position update psi");
    }



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
      const double dt        = batch.time_step;
      const auto  &v_k       = batch.grid[velocity];        // S m̃ₖ⁻¹ p
      const auto  &v_m       = batch.grid[lumped_velocity]; // S m⁻¹ p
      const auto  &a         = batch.grid[lumped_acceleration]; // S m⁻¹ f
      const double a_weight  = (1. - psi) * dt;
      const double dV_weight = 0.5 * psi;
      for (unsigned int q = 0; q < batch.size(); ++q)
        {
          const Tensor<1, dim> V_new = v_k[q] + a[q] * dt;
          batch.position[q] += (v_m[q] + a_weight * a[q] +
                                dV_weight * (V_new - batch.velocity[q])) *
                               dt;
          batch.velocity[q] = V_new;
        }
    }

    FMPM_REGISTER_PARTICLE_UPDATE(
      Xpic,
      "xpic",
      "XPIC(k) of [Nairn2023-FMPM] Eqs. 2.34-2.35 / Table 2.1: V = S m~_k^-1 p + S m^-1 f dt, X += [S m^-1 p + (V(n+1) - V(n))/2] dt (Position update psi = 1; 0: X += S m^-1 p+ dt); k is the order of the mass matrix (lumped: XPIC(1), Eq. 2.38).")
  } // namespace ParticleUpdate
} // namespace fmpm
