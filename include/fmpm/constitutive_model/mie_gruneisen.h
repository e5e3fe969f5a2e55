// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_constitutive_model_mie_gruneisen_h
#define fmpm_constitutive_model_mie_gruneisen_h

#include <fmpm/constitutive_model/elastic_constants.h>
#include <fmpm/constitutive_model/interface.h>
#include <fmpm/constitutive_model/j2_plasticity.h>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    /**
     * @brief Shock model of seed 004 §4.3: the hyperelastic shear term of
     * Eq. (18) with the Mie–Grüneisen pressure of Eq. (51), the artificial
     * viscosity q of Eq. (52), and optional J2 plasticity with linear
     * hardening.
     *
     * With η = 1 − J, the pressure is
     * p = K η (1 − γ0 η/2)/(1 − S1 η)² + ρ0 γ0 U in compression (η > 0) and
     * p = K η in tension (Eq. 51; the paper's case labels have the sign of
     * η swapped, the singular form only makes sense in compression). U is
     * the internal energy per unit mass: every point integrates the stress
     * power, dU = σ : D dt / ρ (pressure, viscosity and shear work; plastic
     * work is part of it). With U the total specific energy, the pressure
     * reproduces the linear Hugoniot U_s = C0 + S1 u_p, C0² = K/ρ0.
     *
     * The viscosity adds q = ρ Δx |D_kk| (A1 C + A2 Δx |D_kk|) to the
     * pressure while D_kk < 0 (Eq. 52), with ρ the current density, Δx the
     * point's cell size and C the current bulk wave speed.
     *
     * Shear: Kirchhoff s = G dev(b̄_e); without plasticity b̄_e = J^{-2/3}
     * F Fᵀ (Eq. 18). With a yield stress, b̄_e is stored per point and
     * returned to the von Mises surface |s| ≤ √(2/3)(σ_y + H ε_p) with the
     * radial return of the multiplicative model (Simo & Hughes, Box 9.1).
     *
     * The model reports ρ0 U as its energy per reference volume, so the
     * run's total energy (kinetic + this) changes only by the external
     * work.
     *
     * @ingroup ConstitutiveModels
     */
    template <int dim>
    class MieGruneisen : public Interface<dim>
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm);

      void
      parse_parameters(ParameterHandler &prm) override;

      void
      request_properties(ParticleProperties<dim> &properties) override;

      bool
      needs_cell_size() const override
      {
        return artificial_viscosity_a1 > 0 || artificial_viscosity_a2 > 0;
      }

      bool
      computes_wave_speed() const override
      {
        return true;
      }

      void
      update_stress(const StressUpdateInputs &inputs,
                    StressUpdateOutputs      &outputs) const override;

      /** Wave speed at volume ratio J with U = 0 (the start of a run). */
      double
      wave_speed(const double density, const double J) const override;

      void
      check_parameters(const std::string &where) const override;

      /**
       * Pressure of Eq. (51) without the energy term, and its derivative
       * dp/dη, at compression η = 1 − J.
       */
      void
      cold_pressure(const double eta, double &p, double &dp_deta) const;

      /**
       * Isentropic tangent bulk modulus −V dp/dV at volume ratio J and
       * pressure p (Eq. 51 with dU = p dη/ρ0). Units: Pa.
       */
      double
      tangent_bulk_modulus(const double J, const double p) const;

      /** Kirchhoff deviatoric stress G dev(b̄) of b̄ = J^{-2/3} F Fᵀ. */
      SymmetricTensor<2, 3>
      elastic_shear_stress(const Tensor<2, 3> &F) const;

      double bulk_modulus            = 188e9;
      double shear_modulus           = 76e9;
      double gruneisen_gamma         = 2.0;
      double s1                      = 1.44;
      double artificial_viscosity_a1 = 0.0;
      double artificial_viscosity_a2 = 0.0;
      /** J2 plasticity of the shear part (none by default). */
      J2Hardening plasticity;
      /** The constants as the scene sets them (K, G or E, ν). */
      ElasticConstants elastic_constants;

    private:
      /** Property slots: U, ε_p, and b̄_e − I (6, with plasticity). */
      unsigned int energy_slot    = 0;
      unsigned int plastic_slot   = 0;
      unsigned int elastic_b_slot = 0;
    };
  } // namespace ConstitutiveModel
} // namespace fmpm

#endif
