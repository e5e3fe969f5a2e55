// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/constitutive_model/linear_elastic.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_properties.h>

#include <cmath>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    template <int dim>
    void
    LinearElastic<dim>::declare_parameters(ParameterHandler &prm)
    {
      const LinearElastic<dim> defaults;
      prm.declare_entry("Young's modulus",
                        format_number(defaults.youngs_modulus),
                        Patterns::Double(),
                        "Young's modulus E of the material. Must be positive. "
                        "Units: Pa.");
      prm.declare_entry("Poisson's ratio",
                        format_number(defaults.poissons_ratio),
                        Patterns::Double(),
                        "Poisson's ratio nu of the material, in [0, 0.5). "
                        "Units: none.");
      prm.declare_entry("Strain measure",
                        "incremental",
                        Patterns::Selection("incremental|total"),
                        "'incremental': sigma += dt C : sym(L) (classic MPM, "
                        "no stress from rigid rotation); 'total': sigma = C : "
                        "(sym(F) - I) (exact for small strains without "
                        "rotation). Units: none.");
    }



    template <int dim>
    void
    LinearElastic<dim>::parse_parameters(ParameterHandler &prm)
    {
      youngs_modulus = prm.get_double("Young's modulus");
      poissons_ratio = prm.get_double("Poisson's ratio");
      strain_measure = prm.get("Strain measure") == "incremental" ?
                         StrainMeasure::incremental :
                         StrainMeasure::total;
    }



    template <int dim>
    void
    LinearElastic<dim>::check_parameters(const std::string &where) const
    {
      AssertThrow(youngs_modulus > 0,
                  ExcMessage(where + "/Young's modulus = " +
                             format_number(youngs_modulus) +
                             " is not positive. Allowed: any value > 0 (Pa)."));
      AssertThrow(poissons_ratio > -1 && poissons_ratio < 0.5,
                  ExcMessage(where + "/Poisson's ratio = " +
                             format_number(poissons_ratio) +
                             " is outside the allowed range (-1, 0.5)."));
    }



    template <int dim>
    void
    LinearElastic<dim>::update_stress(const StressUpdateInputs &inputs,
                                      StressUpdateOutputs      &outputs) const
    {
      const double mu     = youngs_modulus / (2 * (1 + poissons_ratio));
      const double lambda = youngs_modulus * poissons_ratio /
                            ((1 + poissons_ratio) * (1 - 2 * poissons_ratio));
      const SymmetricTensor<2, 3> identity = unit_symmetric_tensor<3>();
      if (strain_measure == StrainMeasure::incremental)
        {
          using Index = PropertyIndex<dim>;
          for (unsigned int q = 0; q < inputs.deformation_gradient.size(); ++q)
            {
              const PointRecord          &p = inputs.properties[q];
              const SymmetricTensor<2, 3> D =
                symmetrize(inputs.velocity_gradient[q]);
              const SymmetricTensor<2, 3> old_stress =
                get_symmetric_tensor3(p, Index::stress);
              const SymmetricTensor<2, 3> stress =
                old_stress +
                inputs.time_step * (lambda * trace(D) * identity + 2 * mu * D);
              const double J = determinant(inputs.deformation_gradient[q]);
              outputs.cauchy_stress[q] = stress;
              outputs.strain_energy_density[q] =
                p[Index::strain_energy_density] +
                0.5 * J * ((old_stress + stress) * D) * inputs.time_step;
            }
          return;
        }
      for (unsigned int q = 0; q < inputs.deformation_gradient.size(); ++q)
        {
          const SymmetricTensor<2, 3> strain =
            symmetrize(inputs.deformation_gradient[q]) - identity;
          const SymmetricTensor<2, 3> stress =
            lambda * trace(strain) * identity + 2 * mu * strain;
          outputs.cauchy_stress[q]         = stress;
          outputs.strain_energy_density[q] = 0.5 * (stress * strain);
        }
    }



    template <int dim>
    double
    LinearElastic<dim>::wave_speed(const double density, const double) const
    {
      const double mu     = youngs_modulus / (2 * (1 + poissons_ratio));
      const double lambda = youngs_modulus * poissons_ratio /
                            ((1 + poissons_ratio) * (1 - 2 * poissons_ratio));
      return std::sqrt((lambda + 2 * mu) / density);
    }

    FMPM_REGISTER_CONSTITUTIVE_MODEL(
      LinearElastic,
      "linear elastic",
      "Small-strain isotropic linear elasticity (total strain sym(F) - I), for "
      "verification against linear analytical solutions.")
  } // namespace ConstitutiveModel
} // namespace fmpm
