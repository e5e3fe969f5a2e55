// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_checkerboard_h
#define fmpm_postprocess_checkerboard_h

#include <deal.II/base/array_view.h>
#include <deal.II/base/point.h>

#include <algorithm>
#include <cmath>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The checkerboard (hourglass) indicator of J: the point-to-point
   * pattern of the volume ratio that the grid cannot see.
   *
   * In each cell the points' J is fitted, mass-weighted, by a linear
   * function J̄ + b·(x − x̄); the residuals r_p are what is left of J at the
   * scale of the point spacing (with 2 x 2 points a cell, the pattern
   * J = 1 ± ε alternating between neighbouring points). The indicator is
   * their RMS against the largest RMS of the volume change J − 1 so far, or
   * against j_floor if that is larger,
   *   sqrt(Σ M_p r_p² / Σ M_p) / max(max_t sqrt(Σ M_p (J_p − 1)² / Σ M_p),
   *                                  j_floor),
   * so 0 for any field that is linear in each cell, 1 for J = 1 ± ε
   * alternating (ε ≥ j_floor), and of the order of the noise's share of the
   * deformation when a checkerboard grows on a smooth field. (The largest
   * RMS so far, not the current one, so that a body swinging back through
   * its undeformed shape does not raise it.) Each cell uses only its own
   * points, so the sums do not depend on how the cells are divided among
   * MPI ranks.
   */
  namespace Checkerboard
  {
    /**
     * The denominator's floor: a body whose RMS volume change stays below
     * 0.15 is measured against 0.15, so that the warning needs a residual
     * RMS of at least 0.015 in J (2D; 0.0225 in 3D) whatever the
     * deformation. Runs that are right stay below that: the rigid rotation
     * (parameters/rigid_rotation.prm) 0.0009 with a volume change of only
     * 0.0019, the colliding disks 0.010, the cantilever with FLIP's
     * position update matching USAVG+ 0.0046; the cantilever runs that
     * leave the reference (FLIP with psi = 0 and USAVG+, FMPM(32), Courant
     * 0.4) reach 0.021-0.027 against a volume change of 0.10
     * (doc/studies/cantilever.md).
     */
    constexpr double j_floor = 0.15;

    /**
     * The run warns (once) above this value. 2D: 0.1, from the cantilever
     * (doc/studies/cantilever.md), where the runs that follow the reference
     * stay below 0.05 and the runs that leave it pass 0.1 as their tip
     * leaves the reference. 3D: 0.15, because the fit of 2 x 2 x 2 points
     * leaves half of uncorrelated point noise in the residual, the fit of
     * 2 x 2 points a quarter (a factor sqrt(2) ≈ 1.41).
     */
    template <int dim>
    constexpr double warning_threshold = dim == 2 ? 0.1 : 0.15;

    /** @brief Sums over the points of one or many cells. */
    struct Sums
    {
      /** Σ M_p r_p² over the cells with enough points for the fit. */
      double residual = 0;
      /** Σ M_p (J_p − 1)². */
      double volume_change = 0;
      /** Σ M_p. */
      double mass = 0;

      Sums &
      operator+=(const Sums &other)
      {
        residual += other.residual;
        volume_change += other.volume_change;
        mass += other.mass;
        return *this;
      }

      /** The RMS of the residuals. */
      double
      residual_rms() const
      {
        return mass > 0 ? std::sqrt(residual / mass) : 0.;
      }

      /** The RMS of J − 1. */
      double
      volume_change_rms() const
      {
        return mass > 0 ? std::sqrt(volume_change / mass) : 0.;
      }
    };

    /**
     * @brief The sums of the points of one cell: positions @p x, masses
     * @p mass and volume ratios @p J. A cell with fewer than dim + 2 points,
     * or with points on a line (a plane in 3D), adds no residual.
     */
    template <int dim>
    Sums
    cell_sums(const ArrayView<const Point<dim>> &x,
              const ArrayView<const double>     &mass,
              const ArrayView<const double>     &J);

    /** @brief The indicator from the residuals' RMS and the largest RMS of
     * J − 1 so far. */
    inline double
    indicator(const double residual_rms, const double largest_volume_change_rms)
    {
      return residual_rms / std::max(largest_volume_change_rms, j_floor);
    }
  } // namespace Checkerboard
} // namespace fmpm

#endif
