// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_mass_matrix_series_h
#define fmpm_mass_matrix_series_h

#include <fmpm/grid_vectors.h>

#include <functional>
#include <vector>

/**
 * The FMPM(k) series m̃ₖ⁻¹ p (seed 000 Eqs. 1.22-1.23) for one or several
 * fields, used by the FMPM(k) mass matrix and by the per-material fields of
 * contact.
 */
namespace fmpm
{
  namespace MassMatrix
  {
    /** One field of fmpm_series(): the lumped masses m, the right-hand
     * side q, the velocities z (z₁ on entry, z_k on exit) and, per
     * component, the nodes whose value is held (or nullptr). */
    struct SeriesField
    {
      const GridScalar              *mass;
      const GridVectorField         *rhs;
      GridVectorField               *velocity;
      const std::vector<GridScalar> *held = nullptr;
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
     * whose increment has ‖Δz‖₂ <= tolerance ‖z₁‖₂ (all fields, nodes and
     * components; one reduction per sweep); 0 runs all k sweeps
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

    /**
     * @brief v = m̃ₖ⁻¹ p of seed 000 Eqs. 1.22-1.23 (= XPIC(k)'s v(k),
     * Eqs. 1.32-1.36) as k Jacobi-preconditioned Richardson sweeps on
     * m̃ v = p from v = 0:
     * \f$v_1 = m^{-1}p,\; v_{j+1} = v_j + m^{-1}(p - \tilde m v_j)\f$,
     * since \f$\tilde m_k^{-1} = \sum_{\ell=0}^{k-1} A^\ell m^{-1}\f$ with
     * \f$A = I - S^+S = I - m^{-1}\tilde m\f$ (Eq. 1.12). With m̃ assembled
     * once per step, each order costs one sparse mat-vec per component
     * instead of a pass over all material points.
     *
     * @param[in] full_mass m̃ = SᵀMS
     * @param[in] lumped_mass m = SᵀM
     * @param[in] p momentum-like field
     * @param[out] v m̃ₖ⁻¹ p on locally owned nodes
     * @param[in] k order (k = 1: lumped)
     * @param[in] mass_floor nodes with less mass are empty
     * @param[in] zero_mask per component, nodes whose velocity is held at
     * known by a grid condition (kept in every sweep), or nullptr
     * @param[in] known_values per component, the known values (zero if
     * nullptr)
     * @param[in] tolerance adaptive order: the series ends after the sweep
     * ℓ < k whose increment Δv_ℓ = v_{ℓ+1} − v_ℓ has ‖Δv_ℓ‖₂ ≤ tolerance
     * ‖v_1‖₂ (all nodes and components; one reduction per sweep); 0 runs
     * all k sweeps, as FMPM(k)
     * @return the order used (k without a tolerance)
     */
    template <typename MatrixType>
    unsigned int
    apply_fmpm_inverse(const MatrixType              &full_mass,
                       const GridScalar              &lumped_mass,
                       const GridVectorField         &p,
                       GridVectorField               &v,
                       const unsigned int             k,
                       const double                   mass_floor,
                       const std::vector<GridScalar> *zero_mask    = nullptr,
                       const std::vector<GridScalar> *known_values = nullptr,
                       const double                   tolerance    = 0);
  } // namespace MassMatrix
} // namespace fmpm

#endif
