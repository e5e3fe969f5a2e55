// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_contact_laws_h
#define fmpm_contact_laws_h

#include <fmpm/contact/parameters.h>
#include <fmpm/plugins.h>

#include <deal.II/base/tensor.h>

#include <memory>
#include <string>
#include <vector>

namespace fmpm
{
  namespace Contact
  {
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
