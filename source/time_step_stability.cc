// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The Courant number limits of the automatic time step. Every number here is a
// measurement of doc/studies/stability.md (vibrating bar, 1D, and the
// shipped 2D scenes of its section "The Courant number limit of each
// method"); change them only together with that document.

#include <fmpm/time_step_stability.h>

#include <algorithm>
#include <cmath>

namespace fmpm
{
  namespace
  {
    /**
     * FMPM(k) with the FMPM update and full-mass strain velocities: the
     * measured critical Courant numbers of the vibrating bar (lower end of
     * each bracket). USAVG+: k = 2: 0.9, 3: 0.75, 5: 0.6, 10: 0.5 (lumped
     * > 1.2); USL-: k = 2: 0.6, 3: 0.55, 5 and 10: 0.5 (lumped 0.75).
     */
    double
    fmpm_order_limit(const unsigned int k, const bool averaged_strain_update)
    {
      struct Entry
      {
        unsigned int order;
        double       usavg, usl;
      };
      static const Entry table[] = {{2, 0.9, 0.6},
                                    {3, 0.75, 0.55},
                                    {5, 0.6, 0.5},
                                    {10, 0.5, 0.5}};
      for (const Entry &entry : table)
        if (k <= entry.order)
          return averaged_strain_update ? entry.usavg : entry.usl;
      return -1; // above 10: the full matrix
    }

    /** The lumped mass matrix's critical Courant number on the bar: above
     * 1.2 with USAVG/USAVG+ (1, the nominal limit, counts), 0.75 with the
     * other strain updates. */
    double
    lumped_limit(const bool averaged_strain_update)
    {
      return averaged_strain_update ? 1 : 0.75;
    }

    /**
     * The leapfrog limit of FMPM(k) with this particle mass matrix (2
     * points per cell: S^T M S is 1/4 of the lumped mass for the shortest
     * wave): 1 / sqrt(sum_{j<k} (3/4)^j) of the lumped limit, item 1 of
     * doc/studies/stability.md. FLIP-type updates lack the damping of the
     * FMPM update that lets it exceed this limit.
     */
    double
    leapfrog_factor(const unsigned int k)
    {
      double sum = 0;
      for (unsigned int j = 0; j < std::min(k, 200u); ++j)
        sum += std::pow(0.75, j);
      return 1 / std::sqrt(sum);
    }

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
    smooth_for_high_orders(const std::string &shape_function,
                           const bool         averaged_strain_update)
    {
      return shape_function == "cpdi" ||
             ((shape_function == "ugimp" || shape_function == "cpgimp") &&
              averaged_strain_update);
    }
  } // namespace



  StabilityLimit
  stability_limit(const StabilityMethod &method)
  {
    StabilityLimit     limit;
    const std::string &su       = method.strain_update;
    const bool         averaged = (su == "usavg" || su == "usavg+");
    const bool         full_mass_strain_velocities =
      method.strain_update_mass_matrix != "lumped";
    const std::string strain_text =
      "strain update '" + su + "' with " +
      (full_mass_strain_velocities ? "the same" : "lumped") + " mass matrix";
    const std::string update_text =
      method.flip_type ? "a FLIP-type update" : "a PIC-type update";

    if (method.mass_matrix == "lumped" ||
        (method.mass_matrix == "fmpm" && method.order <= 1))
      {
        limit.basis = "lumped mass matrix";
        return limit;
      }

    if (method.mass_matrix == "fmpm" || method.mass_matrix == "full")
      {
        const bool   full = method.mass_matrix == "full";
        const double k_limit =
          full ? -1 : fmpm_order_limit(method.order, averaged);
        const std::string name = full ?
                                   std::string("full mass matrix") :
                                   "FMPM(" + std::to_string(method.order) + ")";
        if (k_limit > 0)
          {
            limit.max_courant = k_limit;
            limit.basis       = name + ", " + strain_text +
                          ": the vibrating bar's measured critical Courant "
                          "number";
          }
        else if (!full && full_mass_strain_velocities &&
                 smooth_for_high_orders(method.shape_function, averaged))
          {
            limit.max_courant =
              std::min(fmpm_order_limit(10, averaged),
                       smooth_high_order_constant / std::sqrt(method.order));
            limit.basis = name + ", " + strain_text + ", shape function '" +
                          method.shape_function +
                          "': the rigid rotation is stable at C = "
                          "1.18/sqrt(k) (k = 12 to 64), unstable at 0.3 "
                          "(k = 32)";
          }
        else
          {
            limit.max_courant = full_limit;
            limit.basis       = name + ", " + strain_text +
                          ": the rigid rotation is stable at C = 0.12, "
                          "unstable at 0.15";
            if (!full && full_mass_strain_velocities &&
                high_order_constant / method.order < limit.max_courant)
              {
                limit.max_courant = high_order_constant / method.order;
                limit.basis =
                  name + ", " + strain_text +
                  ": the series amplifies near-null modes by up to k; "
                  "the rigid rotation is stable at C = 2.56/k (k = 32), "
                  "unstable at 3.2/k";
              }
          }
        if (!full && method.periodic && periodic_limit < limit.max_courant)
          {
            limit.max_courant = periodic_limit;
            limit.basis =
              "periodic " + name +
              ": the vibrating bar with period 5 is stable at C = 0.35, "
              "unstable at 0.4 (periods 3 and 10: at 0.5)";
          }
        // Lumped strain velocities are at least as stable as full-mass ones.
        if (!full_mass_strain_velocities &&
            limit.max_courant < lumped_strain_limit)
          {
            limit.max_courant = lumped_strain_limit;
            limit.basis       = name + ", " + strain_text +
                          ": colliding disks stable at C = 0.4, unstable "
                          "at 0.5";
          }
        if (method.flip_type && method.order > 1)
          {
            const double leapfrog =
              leapfrog_factor(method.order) * lumped_limit(averaged);
            if (leapfrog < limit.max_courant)
              {
                limit.max_courant = leapfrog;
                limit.basis       = name + " with " + update_text +
                              ": the leapfrog limit 1/sqrt(sum_{j<k} "
                              "(3/4)^j) of the lumped one for this particle "
                              "mass matrix";
              }
          }
        limit.warning_only_with_free_surfaces =
          method.flip_type && (full || method.order > 10);
        if (method.flip_type && (full || method.order > 10))
          limit.warning =
            "FLIP-type updates (V += S m~^-1 f dt) with the exact full "
            "mass matrix blow up at free surfaces at any time step (the "
            "rigid rotation fails at Courant numbers 0.1 and 0.05; doc/"
            "studies/stability.md). Use 'Particle update/Model name = fmpm' "
            "with the full mass matrix, or keep FLIP with 'Mass matrix/"
            "Model name = fmpm' of order 2 to 5 or 'lumped'.";
        // Large compression (doc/studies/stability.md, "Large compression"):
        // with Table 2.1's averaged position update FMPM(k)/XPIC(k) of k >= 3
        // and the exact solve blow up at any measured Courant number; psi = 0
        // is stable up to C = 1 there but less accurate for displacements.
        if (!method.flip_type && method.order >= 3 &&
            method.position_update_psi > 0)
          limit.note =
            "for large compression (tens of percent strain) set 'Position "
            "update psi = 0' in 'Particle update/Fmpm' (or '/Xpic'): with "
            "psi > 0 this method blew up in the quasi-static compression "
            "of doc/studies/stability.md (\"Large compression\") at every "
            "measured Courant number; psi = 1 is more accurate for "
            "displacements elsewhere.";
        return limit;
      }

    if (method.mass_matrix == "consistent")
      {
        limit.max_courant = consistent_limit;
        limit.basis       = "consistent mass matrix, " + strain_text +
                      ": FLIP on the vibrating bar stable up to C = 0.4";
        limit.warning =
          "the consistent finite element mass matrix amplifies a mode at "
          "free surfaces once material points move relative to the cells, "
          "at any time step (with " +
          update_text + " and strain update '" + su +
          "' the vibrating bar of doc/studies/stability.md is unstable at " +
          (method.flip_type && averaged ? "Courant numbers above 0.45 and " :
                                          "every Courant number and ") +
          "at large displacements); use it for small-displacement studies "
          "only, or choose 'Mass matrix/Model name = full' with the fmpm "
          "update or 'fmpm' (FMPM(k)).";
        return limit;
      }

    // A mass matrix without a measurement: no limit.
    limit.basis =
      "mass matrix '" + method.mass_matrix + "' (not measured: no limit)";
    return limit;
  }
} // namespace fmpm
