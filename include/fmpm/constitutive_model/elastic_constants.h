// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_constitutive_model_elastic_constants_h
#define fmpm_constitutive_model_elastic_constants_h

#include <deal.II/base/parameter_handler.h>

#include <optional>
#include <string>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    using namespace dealii;

    /**
     * @brief The isotropic elastic constants of a model's subsection, given
     * as either of two pairs: 'Bulk modulus' K and 'Shear modulus' G, or
     * 'Young's modulus' E and 'Poisson's ratio' ν.
     *
     * A model computes with one pair (its native pair) and converts the
     * other: K = E/(3(1 − 2ν)), G = E/(2(1 + ν)) and E = 9KG/(3K + G),
     * ν = (3K − 2G)/(2(3K + G)). Each of the four entries is a number or
     * empty (the default). An empty entry of the native pair takes the
     * model's default; the other pair is set completely or not at all, and
     * never together with an entry of the native pair.
     *
     * @ingroup ConstitutiveModels
     */
    class ElasticConstants
    {
    public:
      /** The two pairs. */
      enum class Pair
      {
        bulk_and_shear,
        youngs_and_poisson
      };

      /**
       * @brief Declare the four entries, empty by default. The native
       * pair's entries are documented with @p first_meaning and
       * @p second_meaning (what the constants are in the model: K and G, or
       * E and ν, and their allowed values) and their defaults
       * @p first_default, @p second_default.
       */
      static void
      declare_parameters(ParameterHandler  &prm,
                         const Pair         native,
                         const double       first_default,
                         const double       second_default,
                         const std::string &first_meaning,
                         const std::string &second_meaning);

      /** @brief Read the four entries (not yet checked). */
      void
      parse_parameters(ParameterHandler &prm);

      /**
       * @brief Throw an ExcMessage naming @p where and the entries if an
       * entry of each pair is set, if only one entry of the pair that is not
       * @p native is set, or if that pair is outside its range (E > 0,
       * −1 < ν < 0.5; K > 0, G > 0). The model checks its native pair.
       */
      void
      check(const std::string &where, const Pair native) const;

      /** @brief Whether the scene sets an entry of @p pair. */
      bool
      sets(const Pair pair) const;

      /**
       * @brief K and G: converted from E and ν if the scene sets both, else
       * the entries of K and G it sets; @p bulk_modulus and
       * @p shear_modulus (the model's defaults) stay where it sets nothing,
       * and both stay if it sets both pairs (which check() reports).
       */
      void
      get_bulk_and_shear(double &bulk_modulus, double &shear_modulus) const;

      /** @brief E and ν likewise. */
      void
      get_youngs_and_poisson(double &youngs_modulus,
                             double &poissons_ratio) const;

      /** K = E/(3(1 − 2ν)). Units: Pa. */
      static double
      bulk_modulus_of(const double youngs_modulus, const double poissons_ratio);

      /** G = E/(2(1 + ν)). Units: Pa. */
      static double
      shear_modulus_of(const double youngs_modulus,
                       const double poissons_ratio);

      /** E = 9KG/(3K + G). Units: Pa. */
      static double
      youngs_modulus_of(const double bulk_modulus, const double shear_modulus);

      /** ν = (3K − 2G)/(2(3K + G)). */
      static double
      poissons_ratio_of(const double bulk_modulus, const double shear_modulus);

      /** The entries as the scene sets them (empty: not set). */
      std::optional<double> bulk_modulus, shear_modulus, youngs_modulus,
        poissons_ratio;
    };
  } // namespace ConstitutiveModel
} // namespace fmpm

#endif
