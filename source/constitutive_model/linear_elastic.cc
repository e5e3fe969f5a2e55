// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/constitutive_model/linear_elastic.h>
#include <fmpm/parameters.h>

#include <cmath>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    namespace
    {
      constexpr unsigned int n = StressUpdateInputs::capacity;

      // The kernels loop over the batch's whole capacity, on restrict
      // parameters: GCC vectorizes them at -O2. Entries past n_points are
      // finite and are not read back. The entries are in the stored order
      // (xx, yy, zz, xy, xz, yz; L and F row major), and the sums in the
      // order of deal.II's SymmetricTensor operations (the same results).

      /** σ += Δt (λ tr(D) I + 2μ D), D = sym(L), with the Jaumann rate
       * also + Δt (Ωσ − σΩ), Ω = skew(L) (σ of the step's start); W += J
       * σ_mid : D Δt. */
      template <bool jaumann>
      inline void
      incremental_stress(const double (*__restrict L)[n],
                         const double (*__restrict old_sigma)[n],
                         const double *__restrict old_energy,
                         const double *__restrict J,
                         double (*__restrict sigma)[n],
                         double *__restrict energy,
                         const double lambda,
                         const double mu,
                         const double dt)
      {
        const double two_mu = 2 * mu;
        for (unsigned int q = 0; q < n; ++q)
          {
            const double D_xx = L[0][q], D_yy = L[4][q], D_zz = L[8][q];
            const double D_xy         = (L[1][q] + L[3][q]) * 0.5;
            const double D_xz         = (L[2][q] + L[6][q]) * 0.5;
            const double D_yz         = (L[5][q] + L[7][q]) * 0.5;
            const double lambda_trace = lambda * (D_xx + D_yy + D_zz);
            double       r_xx         = lambda_trace + two_mu * D_xx;
            double       r_yy         = lambda_trace + two_mu * D_yy;
            double       r_zz         = lambda_trace + two_mu * D_zz;
            double       r_xy = two_mu * D_xy, r_xz = two_mu * D_xz,
                   r_yz = two_mu * D_yz;
            if constexpr (jaumann)
              {
                // Ωσ − σΩ = Ωσ + (Ωσ)ᵀ with Ω = skew(L).
                const double w_xy = (L[1][q] - L[3][q]) * 0.5;
                const double w_xz = (L[2][q] - L[6][q]) * 0.5;
                const double w_yz = (L[5][q] - L[7][q]) * 0.5;
                const double s_xx = old_sigma[0][q], s_yy = old_sigma[1][q],
                             s_zz = old_sigma[2][q], s_xy = old_sigma[3][q],
                             s_xz = old_sigma[4][q], s_yz = old_sigma[5][q];
                r_xx += 2 * (w_xy * s_xy + w_xz * s_xz);
                r_yy += 2 * (w_yz * s_yz - w_xy * s_xy);
                r_zz -= 2 * (w_xz * s_xz + w_yz * s_yz);
                r_xy += w_xy * (s_yy - s_xx) + w_xz * s_yz + w_yz * s_xz;
                r_xz += w_xy * s_yz + w_xz * (s_zz - s_xx) - w_yz * s_xy;
                r_yz += w_yz * (s_zz - s_yy) - w_xy * s_xz - w_xz * s_xy;
              }
            const double xx   = old_sigma[0][q] + dt * r_xx;
            const double yy   = old_sigma[1][q] + dt * r_yy;
            const double zz   = old_sigma[2][q] + dt * r_zz;
            const double xy   = old_sigma[3][q] + dt * r_xy;
            const double xz   = old_sigma[4][q] + dt * r_xz;
            const double yz   = old_sigma[5][q] + dt * r_yz;
            double       work = (old_sigma[3][q] + xy) * D_xy;
            work += (old_sigma[4][q] + xz) * D_xz;
            work += (old_sigma[5][q] + yz) * D_yz;
            work += work;
            work += (old_sigma[0][q] + xx) * D_xx;
            work += (old_sigma[1][q] + yy) * D_yy;
            work += (old_sigma[2][q] + zz) * D_zz;
            sigma[0][q] = xx;
            sigma[1][q] = yy;
            sigma[2][q] = zz;
            sigma[3][q] = xy;
            sigma[4][q] = xz;
            sigma[5][q] = yz;
            energy[q]   = old_energy[q] + 0.5 * J[q] * work * dt;
          }
      }

      /** The Kirchhoff stress τ = Jσ with the Jaumann rate: τ += Δt (λ
       * tr(D) I + 2μ D + Ωτ − τΩ), σ = τ/J; W += τ_mid : D Δt. */
      inline void
      kirchhoff_stress(const double (*__restrict L)[n],
                       const double (*__restrict old_sigma)[n],
                       const double *__restrict old_J,
                       const double *__restrict old_energy,
                       const double *__restrict J,
                       double (*__restrict sigma)[n],
                       double *__restrict energy,
                       const double lambda,
                       const double mu,
                       const double dt)
      {
        const double two_mu = 2 * mu;
        for (unsigned int q = 0; q < n; ++q)
          {
            const double D_xx = L[0][q], D_yy = L[4][q], D_zz = L[8][q];
            const double D_xy         = (L[1][q] + L[3][q]) * 0.5;
            const double D_xz         = (L[2][q] + L[6][q]) * 0.5;
            const double D_yz         = (L[5][q] + L[7][q]) * 0.5;
            const double w_xy         = (L[1][q] - L[3][q]) * 0.5;
            const double w_xz         = (L[2][q] - L[6][q]) * 0.5;
            const double w_yz         = (L[5][q] - L[7][q]) * 0.5;
            const double t_xx         = old_J[q] * old_sigma[0][q],
                         t_yy         = old_J[q] * old_sigma[1][q],
                         t_zz         = old_J[q] * old_sigma[2][q],
                         t_xy         = old_J[q] * old_sigma[3][q],
                         t_xz         = old_J[q] * old_sigma[4][q],
                         t_yz         = old_J[q] * old_sigma[5][q];
            const double lambda_trace = lambda * (D_xx + D_yy + D_zz);
            const double xx = t_xx + dt * (lambda_trace + two_mu * D_xx +
                                           2 * (w_xy * t_xy + w_xz * t_xz));
            const double yy = t_yy + dt * (lambda_trace + two_mu * D_yy +
                                           2 * (w_yz * t_yz - w_xy * t_xy));
            const double zz = t_zz + dt * (lambda_trace + two_mu * D_zz -
                                           2 * (w_xz * t_xz + w_yz * t_yz));
            const double xy =
              t_xy + dt * (two_mu * D_xy + w_xy * (t_yy - t_xx) + w_xz * t_yz +
                           w_yz * t_xz);
            const double xz = t_xz + dt * (two_mu * D_xz + w_xy * t_yz +
                                           w_xz * (t_zz - t_xx) - w_yz * t_xy);
            const double yz =
              t_yz + dt * (two_mu * D_yz + w_yz * (t_zz - t_yy) - w_xy * t_xz -
                           w_xz * t_xy);
            const double work =
              (t_xx + xx) * D_xx + (t_yy + yy) * D_yy + (t_zz + zz) * D_zz +
              2 *
                ((t_xy + xy) * D_xy + (t_xz + xz) * D_xz + (t_yz + yz) * D_yz);
            const double inverse_J = 1 / J[q];
            sigma[0][q]            = xx * inverse_J;
            sigma[1][q]            = yy * inverse_J;
            sigma[2][q]            = zz * inverse_J;
            sigma[3][q]            = xy * inverse_J;
            sigma[4][q]            = xz * inverse_J;
            sigma[5][q]            = yz * inverse_J;
            energy[q]              = old_energy[q] + 0.5 * work * dt;
          }
      }

      /** ε = sym(F) − I, σ = λ tr(ε) I + 2μ ε, W = σ:ε / 2. */
      inline void
      total_strain_stress(const double (*__restrict F)[n],
                          double (*__restrict sigma)[n],
                          double *__restrict energy,
                          const double lambda,
                          const double mu)
      {
        const double two_mu = 2 * mu;
        for (unsigned int q = 0; q < n; ++q)
          {
            const double e_xx = F[0][q] - 1, e_yy = F[4][q] - 1,
                         e_zz         = F[8][q] - 1;
            const double e_xy         = (F[1][q] + F[3][q]) * 0.5,
                         e_xz         = (F[2][q] + F[6][q]) * 0.5,
                         e_yz         = (F[5][q] + F[7][q]) * 0.5;
            const double lambda_trace = lambda * (e_xx + e_yy + e_zz);
            const double xx           = lambda_trace + two_mu * e_xx;
            const double yy           = lambda_trace + two_mu * e_yy;
            const double zz           = lambda_trace + two_mu * e_zz;
            const double xy = two_mu * e_xy, xz = two_mu * e_xz,
                         yz = two_mu * e_yz;
            double work     = xy * e_xy;
            work += xz * e_xz;
            work += yz * e_yz;
            work += work;
            work += xx * e_xx;
            work += yy * e_yy;
            work += zz * e_zz;
            sigma[0][q] = xx;
            sigma[1][q] = yy;
            sigma[2][q] = zz;
            sigma[3][q] = xy;
            sigma[4][q] = xz;
            sigma[5][q] = yz;
            energy[q]   = 0.5 * work;
          }
      }
    } // namespace



    template <int dim>
    void
    LinearElastic<dim>::declare_parameters(ParameterHandler &prm)
    {
      const LinearElastic<dim> defaults;
      ElasticConstants::declare_parameters(
        prm,
        ElasticConstants::Pair::youngs_and_poisson,
        defaults.youngs_modulus,
        defaults.poissons_ratio,
        "Young's modulus E of the material. A number > 0.",
        "Poisson's ratio nu of the material. A number in (-1, 0.5).");
      prm.declare_entry(
        "Strain measure",
        strain_measure_names.name(defaults.strain_measure),
        Patterns::Selection(strain_measure_names.pattern()),
        "'incremental': sigma += dt C : sym(L) (classic MPM, no stress from "
        "rigid rotation, but a stress does not turn with the material); "
        "'jaumann': sigma += dt (C : sym(L) + W sigma - sigma W), W = "
        "skew(L), the incremental update with the Jaumann rate (objective: a "
        "stress turns with the material's spin, NairnMPM's hypoelastic "
        "update of the Cauchy stress); 'kirchhoff': the same for the "
        "Kirchhoff stress tau = J sigma, tau += dt (C : sym(L) + W tau - tau "
        "W), sigma = tau/J (NairnMPM's isotropic material, which updates the "
        "stress per unit mass); 'total': sigma = C : (sym(F) - I) (exact for "
        "small strains without rotation). Units: none.");
    }



    template <int dim>
    void
    LinearElastic<dim>::parse_parameters(ParameterHandler &prm)
    {
      elastic_constants.parse_parameters(prm);
      elastic_constants.get_youngs_and_poisson(youngs_modulus, poissons_ratio);
      strain_measure = strain_measure_names.value(prm.get("Strain measure"));
    }



    template <int dim>
    void
    LinearElastic<dim>::check_parameters(const std::string &where) const
    {
      elastic_constants.check(where,
                              ElasticConstants::Pair::youngs_and_poisson);
      AssertThrow(youngs_modulus > 0,
                  ExcMessage(where + "/Young's modulus = " +
                             format_number(youngs_modulus) +
                             " is not positive. Allowed: any value > 0 (Pa)."));
      AssertThrow(poissons_ratio > -1 && poissons_ratio < 0.5,
                  ExcMessage(where + "/Poisson's ratio = " +
                             format_number(poissons_ratio) +
                             " is outside the allowed range (-1, 0.5)."));
    }



    template <int dim>
    void
    LinearElastic<dim>::update_stress(const StressUpdateInputs &inputs,
                                      StressUpdateOutputs      &outputs) const
    {
      const double mu     = youngs_modulus / (2 * (1 + poissons_ratio));
      const double lambda = youngs_modulus * poissons_ratio /
                            ((1 + poissons_ratio) * (1 - 2 * poissons_ratio));
      if (strain_measure == StrainMeasure::kirchhoff)
        kirchhoff_stress(inputs.velocity_gradient,
                         inputs.old_stress,
                         inputs.old_volume_ratio,
                         inputs.old_strain_energy_density,
                         inputs.volume_ratio,
                         outputs.cauchy_stress,
                         outputs.strain_energy_density,
                         lambda,
                         mu,
                         inputs.time_step);
      else if (strain_measure != StrainMeasure::total)
        (strain_measure == StrainMeasure::jaumann ?
           incremental_stress<true> :
           incremental_stress<false>)(inputs.velocity_gradient,
                                      inputs.old_stress,
                                      inputs.old_strain_energy_density,
                                      inputs.volume_ratio,
                                      outputs.cauchy_stress,
                                      outputs.strain_energy_density,
                                      lambda,
                                      mu,
                                      inputs.time_step);
      else
        total_strain_stress(inputs.deformation_gradient,
                            outputs.cauchy_stress,
                            outputs.strain_energy_density,
                            lambda,
                            mu);
    }



    template <int dim>
    double
    LinearElastic<dim>::wave_speed(const double density, const double) const
    {
      const double mu     = youngs_modulus / (2 * (1 + poissons_ratio));
      const double lambda = youngs_modulus * poissons_ratio /
                            ((1 + poissons_ratio) * (1 - 2 * poissons_ratio));
      return std::sqrt((lambda + 2 * mu) / density);
    }

    FMPM_REGISTER_CONSTITUTIVE_MODEL(
      LinearElastic,
      "linear elastic",
      "Small-strain isotropic linear elasticity with lambda = E nu/((1 + "
      "nu)(1 - 2 nu)), mu = E/(2(1 + nu)), for verification against linear "
      "analytical solutions: 'Strain measure = incremental' (default) sigma "
      "+= dt (lambda tr(D) I + 2 mu D), D = sym(L); 'jaumann' the same plus "
      "dt (W sigma - sigma W), W = skew(L); 'kirchhoff' the same for tau = "
      "J sigma; 'total' sigma = lambda tr(eps) I + 2 mu eps, eps = sym(F) - "
      "I. Constants E and nu, or K and G.")
  } // namespace ConstitutiveModel
} // namespace fmpm
