// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_time_step_stability_h
#define fmpm_time_step_stability_h

#include <fmpm/parameters.h>
#include <fmpm/shape_function.h>

#include <limits>
#include <string>

namespace fmpm
{
  /**
   * @brief The MPM method, apart from its mass matrix, as far as its stable
   * time step depends on it (resolved when the scene is read). The mass
   * matrix plugin answers the limit (MassMatrix::Interface::stability_limit()).
   */
  struct StabilityMethod
  {
    /** Whether the particle update adds the grid acceleration m̃ₖ⁻¹ f to
     * the point velocity (FLIP-type: flip, fmpm0, flip midpoint, flip end
     * velocity) instead of resetting it from the grid (PIC-type: fmpm,
     * pic, xpic, ...). */
    bool flip_type = false;
    /** 'Time/Strain update'. */
    StrainUpdateScheme strain_update = StrainUpdateScheme::of("usavg+");
    /** 'Time/Strain update mass matrix = lumped' (else 'same'). */
    bool lumped_strain_velocities = false;
    /** psi of seed 000 Eq. 2.28 in the FMPM/XPIC position update
     * ('Particle update/Fmpm|Xpic/Position update psi'); 0 for the other
     * updates. */
    double position_update_psi = 0;
    /** 'Shape function/Type'. */
    ShapeFunction::Type shape_function = ShapeFunction::Type::classic;
    /** 'Shape function/B-spline boundary = padding' (B-splines only). */
    bool bspline_padding = false;
  };

  /**
   * @brief The largest Courant number at which a method was measured
   * stable, and what that rests on.
   */
  struct StabilityLimit
  {
    /**
     * The measured critical Courant number of the method (the lower end of
     * the measured bracket), which caps 'Time/Courant number': the
     * automatic time step is dt = min(C, max_courant) h_min / (c + |v|max).
     * Infinity for the lumped mass matrix, whose limit is the user's
     * Courant number itself (at most 1).
     */
    double max_courant = std::numeric_limits<double>::infinity();
    /** Where the limit comes from (printed when it caps the Courant
     * number). */
    std::string basis;
    /** Why no time step makes this method stable, and what to choose
     * instead; empty when it is not known to fail. */
    std::string warning;
    /** The warning is about free surfaces: a scene whose bodies fill every
     * cell of the mesh has none. */
    bool warning_only_with_free_surfaces = false;
    /** A setting to consider for some scenes, printed with a numerical
     * failure as its likely remedy; empty when there is none. */
    std::string note;
  };

  /**
   * @brief The measured critical Courant numbers from which the mass matrix
   * plugins answer stability_limit(): fmpm's own measurements
   * (doc/studies/stability.md, "The Courant number limit of each method"),
   * the lower end of each measured bracket. Change them only together with
   * that document.
   */
  namespace Stability
  {
    /**
     * FMPM(k) with the FMPM update and full-mass strain velocities: the
     * vibrating bar's critical Courant number for k <= 10 (orders between
     * the measured 2, 3, 5, 10 take the next larger one: the limit falls
     * with k); -1 above 10.
     */
    double
    fmpm_order_limit(const unsigned int k, const bool averaged_strain_update);

    /**
     * FMPM(k) with the FMPM update and the series' velocities in a strain
     * update without re-extrapolation (USL-, USAVG-): the vibrating bar's
     * critical Courant number with @p shape, where it lies below
     * fmpm_order_limit() (uGIMP and cpGIMP far below: 0.30 for FMPM(5)
     * with USL-; b2spline with a padding layer below open knots with
     * USL-); infinity otherwise and for k > 10.
     */
    double
    shape_order_limit(const unsigned int        k,
                      const ShapeFunction::Type shape,
                      const bool                bspline_padding,
                      const StrainUpdateScheme &strain_update);

    /** The lumped mass matrix (and FMPM(1)): no limit but the user's
     * Courant number (at most 1). */
    StabilityLimit
    lumped_mass_matrix_limit();

    /** The lumped mass matrix's critical Courant number on the bar. */
    double
    lumped_limit(const bool averaged_strain_update);

    /** The leapfrog limit of FMPM(k) as a fraction of the lumped one. */
    double
    leapfrog_factor(const unsigned int k);

    /** Exact full mass matrix, full-mass strain velocities: the rigid
     * rotation completes at C = 0.08, 0.1 and 0.12 and fails at 0.15, the
     * colliding disks complete at 0.15, 0.2 and 0.25 and fail at 0.23 and
     * 0.3, the bar (USL-) completes at 0.4. */
    constexpr double full_limit = 0.12;

    /** Exact full (or FMPM(k)) matrix with lumped strain velocities: the
     * colliding disks complete at C = 0.4 and fail at 0.5, the rigid
     * rotation completes at 0.6, the bar at 0.8. */
    constexpr double lumped_strain_limit = 0.4;

    /** The consistent matrix with FLIP and USAVG+: 0.45-0.5 (0.4 in a run
     * with another build). */
    constexpr double consistent_limit = 0.4;

    /** Periodic FMPM(5) (FMPM update, USAVG+) on the vibrating bar of
     * parameters/nairn_bar.prm: period 5 stable at C = 0.3 and 0.35,
     * unstable at 0.4; periods 3 and 10 stable at 0.4, unstable at 0.5;
     * period 2 stable at 0.5. Switching the mass matrix between steps
     * changes each mode's frequency periodically (a parametric
     * resonance that neither matrix alone has). */
    constexpr double periodic_limit = 0.35;

    /** FMPM(k) of high order with full-mass strain velocities and shape
     * functions whose near-null modes the series amplifies by up to k
     * (classic; GIMP with USF/USL/USL+): the limit falls as 1/k. The rigid
     * rotation (classic): k = 32 stable at C = 0.065 and 0.08, unstable at
     * 0.1; k = 12, 16, 20, 24 stable at 0.12, unstable at 3.2/k; NairnMPM
     * fails it at the same Courant numbers (FMPM(16) at 0.2, FMPM(32) at
     * 0.2). uGIMP with USL-: k = 16 stable at 0.12, k = 32 at 0.08,
     * unstable at 0.15-0.5. The limit is this constant over k where that
     * is below the full matrix's (k > 21). */
    constexpr double high_order_constant = 2.56;

    /** FMPM(k) of high order with CPDI (any strain update) or GIMP with
     * USAVG/USAVG+: the limit falls as 1/sqrt(k), 1.18/sqrt(k) below every
     * stable measurement. The rigid rotation:
     * k = 12 stable at 0.35, 16 at 0.3 (unstable at 0.4 with uGIMP
     * USAVG+ and CPDI USL-), 32 at 0.212 (unstable at 0.3), 64 at 0.15
     * (unstable at 0.3); the 2026 disk impact (CPDI, USL-): k = 16 and 32
     * at 0.2, as NairnMPM. */
    constexpr double smooth_high_order_constant = 1.18;

    /** Whether the shape functions keep the series' near-null modes
     * weak enough for the 1/sqrt(k) limit. */
    bool
    smooth_for_high_orders(const StabilityMethod &method);

    /** "strain update 'usl' with the same mass matrix" (bases, warnings). */
    std::string
    strain_update_text(const StabilityMethod &method);

    /** "a FLIP-type update" or "a PIC-type update". */
    std::string
    update_text(const StabilityMethod &method);

    /**
     * What FMPM(k) and the exact full matrix (@p exact) share once @p limit
     * holds the matrix's own limit: lumped strain velocities are at least
     * as stable, FLIP-type updates have the leapfrog limit, and the known
     * failures (FLIP at free surfaces, large compression with psi > 0) are
     * warned of. @p name is the matrix in the basis text.
     */
    void
    limit_full_mass_method(StabilityLimit        &limit,
                           const StabilityMethod &method,
                           const std::string     &name,
                           const unsigned int     order,
                           const bool             exact);
  } // namespace Stability
} // namespace fmpm

#endif
