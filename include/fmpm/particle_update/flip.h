// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_flip_h
#define fmpm_particle_update_flip_h

#include <fmpm/particle_update/interface.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief FLIP(Std), seed 000 Eqs. 2.27-2.28 and Table 2.1:
     * V += a Δt, X += (v_p − ψ/2 a Δt) Δt with a = S m̃ₖ⁻¹ f and
     * v_p = S m̃ₖ⁻¹ p⁺ (lumped m for the standard method). ψ = 1 (default)
     * is the second-order position update, ψ = 0 the usual first-order one,
     * which lets a checkerboard of J grow in large-deflection dynamics
     * (doc/studies/cantilever.md).
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class Flip : public Interface<dim>
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm);

      void
      parse_parameters(ParameterHandler &prm) override;

      std::vector<GridField>
      required_fields() const override;

      /** With 'Position update psi = auto': ψ = 0 for USL- and USL+, which
       * strain a point with the end-of-step grid velocity v⁺ Δt, ψ = 1 for
       * the others (USAVG± strain it with (v + v⁺)/2 Δt). */
      void
      set_strain_update(const std::string &name) override;

      void
      update(Batch<dim> &batch) const override;

      /** ψ of Eq. 2.28. */
      double psi = 1;

      /** ψ follows the strain update ('auto', the default). */
      bool psi_from_strain_update = true;
    };

    /**
     * @brief FMPM(0) = XPIC(0) of seed 000 Table 2.1: dV = a Δt, V += dV,
     * X += (v_p − dV/2) Δt, i.e. FLIP with the second-order position update
     * ψ = 1.
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class Fmpm0 : public Flip<dim>
    {
    public:
      Fmpm0()
      {
        this->psi                    = 1;
        this->psi_from_strain_update = false;
      }

      static void
      declare_parameters(ParameterHandler &)
      {}

      void
      parse_parameters(ParameterHandler &) override
      {}
    };
  } // namespace ParticleUpdate
} // namespace fmpm

#endif
