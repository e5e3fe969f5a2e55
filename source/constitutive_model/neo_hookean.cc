// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/constitutive_model/neo_hookean.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_properties.h>

#include <algorithm>
#include <cmath>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    template <int dim>
    void
    NeoHookean<dim>::declare_parameters(ParameterHandler &prm)
    {
      const NeoHookean<dim> defaults;
      ElasticConstants::declare_parameters(
        prm,
        ElasticConstants::Pair::bulk_and_shear,
        defaults.bulk_modulus,
        defaults.shear_modulus,
        "Bulk modulus K of [NHS2020-contact] Eq. (18) (with 'Energy form = "
        "ln J': lambda = K - 2G/3). A number > 0.",
        "Shear modulus G of [NHS2020-contact] Eq. (18) (with 'Energy form = "
        "ln J': mu = G). A number > 0.");
      prm.declare_entry(
        "Energy form",
        energy_form_names.name(defaults.energy_form),
        Patterns::Selection(energy_form_names.pattern()),
        "'J^2': W = G/2 (I1 J^(-2/3) - 3) + K/2 ((J^2 - 1)/2 - ln J) "
        "([NHS2020-contact] Eq. 18), Kirchhoff stress tau = G dev(b_bar) + "
        "K/2 (J^2 - 1) I with b_bar = J^(-2/3) b; 'ln J': W = mu/2 (I1 - 3) "
        "- mu ln J + lambda/2 (ln J)^2 ([BonetWood2008] Sec. 6.4.3, the form "
        "most MPM benchmarks use), tau = mu (b - I) + lambda ln J I with mu "
        "= G, lambda = K - 2G/3. Both: b = F F^T, I1 = tr b, Cauchy stress "
        "sigma = tau/J; in 2D (plane strain) b_zz = 1 counts in I1 and "
        "sigma_zz. Units: none.");
      J2Hardening::declare_parameters(prm, defaults.plasticity);
    }



    template <int dim>
    void
    NeoHookean<dim>::parse_parameters(ParameterHandler &prm)
    {
      elastic_constants.parse_parameters(prm);
      elastic_constants.get_bulk_and_shear(bulk_modulus, shear_modulus);
      energy_form = energy_form_names.value(prm.get("Energy form"));
      plasticity.parse_parameters(prm);
    }



    template <int dim>
    void
    NeoHookean<dim>::request_properties(ParticleProperties<dim> &properties)
    {
      if (!plasticity.plastic())
        return;
      plastic_slot   = properties.request("plastic_strain", 1);
      elastic_b_slot = properties.request("elastic_b_minus_identity", 6);
    }



    template <int dim>
    void
    NeoHookean<dim>::check_parameters(const std::string &where) const
    {
      elastic_constants.check(where, ElasticConstants::Pair::bulk_and_shear);
      AssertThrow(bulk_modulus > 0,
                  ExcMessage(where +
                             "/Bulk modulus = " + format_number(bulk_modulus) +
                             " is not positive. Allowed: any value > 0 (Pa)."));
      AssertThrow(shear_modulus > 0,
                  ExcMessage(
                    where + "/Shear modulus = " + format_number(shear_modulus) +
                    " is not positive. Allowed: any value > 0 (Pa)."));
      plasticity.check(where);
      AssertThrow(!plasticity.plastic() || energy_form == EnergyForm::j_squared,
                  ExcMessage(where + "/Yield stress = " +
                             format_number(plasticity.yield_stress) +
                             " needs 'Energy form = J^2' (the plastic flow "
                             "acts on dev(b_bar)); 'ln J' is elastic only. "
                             "Allowed: Yield stress = 0 with 'ln J'."));
    }



    template <int dim>
    void
    NeoHookean<dim>::stress_and_energy(const Tensor<2, 3>    &F,
                                       SymmetricTensor<2, 3> &tau,
                                       double                &W) const
    {
      const double J     = determinant(F);
      const double log_J = std::log(J);
      if (energy_form == EnergyForm::log_j)
        {
          // τ = μ (b − I) + λ ln J I, W = μ/2 (tr b − 3) − μ ln J +
          // λ/2 (ln J)² ([BonetWood2008] §6.4.3).
          const double mu     = shear_modulus;
          const double lambda = bulk_modulus - 2.0 / 3.0 * shear_modulus;
          for (unsigned int a = 0; a < 3; ++a)
            for (unsigned int b = a; b < 3; ++b)
              tau[a][b] = mu * (F[a][0] * F[b][0] + F[a][1] * F[b][1] +
                                F[a][2] * F[b][2]);
          const double I1 = trace(tau) / mu;
          for (unsigned int a = 0; a < 3; ++a)
            tau[a][a] += lambda * log_J - mu;
          W = 0.5 * mu * (I1 - 3) - mu * log_J + 0.5 * lambda * log_J * log_J;
          return;
        }
      // J^{-2/3} from the ln J the energy needs (one exp instead of pow).
      const double          J_m23 = std::exp(-2.0 / 3.0 * log_J);
      SymmetricTensor<2, 3> b_bar; // J^{-2/3} F Fᵀ, its 6 entries
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int b = a; b < 3; ++b)
          b_bar[a][b] =
            J_m23 * (F[a][0] * F[b][0] + F[a][1] * F[b][1] + F[a][2] * F[b][2]);
      const double I1_bar     = trace(b_bar);
      const double volumetric = 0.5 * bulk_modulus * (J * J - 1);
      tau                     = shear_modulus * b_bar;
      for (unsigned int a = 0; a < 3; ++a)
        tau[a][a] += volumetric - shear_modulus * I1_bar / 3.0;
      W = 0.5 * shear_modulus * (I1_bar - 3) +
          0.5 * bulk_modulus * (0.5 * (J * J - 1) - log_J);
    }



    namespace
    {
      /**
       * 2D (no out-of-plane shear) for @p n points: J is the 2x2 block's
       * determinant times F₃₃ (1 in plane strain, the hoop stretch in
       * axisymmetric analysis; ×1 leaves plane strain's bits) and
       * b̄ = J^{-2/3} F Fᵀ has four entries (b̄_zz = J^{-2/3} F₃₃²); otherwise
       * the same Eq. 18 as stress_and_energy(). Three loops, so that the two
       * without log and exp vectorize (restrict- qualified parameters; a
       * constant count for full batches).
       */
      template <typename Count>
      inline void
      plane_strain_neo_hookean(const Count  n,
                               const double K,
                               const double G,
                               const double *__restrict F_xx,
                               const double *__restrict F_xy,
                               const double *__restrict F_yx,
                               const double *__restrict F_yy,
                               const double *__restrict F_zz,
                               double *__restrict J,
                               double *__restrict log_J,
                               double *__restrict J_m23,
                               double *__restrict sigma_xx,
                               double *__restrict sigma_yy,
                               double *__restrict sigma_zz,
                               double *__restrict sigma_xy,
                               double *__restrict sigma_xz,
                               double *__restrict sigma_yz,
                               double *__restrict W)
      {
        for (unsigned int q = 0; q < n; ++q)
          J[q] = (F_xx[q] * F_yy[q] - F_xy[q] * F_yx[q]) * F_zz[q];
        for (unsigned int q = 0; q < n; ++q)
          {
            log_J[q] = std::log(J[q]);
            J_m23[q] = std::exp(-2.0 / 3.0 * log_J[q]);
          }
        for (unsigned int q = 0; q < n; ++q)
          {
            const double b_xx =
              J_m23[q] * (F_xx[q] * F_xx[q] + F_xy[q] * F_xy[q]);
            const double b_yy =
              J_m23[q] * (F_yx[q] * F_yx[q] + F_yy[q] * F_yy[q]);
            const double b_xy =
              J_m23[q] * (F_xx[q] * F_yx[q] + F_xy[q] * F_yy[q]);
            const double b_zz   = J_m23[q] * (F_zz[q] * F_zz[q]);
            const double I1_bar = b_xx + b_yy + b_zz;
            // τ = G b̄ + (K (J² − 1)/2 − G Ī₁/3) I, σ = τ/J.
            const double pressure_part =
              0.5 * K * (J[q] * J[q] - 1) - G * I1_bar / 3.0;
            sigma_xx[q] = (G * b_xx + pressure_part) / J[q];
            sigma_yy[q] = (G * b_yy + pressure_part) / J[q];
            sigma_zz[q] = (G * b_zz + pressure_part) / J[q];
            sigma_xy[q] = G * b_xy / J[q];
            sigma_xz[q] = 0;
            sigma_yz[q] = 0;
            W[q]        = 0.5 * G * (I1_bar - 3) +
                   0.5 * K * (0.5 * (J[q] * J[q] - 1) - log_J[q]);
          }
      }

      /** The batch's points with plane_strain_neo_hookean(). */
      template <typename Count>
      void
      plane_strain_update(const Count               n,
                          const double              K,
                          const double              G,
                          const StressUpdateInputs &inputs,
                          StressUpdateOutputs      &outputs)
      {
        alignas(64) double J[StressUpdateInputs::capacity],
          log_J[StressUpdateInputs::capacity],
          J_m23[StressUpdateInputs::capacity];
        const auto &F     = inputs.deformation_gradient;
        auto       &sigma = outputs.cauchy_stress;
        plane_strain_neo_hookean(n,
                                 K,
                                 G,
                                 F[0],
                                 F[1],
                                 F[3],
                                 F[4],
                                 F[8],
                                 J,
                                 log_J,
                                 J_m23,
                                 sigma[0],
                                 sigma[1],
                                 sigma[2],
                                 sigma[3],
                                 sigma[4],
                                 sigma[5],
                                 outputs.strain_energy_density);
      }

      /**
       * stress_and_energy() entry by entry for @p n points: J = det F^{n+1}
       * as the batch has it (deal.II's determinant()), σ = τ (1/J) as
       * deal.II divides a tensor; the same operations, the same values.
       * @p F and @p sigma are entry blocks (entry c of point q at
       * [c capacity + q]). Log and exp in their own loop, so that the other
       * vectorizes.
       */
      template <typename Count>
      inline void
      neo_hookean_3d(const Count  n,
                     const double K,
                     const double G,
                     const double *__restrict F,
                     const double *__restrict J,
                     double *__restrict log_J,
                     double *__restrict J_m23,
                     double *__restrict sigma,
                     double *__restrict W)
      {
        constexpr unsigned int stride = StressUpdateInputs::capacity;
        for (unsigned int q = 0; q < n; ++q)
          {
            log_J[q] = std::log(J[q]);
            J_m23[q] = std::exp(-2.0 / 3.0 * log_J[q]);
          }
        for (unsigned int q = 0; q < n; ++q)
          {
            const double F_xx = F[0 * stride + q], F_xy = F[1 * stride + q],
                         F_xz = F[2 * stride + q], F_yx = F[3 * stride + q],
                         F_yy = F[4 * stride + q], F_yz = F[5 * stride + q],
                         F_zx = F[6 * stride + q], F_zy = F[7 * stride + q],
                         F_zz = F[8 * stride + q];
            // b̄ = J^{-2/3} F Fᵀ
            const double b_xx =
              J_m23[q] * (F_xx * F_xx + F_xy * F_xy + F_xz * F_xz);
            const double b_yy =
              J_m23[q] * (F_yx * F_yx + F_yy * F_yy + F_yz * F_yz);
            const double b_zz =
              J_m23[q] * (F_zx * F_zx + F_zy * F_zy + F_zz * F_zz);
            const double b_xy =
              J_m23[q] * (F_xx * F_yx + F_xy * F_yy + F_xz * F_yz);
            const double b_xz =
              J_m23[q] * (F_xx * F_zx + F_xy * F_zy + F_xz * F_zz);
            const double b_yz =
              J_m23[q] * (F_yx * F_zx + F_yy * F_zy + F_yz * F_zz);
            const double I1_bar = b_xx + b_yy + b_zz;
            const double diagonal =
              0.5 * K * (J[q] * J[q] - 1) - G * I1_bar / 3.0;
            const double inverse_J = 1. / J[q];
            sigma[0 * stride + q]  = (G * b_xx + diagonal) * inverse_J;
            sigma[1 * stride + q]  = (G * b_yy + diagonal) * inverse_J;
            sigma[2 * stride + q]  = (G * b_zz + diagonal) * inverse_J;
            sigma[3 * stride + q]  = G * b_xy * inverse_J;
            sigma[4 * stride + q]  = G * b_xz * inverse_J;
            sigma[5 * stride + q]  = G * b_yz * inverse_J;
            W[q]                   = 0.5 * G * (I1_bar - 3) +
                   0.5 * K * (0.5 * (J[q] * J[q] - 1) - log_J[q]);
          }
      }

      /** The batch's points with neo_hookean_3d(). */
      template <typename Count>
      void
      update_3d(const Count               n,
                const double              K,
                const double              G,
                const StressUpdateInputs &inputs,
                StressUpdateOutputs      &outputs)
      {
        alignas(64) double log_J[StressUpdateInputs::capacity],
          J_m23[StressUpdateInputs::capacity];
        neo_hookean_3d(n,
                       K,
                       G,
                       &inputs.deformation_gradient[0][0],
                       inputs.volume_ratio,
                       log_J,
                       J_m23,
                       &outputs.cauchy_stress[0][0],
                       outputs.strain_energy_density);
      }

      /**
       * The 'ln J' form for @p n points ([BonetWood2008] §6.4.3):
       * σ = (μ (b − I) + λ ln J I)/J with b = F Fᵀ, and
       * W = μ/2 (tr b − 3) − μ ln J + λ/2 (ln J)². @p F and @p sigma are
       * entry blocks (entry c of point q at [c capacity + q]). In 2D J is
       * the 2x2 block's determinant times F₃₃ and b_zz = F₃₃² (F₃₃ = 1 in
       * plane strain).
       * Log in its own loop, so that the other loops vectorize.
       */
      template <int dim, typename Count>
      inline void
      log_neo_hookean(const Count  n,
                      const double lambda,
                      const double mu,
                      const double *__restrict F,
                      const double *__restrict volume_ratio,
                      double *__restrict J,
                      double *__restrict log_J,
                      double *__restrict sigma,
                      double *__restrict W)
      {
        constexpr unsigned int stride = StressUpdateInputs::capacity;
        for (unsigned int q = 0; q < n; ++q)
          J[q] = dim == 2 ? (F[0 * stride + q] * F[4 * stride + q] -
                             F[1 * stride + q] * F[3 * stride + q]) *
                              F[8 * stride + q] :
                            volume_ratio[q];
        for (unsigned int q = 0; q < n; ++q)
          log_J[q] = std::log(J[q]);
        for (unsigned int q = 0; q < n; ++q)
          {
            const double F_xx = F[0 * stride + q], F_xy = F[1 * stride + q],
                         F_yx = F[3 * stride + q], F_yy = F[4 * stride + q];
            double b_xx = F_xx * F_xx + F_xy * F_xy;
            double b_yy = F_yx * F_yx + F_yy * F_yy;
            double b_xy = F_xx * F_yx + F_xy * F_yy;
            double b_zz = F[8 * stride + q] * F[8 * stride + q], b_xz = 0,
                   b_yz = 0;
            if constexpr (dim == 3)
              {
                const double F_xz = F[2 * stride + q], F_yz = F[5 * stride + q],
                             F_zx = F[6 * stride + q], F_zy = F[7 * stride + q],
                             F_zz = F[8 * stride + q];
                b_xx += F_xz * F_xz;
                b_yy += F_yz * F_yz;
                b_xy += F_xz * F_yz;
                b_zz = F_zx * F_zx + F_zy * F_zy + F_zz * F_zz;
                b_xz = F_xx * F_zx + F_xy * F_zy + F_xz * F_zz;
                b_yz = F_yx * F_zx + F_yy * F_zy + F_yz * F_zz;
              }
            const double diagonal  = lambda * log_J[q] - mu;
            const double inverse_J = 1. / J[q];
            sigma[0 * stride + q]  = (mu * b_xx + diagonal) * inverse_J;
            sigma[1 * stride + q]  = (mu * b_yy + diagonal) * inverse_J;
            sigma[2 * stride + q]  = (mu * b_zz + diagonal) * inverse_J;
            sigma[3 * stride + q]  = mu * b_xy * inverse_J;
            sigma[4 * stride + q]  = mu * b_xz * inverse_J;
            sigma[5 * stride + q]  = mu * b_yz * inverse_J;
            W[q] = 0.5 * mu * (b_xx + b_yy + b_zz - 3) - mu * log_J[q] +
                   0.5 * lambda * log_J[q] * log_J[q];
          }
      }

      /** The batch's points with log_neo_hookean(). */
      template <int dim, typename Count>
      void
      log_update(const Count               n,
                 const double              lambda,
                 const double              mu,
                 const StressUpdateInputs &inputs,
                 StressUpdateOutputs      &outputs)
      {
        alignas(64) double J[StressUpdateInputs::capacity],
          log_J[StressUpdateInputs::capacity];
        log_neo_hookean<dim>(n,
                             lambda,
                             mu,
                             &inputs.deformation_gradient[0][0],
                             inputs.volume_ratio,
                             J,
                             log_J,
                             &outputs.cauchy_stress[0][0],
                             outputs.strain_energy_density);
      }
    } // namespace



    template <int dim>
    void
    NeoHookean<dim>::update_plastic(const StressUpdateInputs &inputs,
                                    StressUpdateOutputs      &outputs) const
    {
      const SymmetricTensor<2, 3> I = unit_symmetric_tensor<3>();
      for (unsigned int q = 0; q < inputs.n_points; ++q)
        {
          const PointRecord &P  = inputs.properties[q];
          const Tensor<2, 3> F1 = inputs.deformation_gradient_tensor(q);
          const Tensor<2, 3> F0 =
            get_tensor3(P, PropertyIndex<dim>::deformation_gradient);
          SymmetricTensor<2, 3> elastic_b_minus_identity =
            get_symmetric_tensor3(P, elastic_b_slot);
          double                     &plastic_strain = P[plastic_slot];
          const SymmetricTensor<2, 3> s =
            plasticity.radial_return(F0,
                                     F1,
                                     shear_modulus,
                                     elastic_b_minus_identity,
                                     plastic_strain,
                                     true);
          set_symmetric_tensor3(P, elastic_b_slot, elastic_b_minus_identity);
          // τ = s + K/2 (J² − 1) I (Eq. 18 with b̄ → b̄_e), σ = τ/J.
          const double J = determinant(F1);
          outputs.set_stress(q, (s + 0.5 * bulk_modulus * (J * J - 1) * I) / J);
          outputs.strain_energy_density[q] =
            0.5 * shear_modulus * trace(elastic_b_minus_identity) +
            0.5 * bulk_modulus * (0.5 * (J * J - 1) - std::log(J)) +
            plasticity.plastic_work(plastic_strain);
        }
    }



    template <int dim>
    void
    NeoHookean<dim>::update_stress(const StressUpdateInputs &inputs,
                                   StressUpdateOutputs      &outputs) const
    {
      if (plasticity.plastic())
        {
          update_plastic(inputs, outputs);
          return;
        }
      // A full batch with a constant count (the loops then vectorize).
      auto update = [&](const auto n) {
        if (energy_form == EnergyForm::log_j)
          log_update<dim>(n,
                          bulk_modulus - 2.0 / 3.0 * shear_modulus,
                          shear_modulus,
                          inputs,
                          outputs);
        else if constexpr (dim == 2)
          plane_strain_update(n, bulk_modulus, shear_modulus, inputs, outputs);
        else
          update_3d(n, bulk_modulus, shear_modulus, inputs, outputs);
      };
      if (inputs.n_points == StressUpdateInputs::capacity)
        update(
          std::integral_constant<unsigned int, StressUpdateInputs::capacity>());
      else
        update(inputs.n_points);
    }



    template <int dim>
    double
    NeoHookean<dim>::wave_speed(const double density, const double J) const
    {
      if (energy_form == EnergyForm::log_j)
        {
          // The 'ln J' form's spatial tangent c = λ/J I⊗I + 2(μ − λ ln J)/J 𝕀
          // ([BonetWood2008] §6.4.3): c_1111 = (λ + 2μ − 2λ ln J)/J at the
          // current density density/J.
          const double lambda = bulk_modulus - 2.0 / 3.0 * shear_modulus;
          return std::sqrt(
            std::max(lambda + 2 * shear_modulus - 2 * lambda * std::log(J),
                     0.) /
            density);
        }
      // Tangent bulk modulus J dp/dJ = K (J + 1/J) / 2 at the current volume
      // ratio, current density density/J.
      const double tangent_bulk = 0.5 * bulk_modulus * (J + 1.0 / J);
      return std::sqrt((tangent_bulk + 4.0 / 3.0 * shear_modulus) * J /
                       density);
    }

    template <int dim>
    double
    NeoHookean<dim>::max_wave_speed(const double                   density,
                                    const ArrayView<const double> &J) const
    {
      // The wave speed grows with J (J² K/2 + K/2 + 4G J/3 over ρ): one
      // evaluation at the largest J.
      // The 'ln J' form's is monotonic in ln J: the larger of the two ends.
      if (J.size() == 0)
        return 0;
      double J_max = J[0];
      for (const double J_q : J)
        J_max = std::max(J_max, J_q);
      if (energy_form == EnergyForm::log_j)
        {
          double J_min = J[0];
          for (const double J_q : J)
            J_min = std::min(J_min, J_q);
          return std::max(NeoHookean<dim>::wave_speed(density, J_min),
                          NeoHookean<dim>::wave_speed(density, J_max));
        }
      return NeoHookean<dim>::wave_speed(density, J_max);
    }



    // Every member for both dimensions (stress_and_energy() is the
    // reference the tests compare the batch updates with).
    template class NeoHookean<2>;
    template class NeoHookean<3>;

    FMPM_REGISTER_CONSTITUTIVE_MODEL(
      NeoHookean,
      "neo hookean",
      "Compressible neo-Hookean hyperelasticity, Cauchy stress sigma = tau/J "
      "with b = F F^T: 'Energy form = J^2' (default) tau = G dev(b_bar) + "
      "K/2 (J^2 - 1) I, b_bar = J^(-2/3) b ([NHS2020-contact] Eq. 18); "
      "'Energy form = ln J' sigma = lambda ln J / J I + mu/J (b - I), mu = "
      "G, lambda = K - 2G/3 ([BonetWood2008] Sec. 6.4.3). Constants K and G, "
      "or E and nu; plane strain in 2D. With 'Yield stress' > 0 J2 "
      "plasticity with linear hardening on the shear part (radial return "
      "on b_bar_e).")
  } // namespace ConstitutiveModel
} // namespace fmpm
