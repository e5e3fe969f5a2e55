// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_contact_geometry_sink_h
#define fmpm_contact_geometry_sink_h

#include <deal.II/base/config.h>
#include <fmpm/contact/normals.h>
#include <fmpm/material_points.h>
#include <fmpm/particle_properties.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <vector>

namespace fmpm
{
  namespace Contact
  {
    template <int dim>
    struct MaterialField;

    /**
     * @brief What a point adds to the per-material fields the contact
     * normals and laws read: g^α = Σ V G and Σ S M X (seed 004 Eq. 11), and
     * for the interface laws u^α = Σ S M (x − X₀) and V^α = Σ S V. The
     * first extrapolation and the re-extrapolation in the particle update
     * add each point's share with the same operations, point() as a sink of
     * the point loop (Transfer::for_each_point()); Manager owns the sink and
     * its fields, zeroes and sums them and hands the sink out
     * (Manager::begin_extrapolation(), begin_re_extrapolation()).
     *
     * Axisymmetric (V per radian, V = A r_p): g^α weights each point by its
     * area A = V/r_p, so that the r-weighting of the volume does not tilt the
     * normals towards +r (the gradient of the r-weighted volume has the
     * component V/r in r inside a body, comparable at r ≈ h to the jump at
     * a surface).
     *
     * @tparam dim space dimension
     */
    template <int dim>
    class GeometrySink
    {
    public:
      /** Zero the fields of @p fields that @p normal_needs and
       * @p interface_state ask for (the others are left alone and not added
       * to), reading the points of @p material_points of materials
       * @p point_material (@p axisymmetric: the weights of g^α are the
       * areas V/r_p). */
      void
      reset(std::vector<MaterialField<dim>> &fields,
            const NormalNeeds               &normal_needs,
            const bool                       interface_state,
            const MaterialPoints<dim>       &material_points,
            const unsigned char *const       point_material,
            const bool                       axisymmetric);

      /** Add the ghosts of @p field's share of what reset() zeroed (after a
       * sweep of add_point()). */
      static void
      compress(MaterialField<dim> &field,
               const NormalNeeds  &normal_needs,
               const bool          interface_state);

      /** Whether add_point() reads G. */
      bool
      needs_gradients() const
      {
        return !gradient.empty();
      }

      /** Point @p k of material @p alpha with its support entries j <
       * @p n_entries: nodes @p node, S and G (G only if needs_gradients()).
       */
      template <typename Count>
      DEAL_II_ALWAYS_INLINE void
      add_point(const unsigned int          k,
                const unsigned int          alpha,
                const unsigned int *const   node,
                const double *const         S,
                const Tensor<1, dim> *const G,
                const Count                 n_entries) const
      {
        const double      M = mass[k];
        const double      V = volume[k];
        const Point<dim> &X = points->position[k];
        if (!gradient.empty())
          {
            const double w = gradient_weight[k];
            for (unsigned int j = 0; j < n_entries; ++j)
              for (unsigned int d = 0; d < dim; ++d)
                gradient[alpha * dim + d][node[j]] += w * G[j][d];
          }
        if (!position.empty())
          for (unsigned int j = 0; j < n_entries; ++j)
            for (unsigned int d = 0; d < dim; ++d)
              position[alpha * dim + d][node[j]] += M * S[j] * X[d];
        if (!displacement.empty())
          {
            // u_p = x_p − X_p (the initial position).
            for (unsigned int d = 0; d < dim; ++d)
              {
                const double u_d = X[d] - initial_position[d][k];
                for (unsigned int j = 0; j < n_entries; ++j)
                  displacement[alpha * dim + d][node[j]] += M * S[j] * u_d;
              }
            for (unsigned int j = 0; j < n_entries; ++j)
              nodal_volume[alpha][node[j]] += S[j] * V;
          }
      }

      /** The sink of the point loop: point @p k of its material. */
      template <typename Count>
      DEAL_II_ALWAYS_INLINE void
      point(const unsigned int          k,
            const unsigned int *const   node,
            const double *const         S,
            const Tensor<1, dim> *const G,
            const Count                 n_entries) const
      {
        add_point(k, material[k], node, S, G, n_entries);
      }

    private:
      const MaterialPoints<dim> *points   = nullptr;
      const unsigned char       *material = nullptr;
      const double              *mass = nullptr, *volume = nullptr;
      /** The weight of a point in g^α: V, or V/r_p axisymmetric. */
      const double       *gradient_weight = nullptr;
      std::vector<double> area;
      const double       *initial_position[dim] = {};
      /** [α dim + d] (nodal_volume: [α]); empty where nothing reads it. */
      std::vector<double *> gradient, position, displacement, nodal_volume;
    };
  } // namespace Contact
} // namespace fmpm

#endif
