// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_mass_matrix_lumped_h
#define fmpm_mass_matrix_lumped_h

#include <fmpm/mass_matrix/interface.h>

namespace fmpm
{
  namespace MassMatrix
  {
    /**
     * @brief The lumped mass matrix m = diag(SᵀM), seed 000 Eq. 1.6:
     * v = m⁻¹p node by node.
     *
     * @ingroup MassMatrices
     */
    template <int dim>
    class Lumped : public Interface<dim>
    {
    public:
      void
      solve(const GridVectorField &momentum,
            GridVectorField       &velocity) const override;

      /** No limit (the user's Courant number, at most 1). */
      StabilityLimit
      stability_limit(const StabilityMethod &method) const override;

      bool
      supports_multimaterial_contact() const override
      {
        return true;
      }
    };
  } // namespace MassMatrix
} // namespace fmpm

#endif
