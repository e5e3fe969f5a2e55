// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_constitutive_model_interface_h
#define fmpm_constitutive_model_interface_h

#include <fmpm/particle_properties.h>
#include <fmpm/plugins.h>

#include <deal.II/base/array_view.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <algorithm>
#include <memory>
#include <vector>

namespace fmpm
{
  /**
   * @defgroup ConstitutiveModels Constitutive models
   * Stress from deformation, one plugin per material.
   */
  namespace ConstitutiveModel
  {
    using namespace dealii;

    /**
     * @brief The material points of one batch (one cell, one material) whose
     * stress the Simulator updates.
     *
     * In 2D the scene is in plane strain: F and L are 3x3 with F_33 = 1.
     */
    struct StressUpdateInputs
    {
      /** Updated deformation gradient F^{n+1} of each point. */
      std::vector<Tensor<2, 3>> deformation_gradient;
      /** Spatial velocity gradient L used for the update. Units: 1/s. */
      std::vector<Tensor<2, 3>> velocity_gradient;
      /** All property slots of each point, for models with history state. */
      std::vector<PointRecord> properties;
      /** Size of each point's cell (its smallest vertex distance), filled
       * only for models whose needs_cell_size() is true. Units: m. */
      std::vector<double> cell_size;
      /** Time increment of this update. Units: s. */
      double time_step = 0;
      /** Reference density ρ0 of the batch's material. Units: kg/m^3. */
      double reference_density = 0;

      void
      resize(const unsigned int n)
      {
        deformation_gradient.resize(n);
        velocity_gradient.resize(n);
        properties.resize(n);
        cell_size.resize(n);
      }
    };

    /** @brief What a model returns for each point of the batch. */
    struct StressUpdateOutputs
    {
      /** Cauchy stress. Units: Pa. */
      std::vector<SymmetricTensor<2, 3>> cauchy_stress;
      /** Stored energy per unit reference volume. Units: J/m^3. */
      std::vector<double> strain_energy_density;
      /** Current wave speed of each point, filled only by models whose
       * computes_wave_speed() is true. Units: m/s. */
      std::vector<double> wave_speed;
      /** The first point (index in the batch) whose state the model cannot
       * continue from, or -1; failure says why. */
      int         failed_point = -1;
      std::string failure;

      void
      resize(const unsigned int n)
      {
        cauchy_stress.resize(n);
        strain_energy_density.resize(n);
        wave_speed.resize(n);
      }
    };

    /**
     * @brief Interface of constitutive models.
     *
     * The Simulator calls update_stress() for whole batches of points (all
     * points of one cell with this material) during every strain update
     * (once for USF/USL, twice for USAVG), and wave_speed() when it
     * chooses the time step. A model may keep history state in property slots
     * it requests through ParticleProperties::request() in initialize().
     *
     * @ingroup ConstitutiveModels
     * @tparam dim space dimension
     */
    template <int dim>
    class Interface : public Plugins::InterfaceBase
    {
    public:
      /** @brief Declare parameters (none by default). */
      static void
      declare_parameters(ParameterHandler &)
      {}

      /**
       * @brief Request the per-point history slots the model keeps (called
       * once, before the material points exist).
       */
      virtual void
      request_properties(ParticleProperties<dim> &)
      {}

      /** @brief Whether update_stress() reads StressUpdateInputs::cell_size
       * (the Simulator fills it only then). */
      virtual bool
      needs_cell_size() const
      {
        return false;
      }

      /** @brief Whether update_stress() fills StressUpdateOutputs::wave_speed
       * (state-dependent wave speeds); otherwise the Simulator asks
       * max_wave_speed(). */
      virtual bool
      computes_wave_speed() const
      {
        return false;
      }

      /**
       * @brief Stress and stored energy of each point from its state.
       * May modify the history slots in @p inputs.properties.
       */
      virtual void
      update_stress(const StressUpdateInputs &inputs,
                    StressUpdateOutputs      &outputs) const = 0;

      /**
       * @brief Largest wave speed of the material at reference density
       * @p density and volume ratio @p J, for the Courant condition.
       * Units: m/s.
       */
      virtual double
      wave_speed(const double density, const double J) const = 0;

      /**
       * @brief The largest wave_speed() over the volume ratios @p J of a
       * batch (one virtual call per batch). Models override it with an
       * inline loop or a closed form. Units: m/s.
       */
      virtual double
      max_wave_speed(const double                   density,
                     const ArrayView<const double> &J) const
      {
        double c = 0;
        for (const double J_q : J)
          c = std::max(c, wave_speed(density, J_q));
        return c;
      }

      /**
       * @brief Throw an ExcMessage naming the parameter if the model's
       * parameters are not physical. @p where names the subsection.
       */
      virtual void
      check_parameters(const std::string &where) const = 0;
    };

    /** @brief The registry of constitutive models. */
    template <int dim>
    using Registry = Plugins::Registry<Interface<dim>>;
  } // namespace ConstitutiveModel
} // namespace fmpm

#define FMPM_REGISTER_CONSTITUTIVE_MODEL(CLASSNAME, NAME, DESCRIPTION) \
  FMPM_REGISTER_PLUGIN(::fmpm::ConstitutiveModel::Interface,           \
                       CLASSNAME,                                      \
                       NAME,                                           \
                       DESCRIPTION)

#endif
