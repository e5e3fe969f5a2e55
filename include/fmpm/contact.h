// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_contact_h
#define fmpm_contact_h

#include <fmpm/plugins.h>
#include <fmpm/shape_function.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/tensor.h>

#include <cmath>
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
      /** n̂ of Eq. 13; approaching and d(x^β) − d(x^α) < 0 (Eq. 15) with
       * d(x) the edge distance of the shape function in use (DF, see
       * EdgeDistance). */
      d_fit,
      /** n̂ and d_LR from the point cloud of the node (LR, Eqs. 19-25 and
       * the appendix); approaching and d_LR < 0 (Eq. 24). */
      logistic_regression,
      /** 'Specified normal' from the lower-numbered material to the
       * higher; contact when approaching. */
      specified
    };

    /** The contact law of a pair of materials: the name of a registered
     * law and its numbers ('Friction coefficient', the interface
     * stiffnesses, or the numbers after the name in 'Pair laws'; what they
     * mean is the law's). */
    struct Law
    {
      std::string         name = "coulomb";
      std::vector<double> coefficients{0.3};
    };

    /** @brief The subsection Contact. */
    struct Parameters
    {
      /** 'Model name = multimaterial'. */
      bool                multimaterial = false;
      NormalMethod        normals       = NormalMethod::logistic_regression;
      std::string         normals_name  = "logistic regression";
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
      Law  default_law;
      /** Overrides of 'Pair laws': (material a, material b, law). */
      struct PairLaw
      {
        unsigned int a, b;
        Law          law;
      };
      std::vector<PairLaw> pair_laws;
      /** μ of 'coulomb', D_n and D_t of 'imperfect' (the numbers of a law
       * named without numbers). */
      double       friction_coefficient           = 0.3;
      double       interface_normal_stiffness     = 1e12;
      double       interface_tangential_stiffness = 1e12;
      unsigned int corrections_per_step           = 2;
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
      ThreeOrMore three_or_more = ThreeOrMore::lumped;
      /** 'XPIC contact term'. */
      XpicContactTerm xpic_contact_term = XpicContactTerm::corrected;
      /** 'Contact in mass-matrix iterations = net incremental': the laws
       * also correct each increment of the FMPM(k)/XPIC(k) series. */
      bool net_incremental = true;

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
      /**
       * Normal momentum of approach the laws leave when the materials are
       * a gap d > 0 apart that the approach closes within the step:
       * m_red d/Δt, so that the gap closes at the end of the step instead
       * of contact acting across it (0 when touching).
       */
      double allowed_approach = 0;
      /** Which momenta the correction changes. */
      enum class Stage
      {
        /** The extrapolated momenta (the first correction, or before the
         * USL+/USAVG+ stresses). */
        extrapolated,
        /** The updated momenta p + f Δt (the second correction). */
        updated,
        /** An increment of the FMPM(k)/XPIC(k) series. */
        increment
      };
      Stage stage = Stage::updated;
      /** Laws with interface_state(): u^β − u^α, the extrapolated
       * displacements' jump (u_p = x_p − X_p). Units: m. */
      Tensor<1, dim> displacement_jump;
      /** Laws with interface_state(): the contact area A_c of the node
       * ([Nairn2013] sqrt(2 min(V^α, V^β)(V^α + V^β))/h with the nodal
       * volumes V^α = Σ S V_p). Units: m^(dim-1) (per unit thickness in
       * 2D). */
      double contact_area = 0;
      /** The time step. Units: s. */
      double time_step = 0;
    };

    /**
     * @brief The geometry of a node shared by α and β: n̂ (from α to β),
     * whether the materials touch there (the normal method's separation
     * test) and the separation in cells. It depends on the points'
     * positions only, so it is found once per extrapolation and used by
     * every correction until the points move.
     */
    template <int dim>
    struct NodeGeometry
    {
      Tensor<1, dim> normal;
      bool           touching   = true;
      double         separation = 0;
    };

    /**
     * @brief d(x) of seed 004 Fig. 1 for the DF method: the signed distance
     * from the edge of a semi-infinite material to a node, as a function of
     * the extrapolated position x = (x^α − x_i)·n̂, both in cells.
     *
     * Tabulated at set-up for the shape function in use and the points'
     * half-length (undeformed points on a line, linear grid functions),
     * then inverted: for each edge position e the row of points at
     * e − (k + 1/2) 2 l_p gives x^α(e) = Σ S_ip x_p / Σ S_ip; d(x) is the
     * inverse on the branch where x^α rises with e, extended with slope 1.
     */
    class EdgeDistance
    {
    public:
      EdgeDistance() = default;
      EdgeDistance(const ShapeFunction::Type type,
                   const double              half_length_in_cells);

      /** d for a material on the −n̂ side of the node (material α). */
      double
      alpha(const double x) const;

      /** d for a material on the +n̂ side: d_β(x) = −d_α(−x). */
      double
      beta(const double x) const
      {
        return -alpha(-x);
      }

    private:
      std::vector<double> x_table, d_table;
    };

    /** @brief The result of a logistic regression fit at a node. */
    template <int dim>
    struct RegressionResult
    {
      /** n̂ = (φ_1, ..., φ_dim)/|...|, from class −1 (α) to class +1 (β). */
      Tensor<1, dim> normal;
      /** NLLS iterations after the first (linear regression) one. */
      unsigned int iterations = 0;
      bool         converged  = false;
      /** False when the normal equations were singular from the start. */
      bool valid = false;
    };

    /**
     * @brief The most probable plane between two point classes (seed 004
     * Eqs. 19-21, appendix Eqs. 53-57): minimise Σ (f(x_p·φ) − c_p)² +
     * Σ λ_j φ_j² with f(s) = 2/(1 + e^{−s}) − 1 = tanh(s/2), by NLLS from
     * φ⁽⁰⁾ = 0 (the first iterate is the linear regression). w_p = 1,
     * λ = 10⁻⁷ Δx² (1, ..., 1, 0), converged when 1 − n̂⁽ᵏ⁺¹⁾·n̂⁽ᵏ⁾ <
     * @p tolerance (Eq. 57), at most @p max_iterations NLLS steps. If an
     * NLLS step is singular or not finite the last good normal is kept.
     *
     * @p x are the positions (any origin; the cloud's mean is the best
     * conditioned), @p c the classes (−1 or 1), @p cell_size Δx.
     */
    template <int dim>
    RegressionResult<dim>
    logistic_regression_normal(const Tensor<1, dim> *x,
                               const double         *c,
                               const unsigned int    n,
                               const double          cell_size,
                               const double          tolerance      = 1e-5,
                               const unsigned int    max_iterations = 15);

    /**
     * @brief R_p of Eq. 25: the distance along n̂ from a point's centre to
     * its deformed ellipsoid, 1/R_p = |n₀/R₀| with n₀ = F⁻¹n̂.
     */
    template <int dim>
    inline double
    deformed_radius(const Tensor<2, dim> &F_inverse,
                    const Tensor<1, dim> &initial_radii,
                    const Tensor<1, dim> &normal)
    {
      const Tensor<1, dim> n0  = F_inverse * normal;
      double               sum = 0;
      for (unsigned int d = 0; d < dim; ++d)
        sum += n0[d] * n0[d] / (initial_radii[d] * initial_radii[d]);
      return 1. / std::sqrt(sum);
    }

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
      /** Interface laws, correction of the updated momenta: the energy the
       * interface stores at the node, ½ A_c (D_n [u]_n² + D_t |[u]_t|²)
       * over the directions it does not treat as perfect. */
      double interface_energy = 0;
    };

    /**
     * @brief A contact law (plugin system): Δp^α at a node shared by α and
     * β (β gets −Δp^α, seed 004 Eq. 7), from the masses, momenta and
     * geometry of the node.
     *
     * Laws are called once per pair at each contact node (not per point).
     * Registered: 'perfect', 'frictionless', 'coulomb' (Eqs. 7-10, the
     * corrected sign of Eq. 10) and 'imperfect' (a bonded interface with
     * normal and tangential stiffnesses, [Nairn2013]). A new law derives
     * from this class and registers with FMPM_REGISTER_CONTACT_LAW.
     */
    template <int dim>
    class LawInterface : public Plugins::InterfaceBase
    {
    public:
      /** How many numbers the law reads ('coulomb 0.2': one). */
      virtual unsigned int
      n_coefficients() const
      {
        return 0;
      }

      /** The law's numbers (n_coefficients() of them). */
      virtual void
      set_coefficients(const std::vector<double> &)
      {}

      /** The law's numbers when the scene names it without numbers (from
       * the subsection Contact). */
      virtual std::vector<double>
      default_coefficients(const Parameters &) const
      {
        return {};
      }

      /** Whether correct() reads NodePair::displacement_jump and
       * contact_area (bonded interfaces): the Simulator extrapolates the
       * displacements and volumes of each material only then. */
      virtual bool
      interface_state() const
      {
        return false;
      }

      virtual Correction<dim>
      correct(const NodePair<dim> &node) const = 0;
    };

    /** @brief The registered law names, '|'-separated. */
    std::string
    law_names();

    /** @brief Create the law @p law names, with its coefficient. */
    template <int dim>
    std::unique_ptr<LawInterface<dim>>
    create_law(const Law &law);

    /**
     * @brief Δp^α of @p law at @p node (creates the law: for tests and
     * one-off uses; the time step keeps one law object per pair).
     */
    template <int dim>
    Correction<dim>
    correct(const Law &law, const NodePair<dim> &node)
    {
      return create_law<dim>(law)->correct(node);
    }

    /** Registers a law class template for dim = 2 and 3 at load time. */
    template <template <int> class LawType>
    struct RegisterLaw
    {
      RegisterLaw(const std::string &name, const std::string &description)
      {
        Plugins::Registry<LawInterface<2>>::instance().register_plugin(
          name, description, nullptr, []() {
            return std::make_unique<LawType<2>>();
          });
        Plugins::Registry<LawInterface<3>>::instance().register_plugin(
          name, description, nullptr, []() {
            return std::make_unique<LawType<3>>();
          });
      }
    };
  } // namespace Contact
} // namespace fmpm

/** Registers the law class template CLASSNAME as NAME. */
#define FMPM_REGISTER_CONTACT_LAW(CLASSNAME, NAME, DESCRIPTION)     \
  namespace                                                         \
  {                                                                 \
    const ::fmpm::Contact::RegisterLaw<CLASSNAME>                   \
      fmpm_contact_law_registration_##CLASSNAME(NAME, DESCRIPTION); \
  }

#endif
