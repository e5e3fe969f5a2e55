// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/lumped.h>
#include <fmpm/simulator.h>

namespace fmpm
{
  namespace MassMatrix
  {
    void
    apply_lumped_inverse(const GridScalar      &m,
                         const GridVectorField &p,
                         GridVectorField       &v,
                         const double           mass_floor)
    {
      // (Raw arrays: one loop per block that the compiler vectorizes.)
      const unsigned int  n_owned = m.locally_owned_size();
      const double *const mass    = m.begin();
      for (unsigned int b = 0; b < p.n_blocks(); ++b)
        {
          const double *const momentum = p.block(b).begin();
          double *const       velocity = v.block(b).begin();
          for (unsigned int i = 0; i < n_owned; ++i)
            velocity[i] = mass[i] > mass_floor ? momentum[i] / mass[i] : 0.0;
        }
    }



    void
    apply_full_mass(const TrilinosWrappers::SparseMatrix &full_mass,
                    GridVectorField                      &dst,
                    const GridVectorField                &src)
    {
      for (unsigned int b = 0; b < src.n_blocks(); ++b)
        full_mass.vmult(dst.block(b), src.block(b));
    }



    void
    apply_full_mass(const CellwiseMatrix  &full_mass,
                    GridVectorField       &dst,
                    const GridVectorField &src)
    {
      full_mass.vmult(dst, src);
    }



    template <int dim>
    void
    Lumped<dim>::solve(const GridVectorField &p, GridVectorField &v) const
    {
      apply_lumped_inverse(this->get_lumped_mass(),
                           p,
                           v,
                           this->get_simulator().mass_floor());
    }

    template <int dim>
    StabilityLimit
    Lumped<dim>::stability_limit(const StabilityMethod &) const
    {
      return Stability::lumped_mass_matrix_limit();
    }

    FMPM_REGISTER_MASS_MATRIX(
      Lumped,
      "lumped",
      "The lumped mass matrix m = S^T M of [Nairn2023-FMPM] "
      "Eq. 1.6: standard MPM.")
  } // namespace MassMatrix
} // namespace fmpm
