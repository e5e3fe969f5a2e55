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
#include <limits>

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


    double
    shape_order_limit(const unsigned int        k,
                      const ShapeFunction::Type shape,
                      const bool                bspline_padding,
                      const StrainUpdateScheme &strain_update)
    {
      // The vibrating bar of parameters/vibrating_bar.prm, 32 cells, 2
      // points per cell, v0 = 1e-3, 20 periods, unstable = the energy
      // doubled or drifted by more than 1 % (doc/studies/stability.md,
      // "Shape functions and strain updates"): the lower end of each
      // bracket (width 0.012) to two decimals. USF, USL+ and USAVG+ were at
      // or above fmpm_order_limit() with every shape function.
      if (strain_update.re_extrapolate || !strain_update.update_last || k <= 1)
        return std::numeric_limits<double>::infinity();
      struct Entry
      {
        ShapeFunction::Type shape;
        double              usl[4], usavg[4]; // k = 2, 3, 5, 10
      };
      using ShapeFunction::Type;
      static const Entry table[] = {
        {Type::classic, {0.64, 0.58, 0.53, 0.50}, {0.76, 0.65, 0.57, 0.51}},
        {Type::cpdi, {0.64, 0.58, 0.53, 0.50}, {0.76, 0.65, 0.57, 0.51}},
        {Type::ugimp, {0.44, 0.37, 0.30, 0.22}, {0.59, 0.49, 0.39, 0.29}},
        {Type::cpgimp, {0.44, 0.37, 0.30, 0.22}, {0.59, 0.49, 0.39, 0.29}},
        {Type::b2spline, {0.67, 0.58, 0.46, 0.35}, {0.89, 0.74, 0.60, 0.46}},
        {Type::b2gimp, {0.76, 0.65, 0.55, 0.42}, {0.97, 0.83, 0.67, 0.53}},
        {Type::b2cpdi, {0.85, 0.74, 0.64, 0.52}, {0.99, 0.91, 0.76, 0.60}},
        {Type::b3spline, {0.89, 0.76, 0.64, 0.52}, {0.99, 0.92, 0.78, 0.62}}};
      static const unsigned int orders[4] = {2, 3, 5, 10};
      // b2spline with a padding layer (parameters/vibrating_bar_b2spline_
      // padding.prm): USL- 0.46 for k = 2 and 5 (0.58 for k = 3: the limit
      // is taken not to rise with k), 0.35 for k = 10; USAVG- as open knots.
      if (bspline_padding && shape == Type::b2spline && !strain_update.average)
        return k <= 5 ? 0.46 : 0.35;
      for (const Entry &entry : table)
        if (entry.shape == shape)
          for (unsigned int j = 0; j < 4; ++j)
            if (k <= orders[j])
              return strain_update.average ? entry.usavg[j] : entry.usl[j];
      return std::numeric_limits<double>::infinity();
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
