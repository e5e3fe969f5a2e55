// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_transfer_stress_update_forces_h
#define fmpm_transfer_stress_update_forces_h

#include <fmpm/external_loads.h>
#include <fmpm/grid_vectors.h>
#include <fmpm/material_points.h>
#include <fmpm/support_cache.h>
#include <fmpm/transfer/sinks.h>

#include <array>

namespace fmpm
{
  namespace Transfer
  {
    /** With @p active one force sink per material into its f^α0
     * (contact, Eq. 29; zeroed by @p contact), else none. */
    template <int dim, bool hoop, typename Manager>
    PerMaterial<ForceSink<dim, hoop>>
    material_force_sinks(const MaterialPoints<dim> &points,
                         ExternalLoads<dim>        &loads,
                         const SupportCache<dim>   &supports,
                         Manager *const             contact,
                         const bool                 active)
    {
      PerMaterial<ForceSink<dim, hoop>> sinks(supports.material.data());
      if (!active)
        return sinks;
      for (auto &material_field : contact->begin_forces())
        {
          double *f_alpha[dim];
          for (unsigned int d = 0; d < dim; ++d)
            f_alpha[d] = material_field.force.block(d).begin();
          sinks.sinks.emplace_back(points, loads, f_alpha);
          if constexpr (hoop)
            sinks.sinks.back().read_hoop_function(supports);
        }
      return sinks;
    }

    /** The force sinks of a stress update (USF/USAVG) and which one takes a
     * batch: f of the centre of mass (zeroed here), or with contact f^α0 of
     * the point's material (Eq. 29; zeroed by the manager), each with the
     * hoop force out of line when axisymmetric. */
    template <int dim>
    struct StressUpdateForces
    {
      template <typename Manager>
      StressUpdateForces(const MaterialPoints<dim> &points,
                         ExternalLoads<dim>        &loads,
                         const SupportCache<dim>   &supports,
                         GridVectorField           &centre_of_mass_force,
                         Manager *const             contact,
                         const bool                 with_forces,
                         const bool                 axisymmetric)
        : with_forces(with_forces)
        , contact(contact != nullptr)
        , axisymmetric(axisymmetric)
        , force(points, loads, block_pointers(centre_of_mass_force).data())
        , hoop_force(points, loads, block_pointers(centre_of_mass_force).data())
        , material_force(material_force_sinks<dim, false>(
            points,
            loads,
            supports,
            contact,
            with_forces && contact != nullptr && !axisymmetric))
        , material_hoop_force(
            material_force_sinks<dim, true>(points,
                                            loads,
                                            supports,
                                            contact,
                                            with_forces && contact != nullptr &&
                                              axisymmetric))
      {
        if (with_forces && contact == nullptr)
          centre_of_mass_force = 0;
        hoop_force.read_hoop_function(supports);
      }

      /** f of the points [batch_begin, batch_end) from their new stresses,
       * in the store's order. */
      template <typename Batch>
      void
      add(const Batch       &batch_supports,
          const unsigned int batch_begin,
          const unsigned int batch_end) const
      {
        if (!with_forces)
          return;
        if (contact && axisymmetric)
          batch_supports.add_points_out_of_line(batch_begin,
                                                batch_end,
                                                material_hoop_force);
        else if (contact)
          batch_supports.add_points(batch_begin, batch_end, material_force);
        else if (axisymmetric)
          batch_supports.add_points_out_of_line(batch_begin,
                                                batch_end,
                                                hoop_force);
        else
          batch_supports.add_points(batch_begin, batch_end, force);
      }

      static std::array<double *, dim>
      block_pointers(GridVectorField &f)
      {
        std::array<double *, dim> result;
        for (unsigned int d = 0; d < dim; ++d)
          result[d] = f.block(d).begin();
        return result;
      }

      const bool                              with_forces;
      const bool                              contact;
      const bool                              axisymmetric;
      const ForceSink<dim>                    force;
      ForceSink<dim, true>                    hoop_force;
      const PerMaterial<ForceSink<dim>>       material_force;
      const PerMaterial<ForceSink<dim, true>> material_hoop_force;
    };
  } // namespace Transfer
} // namespace fmpm

#endif
