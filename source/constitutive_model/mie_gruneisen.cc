// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/constitutive_model/mie_gruneisen.h>
#include <fmpm/parameters.h>

#include <cmath>
#include <sstream>

namespace fmpm
{
  namespace ConstitutiveModel
  {
    template <int dim>
    void
    MieGruneisen<dim>::declare_parameters(ParameterHandler &prm)
    {
      const MieGruneisen<dim> defaults;
      ElasticConstants::declare_parameters(
        prm,
        ElasticConstants::Pair::bulk_and_shear,
        defaults.bulk_modulus,
        defaults.shear_modulus,
        "K of [NHS2020-contact] Eq. (51) (K = ρ0 C0², C0 the bulk sound "
        "speed of the Hugoniot U_s = C0 + S1 u_p). A number > 0.",
        "G of the shear term of [NHS2020-contact] Eq. (18). A number >= 0 "
        "(0: no shear stress).");
      prm.declare_entry("Gruneisen gamma",
                        format_number(defaults.gruneisen_gamma),
                        Patterns::Double(),
                        "γ0 of Eq. (51). Must not be negative. Units: none.");
      prm.declare_entry("S1",
                        format_number(defaults.s1),
                        Patterns::Double(),
                        "Slope S1 of the Hugoniot U_s = C0 + S1 u_p (Eq. "
                        "51). Must be positive. Units: none.");
      prm.declare_entry("Artificial viscosity A1",
                        format_number(defaults.artificial_viscosity_a1),
                        Patterns::Double(),
                        "A1 of q = ρ Δx |D_kk| (A1 C + A2 Δx |D_kk|), Eq. "
                        "(52), added to the pressure in compression; 0 with "
                        "A2 = 0: no viscosity. Must not be negative. Units: "
                        "none.");
      prm.declare_entry("Artificial viscosity A2",
                        format_number(defaults.artificial_viscosity_a2),
                        Patterns::Double(),
                        "A2 of Eq. (52). Must not be negative. Units: none.");
      J2Hardening::declare_parameters(prm, defaults.plasticity);
    }



    template <int dim>
    void
    MieGruneisen<dim>::parse_parameters(ParameterHandler &prm)
    {
      elastic_constants.parse_parameters(prm);
      elastic_constants.get_bulk_and_shear(bulk_modulus, shear_modulus);
      gruneisen_gamma         = prm.get_double("Gruneisen gamma");
      s1                      = prm.get_double("S1");
      artificial_viscosity_a1 = prm.get_double("Artificial viscosity A1");
      artificial_viscosity_a2 = prm.get_double("Artificial viscosity A2");
      plasticity.parse_parameters(prm);
    }



    template <int dim>
    void
    MieGruneisen<dim>::check_parameters(const std::string &where) const
    {
      elastic_constants.check(where, ElasticConstants::Pair::bulk_and_shear);
      auto require = [&](const bool         ok,
                         const std::string &name,
                         const double       value,
                         const std::string &allowed) {
        AssertThrow(ok,
                    ExcMessage(where + "/" + name + " = " +
                               format_number(value) + " is not allowed. " +
                               "Allowed: " + allowed + "."));
      };
      require(bulk_modulus > 0,
              "Bulk modulus",
              bulk_modulus,
              "any value > 0 (Pa)");
      require(shear_modulus >= 0,
              "Shear modulus",
              shear_modulus,
              "any value >= 0 (Pa)");
      require(gruneisen_gamma >= 0,
              "Gruneisen gamma",
              gruneisen_gamma,
              "any value >= 0");
      require(s1 > 0, "S1", s1, "any value > 0");
      require(artificial_viscosity_a1 >= 0,
              "Artificial viscosity A1",
              artificial_viscosity_a1,
              "any value >= 0");
      require(artificial_viscosity_a2 >= 0,
              "Artificial viscosity A2",
              artificial_viscosity_a2,
              "any value >= 0");
      plasticity.check(where);
      require(!plasticity.plastic() || shear_modulus > 0,
              "Shear modulus",
              shear_modulus,
              "a value > 0 when Yield stress > 0 (Pa)");
    }



    template <int dim>
    void
    MieGruneisen<dim>::request_properties(ParticleProperties<dim> &properties)
    {
      energy_slot  = properties.request("internal_energy", 1);
      plastic_slot = properties.request("plastic_strain", 1);
      if (plasticity.plastic())
        elastic_b_slot = properties.request("elastic_b_minus_identity", 6);
    }



    template <int dim>
    void
    MieGruneisen<dim>::cold_pressure(const double eta,
                                     double      &p,
                                     double      &dp_deta) const
    {
      if (eta <= 0)
        {
          p       = bulk_modulus * eta;
          dp_deta = bulk_modulus;
          return;
        }
      // K η (1 − γ0η/2)/(1 − S1η)² (Eq. 51 without ρ0 γ0 U).
      const double g    = gruneisen_gamma;
      const double r    = 1. / (1. - s1 * eta);
      const double term = eta * (1. - 0.5 * g * eta);
      p                 = bulk_modulus * term * r * r;
      dp_deta =
        bulk_modulus * ((1. - g * eta) * r * r + 2. * s1 * term * r * r * r);
    }



    template <int dim>
    double
    MieGruneisen<dim>::tangent_bulk_modulus(const double J,
                                            const double p) const
    {
      const double eta = 1. - J;
      double       p_cold, dp_cold;
      cold_pressure(eta, p_cold, dp_cold);
      // Along an isentrope dU = p dη/ρ0, so d(ρ0 γ0 U)/dη = γ0 p.
      const double dp_deta = eta > 0 ? dp_cold + gruneisen_gamma * p : dp_cold;
      return J * dp_deta;
    }



    template <int dim>
    SymmetricTensor<2, 3>
    MieGruneisen<dim>::elastic_shear_stress(const Tensor<2, 3> &F) const
    {
      const double                J = determinant(F);
      const SymmetricTensor<2, 3> b_bar =
        std::pow(J, -2. / 3.) * symmetrize(F * transpose(F));
      return shear_modulus * deviator(b_bar);
    }



    template <int dim>
    double
    MieGruneisen<dim>::wave_speed(const double density, const double J) const
    {
      double p, dp;
      cold_pressure(1. - J, p, dp);
      const double K_t = tangent_bulk_modulus(J, p);
      return std::sqrt(std::max(K_t + 4. / 3. * shear_modulus, 0.) * J /
                       density);
    }



    template <int dim>
    void
    MieGruneisen<dim>::update_stress(const StressUpdateInputs &inputs,
                                     StressUpdateOutputs      &outputs) const
    {
      using Index                         = PropertyIndex<dim>;
      const double                rho0    = inputs.reference_density;
      const double                dt      = inputs.time_step;
      const double                g0      = gruneisen_gamma;
      const bool                  plastic = plasticity.plastic();
      const bool                  viscous = needs_cell_size();
      const SymmetricTensor<2, 3> I       = unit_symmetric_tensor<3>();

      for (unsigned int q = 0; q < inputs.n_points; ++q)
        {
          const PointRecord &P  = inputs.properties[q];
          const Tensor<2, 3> F1 = inputs.deformation_gradient_tensor(q);
          const Tensor<2, 3> L  = inputs.velocity_gradient_tensor(q);
          const Tensor<2, 3> F0 = get_tensor3(P, Index::deformation_gradient);
          const SymmetricTensor<2, 3> sigma0 =
            get_symmetric_tensor3(P, Index::stress);
          const double J0 = determinant(F0), J1 = determinant(F1);
          const double eta = 1. - J1;
          if (eta > 0 && 1. - s1 * eta <= 0)
            {
              if (outputs.failed_point < 0)
                {
                  std::ostringstream message;
                  message << "is compressed past the Mie-Gruneisen "
                             "singularity 1 - S1 eta = 0 (J = "
                          << J1 << ", S1 eta = " << s1 * eta
                          << "); lower the time step or the loading";
                  outputs.failed_point = q;
                  outputs.failure      = message.str();
                }
              outputs.set_stress(q, sigma0);
              outputs.strain_energy_density[q] = rho0 * P[energy_slot];
              outputs.wave_speed[q]            = 0;
              continue;
            }

          // Kirchhoff deviatoric stress s (elastic, or radial return).
          SymmetricTensor<2, 3> s;
          if (!plastic)
            s = elastic_shear_stress(F1);
          else
            {
              SymmetricTensor<2, 3> elastic_b_minus_identity =
                get_symmetric_tensor3(P, elastic_b_slot);
              s = plasticity.radial_return(F0,
                                           F1,
                                           shear_modulus,
                                           elastic_b_minus_identity,
                                           P[plastic_slot]);
              set_symmetric_tensor3(P,
                                    elastic_b_slot,
                                    elastic_b_minus_identity);
            }

          // Pressure of Eq. (51): cold part now, ρ0 γ0 U after the energy.
          double p_cold, dp_cold;
          cold_pressure(eta, p_cold, dp_cold);
          const double U0        = P[energy_slot];
          const double energy_on = eta > 0 ? 1. : 0.;
          const double rho       = rho0 / J1;
          const double K_t =
            tangent_bulk_modulus(J1, p_cold + energy_on * rho0 * g0 * U0);
          const double C   = std::sqrt(std::max(K_t, 0.) / rho);
          const double Dkk = trace(L);
          // Artificial viscosity, Eq. (52), in compression only.
          double q_visc = 0;
          if (viscous && Dkk < 0)
            {
              const double h = inputs.cell_size[q] * std::abs(Dkk);
              q_visc =
                rho * h *
                (artificial_viscosity_a1 * C + artificial_viscosity_a2 * h);
            }

          // dU = σ : D dt / ρ, midpoint in σ and J; the volumetric part
          // from J (ρ0 dU = −p̄ ΔJ), the deviatoric part from dev(D) dt.
          const SymmetricTensor<2, 3> s_cauchy = s / J1;
          const SymmetricTensor<2, 3> D_dev    = deviator(symmetrize(L));
          const double                J_mid = 0.5 * (J0 + J1), dJ = J1 - J0;
          const double                shear_work =
            0.5 * J_mid * ((deviator(sigma0) + s_cauchy) * D_dev) * dt;
          const double pressure_work =
            0.5 * (trace(sigma0) / 3. - p_cold - q_visc) * dJ;
          const double U1 = (U0 + (shear_work + pressure_work) / rho0) /
                            (1. + 0.5 * energy_on * g0 * dJ);
          P[energy_slot] = U1;

          const double p = p_cold + energy_on * rho0 * g0 * U1;
          outputs.set_stress(q, s_cauchy - (p + q_visc) * I);
          outputs.strain_energy_density[q] = rho0 * U1;
          outputs.wave_speed[q]            = std::sqrt(
            std::max(tangent_bulk_modulus(J1, p) + 4. / 3. * shear_modulus,
                     0.) /
            rho);
        }
    }



    FMPM_REGISTER_CONSTITUTIVE_MODEL(
      MieGruneisen,
      "mie gruneisen",
      "Shock model of [NHS2020-contact] Sec. 4.3: sigma = G dev(b_bar)/J - "
      "(p + q) I with b_bar = J^(-2/3) F F^T (the shear term of Eq. 18; with "
      "J2 plasticity and linear hardening the elastic part of b_bar, radial "
      "return), the Mie-Gruneisen pressure p = K eta (1 - gamma0 eta/2)/(1 - "
      "S1 eta)^2 + rho0 gamma0 U for eta = 1 - J > 0 and p = K eta in "
      "tension (Eq. 51), U the internal energy per unit mass from the "
      "stress power, and the artificial viscosity q (Eq. 52). Constants K "
      "and G, or E and nu.")

    template class MieGruneisen<2>;
    template class MieGruneisen<3>;
  } // namespace ConstitutiveModel
} // namespace fmpm
