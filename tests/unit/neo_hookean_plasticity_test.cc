// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors
// J2 plasticity with linear hardening in the 'neo hookean' model (radial
// return on b̄_e): below yield it is the elastic model; after yield the
// deviatoric Kirchhoff stress stays on the yield surface; in simple shear at
// small strain it follows the closed form of small-strain J2 with linear
// hardening; unloading is elastic; the energy adds the plastic work; bad
// input names the parameter.
#include <fmpm/constitutive_model/neo_hookean.h>
#include <fmpm/particle_properties.h>

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using fmpm::ConstitutiveModel::NeoHookean;
  using fmpm::ConstitutiveModel::StressUpdateInputs;
  using fmpm::ConstitutiveModel::StressUpdateOutputs;

  template <int dim>
  NeoHookean<dim>
  copper(const double yield_stress, const double hardening)
  {
    NeoHookean<dim> model;
    model.bulk_modulus                 = 130e9;
    model.shear_modulus                = 43e9;
    model.plasticity.yield_stress      = yield_stress;
    model.plasticity.hardening_modulus = hardening;
    return model;
  }

  /** One material point with the model's slots, at F = I. */
  template <int dim>
  struct Point
  {
    using Index = fmpm::PropertyIndex<dim>;

    explicit Point(NeoHookean<dim> &model)
    {
      model.request_properties(properties);
      values.assign(properties.n_properties(), 0.);
      for (unsigned int i = 0; i < 3; ++i)
        values[Index::deformation_gradient + 4 * i] = 1;
    }

    /** Update to @p F and store F and σ as the Simulator does. */
    StressUpdateOutputs
    deform_to(const NeoHookean<dim> &model, const Tensor<2, 3> &F)
    {
      StressUpdateInputs  inputs;
      StressUpdateOutputs outputs;
      inputs.resize(1);
      inputs.set_deformation_gradient(0, F);
      const fmpm::RecordColumns record(
        ArrayView<double>(values.data(), values.size()));
      inputs.properties[0] = record.record();
      model.update_stress(inputs, outputs);
      fmpm::set_tensor3(inputs.properties[0], Index::deformation_gradient, F);
      return outputs;
    }

    double
    plastic_strain() const
    {
      return values[properties.offset("plastic_strain")];
    }

    fmpm::ParticleProperties<dim> properties;
    std::vector<double>           values;
  };

  Tensor<2, 3>
  simple_shear(const double gamma)
  {
    Tensor<2, 3> F = unit_symmetric_tensor<3>();
    F[0][1]        = gamma;
    return F;
  }



  // A yield stress that is never reached: the same stress and energy as the
  // elastic model (b̄_e then equals b̄ = J^{-2/3} F Fᵀ up to round-off).
  TEST(NeoHookeanPlasticity, BelowYieldIsTheElasticModel)
  {
    NeoHookean<3> plastic = copper<3>(1e15, 0);
    NeoHookean<3> elastic = copper<3>(0, 0);
    ASSERT_TRUE(plastic.reads_old_state());
    ASSERT_FALSE(elastic.reads_old_state());
    Point<3> point(plastic);
    for (unsigned int k = 1; k <= 20; ++k)
      {
        Tensor<2, 3> F                = simple_shear(0.01 * k);
        F[0][0]                       = 1 - 0.004 * k;
        F[2][1]                       = 0.003 * k;
        F[1][2]                       = -0.002 * k;
        const StressUpdateOutputs   a = point.deform_to(plastic, F);
        Point<3>                    fresh(elastic);
        const StressUpdateOutputs   b = fresh.deform_to(elastic, F);
        const SymmetricTensor<2, 3> difference =
          a.stress_tensor(0) - b.stress_tensor(0);
        EXPECT_LT(difference.norm(), 1e-9 * b.stress_tensor(0).norm());
        EXPECT_NEAR(a.strain_energy_density[0],
                    b.strain_energy_density[0],
                    1e-9 * b.strain_energy_density[0]);
      }
    EXPECT_EQ(point.plastic_strain(), 0);
  }



  // Simple shear to ten times the yield strain at small strain (σ_y/G =
  // 1e-4): τ_xy = (σ_y + H α)/√3 with α = (√3 G γ − σ_y)/(3G + H), the
  // small-strain J2 solution (τ = G (γ − √3 α) on the surface
  // √2 τ = √(2/3)(σ_y + H α)). Finite-strain terms are O(γ) = 1e-3.
  TEST(NeoHookeanPlasticity, SimpleShearFollowsSmallStrainJ2)
  {
    const double  G = 43e9, yield = 1e-4 * G, H = G;
    NeoHookean<2> model = copper<2>(yield, H);
    Point<2>      point(model);
    const double  gamma_yield = yield / (std::sqrt(3.) * G);
    double        previous    = 0;
    for (unsigned int k = 1; k <= 100; ++k)
      {
        const double              gamma = 10 * gamma_yield * k / 100;
        const StressUpdateOutputs out =
          point.deform_to(model, simple_shear(gamma));
        const double tau   = out.stress_tensor(0)[0][1];
        const double alpha = point.plastic_strain();
        EXPECT_GE(alpha, previous);
        previous = alpha;
        const double alpha_exact =
          std::max(0., (std::sqrt(3.) * G * gamma - yield) / (3 * G + H));
        const double tau_exact = alpha_exact > 0 ?
                                   (yield + H * alpha_exact) / std::sqrt(3.) :
                                   G * gamma;
        EXPECT_NEAR(tau, tau_exact, 2e-3 * tau_exact) << "γ = " << gamma;
        EXPECT_NEAR(alpha, alpha_exact, 2e-3 * 10 * gamma_yield)
          << "γ = " << gamma;
        // On the surface once yielded (Kirchhoff = Cauchy here, J = 1).
        const double radius = std::sqrt(2. / 3.) * (yield + H * alpha);
        const double norm   = deviator(out.stress_tensor(0)).norm();
        if (alpha > 0)
          EXPECT_NEAR(norm, radius, 1e-10 * radius);
        else
          EXPECT_LE(norm, radius * (1 + 1e-12));
      }
    EXPECT_GT(previous, 3 * gamma_yield);
  }



  // After yield, shearing back is elastic: Δτ = G Δγ and α unchanged until
  // the reversed stress reaches the (hardened) surface on the other side.
  TEST(NeoHookeanPlasticity, UnloadingIsElastic)
  {
    const double        G = 43e9, yield = 1e-4 * G, H = 0.2 * G;
    NeoHookean<2>       model = copper<2>(yield, H);
    Point<2>            point(model);
    const double        gamma_yield = yield / (std::sqrt(3.) * G);
    StressUpdateOutputs out;
    for (unsigned int k = 1; k <= 40; ++k)
      out = point.deform_to(model, simple_shear(4 * gamma_yield * k / 40));
    const double alpha     = point.plastic_strain();
    const double tau_max   = out.stress_tensor(0)[0][1];
    const double gamma_max = 4 * gamma_yield;
    ASSERT_GT(alpha, 0);
    for (unsigned int k = 1; k <= 10; ++k)
      {
        const double gamma = gamma_max - gamma_yield * k / 10;
        out                = point.deform_to(model, simple_shear(gamma));
        EXPECT_EQ(point.plastic_strain(), alpha);
        EXPECT_NEAR(out.stress_tensor(0)[0][1],
                    tau_max - G * (gamma_max - gamma),
                    2e-3 * tau_max);
      }
  }



  // W = elastic energy of b̄_e and J + σ_y α + H α²/2; uniform compression
  // (no deviator) stays elastic and gives the elastic pressure K/2 (J²−1)/J.
  TEST(NeoHookeanPlasticity, EnergyAddsThePlasticWork)
  {
    const double        G = 43e9, yield = 1e-3 * G, H = 0.5 * G;
    NeoHookean<3>       model = copper<3>(yield, H);
    Point<3>            point(model);
    StressUpdateOutputs out;
    for (unsigned int k = 1; k <= 50; ++k)
      out = point.deform_to(model, simple_shear(0.02 * k / 50));
    const double alpha = point.plastic_strain();
    ASSERT_GT(alpha, 0);
    SymmetricTensor<2, 3> b_e;
    const unsigned int    slot =
      point.properties.offset("elastic_b_minus_identity");
    for (unsigned int c = 0; c < 6; ++c)
      b_e[fmpm::stress_component_i[c]][fmpm::stress_component_j[c]] =
        point.values[slot + c];
    const double elastic = 0.5 * G * trace(b_e); // J = 1
    EXPECT_NEAR(out.strain_energy_density[0],
                elastic + yield * alpha + 0.5 * H * alpha * alpha,
                1e-12 * out.strain_energy_density[0]);

    NeoHookean<3>             fresh_model = copper<3>(yield, H);
    Point<3>                  fresh(fresh_model);
    const double              stretch = 0.98;
    const StressUpdateOutputs compressed =
      fresh.deform_to(fresh_model, stretch * unit_symmetric_tensor<3>());
    const double J = stretch * stretch * stretch;
    EXPECT_EQ(fresh.plastic_strain(), 0);
    EXPECT_NEAR(compressed.stress_tensor(0)[0][0],
                0.5 * fresh_model.bulk_modulus * (J * J - 1) / J,
                1e-9 * fresh_model.bulk_modulus);
  }



  TEST(NeoHookeanPlasticity, BadInputNamesTheParameter)
  {
    const std::string where   = "Material 0/Neo hookean";
    auto              message = [&](const NeoHookean<2> &model) {
      try
        {
          model.check_parameters(where);
        }
      catch (const std::exception &e)
        {
          return std::string(e.what());
        }
      return std::string();
    };
    NeoHookean<2> negative_yield = copper<2>(-1, 0);
    EXPECT_NE(message(negative_yield).find(where + "/Yield stress"),
              std::string::npos);
    NeoHookean<2> negative_hardening = copper<2>(1e8, -1);
    EXPECT_NE(message(negative_hardening).find(where + "/Hardening modulus"),
              std::string::npos);
    NeoHookean<2> log_form = copper<2>(1e8, 0);
    log_form.energy_form   = NeoHookean<2>::EnergyForm::log_j;
    EXPECT_NE(message(log_form).find("Energy form = J^2"), std::string::npos);
    EXPECT_EQ(message(copper<2>(1e8, 1e9)), "");
  }
} // namespace

namespace
{
  // The energy W is the work done on the point, ∫ τ : (Ḟ F⁻¹) dt (per unit
  // reference volume), along a path that yields, unloads and yields again:
  // the plastic work σ_y α + H α²/2 is what the flow dissipates.
  TEST(NeoHookeanPlasticity, EnergyIsTheWorkDone)
  {
    const double          G = 43e9, yield = 4e8, H = 1e8;
    NeoHookean<3>         model = copper<3>(yield, H);
    Point<3>              point(model);
    Tensor<2, 3>          F_old = unit_symmetric_tensor<3>();
    SymmetricTensor<2, 3> tau_old;
    double                work    = 0;
    const unsigned int    n_steps = 4000;
    double                energy  = 0;
    for (unsigned int k = 1; k <= n_steps; ++k)
      {
        const double s = double(k) / n_steps;
        // Compression along x with shear, then partly back.
        const double a                  = s < 0.7 ? s : 1.4 - s;
        Tensor<2, 3> F                  = unit_symmetric_tensor<3>();
        F[0][0]                         = 1 - 0.3 * a;
        F[1][1]                         = 1 + 0.1 * a;
        F[2][2]                         = 1 + 0.12 * a;
        F[0][1]                         = 0.05 * a;
        const StressUpdateOutputs   out = point.deform_to(model, F);
        const SymmetricTensor<2, 3> tau = determinant(F) * out.stress_tensor(0);
        // Trapezoid rule on τ : ΔF F_mid⁻¹.
        const Tensor<2, 3> dF    = F - F_old;
        const Tensor<2, 3> F_mid = 0.5 * (F + F_old);
        work += scalar_product(Tensor<2, 3>(0.5 * (tau + tau_old)),
                               dF * invert(F_mid));
        tau_old = tau;
        F_old   = F;
        energy  = out.strain_energy_density[0];
      }
    EXPECT_GT(point.plastic_strain(), 0.2);
    EXPECT_NEAR(energy, work, 1e-3 * work);
    (void)G;
  }
} // namespace
