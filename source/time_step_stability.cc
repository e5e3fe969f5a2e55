// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The Courant number limits of the automatic time step. Every number here and
// in time_step_stability.h is a measurement of doc/studies/stability.md
// (vibrating bar, 1D, and the shipped 2D scenes of its section "The Courant
// number limit of each method"); change them only together with that
// document. The mass matrix plugins choose among them (stability_limit()).

#include <fmpm/time_step_stability.h>

#include <algorithm>
#include <cmath>

namespace fmpm
{
  namespace Stability
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



    StabilityLimit
    lumped_mass_matrix_limit()
    {
      StabilityLimit limit;
      limit.basis = "lumped mass matrix";
      return limit;
    }



    bool
    smooth_for_high_orders(const StabilityMethod &method)
    {
      using ShapeFunction::Type;
      return method.shape_function == Type::cpdi ||
             ((method.shape_function == Type::ugimp ||
               method.shape_function == Type::cpgimp) &&
              method.strain_update.average);
    }



    std::string
    strain_update_text(const StabilityMethod &method)
    {
      return "strain update '" + method.strain_update.name() + "' with " +
             (method.lumped_strain_velocities ? "lumped" : "the same") +
             " mass matrix";
    }



    std::string
    update_text(const StabilityMethod &method)
    {
      return method.flip_type ? "a FLIP-type update" : "a PIC-type update";
    }



    void
    limit_full_mass_method(StabilityLimit        &limit,
                           const StabilityMethod &method,
                           const std::string     &name,
                           const unsigned int     order,
                           const bool             exact)
    {
      const bool averaged = method.strain_update.average;
      // Lumped strain velocities are at least as stable as full-mass ones.
      if (method.lumped_strain_velocities &&
          limit.max_courant < lumped_strain_limit)
        {
          limit.max_courant = lumped_strain_limit;
          limit.basis       = name + ", " + strain_update_text(method) +
                        ": colliding disks stable at C = 0.4, unstable "
                        "at 0.5";
        }
      if (method.flip_type && order > 1)
        {
          const double leapfrog =
            leapfrog_factor(order) * lumped_limit(averaged);
          if (leapfrog < limit.max_courant)
            {
              limit.max_courant = leapfrog;
              limit.basis       = name + " with " + update_text(method) +
                            ": the leapfrog limit 1/sqrt(sum_{j<k} "
                            "(3/4)^j) of the lumped one for this particle "
                            "mass matrix";
            }
        }
      limit.warning_only_with_free_surfaces =
        method.flip_type && (exact || order > 10);
      if (method.flip_type && (exact || order > 10))
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
      if (!method.flip_type && order >= 3 && method.position_update_psi > 0)
        limit.note =
          "for large compression (tens of percent strain) set 'Position "
          "update psi = 0' in 'Particle update/Fmpm' (or '/Xpic'): with "
          "psi > 0 this method blew up in the quasi-static compression "
          "of doc/studies/stability.md (\"Large compression\") at every "
          "measured Courant number; psi = 1 is more accurate for "
          "displacements elsewhere.";
    }
  } // namespace Stability
} // namespace fmpm
