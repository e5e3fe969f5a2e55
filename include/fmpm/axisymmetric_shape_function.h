// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_axisymmetric_shape_function_h
#define fmpm_axisymmetric_shape_function_h

#include <fmpm/grid_transfer.h>
#include <fmpm/shape_function.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/tria_base.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace fmpm
{
  namespace ShapeFunction
  {
    /**
     * @brief The axisymmetric shape functions (Nairn and Guilkey, IJNME 101
     * (2015) 127–147; NairnMPM's GIMP_Theory, Eqs. 5.5, 5.8, 5.9) in the r–z
     * plane, x_0 = r, x_1 = z:
     *
     *   S_ip = 1/(A_p⟨r_p⟩) ∫_Ωp N_i r dA,   G_ip = 1/(A_p⟨r_p⟩) ∫_Ωp ∇N_i r
     * dA, T_ip = 1/(A_p⟨r_p⟩) ∫_Ωp N_i dA     (the r-weighted mean of N_i/r),
     *
     * with A_p⟨r_p⟩ = ∫_Ωp r dA; the point's mass per radian is
     * m_p = ρ A_p⟨r_p⟩. The hoop strain rate is L_θθ = Σ_i v_r,i T_ip and the
     * hoop force −V_p τ_θθ T_ip acts on the radial component (Eq. 5.13).
     *
     * - classic: S = N_i(x_p), G = ∇N_i(x_p), T = N_i(x_p)/r_p (r_p > 0).
     * - ugimp, cpgimp: the box x_p ± l (l as ShapeFunction's GIMP) is cut at
     *   the axis: Ω_p = [max(r_p − l_r, 0), r_p + l_r] × [z_p ± l_z], the
     *   averages over the part at r ≥ 0 (as NairnMPM). On a uniform patch
     *   the box is a product, so S, G, T are products of exact 1D integrals
     *   (gimp_radial(), and gimp_1d() in z); on other axis-aligned cells
     *   (refined meshes, hanging nodes) a Gauss rule on the box's pieces in
     *   the cells of the patch, exact (N_i r is quadratic in r, linear in z
     *   on a cell).
     * - cpdi: N_i interpolated from the corners x_α = x_p + s r_α of the
     *   parallelogram s = F diag(l⁰) by its bilinear functions M_α; the
     *   r-weighted integrals of M_α give per corner (r_α ∈ {±1}²)
     *     S: w_α = 1/4 + (s r_α)_r / (12 r_p),   T: 1/(4 r_p),
     *     G: g_α = s⁻ᵀ (r_α,0 (r_p + r_α,1 s_01/3), r_α,1 (r_p + r_α,0 s_00/3))
     *            / (4 r_p),
     *   and S_ip = Σ_α w_α N_i(x_α) etc. A domain whose lowest corner would
     *   lie at r < 0 is shrunk about x_p (s scaled) until it touches the axis
     *   (as NairnMPM).
     *
     * Nodes at r < 0 are dropped: with Ω_p at r ≥ 0 their weights vanish.
     * The identities a correct implementation satisfies (the unit tests):
     * Σ_i S_ip = 1, Σ_i S_ip x_i = ∫ x r dA / ∫ r dA (the r-weighted
     * centroid; r_p + l_r²/(3 r_p) for an uncut box), Σ_i G_ip = 0,
     * Σ_i G_ip ⊗ x_i = I, Σ_i T_ip r_i = 1, Σ_i T_ip = ∫ dA / ∫ r dA.
     */
    namespace Axisymmetric
    {
      using namespace dealii;

      /** One node of a point's support: S_ip, G_ip and T_ip. */
      struct Node
      {
        /** Index into the ghosted grid vectors. */
        unsigned int local_index;
        /** Global DoF (for constraints and the full mass matrix). */
        types::global_dof_index dof;
        bool                    constrained;
        double                  S;
        Tensor<1, 2>            G;
        double                  T;
      };

      enum class Status
      {
        ok,
        /** The domain reaches beyond the cells around the point's cell. */
        beyond_neighbors,
        /** The domain reaches outside the mesh by more than half a cell. */
        outside_mesh,
        /** The point (classic, cpdi) or its whole domain (GIMP) lies at
         * r ≤ 0: no hoop term. */
        on_axis,
        /** GIMP over a cell that is not an axis-aligned box. */
        needs_axis_aligned_cells
      };

      /** The radial factors of one node: S^r, G^r = ∂S/∂r part, T^r. */
      struct RadialWeights
      {
        double S = 0, G = 0, T = 0;
      };

      /**
       * @brief The r-weighted 1D integrals of the hat function N_i of the
       * node at @p r_node (spacing @p h) over the GIMP domain
       * [r_p − l, r_p + l] cut at r = 0, [a, b] (b > 0):
       * S = ∫N r dr / ∫r dr, G = ∫N' r dr / ∫r dr, T = ∫N dr / ∫r dr.
       * Exact: N is linear on [r_i − h, r_i] and [r_i, r_i + h], each piece
       * integrated in closed form about the domain's centre c (u = r − c,
       * so that the sums stay of the size of the domain far from the
       * axis).
       */
      inline RadialWeights
      gimp_radial(const double r_p,
                  const double r_node,
                  const double h,
                  const double l)
      {
        RadialWeights w;
        const double  a = std::max(r_p - l, 0.0), b = r_p + l;
        if (!(b > a))
          return w;
        const double c = 0.5 * (a + b), half = 0.5 * (b - a);
        // ∫_a^b r dr = 2 c half.
        const double inverse_r_area = 1 / (2 * c * half);
        double       I0 = 0, I1 = 0, J1 = 0;
        for (int side = -1; side <= 1; side += 2)
          {
            // The piece between r_i and r_i + side h, in u = r − c.
            const double lo = std::max(side < 0 ? r_node - h : r_node, a) - c;
            const double hi = std::min(side < 0 ? r_node : r_node + h, b) - c;
            if (!(hi > lo))
              continue;
            // N = α + β u on the piece.
            const double beta  = side < 0 ? 1 / h : -1 / h;
            const double alpha = 1 + beta * (c - r_node);
            const double d1 = hi - lo, d2 = hi * hi - lo * lo,
                         d3       = hi * hi * hi - lo * lo * lo;
            const double integral = alpha * d1 + beta * d2 * 0.5;
            I0 += integral;
            I1 += c * integral + alpha * d2 * 0.5 + beta * d3 / 3;
            J1 += beta * (c * d1 + d2 * 0.5);
          }
        w.S = I1 * inverse_r_area;
        w.G = J1 * inverse_r_area;
        w.T = I0 * inverse_r_area;
        return w;
      }

      /** @brief The classic radial factors: N(r_p), N'(r_p), N(r_p)/r_p
       * (the limit of gimp_radial() as l → 0; r_p > 0). */
      inline RadialWeights
      classic_radial(const double r_p, const double r_node, const double h)
      {
        RadialWeights w;
        const double  u = r_p - r_node;
        if (u <= -h || u >= h)
          return w;
        w.S = 1 - std::abs(u) / h;
        w.G = u < 0 ? 1 / h : -1 / h;
        w.T = w.S / r_p;
        return w;
      }

      /**
       * @brief The CPDI corner weights of the parallelogram s about a point
       * at radius @p r_p (see the namespace): @p w (S), @p g (G) and
       * @p t (T) of corner α = r_0 + 2 r_1 bits (r_d = −1 for a clear bit,
       * +1 for a set one), the order of compute_support()'s corners.
       */
      DEAL_II_ALWAYS_INLINE inline void
      cpdi_corner_weights(const double                 r_p,
                          const Tensor<2, 2>          &s,
                          std::array<double, 4>       &w,
                          std::array<Tensor<1, 2>, 4> &g,
                          double                      &t)
      {
        const Tensor<2, 2> s_inverse_transpose = transpose(invert(s));
        t                                      = 0.25 / r_p;
        for (unsigned int alpha = 0; alpha < 4; ++alpha)
          {
            const double r0 = (alpha & 1) ? 1. : -1.;
            const double r1 = (alpha & 2) ? 1. : -1.;
            w[alpha]        = 0.25 + (s[0][0] * r0 + s[0][1] * r1) / (12 * r_p);
            Tensor<1, 2> reference;
            reference[0] = r0 * (r_p + r1 * s[0][1] / 3);
            reference[1] = r1 * (r_p + r0 * s[0][0] / 3);
            g[alpha]     = (s_inverse_transpose * reference) * t;
          }
      }

      /**
       * @brief Shrinks the CPDI domain s about the point so that no corner
       * lies at r < 0: s scaled by r_p / Σ_j |s_0j| when that is below 1.
       * @return whether s was changed
       */
      DEAL_II_ALWAYS_INLINE inline bool
      keep_cpdi_domain_off_axis(const double r_p, Tensor<2, 2> &s)
      {
        const double reach = std::abs(s[0][0]) + std::abs(s[0][1]);
        if (reach <= r_p)
          return false;
        s *= r_p / reach;
        return true;
      }

      /**
       * @brief The closed forms around one locally owned cell whose patch is
       * uniform (GridTransfer's CellData::uniform_patch), as
       * ShapeFunction::UniformGimpPatch: S_ip = S^r_i S^z_i,
       * G_ip = (G^r_i S^z_i, S^r_i G^z_i), T_ip = T^r_i S^z_i with the radial
       * factors of gimp_radial() and seed 001's gimp_1d() in z. Built once
       * per cell, read by each of its points.
       */
      class UniformGimpPatch : private UniformPatchPlanes<2>
      {
      public:
        using UniformPatchPlanes<2>::reinit;

        /** @brief The planes and nodes of the cell's patch from those
         * built for it before (ShapeFunction::UniformGimpPatch::planes(),
         * kept across steps). */
        void
        reinit(const UniformPatchPlanes<2> &planes)
        {
          UniformPatchPlanes<2>::operator=(planes);
        }

        /**
         * @brief If the closed forms hold for a point at @p x with
         * half-lengths @p l (x in the cell, l ≤ h/2, r_p + l_r > 0, and
         * the cut box overlaps only cells of the patch), call
         * @p sink(local index, DoF, S, G, T) for every node at r ≥ 0 of
         * the patch cells the cut box overlaps where S, G or T is not zero.
         * @return whether they hold (else nothing is called)
         */
        template <typename Sink>
        DEAL_II_ALWAYS_INLINE bool
        for_each_node_if_applies(const Point<2>     &x,
                                 const Tensor<1, 2> &l,
                                 Sink              &&sink) const
        {
          unsigned int first[2], last[2];
          if (!columns_if_applies(x, l, first, last))
            return false;
          RadialWeights radial[4];
          double        z_value[4], z_gradient[4];
          for (unsigned int p = first[0]; p <= last[0]; ++p)
            radial[p] = gimp_radial(x[0], plane[0][p], h[0], l[0]);
          for (unsigned int p = first[1]; p <= last[1]; ++p)
            gimp_1d(x[1] - plane[1][p], h[1], l[1], z_value[p], z_gradient[p]);
          for (unsigned int p1 = first[1]; p1 <= last[1]; ++p1)
            for (unsigned int p0 = first[0]; p0 <= last[0]; ++p0)
              {
                // Nodes at r < 0 are dropped.
                if (plane[0][p0] < -0.5 * h[0])
                  continue;
                const double S = radial[p0].S * z_value[p1];
                const double T = radial[p0].T * z_value[p1];
                Tensor<1, 2> G;
                G[0] = radial[p0].G * z_value[p1];
                G[1] = radial[p0].S * z_gradient[p1];
                if (S != 0 || T != 0 || G.norm_square() != 0)
                  {
                    const unsigned int slot = p0 + 4 * p1;
                    sink(local_index[slot], dof[slot], S, G, T);
                  }
              }
          return true;
        }

      private:
        /** The columns the cut box overlaps per direction, [first, last),
         * and whether the closed forms apply. */
        bool
        columns_if_applies(const Point<2>     &x,
                           const Tensor<1, 2> &l,
                           unsigned int (&first)[2],
                           unsigned int (&last)[2]) const;
      };

      /**
       * @brief The axisymmetric support of one point (see the namespace):
       * classic on any cell, cpdi on any mesh (corners located with
       * GridTransfer::locate()), ugimp and cpgimp on axis-aligned cells
       * (the closed forms on uniform patches unless @p allow_closed_form is
       * false).
       *
       * @param type the shape function
       * @param transfer the grid's transfer data
       * @param cell active cell index of the point's (locally owned) cell
       * @param x the point's position (r, z)
       * @param F the deformation gradient's r–z block
       * @param l0 the initial half-lengths
       * @param support the nodes, written here
       * @param allow_closed_form GIMP: the closed forms on uniform patches
       *        (false: always the quadrature, for tests)
       */
      Status
      compute_support(const Type             type,
                      const GridTransfer<2> &transfer,
                      const unsigned int     cell,
                      const Point<2>        &x,
                      const Tensor<2, 2>    &F,
                      const Tensor<1, 2>    &l0,
                      std::vector<Node>     &support,
                      const bool             allow_closed_form = true);

      /**
       * @brief The mesh rule of axisymmetric analysis: no vertex at r < 0
       * (the mesh starts at r = 0, the axis on a grid line, or beyond it).
       * Throws an error that names @p where (the parameter that set the
       * geometry) and the smallest r found (over all MPI ranks).
       */
      void
      check_mesh(const parallel::TriangulationBase<2> &triangulation,
                 const std::string                    &where);
    } // namespace Axisymmetric
  }   // namespace ShapeFunction
} // namespace fmpm

#endif
