// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_constitutive_model_linear_elastic_h
#define fmpm_constitutive_model_linear_elastic_h

#include <fmpm/constitutive_model/interface.h>

namespace fmpm {
  namespace ConstitutiveModel {
    /**
     * @brief Small-strain isotropic linear elasticity, for verification:
     * \f$\sigma = \lambda\,\mathrm{tr}(\varepsilon) I + 2\mu\varepsilon\f$
     * with \f$\varepsilon = \mathrm{sym}(F) - I\f$ (total-strain form, so the
     * result does not depend on the number of steps).
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

      void
      check_parameters(const std::string &where) const override;

      /** Young's modulus E. Units: Pa. */
      double youngs_modulus = 1.0e6;
      /** Poisson's ratio nu. */
      double poissons_ratio = 0.3;
    };
  } // namespace ConstitutiveModel
} // namespace fmpm

#endif
