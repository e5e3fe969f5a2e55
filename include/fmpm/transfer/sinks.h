// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_transfer_sinks_h
#define fmpm_transfer_sinks_h

#include <deal.II/base/config.h>
#include <fmpm/external_loads.h>
#include <fmpm/material_points.h>
#include <fmpm/particle_properties.h>

#include <deal.II/base/tensor.h>

#include <vector>

namespace fmpm
{
  /**
   * @brief The sinks of the particle–grid passes: what one point adds to
   * grid vectors from its support entries j < n (node[j], S[j], G[j]).
   *
   * Each sink has point(k, node, S, G, n) (inlined, no virtual call); the
   * count n is an `unsigned int` for stored supports and a compile-time
   * constant for computed ones, so that S and G stay in registers. A sink
   * reads the store's columns through pointers taken once per pass.
   */
  namespace Transfer
  {
    using namespace dealii;

    /**
     * @brief m += M S (with @p with_mass) and p += (M V) S (Eq. 1.6,
     * m = SᵀM, p = SᵀMV), over the point's entries in entry order.
     */
    template <int dim, bool with_mass = true>
    struct MassMomentumSink
    {
      /** Targets @p m (unused without mass) and @p p[d] (raw views of the
       * ghosted grid vectors); M and V from @p points. */
      MassMomentumSink(const MaterialPoints<dim> &points,
                       double *const              m,
                       double *const *const       p)
        : mass(points.column(PropertyIndex<dim>::mass))
        , m(m)
      {
        for (unsigned int d = 0; d < dim; ++d)
          {
            velocity[d] = points.column(PropertyIndex<dim>::velocity + d);
            this->p[d]  = p[d];
          }
      }

      template <typename Count>
      DEAL_II_ALWAYS_INLINE void
      point(const unsigned int        k,
            const unsigned int *const node,
            const double *const       S,
            const Tensor<1, dim> *,
            const Count n) const
      {
        const double M = mass[k];
        double       MV[dim];
        for (unsigned int d = 0; d < dim; ++d)
          MV[d] = M * velocity[d][k];
        for (unsigned int j = 0; j < n; ++j)
          {
            const unsigned int i = node[j];
            if constexpr (with_mass)
              m[i] += M * S[j];
            for (unsigned int d = 0; d < dim; ++d)
              p[d][i] += MV[d] * S[j];
          }
      }

      const double *mass;
      const double *velocity[dim];
      double       *m;
      double       *p[dim];
    };

    /**
     * @brief The nodal force (Eq. 2.11): f_a += M S b_a − V Σ_c σ_ac G_c
     * with the point's body acceleration b (tractions included; g unless
     * the loads depend on the point). Without b the body term is left out
     * (the same bits, M S ≥ 0).
     */
    template <int dim>
    struct ForceSink
    {
      /** Targets @p f[d]; M, V and σ from @p points; b from @p loads. */
      ForceSink(const MaterialPoints<dim> &points,
                ExternalLoads<dim>        &loads,
                double *const *const       f)
        : points(&points)
        , loads(&loads)
        , mass(points.column(PropertyIndex<dim>::mass))
        , volume(points.column(PropertyIndex<dim>::volume))
        , gravity(loads.gravity())
        , uniform_body_force(!loads.has_point_body_force())
      {
        for (unsigned int c = 0; c < 6; ++c)
          stress[c] = points.column(PropertyIndex<dim>::stress + c);
        for (unsigned int d = 0; d < dim; ++d)
          this->f[d] = f[d];
      }

      template <typename Count>
      DEAL_II_ALWAYS_INLINE void
      point(const unsigned int          k,
            const unsigned int *const   node,
            const double *const         S,
            const Tensor<1, dim> *const G,
            const Count                 n) const
      {
        const double M = mass[k];
        const double V = volume[k];
        // The dim x dim block of σ from the six stress columns.
        double sigma[dim][dim];
        for (unsigned int c = 0; c < 6; ++c)
          if (stress_component_i[c] < dim && stress_component_j[c] < dim)
            sigma[stress_component_i[c]][stress_component_j[c]] =
              sigma[stress_component_j[c]][stress_component_i[c]] =
                stress[c][k];
        const Tensor<1, dim> b =
          uniform_body_force ? gravity : loads->acceleration(*points, k);
        if (b.norm_square() == 0)
          for (unsigned int j = 0; j < n; ++j)
            for (unsigned int a = 0; a < dim; ++a)
              {
                double f_a = 0.;
                for (unsigned int c = 0; c < dim; ++c)
                  f_a -= V * sigma[a][c] * G[j][c];
                f[a][node[j]] += f_a;
              }
        else
          for (unsigned int j = 0; j < n; ++j)
            for (unsigned int a = 0; a < dim; ++a)
              {
                double f_a = M * S[j] * b[a];
                for (unsigned int c = 0; c < dim; ++c)
                  f_a -= V * sigma[a][c] * G[j][c];
                f[a][node[j]] += f_a;
              }
      }

      const MaterialPoints<dim> *points;
      ExternalLoads<dim>        *loads;
      const double              *mass, *volume, *stress[6];
      Tensor<1, dim>             gravity;
      bool                       uniform_body_force;
      double                    *f[dim];
    };

    /**
     * @brief Routes a point to the sink of its material α (contact: m^α,
     * p^α, f^α of seed 004 Eqs. 5, 29); one sink per material, made once
     * per pass.
     */
    template <typename Sink>
    struct PerMaterial
    {
      /** @p material: each point's material index (SupportCache). */
      explicit PerMaterial(const unsigned char *const material)
        : material(material)
      {}

      template <typename Count, int dim>
      DEAL_II_ALWAYS_INLINE void
      point(const unsigned int          k,
            const unsigned int *const   node,
            const double *const         S,
            const Tensor<1, dim> *const G,
            const Count                 n) const
      {
        sinks[material[k]].point(k, node, S, G, n);
      }

      const unsigned char *material;
      std::vector<Sink>    sinks;
    };
  } // namespace Transfer
} // namespace fmpm

#endif
