// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/fmpm.h>
#include <fmpm/simulator.h>


namespace fmpm
{
  namespace MassMatrix
  {
    template <typename MatrixType>
    void
    apply_fmpm_inverse(const MatrixType              &m_tilde,
                       const GridScalar              &m,
                       const GridVectorField         &p,
                       GridVectorField               &v,
                       const unsigned int             k,
                       const double                   mass_floor,
                       const std::vector<GridScalar> *zero_mask,
                       const std::vector<GridScalar> *known_values)
    {
      // v_1 = m⁻¹ p; known components hold their values in every sweep.
      apply_lumped_inverse(m, p, v, mass_floor);
      if (zero_mask)
        for (unsigned int b = 0; b < p.n_blocks(); ++b)
          for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
            if ((*zero_mask)[b].local_element(i) != 0)
              v.block(b).local_element(i) =
                known_values ? (*known_values)[b].local_element(i) : 0.;
      if (k == 1)
        return;
      GridVectorField    m_tilde_v(v);
      const unsigned int n_owned = m.locally_owned_size();
      for (unsigned int j = 1; j < k; ++j)
        {
          // v_{j+1} = v_j + m⁻¹ (p − m̃ v_j), all components in one product
          apply_full_mass(m_tilde, m_tilde_v, v);
          for (unsigned int b = 0; b < p.n_blocks(); ++b)
            for (unsigned int i = 0; i < n_owned; ++i)
              {
                const double m_i = m.local_element(i);
                if (m_i > mass_floor &&
                    !(zero_mask && (*zero_mask)[b].local_element(i) != 0))
                  v.block(b).local_element(i) +=
                    (p.block(b).local_element(i) -
                     m_tilde_v.block(b).local_element(i)) /
                    m_i;
              }
        }
    }

    template void
    apply_fmpm_inverse(const TrilinosWrappers::SparseMatrix &,
                       const GridScalar &,
                       const GridVectorField &,
                       GridVectorField &,
                       const unsigned int,
                       const double,
                       const std::vector<GridScalar> *,
                       const std::vector<GridScalar> *);
    template void
    apply_fmpm_inverse(const CellwiseMatrix &,
                       const GridScalar &,
                       const GridVectorField &,
                       GridVectorField &,
                       const unsigned int,
                       const double,
                       const std::vector<GridScalar> *,
                       const std::vector<GridScalar> *);



    template <int dim>
    void
    Fmpm<dim>::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Order",
                        "2",
                        Patterns::Integer(1, 1000),
                        "The order k of the series m~_k^-1 (seed 000 Eq. "
                        "1.23): 1 is the lumped mass matrix, larger k "
                        "approaches the full mass matrix m~ = S^T M S. "
                        "Units: none.");
    }



    template <int dim>
    void
    Fmpm<dim>::parse_parameters(ParameterHandler &prm)
    {
      k = prm.get_integer("Order");
    }



    template <int dim>
    void
    Fmpm<dim>::solve(const GridVectorField &p, GridVectorField &v) const
    {
      if (const CellwiseMatrix *cellwise =
            this->get_simulator().get_cellwise_full_mass_matrix())
        {
          apply_fmpm_inverse(*cellwise,
                             this->get_lumped_mass(),
                             p,
                             v,
                             k,
                             this->get_simulator().mass_floor(),
                             &this->get_known_velocity_mask(),
                             &this->get_known_velocity_values());
          return;
        }
      apply_fmpm_inverse(this->get_full_mass_matrix(),
                         this->get_lumped_mass(),
                         p,
                         v,
                         k,
                         this->get_simulator().mass_floor(),
                         &this->get_known_velocity_mask(),
                         &this->get_known_velocity_values());
    }



    template <int dim>
    void
    Fmpm<dim>::vmult(const GridVectorField &v, GridVectorField &p) const
    {
      // m̃ (the assembled full mass matrix) stands in for m̃_k, as seed 000
      // suggests for the unlumped boundary-condition methods.
      if (k == 1)
        {
          Interface<dim>::vmult(v, p);
          return;
        }
      if (const CellwiseMatrix *cellwise =
            this->get_simulator().get_cellwise_full_mass_matrix())
        apply_full_mass(*cellwise, p, v);
      else
        apply_full_mass(this->get_full_mass_matrix(), p, v);
    }

    FMPM_REGISTER_MASS_MATRIX(
      Fmpm,
      "fmpm",
      "FMPM(k): the approximate full mass matrix inverse m~_k^-1 of seed 000 "
      "Eq. 1.23 (= XPIC(k)), computed as k Jacobi-Richardson sweeps on the "
      "assembled m~ = S^T M S.")
  } // namespace MassMatrix
} // namespace fmpm
