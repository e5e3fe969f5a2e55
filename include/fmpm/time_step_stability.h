// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_time_step_stability_h
#define fmpm_time_step_stability_h

#include <limits>
#include <string>

namespace fmpm
{
  /**
   * @brief The MPM method as far as its stable time step depends on it.
   */
  struct StabilityMethod
  {
    /** The 'Mass matrix/Model name': lumped, fmpm, full or consistent. */
    std::string mass_matrix = "lumped";
    /** The order k of FMPM(k) (MassMatrix::Interface::order()). */
    unsigned int order = 1;
    /** Whether the particle update adds the grid acceleration m̃ₖ⁻¹ f to
     * the point velocity (FLIP-type: flip, fmpm0, flip midpoint, flip end
     * velocity) instead of resetting it from the grid (PIC-type: fmpm,
     * pic, xpic, ...). */
    bool flip_type = false;
    /** 'Time/Strain update': usf, usl, usl+, usavg, usavg+. */
    std::string strain_update = "usavg+";
    /** 'Time/Strain update mass matrix': same or lumped. */
    std::string strain_update_mass_matrix = "same";
    /** psi of seed 000 Eq. 2.28 in the FMPM/XPIC position update
     * ('Particle update/Fmpm|Xpic/Position update psi'); 0 for the other
     * updates. */
    double position_update_psi = 0;
    /** 'Shape function/Type': classic, ugimp, cpgimp or cpdi. */
    std::string shape_function = "classic";
    /** Periodic FMPM(k): the series only in some steps, the lumped mass
     * matrix in the others ('Mass matrix/Fmpm/Period', 'Period time'). */
    bool periodic = false;
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
   * @brief The critical Courant number of @p method from fmpm's own
   * measurements (doc/studies/stability.md, "The Courant number limit of
   * each method"): the lower end of each measured bracket. Orders of
   * FMPM(k) between the measured ones (2, 3, 5, 10) take the next larger
   * measured order (the limit falls with k).
   */
  StabilityLimit
  stability_limit(const StabilityMethod &method);
} // namespace fmpm

#endif
