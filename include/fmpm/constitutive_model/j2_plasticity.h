// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_constitutive_model_j2_plasticity_h
#define fmpm_constitutive_model_j2_plasticity_h

#include <fmpm/parameter_entries.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <cmath>
#include <string>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    using namespace dealii;

    /**
     * @brief J2 (von Mises) plasticity with linear isotropic hardening on
     * the deviatoric Kirchhoff stress s = G dev(b̄_e), integrated by the
     * radial return of [SimoHughes1998] Box 9.1: the elastic left
     * Cauchy–Green tensor b̄_e is carried by each point (stored as b̄_e − I,
     * so that zero means undeformed), the yield function is
     * f = |s| − √(2/3) (σ_y + H ε_p), ε_p the equivalent plastic strain.
     * A model with a volumetric part of its own adds it to s.
     */
    struct J2Hardening
    {
      /** σ_y; 0: no plasticity. Units: Pa. */
      double yield_stress = 0.0;
      /** H of σ_y + H ε_p. Units: Pa. */
      double hardening_modulus = 0.0;

      bool
      plastic() const
      {
        return yield_stress > 0;
      }

      /** The entries 'Yield stress' and 'Hardening modulus'. */
      static void
      declare_parameters(ParameterHandler &prm, const J2Hardening &defaults)
      {
        prm.declare_entry("Yield stress",
                          format_number(defaults.yield_stress),
                          Patterns::Double(),
                          "Initial von Mises yield stress σ_y (J2 plasticity "
                          "on the deviatoric Kirchhoff stress); 0: no "
                          "plasticity. Must not be negative. Units: Pa.");
        prm.declare_entry("Hardening modulus",
                          format_number(defaults.hardening_modulus),
                          Patterns::Double(),
                          "Linear hardening H: the yield stress is σ_y + H "
                          "ε_p (ε_p the equivalent plastic strain). Must not "
                          "be negative. Units: Pa.");
      }

      void
      parse_parameters(ParameterHandler &prm)
      {
        yield_stress      = prm.get_double("Yield stress");
        hardening_modulus = prm.get_double("Hardening modulus");
      }

      /**
       * Deviatoric Kirchhoff stress after the step F0 → F1 by radial return
       * ([SimoHughes1998] Box 9.1): trial b̄_e = f̄ b̄_eⁿ f̄ᵀ with
       * f̄ = det(f)^{-1/3} f, f = F1 F0⁻¹; if f > 0, s = s_trial −
       * 2 μ̄ Δγ n with μ̄ = G tr(b̄_e)/3 and Δγ = f/(2 μ̄ + 2H/3).
       * Updates @p elastic_b_minus_identity and @p plastic_strain: b̄_e =
       * s/G + Ī_e I with Ī_e = tr(b̄_e trial)/3, or, with @p unimodular, the
       * Ī_e that keeps det b̄_e = 1 ([SimoHughes1998] §9.3.2; the trace
       * otherwise drifts upward and with it the stored energy
       * G/2 (tr b̄_e − 3), while s is the same either way).
       */
      SymmetricTensor<2, 3>
      radial_return(const Tensor<2, 3>    &F0,
                    const Tensor<2, 3>    &F1,
                    const double           shear_modulus,
                    SymmetricTensor<2, 3> &elastic_b_minus_identity,
                    double                &plastic_strain,
                    const bool             unimodular = false) const
      {
        const double                sqrt_2_3 = std::sqrt(2. / 3.);
        const SymmetricTensor<2, 3> I        = unit_symmetric_tensor<3>();
        SymmetricTensor<2, 3>       b_e      = elastic_b_minus_identity;
        b_e += I;
        const Tensor<2, 3> f     = F1 * invert(F0);
        const Tensor<2, 3> f_bar = std::pow(determinant(f), -1. / 3.) * f;
        const SymmetricTensor<2, 3> b_trial =
          symmetrize(f_bar * Tensor<2, 3>(b_e) * transpose(f_bar));
        const SymmetricTensor<2, 3> s_trial = shear_modulus * deviator(b_trial);
        const double                I_e     = trace(b_trial) / 3.;
        const double                mu_bar  = shear_modulus * I_e;
        const double                norm    = s_trial.norm();
        const double                f_yield =
          norm - sqrt_2_3 * (yield_stress + hardening_modulus * plastic_strain);
        SymmetricTensor<2, 3> s = s_trial;
        if (f_yield > 0)
          {
            const double dgamma =
              f_yield / (2. * mu_bar + 2. / 3. * hardening_modulus);
            s -= (2. * mu_bar * dgamma / norm) * s_trial;
            plastic_strain += sqrt_2_3 * dgamma;
          }
        const SymmetricTensor<2, 3> A = s / shear_modulus;
        double                      x = I_e;
        if (unimodular)
          {
            // det(A + x I) = x³ − |A|²/2 x + det A = 1 (tr A = 0), Newton
            // from Ī_e (a root near 1 for elastic strains below ~10 %).
            const double A2 = 0.5 * A.norm() * A.norm(), detA = determinant(A);
            x = 1.;
            for (unsigned int i = 0; i < 8; ++i)
              {
                const double dx =
                  (x * x * x - A2 * x + detA - 1.) / (3. * x * x - A2);
                x -= dx;
                if (std::abs(dx) < 1e-10)
                  break;
              }
          }
        elastic_b_minus_identity = A + (x - 1.) * I;
        return s;
      }

      /** Plastic work per unit reference volume done up to @p
       * plastic_strain: ∫ (σ_y + H ε) dε = σ_y ε_p + H ε_p²/2. */
      double
      plastic_work(const double plastic_strain) const
      {
        return plastic_strain *
               (yield_stress + 0.5 * hardening_modulus * plastic_strain);
      }

      /** Throws for a negative σ_y or H, naming @p where. */
      void
      check(const std::string &where) const
      {
        AssertThrow(yield_stress >= 0,
                    ExcMessage(
                      where + "/Yield stress = " + format_number(yield_stress) +
                      " is not allowed. Allowed: 0 (no "
                      "plasticity) or any value > 0 (Pa)."));
        AssertThrow(hardening_modulus >= 0,
                    ExcMessage(where + "/Hardening modulus = " +
                               format_number(hardening_modulus) +
                               " is not allowed. Allowed: any value >= 0 "
                               "(Pa)."));
      }
    };
  } // namespace ConstitutiveModel
} // namespace fmpm

#endif
