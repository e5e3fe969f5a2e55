// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/constitutive_model/elastic_constants.h>
#include <fmpm/parameters.h>

#include <deal.II/base/utilities.h>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    namespace
    {
      const std::string either_pair =
        "Set 'Bulk modulus' and 'Shear modulus', or 'Young's modulus' and "
        "'Poisson's ratio', not both pairs";

      /** A number or nothing: what the four entries allow. */
      Patterns::List
      optional_number()
      {
        return Patterns::List(Patterns::Double(), 0, 1);
      }

      std::optional<double>
      get_optional_double(ParameterHandler &prm, const std::string &name)
      {
        const std::string text = Utilities::trim(prm.get(name));
        if (text.empty())
          return {};
        return Utilities::string_to_double(text);
      }

      std::string
      assignment(const std::string           &where,
                 const std::string           &name,
                 const std::optional<double> &value)
      {
        return where + "/" + name + " = " + format_number(*value);
      }
    } // namespace



    void
    ElasticConstants::declare_parameters(ParameterHandler  &prm,
                                         const Pair         native,
                                         const double       first_default,
                                         const double       second_default,
                                         const std::string &first_meaning,
                                         const std::string &second_meaning)
    {
      const bool        bulk_native = native == Pair::bulk_and_shear;
      const std::string other_pair =
        bulk_native ? "'Young's modulus' and 'Poisson's ratio'" :
                      "'Bulk modulus' and 'Shear modulus'";
      const std::string native_pair =
        bulk_native ? "'Bulk modulus' and 'Shear modulus'" :
                      "'Young's modulus' and 'Poisson's ratio'";
      // The native pair: an empty entry takes the model's default.
      const auto native_text = [&](const std::string &meaning,
                                   const double       default_value,
                                   const std::string &units) {
        return meaning + " Empty: " + format_number(default_value) +
               " (unless " + other_pair + " are set instead). Units: " + units +
               ".";
      };
      // The other pair: both entries or none, and then none of the native.
      const auto other_text = [&](const std::string &meaning,
                                  const std::string &allowed) {
        return meaning + " Set both of " + other_pair + " or neither, and " +
               "then neither of " + native_pair + ". " + allowed;
      };
      const std::string positive_modulus = "A number > 0, or empty. Units: Pa.";
      const std::string ratio = "A number in (-1, 0.5), or empty. Units: none.";
      prm.declare_entry(
        "Bulk modulus",
        "",
        optional_number(),
        bulk_native ?
          native_text(first_meaning, first_default, "Pa") :
          other_text("Bulk modulus K, with 'Shear modulus' G the "
                     "alternative to Young's modulus and Poisson's ratio: "
                     "E = 9KG/(3K + G), nu = (3K - 2G)/(2(3K + G)).",
                     positive_modulus));
      prm.declare_entry(
        "Shear modulus",
        "",
        optional_number(),
        bulk_native ? native_text(second_meaning, second_default, "Pa") :
                      other_text("Shear modulus G, set with 'Bulk modulus'.",
                                 positive_modulus));
      prm.declare_entry(
        "Young's modulus",
        "",
        optional_number(),
        bulk_native ?
          other_text("Young's modulus E, with 'Poisson's ratio' nu the "
                     "alternative to the bulk and shear moduli: K = E/(3(1 - "
                     "2 nu)), G = E/(2(1 + nu)).",
                     positive_modulus) :
          native_text(first_meaning, first_default, "Pa"));
      prm.declare_entry(
        "Poisson's ratio",
        "",
        optional_number(),
        bulk_native ?
          other_text("Poisson's ratio nu, set with 'Young's modulus'.", ratio) :
          native_text(second_meaning, second_default, "none"));
    }



    void
    ElasticConstants::parse_parameters(ParameterHandler &prm)
    {
      bulk_modulus   = get_optional_double(prm, "Bulk modulus");
      shear_modulus  = get_optional_double(prm, "Shear modulus");
      youngs_modulus = get_optional_double(prm, "Young's modulus");
      poissons_ratio = get_optional_double(prm, "Poisson's ratio");
    }



    bool
    ElasticConstants::sets(const Pair pair) const
    {
      return pair == Pair::bulk_and_shear ?
               bulk_modulus.has_value() || shear_modulus.has_value() :
               youngs_modulus.has_value() || poissons_ratio.has_value();
    }



    void
    ElasticConstants::check(const std::string &where, const Pair native) const
    {
      if (sets(Pair::bulk_and_shear) && sets(Pair::youngs_and_poisson))
        {
          const std::string first =
            bulk_modulus ? assignment(where, "Bulk modulus", bulk_modulus) :
                           assignment(where, "Shear modulus", shear_modulus);
          const std::string second =
            youngs_modulus ?
              assignment(where, "Young's modulus", youngs_modulus) :
              assignment(where, "Poisson's ratio", poissons_ratio);
          AssertThrow(false,
                      ExcMessage(first + " and " + second + " are both set. " +
                                 either_pair + "."));
        }
      const auto require_partner = [&](const std::optional<double> &value,
                                       const std::string           &name,
                                       const std::optional<double> &partner,
                                       const std::string &partner_name) {
        AssertThrow(!value || partner,
                    ExcMessage(assignment(where, name, value) +
                               " is set without '" + partner_name +
                               "'. Allowed: both or neither; " + either_pair +
                               "."));
      };
      if (native == Pair::bulk_and_shear)
        {
          require_partner(youngs_modulus,
                          "Young's modulus",
                          poissons_ratio,
                          "Poisson's ratio");
          require_partner(poissons_ratio,
                          "Poisson's ratio",
                          youngs_modulus,
                          "Young's modulus");
          if (youngs_modulus)
            {
              AssertThrow(
                *youngs_modulus > 0,
                ExcMessage(
                  assignment(where, "Young's modulus", youngs_modulus) +
                  " is not positive. Allowed: any value > 0 (Pa)."));
              AssertThrow(
                *poissons_ratio > -1 && *poissons_ratio < 0.5,
                ExcMessage(
                  assignment(where, "Poisson's ratio", poissons_ratio) +
                  " is outside the allowed range (-1, 0.5)."));
            }
        }
      else
        {
          require_partner(bulk_modulus,
                          "Bulk modulus",
                          shear_modulus,
                          "Shear modulus");
          require_partner(shear_modulus,
                          "Shear modulus",
                          bulk_modulus,
                          "Bulk modulus");
          if (bulk_modulus)
            {
              AssertThrow(*bulk_modulus > 0,
                          ExcMessage(
                            assignment(where, "Bulk modulus", bulk_modulus) +
                            " is not positive. Allowed: any value > 0 (Pa)."));
              AssertThrow(*shear_modulus > 0,
                          ExcMessage(
                            assignment(where, "Shear modulus", shear_modulus) +
                            " is not positive. Allowed: any value > 0 (Pa)."));
            }
        }
    }



    void
    ElasticConstants::get_bulk_and_shear(double &bulk, double &shear) const
    {
      if (sets(Pair::bulk_and_shear) && sets(Pair::youngs_and_poisson))
        return;
      if (youngs_modulus && poissons_ratio)
        {
          bulk  = bulk_modulus_of(*youngs_modulus, *poissons_ratio);
          shear = shear_modulus_of(*youngs_modulus, *poissons_ratio);
          return;
        }
      if (bulk_modulus)
        bulk = *bulk_modulus;
      if (shear_modulus)
        shear = *shear_modulus;
    }



    void
    ElasticConstants::get_youngs_and_poisson(double &youngs,
                                             double &poisson) const
    {
      if (sets(Pair::bulk_and_shear) && sets(Pair::youngs_and_poisson))
        return;
      if (bulk_modulus && shear_modulus)
        {
          youngs  = youngs_modulus_of(*bulk_modulus, *shear_modulus);
          poisson = poissons_ratio_of(*bulk_modulus, *shear_modulus);
          return;
        }
      if (youngs_modulus)
        youngs = *youngs_modulus;
      if (poissons_ratio)
        poisson = *poissons_ratio;
    }



    double
    ElasticConstants::bulk_modulus_of(const double E, const double nu)
    {
      return E / (3 * (1 - 2 * nu));
    }



    double
    ElasticConstants::shear_modulus_of(const double E, const double nu)
    {
      return E / (2 * (1 + nu));
    }



    double
    ElasticConstants::youngs_modulus_of(const double K, const double G)
    {
      return 9 * K * G / (3 * K + G);
    }



    double
    ElasticConstants::poissons_ratio_of(const double K, const double G)
    {
      return (3 * K - 2 * G) / (2 * (3 * K + G));
    }
  } // namespace ConstitutiveModel
} // namespace fmpm
