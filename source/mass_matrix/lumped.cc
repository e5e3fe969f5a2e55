// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/lumped.h>
#include <fmpm/simulator.h>

#include <type_traits>

namespace fmpm
{
  namespace MassMatrix
  {
    namespace
    {
      /**
       * v = p / m where m exceeds the floor, else 0, for @p n nodes.
       * Branch-free (this file is compiled with -fno-trapping-math, so
       * the division by an empty node's mass may be done and discarded),
       * restrict-qualified and called with a constant count for full
       * blocks, so that GCC vectorizes it at -O2.
       */
      template <typename Count>
      inline void
      lumped_inverse(const Count n,
                     const double *__restrict mass,
                     const double *__restrict momentum,
                     double *__restrict velocity,
                     const double mass_floor)
      {
        for (unsigned int i = 0; i < n; ++i)
          {
            const double v = momentum[i] / mass[i];
            velocity[i]    = mass[i] > mass_floor ? v : 0.;
          }
      }
    } // namespace



    void
    apply_lumped_inverse(const GridScalar      &m,
                         const GridVectorField &p,
                         GridVectorField       &v,
                         const double           mass_floor)
    {
      constexpr unsigned int block   = 64;
      const unsigned int     n_owned = m.locally_owned_size();
      const unsigned int     n_full  = n_owned - n_owned % block;
      const double *const    mass    = m.begin();
      for (unsigned int b = 0; b < p.n_blocks(); ++b)
        {
          const double *const momentum = p.block(b).begin();
          double *const       velocity = v.block(b).begin();
          for (unsigned int i = 0; i < n_full; i += block)
            lumped_inverse(std::integral_constant<unsigned int, block>(),
                           mass + i,
                           momentum + i,
                           velocity + i,
                           mass_floor);
          lumped_inverse(n_owned - n_full,
                         mass + n_full,
                         momentum + n_full,
                         velocity + n_full,
                         mass_floor);
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
                           this->get_mass_floor());
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
