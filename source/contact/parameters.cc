// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/contact/laws.h>
#include <fmpm/contact/normals.h>
#include <fmpm/contact/parameters.h>
#include <fmpm/parameters.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>

namespace fmpm
{
  namespace Contact
  {
    namespace
    {
      /** "coulomb 0.2", "perfect", "imperfect 1e9 5e8" → Law: a registered
       * name, then its numbers (or none: @p defaults, the numbers of
       * 'Friction coefficient' and the interface stiffnesses); @p where
       * names the parameter in errors. */
      Law
      parse_law(const std::string &text,
                const Parameters  &defaults,
                const std::string &where)
      {
        std::vector<std::string> words;
        for (const auto &w : Utilities::split_string_list(text, ' '))
          if (!w.empty())
            words.push_back(w);
        const std::string allowed =
          " (allowed: " + law_names() +
          ", with the law's numbers after it, e.g. 'coulomb 0.2' or "
          "'imperfect 1e9 5e8').";
        AssertThrow(!words.empty(),
                    ExcMessage(where + ": a law is missing" + allowed));
        // The last words that are numbers are the law's numbers.
        std::vector<double> numbers;
        while (words.size() > 1)
          {
            char        *end   = nullptr;
            const double value = std::strtod(words.back().c_str(), &end);
            if (end == words.back().c_str() || *end != '\0')
              break;
            AssertThrow(std::isfinite(value) && value >= 0,
                        ExcMessage(where + ": '" + words.back() +
                                   "' must be a number >= 0."));
            numbers.insert(numbers.begin(), value);
            words.pop_back();
          }
        Law law;
        law.name = words[0];
        for (unsigned int w = 1; w < words.size(); ++w)
          law.name += " " + words[w];
        const std::string names = "|" + law_names() + "|";
        AssertThrow(names.find("|" + law.name + "|") != std::string::npos,
                    ExcMessage(where + ": unknown law '" + law.name + "'" +
                               allowed));
        law.coefficients =
          numbers.empty() ? defaults.default_coefficients(law.name) : numbers;
        const unsigned int n = create_law<2>(law)->n_coefficients();
        AssertThrow(numbers.empty() || numbers.size() == n,
                    ExcMessage(where + ": '" + text + "': the law '" +
                               law.name + "' takes " +
                               (n == 0 ? std::string("no number") :
                                         std::to_string(n) + " number(s)") +
                               allowed));
        return law;
      }



      /** 'Pair laws' as the scene writes it: "a b: name numbers; ...". */
      std::string
      pair_laws_text(const std::vector<Parameters::PairLaw> &pair_laws)
      {
        std::string text;
        for (const auto &pair : pair_laws)
          {
            text += (text.empty() ? "" : "; ") + std::to_string(pair.a) + " " +
                    std::to_string(pair.b) + ": " + pair.law.name;
            for (const double number : pair.law.coefficients)
              text += " " + format_number(number);
          }
        return text;
      }
    } // namespace



    void
    Parameters::declare_parameters(ParameterHandler &prm)
    {
      const Parameters defaults;
      prm.enter_subsection("Contact");
      prm.declare_entry(
        "Model name",
        model_names.name(defaults.multimaterial),
        Patterns::Selection(model_names.pattern()),
        "'none': all bodies share one velocity field (bodies that touch "
        "stick, as in Sulsky's colliding disks). 'multimaterial': one "
        "velocity field per material ([NHS2020-contact] Eqs. 5-6) and contact "
        "corrections at nodes where materials meet (Eqs. 7-10, §3.2). "
        "Bodies of one material share a field. Units: none.");
      prm.declare_entry(
        "Normals",
        defaults.normals_name,
        Patterns::Selection(normal_method_names()),
        "Contact normal and contact test of a node ([NHS2020-contact] "
        "§2.3, §3.1; a plugin system): " +
          normal_method_documentation() + "Units: none.");
      prm.declare_entry("Specified normal",
                        list_text(defaults.specified_normal, 2),
                        Patterns::List(Patterns::Double(), 2, 3),
                        "The normal of 'Normals = specified'. Units: none.");
      prm.declare_entry("Critical separation",
                        format_number(defaults.critical_separation),
                        Patterns::Double(0),
                        "delta_c of 'contact position' (Eq. 16). Units: cells "
                        "(the local cell size at the node).");
      prm.declare_entry(
        "Touching tolerance",
        format_number(defaults.touching_tolerance),
        Patterns::Double(0, 1),
        "'logistic regression' and 'd fit': materials whose separation d is "
        "below this count as touching (bodies in contact have d = 0 up to "
        "round-off); a larger gap d that the approach closes within the "
        "step, d + (v^b - v^a).n dt < 0, gets contact for the approach "
        "beyond d/dt only, so that the gap closes at the end of the step. "
        "Units: cells (the local cell size at the node).");
      prm.declare_entry(
        "Gap closing",
        bool_text(defaults.gap_closing),
        Patterns::Bool(),
        "'logistic regression' and 'd fit': true gives a gap d above the "
        "'Touching tolerance' that the approach closes within the step, d + "
        "(v^b - v^a).n dt < 0, contact for the approach beyond d/dt (the "
        "surfaces meet at the end of the step, without overlap); false puts "
        "only touching pairs in contact, after their point domains overlap "
        "(NairnMPM). Each arriving node then stops as in a plastic impact: "
        "with FLIP this costs energy at every impact (keep false for energy), "
        "FMPM(k) keeps more energy with it (doc/studies/"
        "two_disks_contact_energy.md). Units: none.");
      prm.declare_entry("Law",
                        defaults.default_law.name,
                        Patterns::Selection(law_names()),
                        "The contact law of every pair of materials unless "
                        "'Pair laws' overrides it (a plugin system): "
                        "'perfect' (no slip, no separation), 'frictionless', "
                        "'coulomb' (Eqs. 7-10, mu = 'Friction coefficient'), "
                        "'imperfect' (a bonded interface with the interface "
                        "stiffnesses). Units: none.");
      prm.declare_entry("Friction coefficient",
                        format_number(defaults.friction_coefficient),
                        Patterns::Double(0),
                        "mu of 'Law = coulomb'. Units: none.");
      prm.declare_entry(
        "Interface normal stiffness",
        format_number(defaults.interface_normal_stiffness),
        Patterns::Double(0),
        "D_n of 'Law = imperfect': the normal traction of a bonded interface "
        "per unit opening, D_n [u]_n, in tension and compression "
        "([Nairn2013]). A stiffness the time step cannot resolve (D A_c dt^2 "
        "> 2.25 m_red at a node) acts as a perfect interface there; 0 "
        "transmits nothing (a debonded interface). Units: Pa/m.");
      prm.declare_entry(
        "Interface tangential stiffness",
        format_number(defaults.interface_tangential_stiffness),
        Patterns::Double(0),
        "D_t of 'Law = imperfect': the shear traction per unit slip, "
        "D_t [u]_t (the same limits as the normal stiffness). Units: Pa/m.");
      prm.declare_entry(
        "Pair laws",
        pair_laws_text(defaults.pair_laws),
        Patterns::Anything(),
        "Overrides by material index, separated by ';': 'a b: law', e.g. "
        "'0 1: coulomb 0.2; 1 2: perfect; 0 2: imperfect 1e9 5e8' (a law's "
        "numbers after its name; without them 'Friction coefficient' and the "
        "interface stiffnesses). Units: none.");
      prm.declare_entry(
        "Corrections per step",
        std::to_string(defaults.corrections_per_step),
        Patterns::Integer(1, 2),
        "2: after the extrapolation and after the momentum "
        "update ([NHS2020-contact] §3.2); 1: after the momentum update "
        "only (the 'LR once' comparison). Units: none.");
      prm.declare_entry(
        "Three or more materials",
        three_or_more_names.name(defaults.three_or_more),
        Patterns::Selection(three_or_more_names.pattern()),
        "Nodes with 3+ materials ([NHS2020-contact] §3.4): 'lumped' treats "
        "each material against the sum of the others (Eq. 50; the paper's "
        "recommendation); 'pairwise' corrects every pair in turn (conserves "
        "momentum); 'explicit' finds the pairs in contact (their own normals "
        "and separations): one pair is corrected alone, two pairs together "
        "(both contact laws hold at once, momentum conserved), three or more "
        "lumped (the algorithm at the paper's Fig. 4). Units: none.");
      prm.declare_entry(
        "XPIC contact term",
        xpic_contact_term_names.name(defaults.xpic_contact_term),
        Patterns::Selection(xpic_contact_term_names.pattern()),
        "Multimaterial XPIC(k)/FMPM(k) (mass matrix 'fmpm' of order k): "
        "'corrected' projects each material with S^{+a} and adds the "
        "contact term (I - S S^{+a})^{k-1} S dv^a of the first correction "
        "([NHS2020-contact] Eq. 37, [Nairn2023-FMPM] Eqs. 3.18, 3.22); 'uncorrected' omits "
        "that term (the simple extension, Eq. 48); 'series' puts the "
        "contact-corrected momenta of every correction through the whole "
        "series, (m~_k^a)^-1 p^a (NairnMPM; Nairn 2026 tech note, Sec. "
        "3.1.1, method 2 with 'net incremental'). Units: none.");
      prm.declare_entry(
        "Contact in mass-matrix iterations",
        iteration_names[defaults.net_incremental ? 0 : 1],
        Patterns::Selection(std::string(iteration_names[0]) + "|" +
                            iteration_names[1]),
        "With the FMPM(k) mass matrix: 'net incremental' applies the contact "
        "laws also to each increment of the series of each material "
        "(Nairn 2026, 'net incremental contact'; the velocity conditions "
        "are re-imposed on every increment); 'once per step' corrects only "
        "the extrapolated and updated momenta ([Nairn2023-FMPM] Ch. 3). Units: "
        "none.");
      prm.leave_subsection();
    }



    void
    Parameters::parse_parameters(ParameterHandler  &prm,
                                 const unsigned int n_materials)
    {
      prm.enter_subsection("Contact");
      multimaterial = model_names.value(prm.get("Model name"));
      normals_name  = prm.get("Normals");
      {
        const auto values = Utilities::string_to_double(
          Utilities::split_string_list(prm.get("Specified normal")));
        specified_normal.assign(3, 0.);
        std::copy(values.begin(), values.end(), specified_normal.begin());
      }
      critical_separation        = prm.get_double("Critical separation");
      touching_tolerance         = prm.get_double("Touching tolerance");
      gap_closing                = prm.get_bool("Gap closing");
      friction_coefficient       = prm.get_double("Friction coefficient");
      interface_normal_stiffness = prm.get_double("Interface normal stiffness");
      interface_tangential_stiffness =
        prm.get_double("Interface tangential stiffness");
      default_law.name         = prm.get("Law");
      default_law.coefficients = default_coefficients(default_law.name);
      pair_laws.clear();
      const std::string pairs = prm.get("Pair laws");
      for (const auto &entry : Utilities::split_string_list(pairs, ';'))
        {
          if (entry.empty())
            continue;
          const std::string where = "Contact/Pair laws, entry '" + entry + "'";
          const auto        colon = entry.find(':');
          AssertThrow(colon != std::string::npos,
                      ExcMessage(where + ": expected 'a b: law' (material "
                                         "indices, then the law)."));
          std::vector<unsigned int> ab;
          for (const auto &w :
               Utilities::split_string_list(entry.substr(0, colon), ' '))
            if (!w.empty())
              {
                AssertThrow(
                  w.find_first_not_of("0123456789") == std::string::npos,
                  ExcMessage(where + ": '" + w + "' is not a material index."));
                ab.push_back(std::stoul(w));
              }
          AssertThrow(ab.size() == 2 && ab[0] != ab[1],
                      ExcMessage(where + ": expected two different material "
                                         "indices before ':'."));
          for (const unsigned int m : ab)
            AssertThrow(m < n_materials,
                        ExcMessage(where + ": material " + std::to_string(m) +
                                   " does not exist (the scene has " +
                                   std::to_string(n_materials) +
                                   " material(s), 0 to " +
                                   std::to_string(n_materials - 1) + ")."));
          pair_laws.push_back(
            {std::min(ab[0], ab[1]),
             std::max(ab[0], ab[1]),
             parse_law(entry.substr(colon + 1), *this, where)});
        }
      corrections_per_step = prm.get_integer("Corrections per step");
      three_or_more =
        three_or_more_names.value(prm.get("Three or more materials"));
      xpic_contact_term =
        xpic_contact_term_names.value(prm.get("XPIC contact term"));
      net_incremental =
        prm.get("Contact in mass-matrix iterations") == iteration_names[0];
      prm.leave_subsection();
    }



    const Law &
    Parameters::law(const unsigned int a, const unsigned int b) const
    {
      const unsigned int lo = std::min(a, b), hi = std::max(a, b);
      for (const auto &pair : pair_laws)
        if (pair.a == lo && pair.b == hi)
          return pair.law;
      return default_law;
    }



    std::vector<double>
    Parameters::default_coefficients(const std::string &name) const
    {
      ParameterHandler unused; // laws read no subsection of their own
      return Plugins::Registry<LawInterface<2>>::instance()
        .create(name, unused)
        ->default_coefficients(*this);
    }



  } // namespace Contact
} // namespace fmpm
