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
      if (strain_measure == StrainMeasure::incremental)
        {
          // σ += Δt (λ tr(D) I + 2μ D), D = sym(L), and the energy from the
          // midpoint stress, entry by entry (the sums in the order of
          // deal.II's SymmetricTensor operations: the same results).
          using Index         = PropertyIndex<dim>;
          const double two_mu = 2 * mu;
          const double dt     = inputs.time_step;
          for (unsigned int q = 0; q < inputs.deformation_gradient.size(); ++q)
            {
              const PointRecord  &p = inputs.properties[q];
              const Tensor<2, 3> &L = inputs.velocity_gradient[q];
              // Voigt-like order xx, yy, zz, xy, xz, yz (the stored order).
              const double D[6] = {L[0][0],
                                   L[1][1],
                                   L[2][2],
                                   (L[0][1] + L[1][0]) * 0.5,
                                   (L[0][2] + L[2][0]) * 0.5,
                                   (L[1][2] + L[2][1]) * 0.5};
              const double lambda_trace = lambda * (D[0] + D[1] + D[2]);
              double       old_stress[6], stress[6];
              for (unsigned int c = 0; c < 6; ++c)
                {
                  old_stress[c] = p[Index::stress + c];
                  const double rate =
                    c < 3 ? lambda_trace + two_mu * D[c] : two_mu * D[c];
                  stress[c] = old_stress[c] + dt * rate;
                }
              double work = (old_stress[3] + stress[3]) * D[3];
              work += (old_stress[4] + stress[4]) * D[4];
              work += (old_stress[5] + stress[5]) * D[5];
              work += work;
              work += (old_stress[0] + stress[0]) * D[0];
              work += (old_stress[1] + stress[1]) * D[1];
              work += (old_stress[2] + stress[2]) * D[2];
              SymmetricTensor<2, 3> &sigma = outputs.cauchy_stress[q];
              for (unsigned int c = 0; c < 6; ++c)
                sigma[stress_component_i[c]][stress_component_j[c]] = stress[c];
              const double J = determinant(inputs.deformation_gradient[q]);
              outputs.strain_energy_density[q] =
                p[Index::strain_energy_density] + 0.5 * J * work * dt;
            }
          return;
        }
      // ε = sym(F) − I, σ = λ tr(ε) I + 2μ ε, W = σ:ε / 2, entry by entry
      // (the sums in the order of deal.II's SymmetricTensor operations).
      const double two_mu = 2 * mu;
      for (unsigned int q = 0; q < inputs.deformation_gradient.size(); ++q)
        {
          const Tensor<2, 3> &F    = inputs.deformation_gradient[q];
          const double        e_xx = F[0][0] - 1, e_yy = F[1][1] - 1,
                       e_zz = F[2][2] - 1;
          const double e_xy = (F[0][1] + F[1][0]) * 0.5,
                       e_xz = (F[0][2] + F[2][0]) * 0.5,
                       e_yz = (F[1][2] + F[2][1]) * 0.5;
          const double lambda_trace = lambda * (e_xx + e_yy + e_zz);
          SymmetricTensor<2, 3> &sigma = outputs.cauchy_stress[q];
          sigma[0][0] = lambda_trace + two_mu * e_xx;
          sigma[1][1] = lambda_trace + two_mu * e_yy;
          sigma[2][2] = lambda_trace + two_mu * e_zz;
          sigma[0][1] = two_mu * e_xy;
          sigma[0][2] = two_mu * e_xz;
          sigma[1][2] = two_mu * e_yz;
          double work = sigma[0][1] * e_xy;
          work += sigma[0][2] * e_xz;
          work += sigma[1][2] * e_yz;
          work += work;
          work += sigma[0][0] * e_xx;
          work += sigma[1][1] * e_yy;
          work += sigma[2][2] * e_zz;
          outputs.strain_energy_density[q] = 0.5 * work;
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
