// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_mass_matrix_series_h
#define fmpm_mass_matrix_series_h

#include <fmpm/grid_vectors.h>

#include <functional>
#include <vector>

/**
 * The FMPM(k) series m̃ₖ⁻¹ p (seed 000 Eqs. 1.22-1.23) for one or several
 * fields: the one series of the FMPM(k) mass matrix (one field, from
 * v₁ = m⁻¹p) and of the per-material fields of contact (from the
 * contact-corrected z₁).
 */
namespace fmpm
{
  namespace MassMatrix
  {
    /** One field of fmpm_series(): the lumped masses m, the right-hand
     * side q, the velocities z (z₁ on entry, z_k on exit), per
     * component, the nodes whose value is held (or nullptr), and the
     * nodes (nonzero) whose increments the adaptive order's test skips
     * (or nullptr): the padding nodes, which an after-update hook sets
     * from their mirrors. */
    struct SeriesField
    {
      const GridScalar              *mass;
      const GridVectorField         *rhs;
      GridVectorField               *velocity;
      const std::vector<GridScalar> *held     = nullptr;
      const GridScalar              *untested = nullptr;
    };

    /** out[f] = m̃_f in[f] for every field of fmpm_series() (in: z, out:
     * the products). */
    using FullMassProduct =
      std::function<void(const std::vector<GridVectorField *> &in,
                         const std::vector<GridVectorField *> &out)>;

    /** What fmpm_series() calls around the update of sweep j: before it
     * (z_j) and after it (z_{j+1}: conditions, contact on the increments,
     * ghost values). Empty functions are skipped. */
    struct SeriesHooks
    {
      std::function<void(unsigned int)> before_update, after_update;
    };

    /**
     * @brief The FMPM(k) series z_{j+1} = z_j + m⁻¹(q − m̃ z_j), j = 1, ...,
     * k − 1 (seed 000 Eqs. 1.22-1.23, 3.13-3.22), for one or more fields
     * at once: one m̃ per field (one material each with contact), all
     * applied by one call of @p product per sweep. Empty nodes (m <=
     * @p mass_floor) and held components keep z.
     *
     * @param[in] tolerance adaptive order: the series ends after the sweep
     * whose increment has ‖Δz‖₂ <= tolerance ‖z₁‖₂ (all fields and
     * components, the nodes but the fields' untested ones; one reduction
     * per sweep); 0 runs all k sweeps
     * @param[in] products scratch fields for m̃ z, one per field
     * @return the order used (k without a tolerance)
     */
    unsigned int
    fmpm_series(const FullMassProduct                &product,
                const std::vector<SeriesField>       &fields,
                const std::vector<GridVectorField *> &products,
                const unsigned int                    k,
                const double                          mass_floor,
                const double                          tolerance = 0,
                const SeriesHooks                    &hooks     = {});
  } // namespace MassMatrix
} // namespace fmpm

#endif
