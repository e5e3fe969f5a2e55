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
        "velocity field per material ([NHS2020-contact] Eqs. 5-6) and contact "
        "corrections at nodes where materials meet (Eqs. 7-10, §3.2). "
        "Bodies of one material share a field. Units: none.");
      prm.declare_entry(
        "Normals",
        "logistic regression",
        Patterns::Selection(normal_names),
        "Contact normal and contact test of a node ([NHS2020-contact] §2.3, §3.1). "
        "'velocity only': n from the volume gradients (Eq. 13), contact "
        "whenever the materials approach (Eq. 14). 'average gradient': n "
        "of Eq. 13, approach and separation of the extrapolated positions "
        "below the delta_c of the linear d(x) fit (Eq. 17: 0.92 cells for "
        "classic and GIMP, 0.96 for CPDI). 'contact position': the same "
        "with delta_c = 'Critical separation' (Eq. 16). 'specified': n = "
        "'Specified normal' from the lower-numbered material to the "
        "higher, contact when approaching. 'd fit' (DF): n of Eq. 13, "
        "approach and d(x^b) - d(x^a) < 0 (Eq. 15) with d(x) the edge "
        "distance of the shape function in use, tabulated at start-up. "
        "'logistic regression' (LR): n and the separation d_LR from the "
        "point cloud around the node (Eqs. 19-25), contact when approaching "
        "and d_LR < 0 (see 'Touching tolerance'). Units: none.");
      prm.declare_entry("Specified normal",
                        "0, 1",
                        Patterns::List(Patterns::Double(), 2, 3),
                        "The normal of 'Normals = specified'. Units: none.");
      prm.declare_entry("Critical separation",
                        "0.8",
                        Patterns::Double(0),
                        "delta_c of 'contact position' (Eq. 16). Units: cells "
                        "(the local cell size at the node).");
      prm.declare_entry(
        "Touching tolerance",
        "0.001",
        Patterns::Double(0, 1),
        "'logistic regression' and 'd fit': materials whose separation d is "
        "below this count as touching (bodies in contact have d = 0 up to "
        "round-off); a larger gap d that the approach closes within the "
        "step, d + (v^b - v^a).n dt < 0, gets contact for the approach "
        "beyond d/dt only, so that the gap closes at the end of the step. "
        "Units: cells (the local cell size at the node).");
      prm.declare_entry(
        "Gap closing",
        "true",
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
                        "coulomb",
                        Patterns::Selection(law_names()),
                        "The contact law of every pair of materials unless "
                        "'Pair laws' overrides it (a plugin system): "
                        "'perfect' (no slip, no separation), 'frictionless', "
                        "'coulomb' (Eqs. 7-10, mu = 'Friction coefficient'), "
                        "'imperfect' (a bonded interface with the interface "
                        "stiffnesses). Units: none.");
      prm.declare_entry("Friction coefficient",
                        "0.3",
                        Patterns::Double(0),
                        "mu of 'Law = coulomb'. Units: none.");
      prm.declare_entry(
        "Interface normal stiffness",
        "1e12",
        Patterns::Double(0),
        "D_n of 'Law = imperfect': the normal traction of a bonded interface "
        "per unit opening, D_n [u]_n, in tension and compression "
        "([Nairn2013]). A stiffness the time step cannot resolve (D A_c dt^2 "
        "> 2.25 m_red at a node) acts as a perfect interface there; 0 "
        "transmits nothing (a debonded interface). Units: Pa/m.");
      prm.declare_entry(
        "Interface tangential stiffness",
        "1e12",
        Patterns::Double(0),
        "D_t of 'Law = imperfect': the shear traction per unit slip, "
        "D_t [u]_t (the same limits as the normal stiffness). Units: Pa/m.");
      prm.declare_entry(
        "Pair laws",
        "",
        Patterns::Anything(),
        "Overrides by material index, separated by ';': 'a b: law', e.g. "
        "'0 1: coulomb 0.2; 1 2: perfect; 0 2: imperfect 1e9 5e8' (a law's "
        "numbers after its name; without them 'Friction coefficient' and the "
        "interface stiffnesses). Units: none.");
      prm.declare_entry(
        "Corrections per step",
        "2",
        Patterns::Integer(1, 2),
        "2: after the extrapolation and after the momentum "
        "update ([NHS2020-contact] §3.2); 1: after the momentum update "
        "only (the 'LR once' comparison). Units: none.");
      prm.declare_entry(
        "Three or more materials",
        "lumped",
        Patterns::Selection("lumped|pairwise|explicit"),
        "Nodes with 3+ materials ([NHS2020-contact] §3.4): 'lumped' treats "
        "each material against the sum of the others (Eq. 50; the paper's "
        "recommendation); 'pairwise' corrects every pair in turn (conserves "
        "momentum); 'explicit' finds the pairs in contact (their own normals "
        "and separations): one pair is corrected alone, two pairs together "
        "(both contact laws hold at once, momentum conserved), three or more "
        "lumped (the algorithm at the paper's Fig. 4). Units: none.");
      prm.declare_entry(
        "XPIC contact term",
        "corrected",
        Patterns::Selection("corrected|uncorrected|series"),
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
        "net incremental",
        Patterns::Selection("net incremental|once per step"),
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
      multimaterial = prm.get("Model name") == "multimaterial";
      normals_name  = prm.get("Normals");
      normals       = normal_method(normals_name);
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
      corrections_per_step    = prm.get_integer("Corrections per step");
      const std::string three = prm.get("Three or more materials");
      three_or_more           = three == "lumped"   ? ThreeOrMore::lumped :
                                three == "pairwise" ? ThreeOrMore::pairwise :
                                                      ThreeOrMore::explicit_pairs;
      const std::string term  = prm.get("XPIC contact term");
      xpic_contact_term = term == "uncorrected" ? XpicContactTerm::uncorrected :
                          term == "series"      ? XpicContactTerm::series :
                                                  XpicContactTerm::corrected;
      net_incremental =
        prm.get("Contact in mass-matrix iterations") == "net incremental";
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



    std::string
    law_names()
    {
      return Plugins::Registry<LawInterface<2>>::instance().pattern();
    }



    std::vector<double>
    Parameters::default_coefficients(const std::string &name) const
    {
      ParameterHandler unused; // laws read no subsection of their own
      return Plugins::Registry<LawInterface<2>>::instance()
        .create(name, unused)
        ->default_coefficients(*this);
    }



    template <int dim>
    std::unique_ptr<LawInterface<dim>>
    create_law(const Law &law)
    {
      ParameterHandler unused; // laws read no subsection of their own
      auto             result =
        Plugins::Registry<LawInterface<dim>>::instance().create(law.name,
                                                                unused);
      if (result->n_coefficients() > 0)
        {
          AssertThrow(law.coefficients.size() == result->n_coefficients(),
                      ExcMessage("The contact law '" + law.name + "' takes " +
                                 std::to_string(result->n_coefficients()) +
                                 " number(s)."));
          result->set_coefficients(law.coefficients);
        }
      return result;
    }

    template std::unique_ptr<LawInterface<2>>
    create_law<2>(const Law &);
    template std::unique_ptr<LawInterface<3>>
    create_law<3>(const Law &);



    namespace
    {
      /** Δp^α(0) = m^α (v^(cm) − v^α): moves both with the centre of mass
       * (Eq. 7). */
      template <int dim>
      Tensor<1, dim>
      centre_of_mass_change(const NodePair<dim> &node)
      {
        const Tensor<1, dim> v_cm = (node.momentum_alpha + node.momentum_beta) /
                                    (node.mass_alpha + node.mass_beta);
        return node.mass_alpha * v_cm - node.momentum_alpha;
      }

      /** No slip, no separation: Δp^α = Δp^α(0) always. */
      template <int dim>
      class PerfectInterface : public LawInterface<dim>
      {
      public:
        Correction<dim>
        correct(const NodePair<dim> &node) const override
        {
          Correction<dim> result;
          result.delta_momentum = centre_of_mass_change(node);
          result.in_contact     = true;
          return result;
        }
      };

      /**
       * Contact when approaching, Δp^α(0)·n̂ < 0 (Eq. 14), and touching (the
       * normal method's separation test); then the normal part
       * (Δp^α(0)·n̂)n̂ and the tangential part up to μ|Δp^α(0)·n̂| (Eq. 10
       * with S_slide = μN_c and N_cA_cΔt = −Δp^α(0)·n̂).
       */
      template <int dim>
      class Coulomb : public LawInterface<dim>
      {
      public:
        unsigned int
        n_coefficients() const override
        {
          return 1;
        }

        void
        set_coefficients(const std::vector<double> &mu) override
        {
          friction = mu[0];
        }

        std::vector<double>
        default_coefficients(const Parameters &contact) const override
        {
          return {contact.friction_coefficient};
        }

        Correction<dim>
        correct(const NodePair<dim> &node) const override
        {
          Correction<dim>      result;
          const Tensor<1, dim> dp0 = centre_of_mass_change(node);
          // With a gap that closes within the step, the approach beyond
          // d/Δt only (NodePair::allowed_approach).
          const double dp0_n = dp0 * node.normal + node.allowed_approach;
          if (!(dp0_n < 0) || !node.touching)
            return result;
          result.in_contact     = true;
          result.delta_momentum = dp0_n * node.normal;
          if (friction == 0)
            return result;
          const Tensor<1, dim> dp0_t      = dp0 - result.delta_momentum;
          const double         dp0_t_norm = dp0_t.norm();
          if (dp0_t_norm == 0)
            return result;
          const double         slide = std::min(-friction * dp0_n, dp0_t_norm);
          const Tensor<1, dim> t_hat = dp0_t / dp0_t_norm;
          result.delta_momentum += slide * t_hat;
          // Energy the tangential impulse J = slide takes from the pair: J
          // times the mean relative tangential speed before and after it.
          const double m_a = node.mass_alpha, m_b = node.mass_beta;
          const double m_red    = m_a * m_b / (m_a + m_b);
          const double u_before = dp0_t_norm / m_red;
          const double u_after  = (dp0_t_norm - slide) / m_red;
          result.friction_work  = slide * 0.5 * (u_before + u_after);
          return result;
        }

      protected:
        double friction = 0;
      };

      /** Coulomb with μ = 0: stops the normal approach only. */
      template <int dim>
      class Frictionless : public Coulomb<dim>
      {
      public:
        unsigned int
        n_coefficients() const override
        {
          return 0;
        }

        std::vector<double>
        default_coefficients(const Parameters &) const override
        {
          return {};
        }
      };

      /**
       * A bonded imperfect interface ([Nairn2013]): the traction
       * D_n [u]_n n̂ + D_t [u]_t on α, [u] = u^β − u^α the jump of the
       * extrapolated displacements, gives the impulse A_c Δt (D_n [u]_n n̂ +
       * D_t [u]_t) in the correction of the updated momenta (the interface
       * force acts once per step). A direction whose stiffness the time step
       * cannot resolve, D A_c Δt² > 2.25 m_red (the oscillator of the
       * reduced mass on that spring takes more than 1.5 radians per step),
       * is perfect there: its part of Δp^α(0) in every correction. D → ∞ is
       * the perfect interface; D = 0 transmits nothing.
       */
      template <int dim>
      class ImperfectInterface : public LawInterface<dim>
      {
      public:
        unsigned int
        n_coefficients() const override
        {
          return 2;
        }

        void
        set_coefficients(const std::vector<double> &D) override
        {
          normal_stiffness     = D[0];
          tangential_stiffness = D[1];
        }

        std::vector<double>
        default_coefficients(const Parameters &contact) const override
        {
          return {contact.interface_normal_stiffness,
                  contact.interface_tangential_stiffness};
        }

        bool
        interface_state() const override
        {
          return true;
        }

        Correction<dim>
        correct(const NodePair<dim> &node) const override
        {
          Correction<dim>       result;
          const Tensor<1, dim>  dp0 = centre_of_mass_change(node);
          const Tensor<1, dim> &n   = node.normal;
          const double          m_a = node.mass_alpha, m_b = node.mass_beta;
          const double          m_red = m_a * m_b / (m_a + m_b);
          const double          area_dt2 =
            node.contact_area * node.time_step * node.time_step;
          const bool stiff_normal = normal_stiffness * area_dt2 > 2.25 * m_red;
          const bool stiff_tangential =
            tangential_stiffness * area_dt2 > 2.25 * m_red;
          result.in_contact          = true;
          const double         dp0_n = dp0 * n;
          const Tensor<1, dim> dp0_t = dp0 - dp0_n * n;
          if (stiff_normal)
            result.delta_momentum += dp0_n * n;
          if (stiff_tangential)
            result.delta_momentum += dp0_t;
          if (node.stage != NodePair<dim>::Stage::updated)
            return result;
          const Tensor<1, dim> &jump   = node.displacement_jump;
          const double          jump_n = jump * n;
          const double impulse_scale   = node.contact_area * node.time_step;
          if (!stiff_normal)
            result.delta_momentum +=
              impulse_scale * normal_stiffness * jump_n * n;
          const Tensor<1, dim> jump_t = jump - jump_n * n;
          if (!stiff_tangential)
            result.delta_momentum +=
              impulse_scale * tangential_stiffness * jump_t;
          result.interface_energy =
            0.5 * node.contact_area *
            ((stiff_normal ? 0. : normal_stiffness * jump_n * jump_n) +
             (stiff_tangential ? 0. :
                                 tangential_stiffness * jump_t.norm_square()));
          return result;
        }

      private:
        double normal_stiffness = 0, tangential_stiffness = 0;
      };
    } // namespace

    FMPM_REGISTER_CONTACT_LAW(
      PerfectInterface,
      "perfect",
      "No slip and no separation: both materials move "
      "with the centre of mass ([NHS2020-contact] Eq. 7).")
    FMPM_REGISTER_CONTACT_LAW(Frictionless,
                              "frictionless",
                              "Stops the normal approach of touching "
                              "materials, free slip (Eqs. 7-9).")
    FMPM_REGISTER_CONTACT_LAW(
      ImperfectInterface,
      "imperfect",
      "A bonded interface with normal and tangential stiffnesses D_n, D_t: "
      "traction D [u] from the jump of the extrapolated displacements "
      "([Nairn2013]); the numbers are D_n and D_t in Pa/m.")
    FMPM_REGISTER_CONTACT_LAW(Coulomb,
                              "coulomb",
                              "Stops the normal approach, tangential impulse "
                              "up to mu times the normal one (Eqs. 7-10); the "
                              "number is mu.")



    EdgeDistance::EdgeDistance(const ShapeFunction::Type type,
                               const double              half_length)
    {
      AssertThrow(half_length > 0 && half_length < 1,
                  ExcMessage("d(x) fit: the points' half-length must be "
                             "between 0 and 1 cell."));
      // Linear grid function of the node at 0 and its integral.
      auto N = [](const double s) { return std::max(0., 1. - std::abs(s)); };
      auto integral = [](const double s) {
        if (s <= -1)
          return 0.;
        if (s <= 0)
          return 0.5 * (s + 1) * (s + 1);
        if (s <= 1)
          return 1. - 0.5 * (1 - s) * (1 - s);
        return 1.;
      };
      auto shape = [&](const double center) {
        switch (type)
          {
            case ShapeFunction::Type::classic:
              return N(center);
            case ShapeFunction::Type::cpdi: // mean of the corner values
              return 0.5 * (N(center - half_length) + N(center + half_length));
            default: // uGIMP, cpGIMP: N averaged over the point's domain
              return (integral(center + half_length) -
                      integral(center - half_length)) /
                     (2 * half_length);
          }
      };
      const double reach = 1 + half_length;
      const double step  = 1e-3;
      for (double edge = -reach; edge <= reach; edge += step)
        {
          double sum_S = 0, sum_Sx = 0;
          for (double center = edge - half_length; center > -reach;
               center -= 2 * half_length)
            {
              const double S = shape(center);
              sum_S += S;
              sum_Sx += S * center;
            }
          if (sum_S < 1e-12)
            continue;
          const double x = sum_Sx / sum_S;
          if (!x_table.empty() && x <= x_table.back() + 1e-12)
            {
              if (x_table.size() > 1)
                break; // the end of the rising branch
              continue;
            }
          x_table.push_back(x);
          d_table.push_back(edge);
        }
      AssertThrow(x_table.size() > 1, ExcInternalError());
    }



    double
    EdgeDistance::alpha(const double x) const
    {
      if (x <= x_table.front())
        return d_table.front() + (x - x_table.front());
      if (x >= x_table.back())
        return d_table.back() + (x - x_table.back());
      const auto   upper = std::upper_bound(x_table.begin(), x_table.end(), x);
      const auto   k     = upper - x_table.begin();
      const double w     = (x - x_table[k - 1]) / (x_table[k] - x_table[k - 1]);
      return (1 - w) * d_table[k - 1] + w * d_table[k];
    }



    namespace
    {
      /** Solve the SPD system A y = b of size n <= 4 by Cholesky; false if
       * A is not positive definite. */
      bool
      cholesky_solve(double *A, double *b, const unsigned int n)
      {
        for (unsigned int j = 0; j < n; ++j)
          {
            double diagonal = A[j * n + j];
            for (unsigned int k = 0; k < j; ++k)
              diagonal -= A[j * n + k] * A[j * n + k];
            if (!(diagonal > 1e-300))
              return false;
            const double L_jj = std::sqrt(diagonal);
            A[j * n + j]      = L_jj;
            for (unsigned int i = j + 1; i < n; ++i)
              {
                double value = A[i * n + j];
                for (unsigned int k = 0; k < j; ++k)
                  value -= A[i * n + k] * A[j * n + k];
                A[i * n + j] = value / L_jj;
              }
          }
        for (unsigned int i = 0; i < n; ++i) // L z = b
          {
            for (unsigned int k = 0; k < i; ++k)
              b[i] -= A[i * n + k] * b[k];
            b[i] /= A[i * n + i];
          }
        for (unsigned int i = n; i-- > 0;) // Lᵀ y = z
          {
            for (unsigned int k = i + 1; k < n; ++k)
              b[i] -= A[k * n + i] * b[k];
            b[i] /= A[i * n + i];
          }
        return true;
      }
    } // namespace



    template <int dim>
    RegressionResult<dim>
    logistic_regression_normal(const Tensor<1, dim> *x,
                               const double         *c,
                               const unsigned int    n_points,
                               const double          cell_size,
                               const double          tolerance,
                               const unsigned int    max_iterations)
    {
      constexpr unsigned int n = dim + 1; // φ = (normal, offset)
      RegressionResult<dim>  result;
      if (n_points == 0)
        return result;
      Tensor<1, dim> origin;
      for (unsigned int p = 0; p < n_points; ++p)
        origin += x[p];
      origin /= n_points;
      // λ = 10⁻⁷ Δx² on the normal's components, none on the offset.
      double lambda[n];
      for (unsigned int j = 0; j < dim; ++j)
        lambda[j] = 1e-7 * cell_size * cell_size;
      lambda[dim] = 0;

      double phi[n] = {};
      for (unsigned int iteration = 0; iteration <= max_iterations; ++iteration)
        {
          // Eq. 21 with Eqs. 54-56: (JᵀWJ + Λ) Δφ = JᵀW(c − f) − Λφ,
          // J_pj = ψ(x_p) x_pj, ψ = 2e^{−s}/(1 + e^{−s})² = 1/(2cosh²(s/2)).
          double A[n * n] = {}, b[n];
          for (unsigned int j = 0; j < n; ++j)
            b[j] = -lambda[j] * phi[j];
          for (unsigned int p = 0; p < n_points; ++p)
            {
              double xp[n];
              for (unsigned int d = 0; d < dim; ++d)
                xp[d] = x[p][d] - origin[d];
              xp[dim]  = 1;
              double s = 0;
              for (unsigned int j = 0; j < n; ++j)
                s += xp[j] * phi[j];
              const double cosh_half = std::cosh(0.5 * s);
              const double psi       = 0.5 / (cosh_half * cosh_half);
              const double f         = std::tanh(0.5 * s); // Eq. 20
              const double psi2      = psi * psi;
              const double residual  = psi * (c[p] - f);
              for (unsigned int j = 0; j < n; ++j)
                {
                  b[j] += residual * xp[j];
                  for (unsigned int k = 0; k <= j; ++k)
                    A[j * n + k] += psi2 * xp[j] * xp[k];
                }
            }
          for (unsigned int j = 0; j < n; ++j)
            {
              A[j * n + j] += lambda[j];
              for (unsigned int k = 0; k < j; ++k)
                A[k * n + j] = A[j * n + k];
            }
          if (!cholesky_solve(A, b, n))
            break;
          double candidate[n];
          for (unsigned int j = 0; j < n; ++j)
            candidate[j] = phi[j] + b[j];
          Tensor<1, dim> normal;
          for (unsigned int d = 0; d < dim; ++d)
            normal[d] = candidate[d];
          const double length = normal.norm();
          if (!(length > 0) || !std::isfinite(length))
            break;
          normal /= length;
          std::copy(candidate, candidate + n, phi);
          if (!result.valid) // φ⁽¹⁾: the linear regression
            {
              result.valid  = true;
              result.normal = normal;
              continue;
            }
          ++result.iterations;
          const double change = 1. - normal * result.normal; // Eq. 57
          result.normal       = normal;
          if (change < tolerance)
            {
              result.converged = true;
              break;
            }
        }
      return result;
    }

    template RegressionResult<2>
    logistic_regression_normal(const Tensor<1, 2> *,
                               const double *,
                               const unsigned int,
                               const double,
                               const double,
                               const unsigned int);
    template RegressionResult<3>
    logistic_regression_normal(const Tensor<1, 3> *,
                               const double *,
                               const unsigned int,
                               const double,
                               const double,
                               const unsigned int);

  } // namespace Contact
} // namespace fmpm
