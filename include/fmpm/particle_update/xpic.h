// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_xpic_h
#define fmpm_particle_update_xpic_h

#include <fmpm/particle_update/interface.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief XPIC(k), seed 000 Eqs. 2.34-2.35 (Table 2.1): V = S m̃ₖ⁻¹ p + S m⁻¹
     * f Δt, X += [S m⁻¹ p + (V^(n+1) − V^(n))/2] Δt. With the lumped mass
     * matrix this is XPIC(1), Eq. 2.38.
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class Xpic : public Interface<dim>
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm);

      void
      parse_parameters(ParameterHandler &prm) override;

      std::vector<GridField>
      required_fields() const override;

      void
      update(Batch<dim> &batch) const override;

      double
      position_update_psi() const override
      {
        return psi;
      }

      /**
       * 1: Table 2.1's X += (v_m + dV/2) dt; 0: X += (v_m + a dt) dt, the
       * lumped grid velocity S m⁻¹p⁺ that also updates F (FLIP's).
       */
      double psi = 1;
    };
  } // namespace ParticleUpdate
} // namespace fmpm

#endif
