// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/contact.h>
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
      const char *const normal_names =
        "average gradient|velocity only|contact position|d fit|logistic "
        "regression|specified";

      NormalMethod
      normal_method(const std::string &name)
      {
        if (name == "average gradient")
          return NormalMethod::average_gradient;
        if (name == "velocity only")
          return NormalMethod::velocity_only;
        if (name == "contact position")
          return NormalMethod::contact_position;
        if (name == "d fit")
          return NormalMethod::d_fit;
        if (name == "specified")
          return NormalMethod::specified;
        return NormalMethod::logistic_regression;
      }

      /** "coulomb 0.2", "perfect", "frictionless" → Law; @p where names the
       * parameter in errors. */
      Law
      parse_law(const std::string &text,
                const double       default_friction,
                const std::string &where)
      {
        const auto words = Utilities::split_string_list(text, ' ');
        std::vector<std::string> parts;
        for (const auto &w : words)
          if (!w.empty())
            parts.push_back(w);
        AssertThrow(!parts.empty(),
                    ExcMessage(where + ": a law is missing (allowed: perfect, "
                                       "frictionless, coulomb [mu])."));
        Law law;
        law.friction = default_friction;
        if (parts[0] == "perfect")
          law.type = LawType::perfect;
        else if (parts[0] == "frictionless")
          law.type = LawType::frictionless;
        else if (parts[0] == "coulomb")
          law.type = LawType::coulomb;
        else
          AssertThrow(false,
                      ExcMessage(where + ": unknown law '" + parts[0] +
                                 "' (allowed: perfect, frictionless, "
                                 "coulomb [mu])."));
        if (parts.size() > 1)
          {
            AssertThrow(law.type == LawType::coulomb && parts.size() == 2,
                        ExcMessage(where + ": '" + text +
                                   "': only 'coulomb' takes a number (the "
                                   "friction coefficient)."));
            try
              {
                law.friction = std::stod(parts[1]);
              }
            catch (...)
              {
                AssertThrow(false,
                            ExcMessage(where + ": '" + parts[1] +
                                       "' is not a friction coefficient."));
              }
          }
        AssertThrow(law.friction >= 0 && std::isfinite(law.friction),
                    ExcMessage(where + ": the friction coefficient must be "
                                       "a number >= 0."));
        return law;
      }
    } // namespace



    void
    Parameters::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Contact");
      prm.declare_entry(
        "Model name",
        "none",
        Patterns::Selection("none|multimaterial"),
        "'none': all bodies share one velocity field (bodies that touch "
        "stick, as in Sulsky's colliding disks). 'multimaterial': one "
        "velocity field per material (seed 004 Eqs. 5-6) and contact "
        "corrections at nodes where materials meet (Eqs. 7-10, §3.2). "
        "Bodies of one material share a field. Units: none.");
      prm.declare_entry(
        "Normals",
        "logistic regression",
        Patterns::Selection(normal_names),
        "Contact normal and contact test of a node (seed 004 §2.3, §3.1). "
        "'velocity only': n from the volume gradients (Eq. 13), contact "
        "whenever the materials approach (Eq. 14). 'average gradient': n "
        "of Eq. 13, approach and separation of the extrapolated positions "
        "below the delta_c of the linear d(x) fit (Eq. 17: 0.92 cells for "
        "classic and GIMP, 0.96 for CPDI). 'contact position': the same "
        "with delta_c = 'Critical separation' (Eq. 16). 'specified': n = "
        "'Specified normal' from the lower-numbered material to the "
        "higher, contact when approaching. 'd fit' and 'logistic "
        "regression' are not implemented yet. Units: none.");
      prm.declare_entry("Specified normal",
                        "0, 1",
                        Patterns::List(Patterns::Double(), 2, 3),
                        "The normal of 'Normals = specified'. Units: none.");
      prm.declare_entry("Critical separation",
                        "0.8",
                        Patterns::Double(0),
                        "delta_c of 'contact position' (Eq. 16). Units: cells "
                        "(the local cell size at the node).");
      prm.declare_entry("Law",
                        "coulomb",
                        Patterns::Selection("perfect|frictionless|coulomb"),
                        "The contact law of every pair of materials unless "
                        "'Pair laws' overrides it: 'perfect' (no slip, no "
                        "separation), 'frictionless', 'coulomb' (Eqs. 7-10). "
                        "Units: none.");
      prm.declare_entry("Friction coefficient",
                        "0.3",
                        Patterns::Double(0),
                        "mu of 'Law = coulomb'. Units: none.");
      prm.declare_entry(
        "Pair laws",
        "",
        Patterns::Anything(),
        "Overrides by material index, separated by ';': 'a b: law', e.g. "
        "'0 1: coulomb 0.2; 1 2: perfect'. Units: none.");
      prm.declare_entry("Corrections per step",
                        "2",
                        Patterns::Integer(1, 2),
                        "2: after the extrapolation and after the momentum "
                        "update (seed 004 §3.2); 1: after the momentum update "
                        "only (the 'LR once' comparison). Units: none.");
      prm.declare_entry("Three or more materials",
                        "lumped",
                        Patterns::Selection("lumped|pairwise"),
                        "Nodes with 3+ materials (seed 004 §3.4): 'lumped' "
                        "treats each material against the sum of the others "
                        "(Eq. 50); 'pairwise' corrects every pair in turn "
                        "(conserves momentum). Units: none.");
      prm.leave_subsection();
    }



    void
    Parameters::parse_parameters(ParameterHandler  &prm,
                                 const unsigned int n_materials)
    {
      prm.enter_subsection("Contact");
      multimaterial = prm.get("Model name") == "multimaterial";
      normals_name  = prm.get("Normals");
      normals       = normal_method(normals_name);
      {
        const auto values =
          Utilities::string_to_double(Utilities::split_string_list(
            prm.get("Specified normal")));
        specified_normal.assign(3, 0.);
        std::copy(values.begin(), values.end(), specified_normal.begin());
      }
      critical_separation = prm.get_double("Critical separation");
      const std::string law_name = prm.get("Law");
      default_law.friction       = prm.get_double("Friction coefficient");
      default_law.type           = law_name == "perfect" ? LawType::perfect :
                                   law_name == "frictionless" ?
                                                       LawType::frictionless :
                                                       LawType::coulomb;
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
                AssertThrow(w.find_first_not_of("0123456789") ==
                              std::string::npos,
                            ExcMessage(where + ": '" + w +
                                       "' is not a material index."));
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
          pair_laws.push_back({std::min(ab[0], ab[1]),
                               std::max(ab[0], ab[1]),
                               parse_law(entry.substr(colon + 1),
                                         default_law.friction,
                                         where)});
        }
      corrections_per_step = prm.get_integer("Corrections per step");
      lumped_three_or_more = prm.get("Three or more materials") == "lumped";
      prm.leave_subsection();

      if (multimaterial)
        AssertThrow(normals != NormalMethod::d_fit &&
                      normals != NormalMethod::logistic_regression,
                    ExcMessage("Contact/Normals = " + normals_name +
                               " is not implemented yet; choose average "
                               "gradient, velocity only, contact position or "
                               "specified."));
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



    template <int dim>
    Correction<dim>
    correct(const Law &law, const NodePair<dim> &node)
    {
      Correction<dim> result;
      const double    m_a = node.mass_alpha, m_b = node.mass_beta;
      // Δp^α(0) = m^α (v^(cm) − v^α)
      const Tensor<1, dim> v_cm =
        (node.momentum_alpha + node.momentum_beta) / (m_a + m_b);
      const Tensor<1, dim> dp0 = m_a * v_cm - node.momentum_alpha;
      if (law.type == LawType::perfect)
        {
          result.delta_momentum = dp0;
          result.in_contact     = true;
          return result;
        }
      const double dp0_n = dp0 * node.normal;
      // Eq. 14: approaching (Δp^α(0)·n̂ = m_red (v^β − v^α)·n̂ < 0), and
      // touching (the normal method's separation test).
      if (!(dp0_n < 0) || !node.touching)
        return result;
      result.in_contact = true;
      result.delta_momentum = dp0_n * node.normal;
      if (law.type == LawType::frictionless)
        return result;
      // Coulomb: S_slide A_c Δt = min(μ N_c A_c Δt, Δp^α(0)·t̂) with
      // N_c A_c Δt = −Δp^α(0)·n̂ and t̂ along the tangential part of Δp^α(0).
      const Tensor<1, dim> dp0_t    = dp0 - result.delta_momentum;
      const double         dp0_t_norm = dp0_t.norm();
      if (dp0_t_norm == 0)
        return result;
      const double slide = std::min(-law.friction * dp0_n, dp0_t_norm);
      const Tensor<1, dim> t_hat = dp0_t / dp0_t_norm;
      result.delta_momentum += slide * t_hat;
      // Energy the tangential impulse J = slide takes from the pair: J times
      // the mean relative tangential speed before and after it.
      const double m_red        = m_a * m_b / (m_a + m_b);
      const double u_before     = dp0_t_norm / m_red;
      const double u_after      = (dp0_t_norm - slide) / m_red;
      result.friction_work      = slide * 0.5 * (u_before + u_after);
      return result;
    }

    template Correction<2>
    correct(const Law &, const NodePair<2> &);
    template Correction<3>
    correct(const Law &, const NodePair<3> &);
  } // namespace Contact
} // namespace fmpm
