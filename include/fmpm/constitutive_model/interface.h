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
     * @brief The material points of one batch (up to capacity points of one
     * material) whose stress the Simulator updates, one array per tensor
     * entry so that a model's loop over the points vectorizes.
     *
     * Tensor entry (a, b) of point q is at [3 a + b][q]; symmetric tensors
     * are in the stored order xx, yy, zz, xy, xz, yz (stress_component_i/j).
     * In 2D the scene is in plane strain: F_33 = 1 and the out-of-plane
     * shear entries of F, L and σ are zero.
     */
    struct StressUpdateInputs
    {
      static constexpr unsigned int capacity = 64;
      /** Points in the batch. */
      unsigned int n_points = 0;
      /** Updated deformation gradient F^{n+1}. */
      alignas(64) double deformation_gradient[9][capacity] = {};
      /** J = det F^{n+1}. */
      alignas(64) double volume_ratio[capacity] = {};
      /** Spatial velocity gradient L used for the update. Units: 1/s. */
      alignas(64) double velocity_gradient[9][capacity] = {};
      /** Cauchy stress σ^n before the update (filled for models whose
       * reads_old_state() is true, as the next two). Units: Pa. */
      alignas(64) double old_stress[6][capacity] = {};
      /** J^n = V/V0 before the update, filled only for models whose
       * needs_old_volume_ratio() is true. */
      alignas(64) double old_volume_ratio[capacity] = {};
      /** Stored energy per unit reference volume before the update.
       * Units: J/m^3. */
      alignas(64) double old_strain_energy_density[capacity] = {};
      /** All property slots of each point, for models with history state. */
      PointRecord properties[capacity] = {};
      /** Size of each point's cell (its smallest vertex distance), filled
       * only for models whose needs_cell_size() is true. Units: m. */
      double cell_size[capacity] = {};
      /** Time increment of this update. Units: s. */
      double time_step = 0;
      /** Reference density ρ0 of the batch's material. Units: kg/m^3. */
      double reference_density = 0;

      void
      resize(const unsigned int n)
      {
        AssertIndexRange(n, capacity + 1);
        n_points = n;
      }

      Tensor<2, 3>
      deformation_gradient_tensor(const unsigned int q) const
      {
        return entries_as_tensor(deformation_gradient, q);
      }

      Tensor<2, 3>
      velocity_gradient_tensor(const unsigned int q) const
      {
        return entries_as_tensor(velocity_gradient, q);
      }

      /** Sets F^{n+1} of point q and its volume ratio. */
      void
      set_deformation_gradient(const unsigned int q, const Tensor<2, 3> &F)
      {
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = 0; b < 3; ++b)
            deformation_gradient[3 * a + b][q] = F[a][b];
        volume_ratio[q] = determinant(F);
      }

      void
      set_velocity_gradient(const unsigned int q, const Tensor<2, 3> &L)
      {
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = 0; b < 3; ++b)
            velocity_gradient[3 * a + b][q] = L[a][b];
      }

      SymmetricTensor<2, 3>
      old_stress_tensor(const unsigned int q) const
      {
        SymmetricTensor<2, 3> sigma;
        for (unsigned int c = 0; c < 6; ++c)
          sigma[stress_component_i[c]][stress_component_j[c]] =
            old_stress[c][q];
        return sigma;
      }

      void
      set_old_stress(const unsigned int q, const SymmetricTensor<2, 3> &sigma)
      {
        for (unsigned int c = 0; c < 6; ++c)
          old_stress[c][q] =
            sigma[stress_component_i[c]][stress_component_j[c]];
      }

    private:
      static Tensor<2, 3>
      entries_as_tensor(const double (&entries)[9][capacity],
                        const unsigned int q)
      {
        Tensor<2, 3> t;
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = 0; b < 3; ++b)
            t[a][b] = entries[3 * a + b][q];
        return t;
      }
    };

    /** @brief What a model returns for each point of the batch. */
    struct StressUpdateOutputs
    {
      static constexpr unsigned int capacity = StressUpdateInputs::capacity;
      /** Cauchy stress, in the stored order. Units: Pa. */
      alignas(64) double cauchy_stress[6][capacity] = {};
      /** Stored energy per unit reference volume. Units: J/m^3. */
      alignas(64) double strain_energy_density[capacity] = {};
      /** Current wave speed of each point, filled only by models whose
       * computes_wave_speed() is true. Units: m/s. */
      alignas(64) double wave_speed[capacity] = {};
      /** The first point (index in the batch) whose state the model cannot
       * continue from, or -1; failure says why. */
      int         failed_point = -1;
      std::string failure;

      SymmetricTensor<2, 3>
      stress_tensor(const unsigned int q) const
      {
        SymmetricTensor<2, 3> sigma;
        for (unsigned int c = 0; c < 6; ++c)
          sigma[stress_component_i[c]][stress_component_j[c]] =
            cauchy_stress[c][q];
        return sigma;
      }

      void
      set_stress(const unsigned int q, const SymmetricTensor<2, 3> &sigma)
      {
        for (unsigned int c = 0; c < 6; ++c)
          cauchy_stress[c][q] =
            sigma[stress_component_i[c]][stress_component_j[c]];
      }
    };

    /**
     * @brief Interface of constitutive models.
     *
     * The Simulator calls update_stress() for whole batches of points (up to
     * StressUpdateInputs::capacity points of one material, in store order)
     * during every strain update (once for USF/USL, twice for USAVG), and
     * wave_speed() when it chooses the time step. A model may keep history
     * state in property slots it requests through ParticleProperties::request()
     * in initialize().
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

      /** @brief Whether update_stress() reads
       * StressUpdateInputs::old_volume_ratio (the Simulator fills it only
       * then). */
      virtual bool
      needs_old_volume_ratio() const
      {
        return false;
      }

      /** @brief Whether update_stress() reads the state before the update:
       * StressUpdateInputs::old_stress, old_strain_energy_density or
       * properties (the Simulator fills them only then). */
      virtual bool
      reads_old_state() const
      {
        return true;
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
       * @brief Stress and stored energy of each point from its state: a loop
       * over q < inputs.n_points on the entry arrays. May modify the history
       * slots in @p inputs.properties (not σ, F, W or V: the Simulator
       * writes those from the outputs).
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
