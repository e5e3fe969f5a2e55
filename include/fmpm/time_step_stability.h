// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_time_step_stability_h
#define fmpm_time_step_stability_h

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
  };

  /**
   * @brief The stability factor of a method and what it rests on.
   */
  struct StabilityLimit
  {
    /**
     * The factor the automatic time step multiplies the Courant number
     * with: dt = C f h_min / (c + |v|max), so that 'Time/Courant number'
     * stays the fraction of the method's own limit. 1 for the lumped mass
     * matrix with any particle and strain update.
     */
    double factor = 1;
    /** Where the factor comes from (printed at start-up). */
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
   * @brief The stability factor of @p method from fmpm's own measurements
   * (doc/studies/stability.md and its section "The stability factor of the
   * automatic time step").
   *
   * The factor is the measured critical Courant number of the method over
   * that of the lumped mass matrix with the same strain update (capped at
   * 1, the nominal limit h_min / (c + |v|max)), from the lower end of each
   * measured bracket: a Courant number that is stable with the lumped mass
   * matrix stays stable with the method. Orders of FMPM(k) between the
   * measured ones (2, 3, 5, 10) take the next larger measured order (the
   * limit falls with k), orders above 10 the full matrix's.
   */
  StabilityLimit
  stability_limit(const StabilityMethod &method);
} // namespace fmpm

#endif
