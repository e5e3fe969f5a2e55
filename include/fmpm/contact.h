// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_contact_h
#define fmpm_contact_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/tensor.h>

#include <memory>
#include <string>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * Multimaterial contact (seed 004 §2-3, seed 000 Ch. 3): one velocity
   * field per material, contact corrections at nodes shared by materials.
   */
  namespace Contact
  {
    /** How the contact normal n̂ and the contact test of a node are found. */
    enum class NormalMethod
    {
      /** n̂ from the volume gradients (Eq. 13); contact when approaching
       * (Eq. 14) and the extrapolated positions are closer than the δc of
       * the linear fit of the shape function (Eq. 17: 0.92 cells classic
       * and GIMP, 0.96 CPDI). */
      average_gradient,
      /** n̂ of Eq. 13; contact whenever approaching (Eq. 14 alone). */
      velocity_only,
      /** n̂ of Eq. 13; approaching and separation below 'Critical
       * separation' cells (Eq. 16, "CP = δc"). */
      contact_position,
      /** d(x) fit (DF): not implemented yet. */
      d_fit,
      /** logistic regression (LR, Eqs. 19-25): not implemented yet. */
      logistic_regression,
      /** 'Specified normal' from the lower-numbered material to the
       * higher; contact when approaching. */
      specified
    };

    /** The contact law of a pair of materials (Eqs. 7-10). */
    enum class LawType
    {
      perfect,
      frictionless,
      coulomb
    };

    /** A law and its friction coefficient. */
    struct Law
    {
      LawType type     = LawType::coulomb;
      double  friction = 0.3;
    };

    /** @brief The subsection Contact. */
    struct Parameters
    {
      /** 'Model name = multimaterial'. */
      bool         multimaterial = false;
      NormalMethod normals       = NormalMethod::logistic_regression;
      std::string  normals_name  = "logistic regression";
      std::vector<double> specified_normal{0, 1, 0};
      /** δc in cells. */
      double critical_separation = 0.8;
      Law    default_law;
      /** Overrides of 'Pair laws': (material a, material b, law). */
      struct PairLaw
      {
        unsigned int a, b;
        Law          law;
      };
      std::vector<PairLaw> pair_laws;
      unsigned int         corrections_per_step = 2;
      /** 'Three or more materials = lumped' (else pairwise). */
      bool lumped_three_or_more = true;

      static void
      declare_parameters(ParameterHandler &prm);
      /** Reads the subsection; errors name the parameter and the allowed
       * values. */
      void
      parse_parameters(ParameterHandler &prm, const unsigned int n_materials);

      /** @brief The law between materials @p a and @p b. */
      const Law &
      law(const unsigned int a, const unsigned int b) const;
    };

    /**
     * @brief The state of one node seen by the contact law of a pair α, β:
     * the masses, the momenta, n̂ (from α to β) and whether the materials
     * touch there (the separation test of the normal method).
     */
    template <int dim>
    struct NodePair
    {
      double         mass_alpha = 0, mass_beta = 0;
      Tensor<1, dim> momentum_alpha, momentum_beta;
      Tensor<1, dim> normal;
      bool           touching = true;
      /** (x^β − x^α)·n̂ in cells where the normal method measures it. */
      double separation = 0;
    };

    /** @brief What a law did at a node. */
    template <int dim>
    struct Correction
    {
      /** Δp^α; material β gets −Δp^α (Eq. 7). */
      Tensor<1, dim> delta_momentum;
      /** Whether the materials were in contact (approach and touching). */
      bool in_contact = false;
      /** The tangential impulse's energy loss (friction work). */
      double friction_work = 0;
    };

    /**
     * @brief Δp^α of Eqs. 7-10 (with the corrected sign of Eq. 10) for a
     * node shared by α and β.
     *
     * Δp^α(0) = m^α(v^(cm) − v^α) moves both with the centre of mass.
     * Perfect: Δp^α = Δp^α(0) always. Otherwise contact needs approach,
     * Δp^α(0)·n̂ < 0 (Eq. 14), and touching; frictionless keeps the normal
     * part (Δp^α(0)·n̂)n̂; Coulomb adds the tangential part capped at
     * μN_cA_cΔt = −μΔp^α(0)·n̂ (Eq. 10 with S_slide = μN_c).
     */
    template <int dim>
    Correction<dim>
    correct(const Law &law, const NodePair<dim> &node);
  } // namespace Contact
} // namespace fmpm

#endif
