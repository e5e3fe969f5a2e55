// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/contact/laws.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>

namespace fmpm
{
  namespace Contact
  {
    std::string
    law_names()
    {
      return Plugins::Registry<LawInterface<2>>::instance().pattern();
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



  } // namespace Contact
} // namespace fmpm
