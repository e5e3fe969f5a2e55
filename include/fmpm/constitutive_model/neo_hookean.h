// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_constitutive_model_neo_hookean_h
#define fmpm_constitutive_model_neo_hookean_h

#include <fmpm/constitutive_model/elastic_constants.h>
#include <fmpm/constitutive_model/interface.h>
#include <fmpm/constitutive_model/j2_plasticity.h>
#include <fmpm/parameter_entries.h>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    /**
     * @brief Compressible neo-Hookean hyperelasticity in one of two forms
     * ('Energy form'):
     * - 'J^2' (default), seed 004 Eq. (18):
     *   \f$W = \frac{G}{2}(I_1 J^{-2/3} - 3) + \frac{K}{2}(\frac{1}{2}(J^2-1)
     *   - \ln J)\f$, giving the Kirchhoff stress
     *   \f$\tau = G\,\mathrm{dev}(\bar b) + \frac{K}{2}(J^2-1) I\f$ with
     *   \f$\bar b = J^{-2/3} F F^T\f$;
     * - 'ln J', the form of [BonetWood2008] §6.4.3 most MPM benchmarks use:
     *   \f$W = \frac{\mu}{2}(I_1 - 3) - \mu\ln J +
     *   \frac{\lambda}{2}(\ln J)^2\f$, giving
     *   \f$\tau = \mu (b - I) + \lambda \ln J\, I\f$ with \f$b = F F^T\f$,
     *   \f$\mu = G\f$, \f$\lambda = K - 2G/3\f$.
     *
     * The Cauchy stress is \f$\sigma = \tau/J\f$. Both depend on F only
     * through b and J: objective. In 2D b_zz = F_33² is part of I_1 and of
     * σ_zz (F_33 = 1 in plane strain, the hoop stretch in axisymmetric
     * analysis).
     *
     * With a 'Yield stress' > 0 (the 'J^2' form only) the shear part is
     * elastic–plastic: s = G dev(b̄_e) with J2 plasticity and linear
     * hardening by radial return (J2Hardening), the volumetric part stays
     * K/2 (J² − 1) I, and W adds the plastic work σ_y ε_p + H ε_p²/2.
     *
     * @ingroup ConstitutiveModels
     */
    template <int dim>
    class NeoHookean : public Interface<dim>
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm);

      void
      parse_parameters(ParameterHandler &prm) override;

      void
      update_stress(const StressUpdateInputs &inputs,
                    StressUpdateOutputs      &outputs) const override;

      void
      request_properties(ParticleProperties<dim> &properties) override;

      /** σ and W follow from F^{n+1} alone, unless the shear part is
       * plastic (F^n and b̄_eⁿ then). */
      bool
      reads_old_state() const override
      {
        return plasticity.plastic();
      }

      double
      wave_speed(const double density, const double J) const override;

      /** wave_speed() over a batch, inline. */
      double
      max_wave_speed(const double                   density,
                     const ArrayView<const double> &J) const override;

      void
      check_parameters(const std::string &where) const override;

      /** Kirchhoff stress and energy density W of one deformation gradient. */
      void
      stress_and_energy(const Tensor<2, 3>    &F,
                        SymmetricTensor<2, 3> &kirchhoff_stress,
                        double                &energy_density) const;

      /** Bulk modulus K. Units: Pa. */
      double bulk_modulus = 1.0e6;
      /** Shear modulus G. Units: Pa. */
      double shear_modulus = 0.5e6;
      /** 'Energy form', resolved from its name when parsed. */
      enum class EnergyForm
      {
        /** [NHS2020-contact] Eq. (18). */
        j_squared,
        /** λ ln J / J I + μ/J (b − I). */
        log_j
      };
      EnergyForm energy_form = EnergyForm::j_squared;
      static constexpr SelectionNames<EnergyForm, 2> energy_form_names{
        {"J^2", "ln J"}};
      /** J2 plasticity of the shear part (none by default). */
      J2Hardening plasticity;
      /** The constants as the scene sets them (K, G or E, ν). */
      ElasticConstants elastic_constants;

    private:
      /** The batch's points with plasticity (one point at a time). */
      void
      update_plastic(const StressUpdateInputs &inputs,
                     StressUpdateOutputs      &outputs) const;

      /** Property slots (with plasticity): ε_p and b̄_e − I (6). */
      unsigned int plastic_slot   = 0;
      unsigned int elastic_b_slot = 0;
    };
  } // namespace ConstitutiveModel
} // namespace fmpm

#endif
