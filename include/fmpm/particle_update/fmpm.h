// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_fmpm_h
#define fmpm_particle_update_fmpm_h

#include <fmpm/particle_update/interface.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief FMPM(k), seed 000 Eq. 2.26 and Table 2.1: V = v_p, X += (V + v_p)
     * Δt/2 with v_p = S m̃ₖ⁻¹ p⁺. With the lumped mass matrix this is FMPM(1),
     * Eq. 2.40.
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class Fmpm : public Interface<dim>
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
       * psi of seed 000 Eq. 2.28 with the FMPM acceleration A dt = v_p - V:
       * X += (v_p - psi (v_p - V)/2) dt. 1 is Table 2.1's average of the old
       * and new velocities, 0 moves the points with the grid velocity that
       * also updates F.
       */
      double psi = 1;
    };
  } // namespace ParticleUpdate
} // namespace fmpm

#endif
