// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_constitutive_model_linear_elastic_h
#define fmpm_constitutive_model_linear_elastic_h

#include <fmpm/constitutive_model/elastic_constants.h>
#include <fmpm/constitutive_model/interface.h>
#include <fmpm/parameter_entries.h>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    /**
     * @brief Small-strain isotropic linear elasticity, for verification, in
     * one of two forms:
     * - 'incremental' (default, the classic MPM form of Sulsky et al.):
     *   \f$\sigma^{n+1} = \sigma^n + \Delta t\,(\lambda\,\mathrm{tr}(D) I +
     *   2\mu D)\f$ with \f$D = \mathrm{sym}(L)\f$, so that rigid rotations
     *   create no stress; the stored energy grows by the stress power
     *   \f$J\,\bar\sigma : D\,\Delta t\f$ (trapezoidal in σ);
     * - 'total': \f$\sigma = \lambda\,\mathrm{tr}(\varepsilon) I +
     *   2\mu\varepsilon\f$ with \f$\varepsilon = \mathrm{sym}(F) - I\f$,
     *   exact for small strains without rotation (energy ½σ:ε).
     *
     * @ingroup ConstitutiveModels
     */
    template <int dim>
    class LinearElastic : public Interface<dim>
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm);

      void
      parse_parameters(ParameterHandler &prm) override;

      void
      update_stress(const StressUpdateInputs &inputs,
                    StressUpdateOutputs      &outputs) const override;

      double
      wave_speed(const double density, const double J) const override;

      /** The wave speed does not depend on J: one evaluation. */
      double
      max_wave_speed(const double                   density,
                     const ArrayView<const double> &J) const override
      {
        return J.size() == 0 ? 0. : wave_speed(density, J[0]);
      }

      void
      check_parameters(const std::string &where) const override;

      bool
      needs_old_volume_ratio() const override
      {
        return strain_measure == StrainMeasure::kirchhoff;
      }

      /** Young's modulus E. Units: Pa. */
      double youngs_modulus = 1.0e6;
      /** Poisson's ratio nu. */
      double poissons_ratio = 0.3;
      /** 'Strain measure', resolved from its name when parsed. */
      enum class StrainMeasure
      {
        incremental,
        /** Incremental with the Jaumann rate (objective). */
        jaumann,
        /** The Kirchhoff stress, incremental with the Jaumann rate. */
        kirchhoff,
        total
      };
      StrainMeasure strain_measure = StrainMeasure::incremental;
      static constexpr SelectionNames<StrainMeasure, 4> strain_measure_names{
        {"incremental", "jaumann", "kirchhoff", "total"}};
      /** The constants as the scene sets them (E, ν or K, G). */
      ElasticConstants elastic_constants;
    };
  } // namespace ConstitutiveModel
} // namespace fmpm

#endif
