// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_transfer_kinematics_h
#define fmpm_transfer_kinematics_h

#include <deal.II/base/config.h>
#include <fmpm/constitutive_model/interface.h>
#include <fmpm/parameters.h>

#include <deal.II/base/tensor.h>

#include <array>
#include <type_traits>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The kinematics of a batch of points in the strain update: the
   * velocity gradient L = Σ_j v_j ⊗ G_pj gathered from the grid (Eq. 2.7),
   * the increment ΔF and F^{n+1} = ΔF F^n with J = det F^{n+1} (seed 001),
   * and the gather v_p = Σ_j S_pj v_j of the particle update. The per-point
   * and per-batch kernels are inline: the passes call them in their loops.
   */
  namespace Kinematics
  {
    /** The entries c = 3a + b of a 3x3 tensor of each point q of a batch,
     * at [c][q] (the constitutive models' batch layout). */
    using BatchEntries =
      double[9][ConstitutiveModel::StressUpdateInputs::capacity];

    /**
     * ΔF with F^{n+1} = ΔF F^n for the velocity gradients L (entry (a, b)
     * of point q at L[3a + b][q]) over Δt, ΔF ≈ exp(L Δt) for L constant
     * over the step (seed 001, computeDeformationGradientFromVelocity). The
     * method is chosen once for the batch. In 2D (plane strain) L and ΔF
     * live in the 2x2 block (ΔF_33 = 1): only that block is computed.
     * First order is written entry by entry (one loop over the points that
     * vectorizes); Cayley is cayley_update(), with F^{n+1} and J.
     *
     * @tparam n the dimension of the block (2 or 3)
     */
    template <int n>
    void
    increments(const DeformationGradientUpdate update,
               const MethodParameters         &method,
               const BatchEntries             &L,
               const double                    dt,
               const unsigned int              n_points,
               BatchEntries                   &dF);

    /**
     * The 2D Cayley update of @p n points: ΔF = (I − LΔt/2)⁻¹(I + LΔt/2)
     * (seed 001; 2x2 inverse by cofactors), F^{n+1} = ΔF F^n on the 2x2
     * block and
     * J = F_xx^{n+1} (F_yy^{n+1} F_33) − F_xy^{n+1} (F_yx^{n+1} F_33). The
     * restrict-qualified parameters and, for full batches, the constant
     * count let GCC vectorize the loop at -O2.
     */
    template <typename Count>
    inline void
    plane_strain_cayley_update(const Count  n,
                               const double dt,
                               const double *__restrict L_xx,
                               const double *__restrict L_xy,
                               const double *__restrict L_yx,
                               const double *__restrict L_yy,
                               const double *__restrict F_xx_old,
                               const double *__restrict F_xy_old,
                               const double *__restrict F_yx_old,
                               const double *__restrict F_yy_old,
                               const double *__restrict F_zz,
                               double *__restrict F_xx,
                               double *__restrict F_xy,
                               double *__restrict F_yx,
                               double *__restrict F_yy,
                               double *__restrict F_zz_new,
                               double *__restrict J)
    {
      for (unsigned int q = 0; q < n; ++q)
        {
          // ΔF = (I − L Δt/2)⁻¹ (I + L Δt/2) = R B.
          const double h_xx = 0.5 * (L_xx[q] * dt), h_xy = 0.5 * (L_xy[q] * dt),
                       h_yx = 0.5 * (L_yx[q] * dt), h_yy = 0.5 * (L_yy[q] * dt);
          const double A_xx = 1.0 - h_xx, A_xy = 0.0 - h_xy, A_yx = 0.0 - h_yx,
                       A_yy = 1.0 - h_yy;
          const double B_xx = 1.0 + h_xx, B_xy = 0.0 + h_xy, B_yx = 0.0 + h_yx,
                       B_yy                = 1.0 + h_yy;
          const double inverse_determinant = 1.0 / (A_xx * A_yy - A_yx * A_xy);
          const double R_xx                = A_yy * inverse_determinant,
                       R_xy                = -A_xy * inverse_determinant,
                       R_yx                = -A_yx * inverse_determinant,
                       R_yy                = A_xx * inverse_determinant;
          const double dF_xx               = R_xx * B_xx + R_xy * B_yx,
                       dF_xy               = R_xx * B_xy + R_xy * B_yy,
                       dF_yx               = R_yx * B_xx + R_yy * B_yx,
                       dF_yy               = R_yx * B_xy + R_yy * B_yy;
          const double a = F_xx_old[q], b = F_xy_old[q], c = F_yx_old[q],
                       e  = F_yy_old[q];
          const double xx = dF_xx * a + dF_xy * c, xy = dF_xx * b + dF_xy * e,
                       yx = dF_yx * a + dF_yy * c, yy = dF_yx * b + dF_yy * e;
          F_xx[q]     = xx;
          F_xy[q]     = xy;
          F_yx[q]     = yx;
          F_yy[q]     = yy;
          F_zz_new[q] = F_zz[q];
          J[q]        = xx * (yy * F_zz[q]) - xy * (yx * F_zz[q]);
        }
    }

    /**
     * The 3D Cayley update of @p n points: ΔF = (I − LΔt/2)⁻¹(I + LΔt/2)
     * (3x3 inverse by cofactors), F^{n+1} = ΔF F^n and J = det F^{n+1}
     * (deal.II's determinant()). @p L and @p F are batch entry blocks
     * (entry c of point q at [c capacity + q]); @p F_old one array per
     * entry. Restrict-qualified, with a constant
     * count for full batches, so that GCC vectorizes it at -O2.
     */
    template <typename Count>
    inline void
    cayley_update_3d(const Count  n,
                     const double dt,
                     const double *__restrict L,
                     const std::array<const double *, 9> &F_old,
                     double *__restrict F,
                     double *__restrict J)
    {
      constexpr unsigned int stride =
        ConstitutiveModel::StressUpdateInputs::capacity;
      const double *__restrict F0 = F_old[0];
      const double *__restrict F1 = F_old[1];
      const double *__restrict F2 = F_old[2];
      const double *__restrict F3 = F_old[3];
      const double *__restrict F4 = F_old[4];
      const double *__restrict F5 = F_old[5];
      const double *__restrict F6 = F_old[6];
      const double *__restrict F7 = F_old[7];
      const double *__restrict F8 = F_old[8];
      for (unsigned int q = 0; q < n; ++q)
        {
          double A[3][3], B[3][3], R[3][3], dF[3][3];
#pragma GCC unroll 9
          for (unsigned int a = 0; a < 3; ++a)
#pragma GCC unroll 3
            for (unsigned int b = 0; b < 3; ++b)
              {
                const double half = 0.5 * (L[(3 * a + b) * stride + q] * dt);
                const double I_ab = a == b ? 1.0 : 0.0;
                A[a][b]           = I_ab - half;
                B[a][b]           = I_ab + half;
              }
          R[0][0] = A[1][1] * A[2][2] - A[1][2] * A[2][1];
          R[0][1] = A[0][2] * A[2][1] - A[0][1] * A[2][2];
          R[0][2] = A[0][1] * A[1][2] - A[0][2] * A[1][1];
          R[1][0] = A[1][2] * A[2][0] - A[1][0] * A[2][2];
          R[1][1] = A[0][0] * A[2][2] - A[0][2] * A[2][0];
          R[1][2] = A[0][2] * A[1][0] - A[0][0] * A[1][2];
          R[2][0] = A[1][0] * A[2][1] - A[1][1] * A[2][0];
          R[2][1] = A[0][1] * A[2][0] - A[0][0] * A[2][1];
          R[2][2] = A[0][0] * A[1][1] - A[0][1] * A[1][0];
          const double inverse_determinant =
            1.0 / (A[0][0] * R[0][0] + A[0][1] * R[1][0] + A[0][2] * R[2][0]);
#pragma GCC unroll 9
          for (unsigned int a = 0; a < 3; ++a)
#pragma GCC unroll 3
            for (unsigned int b = 0; b < 3; ++b)
              R[a][b] *= inverse_determinant;
#pragma GCC unroll 9
          for (unsigned int a = 0; a < 3; ++a)
#pragma GCC unroll 3
            for (unsigned int b = 0; b < 3; ++b)
              {
                double sum = R[a][0] * B[0][b];
                sum += R[a][1] * B[1][b];
                sum += R[a][2] * B[2][b];
                dF[a][b] = sum;
              }
          const double old[9] = {
            F0[q], F1[q], F2[q], F3[q], F4[q], F5[q], F6[q], F7[q], F8[q]};
          double G[9];
#pragma GCC unroll 9
          for (unsigned int a = 0; a < 3; ++a)
#pragma GCC unroll 3
            for (unsigned int b = 0; b < 3; ++b)
              G[3 * a + b] = dF[a][0] * old[b] + dF[a][1] * old[3 + b] +
                             dF[a][2] * old[6 + b];
#pragma GCC unroll 9
          for (unsigned int c = 0; c < 9; ++c)
            F[c * stride + q] = G[c];
          const double C0 = G[4] * G[8] - G[5] * G[7];
          const double C1 = G[5] * G[6] - G[3] * G[8];
          const double C2 = G[3] * G[7] - G[4] * G[6];
          J[q]            = G[0] * C0 + G[1] * C1 + G[2] * C2;
        }
    }

    /**
     * The Cayley update of a batch of @p n_points: ΔF, F^{n+1} = ΔF F^n and
     * J into @p F and @p J from the velocity gradients @p L and F^n at
     * @p F_old (one array per entry, the batch's points one after another),
     * with a constant count for a full batch.
     */
    template <int dim>
    inline void
    cayley_update(const unsigned int                   n_points,
                  const double                         dt,
                  const BatchEntries                  &L,
                  const std::array<const double *, 9> &F_old,
                  BatchEntries                        &F,
                  double                              *J)
    {
      auto update = [&](const auto count) {
        if constexpr (dim == 2)
          plane_strain_cayley_update(count,
                                     dt,
                                     L[0],
                                     L[1],
                                     L[3],
                                     L[4],
                                     F_old[0],
                                     F_old[1],
                                     F_old[3],
                                     F_old[4],
                                     F_old[8],
                                     F[0],
                                     F[1],
                                     F[3],
                                     F[4],
                                     F[8],
                                     J);
        else
          cayley_update_3d(count, dt, &L[0][0], F_old, &F[0][0], J);
      };
      constexpr unsigned int capacity =
        ConstitutiveModel::StressUpdateInputs::capacity;
      if (n_points == capacity)
        update(std::integral_constant<unsigned int, capacity>());
      else
        update(n_points);
    }

    /**
     * v_p = Σ_j S_pj v_j over one point's support entries [begin, end), and
     * L_p = Σ_j v_j ⊗ G_pj (Eq. 2.7) below: each sum in its own scalar, so
     * that the compiler keeps it in a register (an array or Tensor summand
     * went through the stack on every entry).
     */
    template <int dim, typename Count>
    inline void
    interpolate(const unsigned int *const  node,
                const double *const        S,
                const unsigned int         begin,
                const Count                end,
                const double *const *const v,
                Tensor<1, dim>            &value)
    {
      double x = 0, y = 0, z = 0;
      for (unsigned int j = begin; j < end; ++j)
        {
          const double       s = S[j];
          const unsigned int i = node[j];
          x += s * v[0][i];
          y += s * v[1][i];
          if constexpr (dim == 3)
            z += s * v[2][i];
        }
      value[0] = x;
      value[1] = y;
      if constexpr (dim == 3)
        value[2] = z;
    }

    template <int dim, typename Count>
    inline void
    velocity_gradient(const unsigned int *const   node,
                      const Tensor<1, dim> *const G,
                      const unsigned int          begin,
                      const Count                 end,
                      const double *const *const  v,
                      BatchEntries               &L,
                      const unsigned int          q)
    {
      double xx = 0, xy = 0, xz = 0, yx = 0, yy = 0, yz = 0, zx = 0, zy = 0,
             zz = 0;
      for (unsigned int j = begin; j < end; ++j)
        {
          const unsigned int i  = node[j];
          const double       vx = v[0][i], vy = v[1][i];
          xx += vx * G[j][0];
          xy += vx * G[j][1];
          yx += vy * G[j][0];
          yy += vy * G[j][1];
          if constexpr (dim == 3)
            {
              const double vz = v[2][i];
              xz += vx * G[j][2];
              yz += vy * G[j][2];
              zx += vz * G[j][0];
              zy += vz * G[j][1];
              zz += vz * G[j][2];
            }
        }
      // (In 2D the other entries stay zero.)
      L[0][q] = xx;
      L[1][q] = xy;
      L[3][q] = yx;
      L[4][q] = yy;
      if constexpr (dim == 3)
        {
          L[2][q] = xz;
          L[5][q] = yz;
          L[6][q] = zx;
          L[7][q] = zy;
          L[8][q] = zz;
        }
    }

    /**
     * The hoop rate of an axisymmetric point, L_33 = L_θθ = Σ_j v_r,j T_pj
     * (Nairn and Guilkey 2015; GIMP_Theory Eq. 5.7: the hoop function T
     * takes the place of G for ∂/∂θ), over the support entries
     * [begin, end), into L[8][q]. @p v_r: the nodal radial velocities.
     */
    template <typename Count>
    inline void
    hoop_rate(const unsigned int *const node,
              const double *const       T,
              const unsigned int        begin,
              const Count               end,
              const double *const       v_r,
              BatchEntries             &L,
              const unsigned int        q)
    {
      double rate = 0;
      for (unsigned int j = begin; j < end; ++j)
        rate += T[j] * v_r[node[j]];
      L[8][q] = rate;
    }

    /**
     * The axisymmetric Cayley update of @p n points: the r–z block as
     * plane_strain_cayley_update() and the hoop stretch
     * F_33^{n+1} = ΔF_33 F_33^n with ΔF_33 = (1 + L_33Δt/2)/(1 − L_33Δt/2)
     * (L is block diagonal, so its Cayley transform is too);
     * J = det(F^{n+1}_{2x2}) F_33^{n+1}.
     */
    template <typename Count>
    inline void
    axisymmetric_cayley_update(const Count  n,
                               const double dt,
                               const double *__restrict L_xx,
                               const double *__restrict L_xy,
                               const double *__restrict L_yx,
                               const double *__restrict L_yy,
                               const double *__restrict L_hoop,
                               const double *__restrict F_xx_old,
                               const double *__restrict F_xy_old,
                               const double *__restrict F_yx_old,
                               const double *__restrict F_yy_old,
                               const double *__restrict F_hoop_old,
                               double *__restrict F_xx,
                               double *__restrict F_xy,
                               double *__restrict F_yx,
                               double *__restrict F_yy,
                               double *__restrict F_hoop,
                               double *__restrict J)
    {
      alignas(
        64) double F_hoop_new[ConstitutiveModel::StressUpdateInputs::capacity];
      for (unsigned int q = 0; q < n; ++q)
        {
          const double half = 0.5 * (L_hoop[q] * dt);
          F_hoop_new[q]     = (1.0 + half) / (1.0 - half) * F_hoop_old[q];
        }
      plane_strain_cayley_update(n,
                                 dt,
                                 L_xx,
                                 L_xy,
                                 L_yx,
                                 L_yy,
                                 F_xx_old,
                                 F_xy_old,
                                 F_yx_old,
                                 F_yy_old,
                                 F_hoop_new,
                                 F_xx,
                                 F_xy,
                                 F_yx,
                                 F_yy,
                                 F_hoop,
                                 J);
    }

    /**
     * axisymmetric_cayley_update() of a batch (as cayley_update<2>(), with
     * the hoop entries L[8] and F_old[8]), with a constant count for a full
     * batch.
     */
    inline void
    axisymmetric_cayley_update(const unsigned int                   n_points,
                               const double                         dt,
                               const BatchEntries                  &L,
                               const std::array<const double *, 9> &F_old,
                               BatchEntries                        &F,
                               double                              *J)
    {
      auto update = [&](const auto count) {
        axisymmetric_cayley_update(count,
                                   dt,
                                   L[0],
                                   L[1],
                                   L[3],
                                   L[4],
                                   L[8],
                                   F_old[0],
                                   F_old[1],
                                   F_old[3],
                                   F_old[4],
                                   F_old[8],
                                   F[0],
                                   F[1],
                                   F[3],
                                   F[4],
                                   F[8],
                                   J);
      };
      constexpr unsigned int capacity =
        ConstitutiveModel::StressUpdateInputs::capacity;
      if (n_points == capacity)
        update(std::integral_constant<unsigned int, capacity>());
      else
        update(n_points);
    }

    /**
     * The increments ΔF of the other methods (first order, Taylor,
     * subcycles) for axisymmetric points: increments<3>() of the block
     * diagonal L (r–z block and L_33; the out-of-plane shears are zero, so
     * ΔF is block diagonal too, its zeros exact), after which
     * F^{n+1} = ΔF F^n on the r–z block and F_33^{n+1} = ΔF_33 F_33^n.
     */
    inline void
    axisymmetric_increments(const DeformationGradientUpdate update,
                            const MethodParameters         &method,
                            const BatchEntries             &L,
                            const double                    dt,
                            const unsigned int              n_points,
                            BatchEntries                   &dF)
    {
      for (unsigned int q = 0; q < n_points; ++q)
        Assert(L[2][q] == 0 && L[5][q] == 0 && L[6][q] == 0 && L[7][q] == 0,
               ExcMessage("An axisymmetric velocity gradient has no "
                          "out-of-plane shear."));
      increments<3>(update, method, L, dt, n_points, dF);
    }
  } // namespace Kinematics
} // namespace fmpm

#endif
