// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_contact_parameters_h
#define fmpm_contact_parameters_h

#include <fmpm/parameter_entries.h>

#include <deal.II/base/parameter_handler.h>

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
    /** The contact term of multimaterial XPIC(k)/FMPM(k). */
    enum class XpicContactTerm
    {
      /** The first correction's Δv^α decays as (I − A^α)^{k−1} (seed 004
       * Eq. 37, seed 000 Eqs. 3.18, 3.22). */
      corrected,
      /** Without the first correction (seed 004 Eq. 48). */
      uncorrected,
      /** (m̃ₖ^α)⁻¹ p^α of the corrected momenta (Nairn 2026 tech note,
       * Sec. 3.1.1, method 2). */
      series
    };

    /** The contact law of a pair of materials: the name of a registered
     * law and its numbers ('Friction coefficient', the interface
     * stiffnesses, or the numbers after the name in 'Pair laws'; what they
     * mean is the law's). */
    struct Law
    {
      std::string         name;
      std::vector<double> coefficients;
    };

    /** @brief The subsection Contact. */
    struct Parameters
    {
      /** 'Model name = multimaterial'. */
      bool                                     multimaterial = false;
      static constexpr SelectionNames<bool, 2> model_names{
        {"none", "multimaterial"}};
      /** 'Normals': the name of a registered normal method
       * (NormalMethodInterface). */
      std::string         normals_name = "logistic regression";
      std::vector<double> specified_normal{0, 1, 0};
      /** δc in cells. */
      double critical_separation = 0.8;
      /**
       * LR and DF: materials closer than this (in cells) count as touching,
       * so that bodies whose point domains tile exactly (d = 0) are not left
       * to the sign of round-off; farther gaps that the approach closes
       * within the step get contact for the approach beyond d/Δt only.
       */
      double touching_tolerance = 1e-3;
      /** 'Gap closing': whether a gap that the approach closes within the
       * step gets contact for the approach beyond d/Δt (true), or DF and LR
       * pairs are in contact only when they touch (false). */
      bool gap_closing = true;
      /** μ of 'coulomb', D_n and D_t of 'imperfect' (the numbers of a law
       * named without numbers). */
      double friction_coefficient           = 0.3;
      double interface_normal_stiffness     = 1e12;
      double interface_tangential_stiffness = 1e12;
      /** 'Law' with the numbers default_coefficients() gives it. */
      Law default_law{"coulomb", {friction_coefficient}};
      /** Overrides of 'Pair laws': (material a, material b, law). */
      struct PairLaw
      {
        unsigned int a, b;
        Law          law;
      };
      std::vector<PairLaw> pair_laws;
      unsigned int         corrections_per_step = 2;
      /** 'Three or more materials' ([NHS2020-contact] §3.4). */
      enum class ThreeOrMore
      {
        /** Each material against the sum of the others (Eq. 50). */
        lumped,
        /** Every pair in turn. */
        pairwise,
        /** The pairs in contact: one pair alone, two pairs solved
         * together, three or more lumped (the algorithm at Fig. 4). */
        explicit_pairs
      };
      static constexpr SelectionNames<ThreeOrMore, 3> three_or_more_names{
        {"lumped", "pairwise", "explicit"}};
      ThreeOrMore three_or_more = ThreeOrMore::lumped;
      /** 'XPIC contact term'. */
      XpicContactTerm xpic_contact_term = XpicContactTerm::corrected;
      static constexpr SelectionNames<XpicContactTerm, 3>
        xpic_contact_term_names{{"corrected", "uncorrected", "series"}};
      /** 'Contact in mass-matrix iterations = net incremental': the laws
       * also correct each increment of the FMPM(k)/XPIC(k) series. */
      bool net_incremental = true;
      /** The names of net_incremental = true and false, in this order. */
      static constexpr const char *iteration_names[2] = {"net incremental",
                                                         "once per step"};

      static void
      declare_parameters(ParameterHandler &prm);
      /** Reads the subsection; errors name the parameter and the allowed
       * values. */
      void
      parse_parameters(ParameterHandler &prm, const unsigned int n_materials);

      /** @brief The numbers of the law @p name when the scene names it
       * without any (the law's default_coefficients()). */
      std::vector<double>
      default_coefficients(const std::string &name) const;

      /** @brief The law between materials @p a and @p b. */
      const Law &
      law(const unsigned int a, const unsigned int b) const;
    };

  } // namespace Contact
} // namespace fmpm

#endif
