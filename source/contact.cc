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
        "higher, contact when approaching. 'd fit' (DF): n of Eq. 13, "
        "approach and d(x^b) - d(x^a) < 0 (Eq. 15) with d(x) the edge "
        "distance of the shape function in use, tabulated at start-up. "
        "'logistic regression' (LR): n and the separation d_LR from the "
        "point cloud around the node (Eqs. 19-25), contact when approaching "
        "and d_LR < 0. Units: none.");
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
      const double w = (x - x_table[k - 1]) / (x_table[k] - x_table[k - 1]);
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
      for (unsigned int iteration = 0; iteration <= max_iterations;
           ++iteration)
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

    template Correction<2>
    correct(const Law &, const NodePair<2> &);
    template Correction<3>
    correct(const Law &, const NodePair<3> &);
  } // namespace Contact
} // namespace fmpm
