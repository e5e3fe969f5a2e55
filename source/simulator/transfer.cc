// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The particle-grid passes of the time step: the support cache (S, G of
// every point, once per step), extrapolations to the grid (Sᵀ, Gᵀ), the
// particle update (S) and the strain update (G), and the re-sorting of
// moved points into cells. Every pass loops over the support cache.

#include <fmpm/neighbour_exchange.h>
#include <fmpm/simulator.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <sstream>

namespace fmpm
{
  namespace
  {
    /**
     * One point's m += M S (with @p with_mass) and p += (M V) S over its
     * support entries j < n, in entry order (Eq. 1.6, p = SᵀMV; @p MV =
     * M V).
     */
    template <int dim, bool with_mass, typename Count>
    inline void
    scatter_mass_momentum(const unsigned int *const node,
                          const double *const       S,
                          const Count               n,
                          const double              M,
                          const double (&MV)[dim],
                          double *const        m,
                          double *const *const p)
    {
      for (unsigned int j = 0; j < n; ++j)
        {
          const unsigned int i = node[j];
          if constexpr (with_mass)
            m[i] += M * S[j];
          for (unsigned int d = 0; d < dim; ++d)
            p[d][i] += MV[d] * S[j];
        }
    }

    /**
     * The force component @p a one point gives its node (Eq. 2.11):
     * M S b_a − V Σ_b σ_ab G_b, with @p MS = M S and the point's body
     * acceleration (tractions included) @p b.
     */
    template <int dim>
    inline double
    nodal_force(const unsigned int    a,
                const double          MS,
                const Tensor<1, dim> &b,
                const double          V,
                const double (&sigma)[dim][dim],
                const Tensor<1, dim> &G)
    {
      double f = MS * b[a];
      for (unsigned int c = 0; c < dim; ++c)
        f -= V * sigma[a][c] * G[c];
      return f;
    }

    /**
     * nodal_force() without body acceleration: −V Σ_b σ_ab G_b (the same
     * bits as with b = 0, M S ≥ 0).
     */
    template <int dim>
    inline double
    internal_nodal_force(const unsigned int a,
                         const double       V,
                         const double (&sigma)[dim][dim],
                         const Tensor<1, dim> &G)
    {
      double f = 0.;
      for (unsigned int c = 0; c < dim; ++c)
        f -= V * sigma[a][c] * G[c];
      return f;
    }

    /** The dim x dim block of point k's stored Cauchy stress, from the six
     * stress columns (Voigt-like order). */
    template <int dim>
    inline void
    stress_block(const double *const *stress,
                 const unsigned int   k,
                 double (&sigma)[dim][dim])
    {
      for (unsigned int c = 0; c < 6; ++c)
        if (stress_component_i[c] < dim && stress_component_j[c] < dim)
          sigma[stress_component_i[c]][stress_component_j[c]] =
            sigma[stress_component_j[c]][stress_component_i[c]] = stress[c][k];
    }

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
     */
    template <int n>
    void
    increments(const DeformationGradientUpdate update,
               const MethodParameters         &method,
               const BatchEntries             &L,
               const double                    dt,
               const unsigned int              n_points,
               BatchEntries                   &dF)
    {
      if (update == DeformationGradientUpdate::first_order)
        {
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < n; ++b)
              for (unsigned int q = 0; q < n_points; ++q)
                dF[3 * a + b][q] = (a == b ? 1.0 : 0.0) + L[3 * a + b][q] * dt;
          return;
        }
      Assert(update != DeformationGradientUpdate::cayley,
             ExcMessage("Cayley: cayley_update()."));
      const Tensor<2, n> I = unit_symmetric_tensor<n>();
      for (unsigned int q = 0; q < n_points; ++q)
        {
          Tensor<2, n> L_dt;
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < n; ++b)
              L_dt[a][b] = L[3 * a + b][q] * dt;
          Tensor<2, n> increment;
          if (update == DeformationGradientUpdate::taylor)
            {
              Tensor<2, n> term = I;
              increment         = I;
              for (unsigned int k = 1; k <= method.taylor_terms; ++k)
                {
                  term = term * L_dt / static_cast<double>(k);
                  increment += term;
                }
            }
          else
            {
              // Subcycles: first-order substeps with |L Δt_sub| below the
              // bound.
              const unsigned int n_sub =
                std::max(1u,
                         static_cast<unsigned int>(std::ceil(
                           L_dt.norm() / method.subcycle_strain_increment)));
              const Tensor<2, n> step = I + L_dt / static_cast<double>(n_sub);
              increment               = I;
              for (unsigned int k = 0; k < n_sub; ++k)
                increment = step * increment;
            }
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < n; ++b)
              dF[3 * a + b][q] = increment[a][b];
        }
    }

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

    /** Points per batch of the strain update (constitutive model calls). */
    constexpr unsigned int stress_batch_size =
      ConstitutiveModel::StressUpdateInputs::capacity;

    /**
     * The per-material fields the contact normals and laws read of the
     * points: g^α = Σ V G and Σ S M X (seed 004 Eq. 11), and for the
     * interface laws u^α = Σ S M (x − X₀) and V^α = Σ S V. The first
     * extrapolation and the re-extrapolation in the particle update add
     * each point's share with the same operations.
     */
    template <int dim>
    class ContactGeometry
    {
    public:
      /** Zero the fields that @p normal_needs and @p interface_state ask
       * for (the others are left alone and not added to). */
      void
      reset(std::vector<Contact::MaterialField<dim>> &fields,
            const Contact::NormalNeeds               &normal_needs,
            const bool                                interface_state,
            const MaterialPoints<dim>                &material_points)
      {
        points      = &material_points;
        using Index = PropertyIndex<dim>;
        mass        = points->column(Index::mass);
        volume      = points->column(Index::volume);
        for (unsigned int d = 0; d < dim; ++d)
          initial_position[d] = points->column(Index::initial_position + d);
        gradient.clear();
        position.clear();
        displacement.clear();
        nodal_volume.clear();
        for (auto &field : fields)
          {
            if (normal_needs.volume_gradients)
              field.volume_gradient = 0;
            if (normal_needs.positions)
              field.position_moment = 0;
            if (interface_state)
              {
                field.displacement_moment = 0;
                field.volume              = 0;
                nodal_volume.push_back(field.volume.begin());
              }
            for (unsigned int d = 0; d < dim; ++d)
              {
                if (normal_needs.volume_gradients)
                  gradient.push_back(field.volume_gradient.block(d).begin());
                if (normal_needs.positions)
                  position.push_back(field.position_moment.block(d).begin());
                if (interface_state)
                  displacement.push_back(
                    field.displacement_moment.block(d).begin());
              }
          }
      }

      /** Add the ghosts of @p field's share of what reset() zeroed (after a
       * sweep of add_point()). */
      static void
      compress(Contact::MaterialField<dim> &field,
               const Contact::NormalNeeds  &normal_needs,
               const bool                   interface_state)
      {
        if (normal_needs.volume_gradients)
          field.volume_gradient.compress(VectorOperation::add);
        if (normal_needs.positions)
          field.position_moment.compress(VectorOperation::add);
        if (interface_state)
          {
            field.displacement_moment.compress(VectorOperation::add);
            field.volume.compress(VectorOperation::add);
          }
      }

      /** Whether add_point() reads G. */
      bool
      needs_gradients() const
      {
        return !gradient.empty();
      }

      /** Point @p k of material @p alpha with its support (G only if
       * needs_gradients()). */
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
          for (unsigned int j = 0; j < n_entries; ++j)
            for (unsigned int d = 0; d < dim; ++d)
              gradient[alpha * dim + d][node[j]] += V * G[j][d];
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

    private:
      const MaterialPoints<dim> *points = nullptr;
      const double              *mass = nullptr, *volume = nullptr;
      const double              *initial_position[dim] = {};
      /** [α dim + d] (nodal_volume: [α]); empty where nothing reads it. */
      std::vector<double *> gradient, position, displacement, nodal_volume;
    };
  } // namespace



  template <int dim>
  Tensor<1, dim>
  Simulator<dim>::body_acceleration_at(const Point<dim>     &x,
                                       const Tensor<1, dim> &V,
                                       const Tensor<1, dim> &gravity,
                                       const Point<dim> &expression_point) const
  {
    Tensor<1, dim> b = gravity;
    if (body_acceleration)
      for (unsigned int d = 0; d < dim; ++d)
        b[d] += body_acceleration->value(expression_point, d);
    if (angular_velocity)
      {
        // Rotating frame (seed 001, computeParticleBodyForce):
        // b = g − ω × (ω × r) − 2 ω × V − ω̇ × r.
        Tensor<1, 3> omega, omega_dot, r, v;
        const double t  = angular_velocity->get_time();
        const double dt = 1e-6 * std::max(1.0, std::abs(t));
        for (unsigned int d = 0; d < 3; ++d)
          {
            omega[d] = angular_velocity->value(Point<1>(), d);
          }
        auto &omega_function = *angular_velocity;
        omega_function.set_time(t + dt);
        for (unsigned int d = 0; d < 3; ++d)
          omega_dot[d] = omega_function.value(Point<1>(), d);
        omega_function.set_time(t - dt);
        for (unsigned int d = 0; d < 3; ++d)
          omega_dot[d] =
            (omega_dot[d] - omega_function.value(Point<1>(), d)) / (2 * dt);
        omega_function.set_time(t);
        for (unsigned int d = 0; d < dim; ++d)
          {
            r[d] = x[d] - parameters.rotating_frame.center[d];
            v[d] = V[d];
          }
        const Tensor<1, 3> a =
          cross_product_3d(omega, cross_product_3d(omega, r)) +
          2 * cross_product_3d(omega, v) + cross_product_3d(omega_dot, r);
        for (unsigned int d = 0; d < dim; ++d)
          b[d] -= a[d];
      }
    return b;
  }



  template <int dim>
  Tensor<1, dim>
  Simulator<dim>::traction_force_of(const unsigned int k) const
  {
    Tensor<1, dim> F;
    const int      index =
      static_cast<int>(points.column(traction_index_slot)[k] + 0.5) - 1;
    if (index < 0)
      return F;
    // F_p = t(t) A_p, the f_T term of Eq. 2.10 (at mid-step, like b).
    const double area = points.column(traction_index_slot + 1)[k];
    for (unsigned int d = 0; d < dim; ++d)
      F[d] = traction_functions[index]->value(Point<1>(), d) * area;
    return F;
  }



  template <int dim>
  Tensor<1, dim>
  Simulator<dim>::external_acceleration(const unsigned int    k,
                                        const Tensor<1, dim> &gravity)
  {
    using Index            = PropertyIndex<dim>;
    const PointRecord    p = points.record(k);
    const Point<dim>    &x = points.position[k];
    const Tensor<1, dim> V = get_vector<dim>(p, Index::velocity);
    Tensor<1, dim>       b =
      parameters.body_acceleration_at_initial_position ?
              body_acceleration_at(x,
                             V,
                             gravity,
                             Point<dim>(
                               get_vector<dim>(p, Index::initial_position))) :
              body_acceleration_at(x, V, gravity, x);
    if (!traction_functions.empty())
      {
        // The traction force as an acceleration, F_p / M_p (Eq. 2.10).
        const Tensor<1, dim> F_p = traction_force_of(k);
        b += F_p / p[Index::mass];
        local_traction_power += F_p * V;
        local_traction_magnitude += F_p.norm();
      }
    return b;
  }



  template <int dim>
  void
  Simulator<dim>::compute_supports(const bool extrapolate)
  {
    TimerOutput::Scope timer(computing_timer, "shape functions");
    using Index              = PropertyIndex<dim>;
    constexpr unsigned int n = GridTransfer<dim>::n_nodes;
    supports.clear();
    supports_extrapolated       = false;
    const unsigned int n_points = points.n_points();
    if (n_points == 0)
      return;
    const bool classic = (shape_function == ShapeFunction::Type::classic);
    const bool multiple_materials   = constitutive_models.size() > 1;
    const double *const material_id = points.column(Index::material_id);
    if (multiple_materials)
      {
        supports.material.resize(n_points);
        for (unsigned int k = 0; k < n_points; ++k)
          supports.material[k] = static_cast<unsigned char>(material_id[k]);
      }

    // Classic on affine cells without hanging nodes: the passes compute the
    // entries from the step's ξ (SupportReader).
    if (classic)
      {
        bool affine_without_hanging_nodes = true;
        for (unsigned int c = 0; c < points.n_cells(); ++c)
          {
            const auto &data = transfer.cell_data(points.cell_index[c]);
            affine_without_hanging_nodes = affine_without_hanging_nodes &&
                                           data.is_affine &&
                                           !data.has_constraints;
          }
        if (affine_without_hanging_nodes)
          {
            supports.implicit_classic  = true;
            supports.n_implicit_points = n_points;
            if (parameters.method.strain_update_scheme.update_last)
              {
                supports.reference_position_copy = points.reference_position;
                supports.reference_position =
                  supports.reference_position_copy.data();
              }
            else
              supports.reference_position = points.reference_position.data();
            return;
          }
      }

    // (GIMP on a uniform patch: at most 3^dim nodes per point.)
    const bool gimp = (shape_function == ShapeFunction::Type::ugimp ||
                       shape_function == ShapeFunction::Type::cpgimp);
    supports.support_begin.resize(n_points + 1);
    supports.make_room((gimp ? Utilities::pow(3, dim) : n) * n_points);
    unsigned int *const support_end = supports.support_begin.data() + 1;

    // m = SᵀM, p = SᵀMV of each point once its entries are stored.
    const bool extrapolate_here = extrapolate && extrapolates_with_supports();
    double    *m = nullptr, *p[dim] = {};
    const double *const mass_column = points.column(Index::mass);
    const double       *velocity_column[dim];
    for (unsigned int d = 0; d < dim; ++d)
      velocity_column[d] = points.column(Index::velocity + d);
    if (extrapolate_here)
      {
        centre_of_mass.mass     = 0;
        centre_of_mass.momentum = 0;
        m                       = centre_of_mass.mass.begin();
        for (unsigned int d = 0; d < dim; ++d)
          p[d] = centre_of_mass.momentum.block(d).begin();
        supports_extrapolated = true;
      }
    auto extrapolate_point = [&](const unsigned int k,
                                 const std::size_t  first) {
      const double M = mass_column[k];
      double       MV[dim];
      for (unsigned int d = 0; d < dim; ++d)
        MV[d] = M * velocity_column[d][k];
      scatter_mass_momentum<dim, true>(supports.node.data() + first,
                                       supports.S.data() + first,
                                       supports.n_stored - first,
                                       M,
                                       MV,
                                       m,
                                       p);
    };
    const auto   &partitioner = *centre_of_mass.mass.get_partitioner();
    const double *F_column[dim][dim], *l0_column[dim];
    for (unsigned int a = 0; a < dim; ++a)
      {
        l0_column[a] = points.column(Index::initial_half_length + a);
        for (unsigned int b = 0; b < dim; ++b)
          F_column[a][b] =
            points.column(Index::deformation_gradient + 3 * a + b);
      }

    // A node of a support: itself, or for a hanging node its masters with
    // the constraint weights (S_jp += c_ij S_ip).
    auto add_node = [&](const unsigned int            first,
                        const unsigned int            local_index,
                        const types::global_dof_index dof,
                        const bool                    constrained,
                        const double                  S,
                        const Tensor<1, dim>         &G) {
      if (!constrained)
        supports.add_entry(first, local_index, S, G);
      else
        for (const auto &entry : *constraints.get_constraint_entries(dof))
          supports.add_entry(first,
                             partitioner.global_to_local(entry.first),
                             entry.second * S,
                             entry.second * G);
    };

    std::array<double, n>                 S;
    std::array<Tensor<1, dim>, n>         G;
    std::vector<ShapeFunction::Node<dim>> support;
    if (gimp)
      gimp_patch_of_cell.resize(triangulation.n_active_cells(),
                                numbers::invalid_unsigned_int);
    const ShapeFunction::UniformGimpPatch<dim> *gimp_patch = nullptr;
    const bool cpdi = (shape_function == ShapeFunction::Type::cpdi);
    if (cpdi)
      cpdi_patch_of_cell.resize(triangulation.n_active_cells(),
                                numbers::invalid_unsigned_int);
    const ShapeFunction::UniformCpdiPatch<dim> *cpdi_patch = nullptr;
    // The points in the store's order: cell by cell (cells in the order of
    // their ids, so that the sums over points onto nodes do not depend on
    // the mesh's storage order, which a mesh loaded from a checkpoint does
    // not share: bitwise resumes), by id in a cell.
    for (unsigned int cell_number = 0; cell_number < points.n_cells();
         ++cell_number)
      {
        const unsigned int c    = points.cell_index[cell_number];
        const auto        &data = transfer.cell_data(c);
        if (gimp && data.uniform_patch)
          {
            if (gimp_patch_of_cell[c] == numbers::invalid_unsigned_int)
              {
                gimp_patch_of_cell[c] = gimp_patches.size();
                gimp_patches.emplace_back();
                gimp_patches.back().reinit(transfer, c);
              }
            gimp_patch = &gimp_patches[gimp_patch_of_cell[c]];
          }
        cpdi_patch = nullptr;
        if (cpdi && data.uniform_patch)
          {
            if (cpdi_patch_of_cell[c] == numbers::invalid_unsigned_int)
              {
                cpdi_patch_of_cell[c] = cpdi_patches.size();
                cpdi_patches.emplace_back();
                cpdi_patches.back().reinit(transfer, c);
              }
            if (cpdi_patches[cpdi_patch_of_cell[c]].applies())
              cpdi_patch = &cpdi_patches[cpdi_patch_of_cell[c]];
          }
        for (unsigned int k = points.cell_point_begin[cell_number];
             k < points.cell_point_begin[cell_number + 1];
             ++k)
          {
            const Point<dim>  &location = points.position[k];
            const unsigned int first    = supports.n_stored;
            if (classic)
              {
                GridTransfer<dim>::values_and_gradients(
                  data, points.reference_position[k], S, G);
                if (!data.has_constraints)
                  {
                    supports.make_room(n);
                    for (unsigned int i = 0; i < n; ++i)
                      supports.append(data.local_index[i], S[i], G[i]);
                  }
                else
                  for (unsigned int i = 0; i < n; ++i)
                    add_node(first,
                             data.local_index[i],
                             transfer.dof_index(data, i),
                             data.constrained_nodes & (1u << i),
                             S[i],
                             G[i]);
              }
            else
              {
                Tensor<2, dim> F;
                Tensor<1, dim> l0, l;
                for (unsigned int a = 0; a < dim; ++a)
                  {
                    l0[a] = l0_column[a][k];
                    l[a]  = l0_column[a][k];
                  }
                // (uGIMP reads no F.)
                if (shape_function != ShapeFunction::Type::ugimp)
                  for (unsigned int a = 0; a < dim; ++a)
                    for (unsigned int b = 0; b < dim; ++b)
                      F[a][b] = F_column[a][b][k];
                // GIMP's closed forms on a uniform patch from the cell's
                // planes (built once per cell), else the general support.
                ShapeFunction::Status status = ShapeFunction::Status::ok;
                if (shape_function == ShapeFunction::Type::cpgimp)
                  l = ShapeFunction::gimp_half_lengths(shape_function, F, l0);
                // No hanging nodes on a uniform patch: straight into the
                // cache.
                if (gimp && data.uniform_patch)
                  {
                    supports.make_room(Utilities::pow(4, dim));
                    unsigned int *const node_out = supports.node.data() + first;
                    double *const       S_out    = supports.S.data() + first;
                    Tensor<1, dim> *const G_out  = supports.G.data() + first;
                    unsigned int          count  = 0;
                    if (gimp_patch->for_each_node_if_applies(
                          location,
                          l,
                          [&](const unsigned int local_index,
                              const types::global_dof_index,
                              const double          S_ip,
                              const Tensor<1, dim> &G_ip) {
                            node_out[count] = local_index;
                            S_out[count]    = S_ip;
                            G_out[count]    = G_ip;
                            ++count;
                          }))
                      {
                        supports.n_stored += count;
                        support_end[k] = supports.n_stored;
                        if (extrapolate_here)
                          extrapolate_point(k, first);
                        continue;
                      }
                  }
                // CPDI on a uniform patch: the corners' cells found
                // arithmetically (the general path's bits).
                if (cpdi_patch != nullptr)
                  {
                    supports.make_room(
                      ShapeFunction::UniformCpdiPatch<dim>::max_support_size);
                    const unsigned int count = cpdi_patch->support(
                      transfer,
                      location,
                      F,
                      l0,
                      parameters.method.cpdi_critical_radius,
                      supports.node.data() + first,
                      supports.S.data() + first,
                      supports.G.data() + first);
                    if (count > 0)
                      {
                        supports.n_stored += count;
                        support_end[k] = supports.n_stored;
                        if (extrapolate_here)
                          extrapolate_point(k, first);
                        continue;
                      }
                  }
                if (shape_function == ShapeFunction::Type::ugimp)
                  for (unsigned int a = 0; a < dim; ++a)
                    for (unsigned int b = 0; b < dim; ++b)
                      F[a][b] = F_column[a][b][k];
                status = ShapeFunction::compute_support(
                  shape_function,
                  transfer,
                  c,
                  location,
                  F,
                  l0,
                  support,
                  true,
                  parameters.method.cpdi_critical_radius);
                if (status != ShapeFunction::Status::ok)
                  {
                    if (local_failure.empty())
                      {
                        std::ostringstream message;
                        message
                          << "the domain of material point " << points.id[k]
                          << " at (" << location << ") "
                          << (status == ShapeFunction::Status::outside_mesh ?
                                "reaches outside the mesh by more than half a "
                                "cell" :
                                "reaches beyond the cells that share a vertex "
                                "with its cell (one layer of neighbour or "
                                "ghost cells)")
                          << " (Shape function/Type = "
                          << parameters.method.shape_function
                          << "): use smaller points (more Points per cell), "
                             "a coarser mesh there, classic shape "
                             "functions, or for CPDI a Shape function/CPDI "
                             "critical radius of at most 1";
                        local_failure = message.str();
                      }
                    // Carry on with the classic weights; the step fails.
                    ShapeFunction::compute_support(ShapeFunction::Type::classic,
                                                   transfer,
                                                   c,
                                                   location,
                                                   F,
                                                   l0,
                                                   support);
                  }
                // compute_support() names each node once: only the masters
                // of hanging nodes can repeat a node.
                bool any_constrained = false;
                for (const auto &node : support)
                  any_constrained = any_constrained || node.constrained;
                if (!any_constrained)
                  {
                    supports.make_room(support.size());
                    for (const auto &node : support)
                      supports.append(node.local_index, node.S, node.G);
                  }
                else
                  for (const auto &node : support)
                    add_node(first,
                             node.local_index,
                             node.dof,
                             node.constrained,
                             node.S,
                             node.G);
              }
            support_end[k] = supports.n_stored;
            if (extrapolate_here)
              extrapolate_point(k, first);
          }
      }
  }



  template <int dim>
  void
  Simulator<dim>::particles_to_grid(const bool with_forces)
  {
    TimerOutput::Scope timer(computing_timer, "particles to grid");
    using Index = PropertyIndex<dim>;
    // m and p extrapolated by compute_supports() (one field, no forces, no
    // m̃): only the ghosts to add.
    const bool extrapolated = supports_extrapolated;
    supports_extrapolated   = false;

    // m̃ as cell-wise matrices where the mass matrix accepts them, else the
    // assembled sparse matrix (the collection BC methods need its entries).
    use_cellwise_full_mass = mass_matrix->needs_full_mass_matrix() &&
                             mass_matrix->accepts_cellwise_full_mass_matrix() &&
                             !velocity_conditions.needs_full_mass_matrix();
    const bool assemble_full =
      !use_cellwise_full_mass && (mass_matrix->needs_full_mass_matrix() ||
                                  velocity_conditions.needs_full_mass_matrix());
    const bool with_full_mass = use_cellwise_full_mass || assemble_full;
    // (With contact m, p and f are set from the material fields after the
    // sweep.)
    const bool contact = contact_active();
    if (!contact && !extrapolated)
      {
        centre_of_mass.mass     = 0;
        centre_of_mass.momentum = 0;
        if (with_forces)
          centre_of_mass.force = 0;
      }
    if (assemble_full)
      full_mass_matrix = 0;
    if (with_full_mass && use_cellwise_full_mass)
      cellwise_full_mass.clear();

    // Per-material fields (contact): m^α, p^α0, f^α0, g^α, Σ S M X.
    if (contact)
      this->contact->invalidate_geometry(true);
    std::vector<Contact::MaterialField<dim>>  no_material_fields;
    std::vector<Contact::MaterialField<dim>> &material_fields =
      contact ? this->contact->material_fields() : no_material_fields;
    const unsigned int n_materials = material_fields.size();
    // m̃^α = Σ_{p∈α} S M Sᵀ (seed 004 Eq. 37) as local matrices of the cells
    // with points of α, for the multimaterial series and exact solve.
    const bool material_full_mass =
      contact && this->contact->needs_material_full_mass();
    std::vector<CellwiseMatrix> *const material_full_mass_matrices =
      material_full_mass ? &this->contact->material_full_mass() : nullptr;
    if (material_full_mass)
      for (auto &matrix : *material_full_mass_matrices)
        matrix.clear();
    std::vector<double *> m_alpha(n_materials), p_alpha(n_materials * dim),
      f_alpha(n_materials * dim);
    ContactGeometry<dim> contact_geometry;
    if (contact)
      contact_geometry.reset(material_fields,
                             this->contact->normal_needs(),
                             this->contact->needs_interface_state(),
                             points);
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        Contact::MaterialField<dim> &field = material_fields[a];
        field.mass                         = 0;
        field.momentum                     = 0;
        if (with_forces)
          field.force = 0;
        m_alpha[a] = field.mass.begin();
        for (unsigned int d = 0; d < dim; ++d)
          {
            p_alpha[a * dim + d] = field.momentum.block(d).begin();
            f_alpha[a * dim + d] = field.force.block(d).begin();
          }
      }

    const auto    &partitioner        = *centre_of_mass.mass.get_partitioner();
    const bool     uniform_body_force = !has_point_body_force();
    Tensor<1, dim> gravity;
    for (unsigned int d = 0; d < dim; ++d)
      gravity[d] = parameters.gravity[d];

    // Raw views of the ghosted grid vectors (owned and ghost entries).
    double *const m = centre_of_mass.mass.begin();
    double       *p[dim], *f[dim];
    for (unsigned int d = 0; d < dim; ++d)
      {
        p[d] = centre_of_mass.momentum.block(d).begin();
        f[d] = centre_of_mass.force.block(d).begin();
      }
    const unsigned int *const cached_node = supports.node.data();
    const SupportReader<dim> support_of(supports, transfer, points.cell.data());
    // The columns this pass reads: M, V (and V, σ for the forces; X for
    // contact positions).
    const double *const mass_column   = points.column(Index::mass);
    const double *const volume_column = points.column(Index::volume);
    const double       *velocity_column[dim], *stress_column[6];
    for (unsigned int d = 0; d < dim; ++d)
      velocity_column[d] = points.column(Index::velocity + d);
    for (unsigned int c = 0; c < 6; ++c)
      stress_column[c] = points.column(Index::stress + c);
    // m̃ of one cell over the union of its points' supports: the nodes, and
    // the place in them of each support entry of the cell's points.
    std::vector<unsigned int>        cell_nodes, slot;
    std::vector<double>              local_full_mass;
    std::vector<std::vector<double>> local_material_mass(
      material_full_mass ? n_materials : 0);
    std::vector<char> material_in_cell(material_full_mass ? n_materials : 0);
    std::vector<types::global_dof_index> dofs;
    // A cell's m̃ (local_full_mass over its n nodes) into the cell-wise or
    // the assembled matrix.
    auto add_cell_full_mass = [&](const unsigned int        n,
                                  const unsigned int *const nodes) {
      if (with_full_mass && use_cellwise_full_mass)
        cellwise_full_mass.add_cell(n, nodes, local_full_mass.data());
      else if (assemble_full)
        {
          dofs.resize(n);
          for (unsigned int i = 0; i < n; ++i)
            dofs[i] = partitioner.local_to_global(nodes[i]);
          for (unsigned int i = 0; i < n; ++i)
            full_mass_matrix.add(dofs[i],
                                 n,
                                 dofs.data(),
                                 &local_full_mass[i * n]);
        }
    };

    // Per point: the entries j of its support (computed: the cell's nodes;
    // stored: the cache's), at place place_of(j) of the cell's nodes.
    const bool with_gradients =
      with_forces || contact_geometry.needs_gradients();
    for (unsigned int c = 0; c < (extrapolated ? 0 : points.n_cells()); ++c)
      {
        if (supports.implicit_classic && !contact)
          {
            // Computed supports, one velocity field (the general loop below
            // keeps fewer values in registers): the cell's nodes for all its
            // points, m̃ over them.
            constexpr unsigned int n = GridTransfer<dim>::n_nodes;
            const auto &cell_data    = transfer.cell_data(points.cell_index[c]);
            const std::array<unsigned int, n> &cell_node =
              cell_data.local_index;
            if (with_full_mass)
              local_full_mass.assign(n * n, 0.);
            for (unsigned int k = points.cell_point_begin[c];
                 k < points.cell_point_begin[c + 1];
                 ++k)
              {
                std::array<double, n>         S_k;
                std::array<Tensor<1, dim>, n> G_k;
                support_of.compute(k, cell_data, with_forces, S_k, G_k);
                const double M = mass_column[k];
                double       MV[dim];
                for (unsigned int d = 0; d < dim; ++d)
                  MV[d] = M * velocity_column[d][k];
                for (unsigned int j = 0; j < n; ++j)
                  {
                    const unsigned int i = cell_node[j];
                    m[i] += M * S_k[j];
                    for (unsigned int d = 0; d < dim; ++d)
                      p[d][i] += MV[d] * S_k[j];
                  }
                if (with_forces)
                  {
                    const Tensor<1, dim> b =
                      uniform_body_force ? gravity :
                                           external_acceleration(k, gravity);
                    double sigma[dim][dim];
                    stress_block<dim>(stress_column, k, sigma);
                    const double V = volume_column[k];
                    for (unsigned int j = 0; j < n; ++j)
                      for (unsigned int a = 0; a < dim; ++a)
                        f[a][cell_node[j]] +=
                          nodal_force<dim>(a, M * S_k[j], b, V, sigma, G_k[j]);
                  }
                if (with_full_mass) // m̃ = SᵀMS (1.9)
                  for (unsigned int i = 0; i < n; ++i)
                    {
                      const double MS_i = M * S_k[i];
                      for (unsigned int j = 0; j < n; ++j)
                        local_full_mass[i * n + j] += MS_i * S_k[j];
                    }
              }
            add_cell_full_mass(n, cell_node.data());
            continue;
          }
        const auto        &cell_data = transfer.cell_data(points.cell_index[c]);
        const unsigned int first_point = points.cell_point_begin[c];
        const unsigned int end_point   = points.cell_point_begin[c + 1];
        // m̃ of the cell over the union of its points' supports: computed
        // supports have the cell's nodes, in the order of the entries.
        const unsigned int *cell_node_list = cell_data.local_index.data();
        unsigned int        n_cell_nodes   = GridTransfer<dim>::n_nodes;
        unsigned int        first_entry    = 0;
        if (!supports.implicit_classic)
          {
            first_entry = supports.support_begin[first_point];
            if (with_full_mass || material_full_mass)
              {
                const unsigned int entry_end =
                  supports.support_begin[end_point];
                cell_nodes.clear();
                slot.resize(entry_end - first_entry);
                for (unsigned int j = first_entry; j < entry_end; ++j)
                  {
                    const auto place      = std::find(cell_nodes.begin(),
                                                 cell_nodes.end(),
                                                 cached_node[j]);
                    slot[j - first_entry] = place - cell_nodes.begin();
                    if (place == cell_nodes.end())
                      cell_nodes.push_back(cached_node[j]);
                  }
                cell_node_list = cell_nodes.data();
                n_cell_nodes   = cell_nodes.size();
              }
          }
        // A large union against the points' supports (GIMP, CPDI): m̃ of
        // the cell kept as those supports.
        const bool factored =
          !supports.implicit_classic &&
          CellwiseMatrix::factored_is_cheaper(
            n_cell_nodes, supports.support_begin[end_point] - first_entry);
        const bool factored_total =
          factored && with_full_mass && use_cellwise_full_mass;
        const bool factored_material = factored && material_full_mass;
        if (factored_total)
          cellwise_full_mass.begin_factored_cell(n_cell_nodes, cell_node_list);
        else if (with_full_mass)
          local_full_mass.assign(n_cell_nodes * n_cell_nodes, 0.);
        for (unsigned int k = first_point; k < end_point; ++k)
          support_of.visit(
            k,
            cell_data,
            with_gradients,
            [&](const unsigned int *const   node,
                const double *const         S,
                const Tensor<1, dim> *const G,
                const auto                  n_entries) DEAL_II_ALWAYS_INLINE {
              constexpr bool computed =
                !std::is_same_v<std::decay_t<decltype(n_entries)>,
                                unsigned int>;
              const unsigned int *const entry_slot =
                computed ?
                  nullptr :
                  slot.data() + (supports.support_begin[k] - first_entry);
              auto place_of = [&](const unsigned int j) {
                if constexpr (computed)
                  return j;
                else
                  return entry_slot[j];
              };
              const double M = mass_column[k];
              double       MV[dim];
              for (unsigned int d = 0; d < dim; ++d)
                MV[d] = M * velocity_column[d][k];
              // m = SᵀM (Eq. 1.6), p = SᵀMV; with contact also m^α, p^α0
              // of the point's material (Eq. 5).
              auto scatter = [&](double *const        m_target,
                                 double *const *const p_target) {
                scatter_mass_momentum<dim, true>(
                  node, S, n_entries, M, MV, m_target, p_target);
              };
              // (With contact m and p are the sums of m^α and p^α0, formed
              // after the sweep.)
              if (!contact)
                scatter(m, p);
              if (with_forces)
                {
                  // f = −Σ V_p σ_p G_p + Σ S_p (M_p b + F_p)  (Eq. 2.11,
                  // τ/ρ₀ M = σ V; F_p the traction force)
                  const Tensor<1, dim> b = uniform_body_force ?
                                             gravity :
                                             external_acceleration(k, gravity);
                  double               sigma[dim][dim];
                  stress_block<dim>(stress_column, k, sigma);
                  const double V = volume_column[k];
                  // (with contact f^α0 of the point's material, Eq. 29)
                  double *const *f_target =
                    contact ? &f_alpha[supports.material[k] * dim] : f;
                  if (b.norm_square() == 0)
                    for (unsigned int j = 0; j < n_entries; ++j)
                      for (unsigned int a = 0; a < dim; ++a)
                        f_target[a][node[j]] +=
                          internal_nodal_force<dim>(a, V, sigma, G[j]);
                  else
                    for (unsigned int j = 0; j < n_entries; ++j)
                      for (unsigned int a = 0; a < dim; ++a)
                        f_target[a][node[j]] +=
                          nodal_force<dim>(a, M * S[j], b, V, sigma, G[j]);
                }
              if (contact)
                {
                  // Eqs. 5 and 11 for the point's material α.
                  const unsigned int alpha = supports.material[k];
                  scatter(m_alpha[alpha], &p_alpha[alpha * dim]);
                  contact_geometry.add_point(k, alpha, node, S, G, n_entries);
                }
              if constexpr (!computed)
                {
                  if (factored_total)
                    cellwise_full_mass.add_point(M, n_entries, entry_slot, S);
                  if (factored_material)
                    {
                      const unsigned int alpha = supports.material[k];
                      CellwiseMatrix    &m_tilde_alpha =
                        (*material_full_mass_matrices)[alpha];
                      if (!material_in_cell[alpha])
                        {
                          m_tilde_alpha.begin_factored_cell(n_cell_nodes,
                                                            cell_node_list);
                          material_in_cell[alpha] = 1;
                        }
                      m_tilde_alpha.add_point(M, n_entries, entry_slot, S);
                    }
                }
              if (with_full_mass && !factored_total) // m̃ = SᵀMS (1.9)
                for (unsigned int i = 0; i < n_entries; ++i)
                  {
                    const double MS_i = M * S[i];
                    double *row = &local_full_mass[place_of(i) * n_cell_nodes];
                    for (unsigned int j = 0; j < n_entries; ++j)
                      row[place_of(j)] += MS_i * S[j];
                  }
              if (material_full_mass && !factored_material) // m̃^α of α
                {
                  const unsigned int   alpha = supports.material[k];
                  std::vector<double> &local = local_material_mass[alpha];
                  if (!material_in_cell[alpha])
                    {
                      local.assign(n_cell_nodes * n_cell_nodes, 0.);
                      material_in_cell[alpha] = 1;
                    }
                  for (unsigned int i = 0; i < n_entries; ++i)
                    {
                      const double MS_i = M * S[i];
                      double      *row  = &local[place_of(i) * n_cell_nodes];
                      for (unsigned int j = 0; j < n_entries; ++j)
                        row[place_of(j)] += MS_i * S[j];
                    }
                }
            });
        if (material_full_mass)
          for (unsigned int a = 0; a < n_materials; ++a)
            if (material_in_cell[a])
              {
                if (!factored_material)
                  (*material_full_mass_matrices)[a].add_cell(
                    n_cell_nodes,
                    cell_node_list,
                    local_material_mass[a].data());
                material_in_cell[a] = 0;
              }
        if (!factored_total)
          add_cell_full_mass(n_cell_nodes, cell_node_list);
      }

    if (contact)
      {
        // m = Σ_α m^α, p = Σ_α p^α, f = Σ_α f^α0.
        centre_of_mass.set_to_sum(material_fields, true, true, with_forces);
      }
    centre_of_mass.mass.compress(VectorOperation::add);
    centre_of_mass.momentum.compress(VectorOperation::add);
    if (with_forces)
      centre_of_mass.force.compress(VectorOperation::add);
    if (assemble_full)
      full_mass_matrix.compress(VectorOperation::add);
    centre_of_mass.mass.update_ghost_values();
    for (auto &field : material_fields)
      {
        field.mass.compress(VectorOperation::add);
        field.momentum.compress(VectorOperation::add);
        if (with_forces)
          field.force.compress(VectorOperation::add);
        ContactGeometry<dim>::compress(field,
                                       this->contact->normal_needs(),
                                       this->contact->needs_interface_state());
        field.mass.update_ghost_values();
        field.computed.fill(false);
      }
    mass_matrix->setup();
  }



  template <int dim>
  bool
  Simulator<dim>::re_extrapolates_in_particle_update() const
  {
    return parameters.method.strain_update_scheme.update_last &&
           parameters.method.strain_update_scheme.re_extrapolate;
  }



  template <int dim>
  void
  Simulator<dim>::finish_re_extrapolation()
  {
    // The tail of the re-extrapolation the particle update made: with
    // contact p = Σ_α p^α (Eq. 6); the ghosts added (with contact also of
    // g^α, Σ S M X, u^α, V^α where read).
    TimerOutput::Scope timer(computing_timer, "particles to grid");
    if (contact_active())
      {
        this->contact->invalidate_geometry(false);
        centre_of_mass.set_to_sum(this->contact->material_fields(),
                                  false,
                                  true,
                                  false);
      }
    centre_of_mass.momentum.compress(VectorOperation::add);
    if (contact_active())
      for (auto &field : this->contact->material_fields())
        {
          field.momentum.compress(VectorOperation::add);
          ContactGeometry<dim>::compress(
            field,
            this->contact->normal_needs(),
            this->contact->needs_interface_state());
          field.computed.fill(false);
        }
  }



  template <int dim>
  Simulator<dim>::ForceColumns::ForceColumns(const MaterialPoints<dim> &points)
    : mass(points.column(PropertyIndex<dim>::mass))
    , volume(points.column(PropertyIndex<dim>::volume))
  {
    for (unsigned int c = 0; c < 6; ++c)
      stress[c] = points.column(PropertyIndex<dim>::stress + c);
  }



  template <int dim>
  template <typename Count>
  DEAL_II_ALWAYS_INLINE inline void
  Simulator<dim>::scatter_point_force(const unsigned int          k,
                                      const unsigned int *const   node,
                                      const double *const         S,
                                      const Tensor<1, dim> *const G,
                                      const Count                 n_entries,
                                      const ForceColumns         &columns,
                                      const Tensor<1, dim>       &gravity,
                                      const bool     uniform_body_force,
                                      double *const *f)
  {
    using Index    = PropertyIndex<dim>;
    const double M = columns.mass[k];
    const double V = columns.volume[k];
    double       sigma[dim][dim];
    stress_block<dim>(columns.stress, k, sigma);
    const Tensor<1, dim> b =
      uniform_body_force ? gravity : external_acceleration(k, gravity);
    if (b.norm_square() == 0)
      for (unsigned int j = 0; j < n_entries; ++j)
        for (unsigned int a = 0; a < dim; ++a)
          f[a][node[j]] += internal_nodal_force<dim>(a, V, sigma, G[j]);
    else
      for (unsigned int j = 0; j < n_entries; ++j)
        for (unsigned int a = 0; a < dim; ++a)
          f[a][node[j]] += nodal_force<dim>(a, M * S[j], b, V, sigma, G[j]);
  }



  template <int dim>
  void
  Simulator<dim>::update_particles()
  {
    TimerOutput::Scope timer(computing_timer, "particle update");
    using Index = PropertyIndex<dim>;

    unsigned int fields[ParticleUpdate::n_grid_fields];
    unsigned int n_fields = 0;
    using FieldViews      = std::array<std::array<const double *, dim>,
                                  ParticleUpdate::n_grid_fields>;
    // The fields of the centre of mass, or with contact of each material
    // (the point reads its material's field, Eq. 32).
    const bool              contact = contact_active();
    std::vector<FieldViews> views(
      contact ? this->contact->material_fields().size() : 1);
    const auto &needed = active_fields();
    for (unsigned int f = 0; f < ParticleUpdate::n_grid_fields; ++f)
      if (needed[f])
        {
          fields[n_fields++] = f;
          for (unsigned int a = 0; a < views.size(); ++a)
            for (unsigned int d = 0; d < dim; ++d)
              views[a][f][d] =
                (contact ? this->contact->material_fields()[a].fields[f] :
                           centre_of_mass.fields[f])
                  .block(d)
                  .begin();
        }

    // Periodic FMPM(k): FLIP in the lumped steps between the series.
    ParticleUpdate::Interface<dim> &update = active_update();
    ParticleUpdate::Batch<dim>      batch;
    batch.time_step = control.time_step();
    points_that_left_their_cell.clear();
    const bool   track_dissipation = parameters.output.track_dissipation;
    const double grid_damping      = parameters.method.grid_damping;
    const double particle_damping  = parameters.method.particle_damping;
    std::vector<Tensor<1, dim>> old_velocity, damping_velocity;
    std::vector<Point<dim>>     old_position;
    double                      max_V2 = 0;
    const bool has_moving_walls        = velocity_conditions.has_moving_boxes();
    SupportReader<dim> support_of(supports, transfer, points.cell.data());
    double            *velocity_column[dim];
    for (unsigned int d = 0; d < dim; ++d)
      velocity_column[d] = points.column(Index::velocity + d);
    const double *const mass_column = points.column(Index::mass);
    // USL+/USAVG+: p = SᵀMV^{n+1} in this sweep, into momentum_target[d]
    // (with contact p^α of the point's material α: [α dim + d], and what
    // the normals and laws read of the moved points).
    const bool            re_extrapolate = re_extrapolates_in_particle_update();
    std::vector<double *> momentum_target;
    ContactGeometry<dim>  contact_geometry;
    if (re_extrapolate && contact)
      {
        contact_geometry.reset(this->contact->material_fields(),
                               this->contact->normal_needs(),
                               this->contact->needs_interface_state(),
                               points);
        for (auto &field : this->contact->material_fields())
          {
            field.momentum = 0;
            for (unsigned int d = 0; d < dim; ++d)
              momentum_target.push_back(field.momentum.block(d).begin());
          }
      }
    else if (re_extrapolate)
      {
        centre_of_mass.momentum = 0;
        for (unsigned int d = 0; d < dim; ++d)
          momentum_target.push_back(centre_of_mass.momentum.block(d).begin());
      }

    // Point k's share of p = SᵀMV^{n+1} (Eq. 5 with contact) and of the
    // contact geometry once its V and X are final: the operations of
    // particles_to_grid().
    const auto re_extrapolate_point =
      [&](const unsigned int k, const auto &data, const Tensor<1, dim> &V)
        DEAL_II_ALWAYS_INLINE {
          support_of.visit(
            k,
            data,
            contact_geometry.needs_gradients(),
            [&](const unsigned int *const   node,
                const double *const         S,
                const Tensor<1, dim> *const G,
                const auto                  n_entries) DEAL_II_ALWAYS_INLINE {
              const double       M     = mass_column[k];
              const unsigned int alpha = contact ? supports.material[k] : 0;
              double             MV[dim];
              for (unsigned int d = 0; d < dim; ++d)
                MV[d] = M * V[d];
              scatter_mass_momentum<dim, false>(node,
                                                S,
                                                n_entries,
                                                M,
                                                MV,
                                                nullptr,
                                                &momentum_target[alpha * dim]);
              if (contact)
                contact_geometry.add_point(k, alpha, node, S, G, n_entries);
            });
        };

    // One batch per cell with points (the plugin's virtual call per batch).
    for (unsigned int c = 0; c < points.n_cells(); ++c)
      {
        const unsigned int first_point = points.cell_point_begin[c];
        const unsigned int n_points =
          points.cell_point_begin[c + 1] - first_point;
        const auto &data = transfer.cell_data(points.cell_index[c]);
        batch.resize(n_points);

        // Gather: V, X and the requested fields extrapolated with S.
        for (unsigned int q = 0; q < n_points; ++q)
          {
            const unsigned int k = first_point + q;
            for (unsigned int d = 0; d < dim; ++d)
              batch.velocity[q][d] = velocity_column[d][k];
            batch.position[q] = points.position[k];
            const FieldViews &field_values =
              views[contact ? supports.material[k] : 0];
            support_of.visit(k,
                             data,
                             false,
                             [&](const unsigned int *const node,
                                 const double *const       S,
                                 const Tensor<1, dim> *,
                                 const auto n_entries) {
                               for (unsigned int field = 0; field < n_fields;
                                    ++field)
                                 {
                                   const unsigned int f = fields[field];
                                   interpolate<dim>(node,
                                                    S,
                                                    0,
                                                    n_entries,
                                                    field_values[f].data(),
                                                    batch.grid[f][q]);
                                 }
                             });
          }

        // Keep V^(n), X^(n) where damping or the dissipation measure need
        // them.
        if (track_dissipation)
          {
            old_velocity.assign(batch.velocity.begin(), batch.velocity.end());
            old_position.assign(batch.position.begin(), batch.position.end());
          }
        const std::vector<Tensor<1, dim>> *V_n = &batch.velocity;
        if (particle_damping != 0)
          {
            damping_velocity.assign(batch.velocity.begin(),
                                    batch.velocity.end());
            V_n = &damping_velocity;
          }

        update.update(batch);

        // Damping (seed 003 Eqs. 1.21-1.25): the acceleration loses
        // A_damp = α_g S v + α_p V^(n); V^(n+1) -= A_damp Δt and, the
        // effective velocity being unchanged, X^(n+1) -= A_damp Δt²/2.
        if (grid_damping != 0 || particle_damping != 0)
          for (unsigned int q = 0; q < n_points; ++q)
            {
              Tensor<1, dim> A_damp;
              if (grid_damping != 0)
                A_damp +=
                  grid_damping * batch.grid[ParticleUpdate::velocity][q];
              if (particle_damping != 0)
                A_damp += particle_damping * (*V_n)[q];
              batch.velocity[q] -= A_damp * control.time_step();
              batch.position[q] -=
                A_damp * (0.5 * control.time_step() * control.time_step());
            }

        // Energy dissipated compared with non-dissipative FLIP (seed 003
        // Eqs. 1.44-1.45): M [A_g→p Δt·(V_g→p + A_g→p Δt/2) − ΔV·ΔX/Δt].
        if (track_dissipation)
          for (unsigned int q = 0; q < n_points; ++q)
            {
              const double         M = mass_column[first_point + q];
              const Tensor<1, dim> a_dt =
                batch.grid[ParticleUpdate::acceleration][q] *
                control.time_step();
              const Tensor<1, dim> &v_g =
                batch.grid[ParticleUpdate::velocity][q];
              const Tensor<1, dim> dV = batch.velocity[q] - old_velocity[q];
              const Tensor<1, dim> dX_dt =
                (batch.position[q] - old_position[q]) / control.time_step();
              local_dissipation += M * (a_dt * (v_g + 0.5 * a_dt) - dV * dX_dt);
            }

        // Scatter the new V and X, and the new reference location of each
        // point still in its cell (the batch has read its supports; later
        // passes of the step read the support cache's copy of ξ); the
        // others are re-binned at the step's end.
        for (unsigned int q = 0; q < n_points; ++q)
          {
            const unsigned int    k  = first_point + q;
            const Tensor<1, dim> &V  = batch.velocity[q];
            const double          V2 = V * V;
            if (!std::isfinite(V2) && local_failure.empty())
              {
                std::ostringstream message;
                message << "velocity of material point " << points.id[k]
                        << " at (" << points.position[k]
                        << ") is not finite (NaN or Inf)";
                local_failure = message.str();
              }
            max_V2 = std::max(max_V2, V2);
            for (unsigned int d = 0; d < dim; ++d)
              velocity_column[d][k] = V[d];
            // Points do not enter a moving wall's box.
            if (has_moving_walls)
              velocity_conditions.push_out_of_walls(batch.position[q]);
            points.position[k] = batch.position[q];
            if (re_extrapolate)
              re_extrapolate_point(k, data, V);
            const Point<dim> xi =
              GridTransfer<dim>::reference_point(data,
                                                 batch.position[q],
                                                 points.reference_position[k]);
            if (GridTransfer<dim>::is_inside(xi))
              points.reference_position[k] = xi;
            else
              points_that_left_their_cell.push_back(k);
          }
      }
    local_max_point_speed = std::sqrt(max_V2);
  }



  template <int dim>
  void
  Simulator<dim>::update_stresses(const ParticleUpdate::GridField field,
                                  const double                    dt,
                                  const bool                      with_forces)
  {
    // The velocities of the centre of mass, or with contact of the group's
    // material (Eq. 28); their solves time themselves.
    const bool contact = contact_active();
    if (contact)
      this->contact->compute_field(field);
    else
      compute_field(field);
    TimerOutput::Scope timer(computing_timer, "stress update");
    using Index                                 = PropertyIndex<dim>;
    const unsigned int              n_materials = constitutive_models.size();
    const DeformationGradientUpdate F_update =
      parameters.method.deformation_gradient_update;
    // The batch's entry arrays (zero: in 2D the out-of-plane entries stay
    // so).
    ConstitutiveModel::StressUpdateInputs  inputs;
    ConstitutiveModel::StressUpdateOutputs outputs;
    inputs.time_step = dt;
    BatchEntries  dF, F_gathered;
    double        wave_speed = 0;
    const double *v_a[dim];
    auto          view_velocities = [&](const GridVectorField &v) {
      for (unsigned int a = 0; a < dim; ++a)
        v_a[a] = v.block(a).begin();
    };
    view_velocities(centre_of_mass.fields[field]);
    SupportReader<dim> support_of(supports, transfer, points.cell.data());
    // Computed supports: S and G of the batch's points (by place in the
    // batch).
    constexpr unsigned int              n_nodes = GridTransfer<dim>::n_nodes;
    std::array<double, n_nodes>         batch_S[stress_batch_size];
    std::array<Tensor<1, dim>, n_nodes> batch_G[stress_batch_size];
    const unsigned int                 *batch_node[stress_batch_size];

    // USF/USAVG: f (and with contact f^α0, Eq. 29) from the new stresses
    // in this sweep, each batch's points in the store's order once their
    // stresses are updated.
    const ForceColumns    force_columns(points);
    double               *f[dim];
    std::vector<double *> f_alpha;
    Tensor<1, dim>        gravity;
    const bool            uniform_body_force = !has_point_body_force();
    if (with_forces)
      {
        // (With contact f is set from the f^α0 after the sweep.)
        if (!contact)
          centre_of_mass.force = 0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            f[d]       = centre_of_mass.force.block(d).begin();
            gravity[d] = parameters.gravity[d];
          }
        if (contact)
          for (auto &material_field : this->contact->material_fields())
            {
              material_field.force = 0;
              for (unsigned int d = 0; d < dim; ++d)
                f_alpha.push_back(material_field.force.block(d).begin());
            }
      }

    // Cell sizes (Eq. 52's Δx) only for models that read them, by active
    // cell index for the cells with points.
    bool needs_cell_size = false;
    for (const auto &model : constitutive_models)
      needs_cell_size = needs_cell_size || model->needs_cell_size();
    if (needs_cell_size)
      {
        cell_size_by_index.resize(triangulation.n_active_cells());
        for (unsigned int c = 0; c < points.n_cells(); ++c)
          cell_size_by_index[points.cell_index[c]] =
            points.cell_iterator(c)->minimum_vertex_distance();
      }

    // Points of a batch grouped by material for the model call (one group
    // when the scene has one material).
    std::vector<std::vector<unsigned int>> by_material(n_materials);
    for (auto &group : by_material)
      group.reserve(stress_batch_size);
    unsigned int group_points[stress_batch_size];
    double       J_of_group[stress_batch_size];
    // F (row major) and σ in the store. In 2D (plane strain) only the 2x2
    // block and F_33 of F, and σ_xx, σ_yy, σ_zz, σ_xy are stored: the other
    // entries are zero and are not written.
    double                *F_column[9], *stress_column[6];
    constexpr unsigned int n_stress_entries = dim == 3 ? 6 : 4;
    for (unsigned int c = 0; c < 9; ++c)
      F_column[c] = points.column(Index::deformation_gradient + c);
    for (unsigned int c = 0; c < 6; ++c)
      stress_column[c] = points.column(Index::stress + c);
    double *const energy_column = points.column(Index::strain_energy_density);
    double *const volume_column = points.column(Index::volume);
    const double *const initial_volume_column =
      points.column(Index::initial_volume);

    for (unsigned int batch_begin = 0; batch_begin < supports.n_points();
         batch_begin += stress_batch_size)
      {
        const unsigned int batch_end =
          std::min(batch_begin + stress_batch_size, supports.n_points());
        if (n_materials > 1)
          {
            for (unsigned int m = 0; m < n_materials; ++m)
              by_material[m].clear();
            for (unsigned int k = batch_begin; k < batch_end; ++k)
              by_material[supports.material[k]].push_back(k);
          }

        for (unsigned int m = 0; m < n_materials; ++m)
          {
            const unsigned int n_group = n_materials == 1 ?
                                           batch_end - batch_begin :
                                           by_material[m].size();
            if (n_group == 0)
              continue;
            if (n_materials == 1)
              std::iota(group_points, group_points + n_group, batch_begin);
            else
              std::copy(by_material[m].begin(),
                        by_material[m].end(),
                        group_points);
            // (one material: the batch, stored one after another)
            const unsigned int k0 = group_points[0];
            const bool         contiguous =
              group_points[n_group - 1] == k0 + n_group - 1;
            if (contact)
              view_velocities(
                this->contact->material_fields()[m].fields[field]);
            inputs.resize(n_group);
            inputs.reference_density = parameters.materials[m].density;
            if (constitutive_models[m]->needs_cell_size())
              for (unsigned int q = 0; q < n_group; ++q)
                inputs.cell_size[q] =
                  cell_size_by_index[points.cell[group_points[q]]];
            // L = ∇v = Σ_i v_i ⊗ G_pi (Eqs. 2.7, 2.18), plane strain in 2D;
            // σ^n, W^n and the history slots if the model reads them.
            for (unsigned int q = 0; q < n_group; ++q)
              {
                const unsigned int k = group_points[q];
                if (supports.implicit_classic)
                  {
                    // Computed once for L and the forces.
                    const unsigned int b = k - batch_begin;
                    const auto &cell     = transfer.cell_data(points.cell[k]);
                    support_of.compute(k, cell, true, batch_S[b], batch_G[b]);
                    batch_node[b] = cell.local_index.data();
                    velocity_gradient<dim>(
                      batch_node[b],
                      batch_G[b].data(),
                      0,
                      std::integral_constant<unsigned int, n_nodes>(),
                      v_a,
                      inputs.velocity_gradient,
                      q);
                  }
                else
                  support_of.visit(k,
                                   true,
                                   [&](const unsigned int *const node,
                                       const double *,
                                       const Tensor<1, dim> *const G,
                                       const auto                  n_entries) {
                                     velocity_gradient<dim>(
                                       node,
                                       G,
                                       0,
                                       n_entries,
                                       v_a,
                                       inputs.velocity_gradient,
                                       q);
                                   });
              }
            if (constitutive_models[m]->reads_old_state())
              {
                if (contiguous)
                  {
                    for (unsigned int c = 0; c < n_stress_entries; ++c)
                      std::copy(stress_column[c] + k0,
                                stress_column[c] + k0 + n_group,
                                inputs.old_stress[c]);
                    std::copy(energy_column + k0,
                              energy_column + k0 + n_group,
                              inputs.old_strain_energy_density);
                  }
                else
                  for (unsigned int q = 0; q < n_group; ++q)
                    {
                      const unsigned int k = group_points[q];
                      for (unsigned int c = 0; c < n_stress_entries; ++c)
                        inputs.old_stress[c][q] = stress_column[c][k];
                      inputs.old_strain_energy_density[q] = energy_column[k];
                    }
                for (unsigned int q = 0; q < n_group; ++q)
                  inputs.properties[q] = points.record(group_points[q]);
              }
            if (constitutive_models[m]->needs_old_volume_ratio())
              for (unsigned int q = 0; q < n_group; ++q)
                inputs.old_volume_ratio[q] =
                  volume_column[group_points[q]] /
                  initial_volume_column[group_points[q]];
            auto &F = inputs.deformation_gradient;
            auto &J = inputs.volume_ratio;
            if (F_update == DeformationGradientUpdate::cayley)
              {
                // F^n: the store's columns, or gathered for a group spread
                // over the batch (several materials).
                std::array<const double *, 9> F_old;
                for (unsigned int c = 0; c < 9; ++c)
                  if (contiguous)
                    F_old[c] = F_column[c] + k0;
                  else
                    {
                      for (unsigned int q = 0; q < n_group; ++q)
                        F_gathered[c][q] = F_column[c][group_points[q]];
                      F_old[c] = F_gathered[c];
                    }
                cayley_update<dim>(
                  n_group, dt, inputs.velocity_gradient, F_old, F, J);
              }
            else
              {
                increments<dim>(F_update,
                                parameters.method,
                                inputs.velocity_gradient,
                                dt,
                                n_group,
                                dF);
                // F^{n+1} = ΔF F^n and J = det F^{n+1} (the operations of
                // deal.II's Tensor product and determinant()); in 2D on the
                // 2x2 block, F_33 kept (plane strain).
                for (unsigned int q = 0; q < n_group; ++q)
                  {
                    const unsigned int k = group_points[q];
                    if constexpr (dim == 2)
                      {
                        const double a = F_column[0][k], b = F_column[1][k],
                                     c = F_column[3][k], e = F_column[4][k];
                        F[0][q] = dF[0][q] * a + dF[1][q] * c;
                        F[1][q] = dF[0][q] * b + dF[1][q] * e;
                        F[3][q] = dF[3][q] * a + dF[4][q] * c;
                        F[4][q] = dF[3][q] * b + dF[4][q] * e;
                        F[8][q] = F_column[8][k];
                      }
                    else
                      for (unsigned int a = 0; a < 3; ++a)
                        for (unsigned int b = 0; b < 3; ++b)
                          F[3 * a + b][q] =
                            dF[3 * a][q] * F_column[b][k] +
                            dF[3 * a + 1][q] * F_column[3 + b][k] +
                            dF[3 * a + 2][q] * F_column[6 + b][k];
                  }
                for (unsigned int q = 0; q < n_group; ++q)
                  if constexpr (dim == 2)
                    // The same value without the plane-strain zeros' products.
                    J[q] = F[0][q] * (F[4][q] * F[8][q]) -
                           F[1][q] * (F[3][q] * F[8][q]);
                  else
                    {
                      const double C0 = F[4][q] * F[8][q] - F[5][q] * F[7][q];
                      const double C1 = F[5][q] * F[6][q] - F[3][q] * F[8][q];
                      const double C2 = F[3][q] * F[7][q] - F[4][q] * F[6][q];
                      J[q] = F[0][q] * C0 + F[1][q] * C1 + F[2][q] * C2;
                    }
              }
            for (unsigned int q = 0; q < n_group; ++q)
              if (!(J[q] > 0) && local_failure.empty())
                {
                  const unsigned int k = group_points[q];
                  std::ostringstream message;
                  message << "material point " << points.id[k] << " at ("
                          << points.position[k]
                          << ") has an inverted deformation gradient, J = "
                          << J[q];
                  local_failure = message.str();
                }

            outputs.failed_point = -1;
            constitutive_models[m]->update_stress(inputs, outputs);
            if (outputs.failed_point >= 0 && local_failure.empty())
              {
                const unsigned int k = group_points[outputs.failed_point];
                std::ostringstream message;
                message << "material point " << points.id[k] << " at ("
                        << points.position[k] << ") " << outputs.failure;
                local_failure = message.str();
              }

            // F, σ, W and V = J V0 into the store (in 2D the plane-strain
            // zero entries are not stored; F_33 is unchanged).
            if (contiguous)
              {
                for (unsigned int c = 0; c < 9; ++c)
                  if (dim == 3 || c == 0 || c == 1 || c == 3 || c == 4)
                    std::copy(F[c], F[c] + n_group, F_column[c] + k0);
                for (unsigned int c = 0; c < n_stress_entries; ++c)
                  std::copy(outputs.cauchy_stress[c],
                            outputs.cauchy_stress[c] + n_group,
                            stress_column[c] + k0);
                std::copy(outputs.strain_energy_density,
                          outputs.strain_energy_density + n_group,
                          energy_column + k0);
                for (unsigned int q = 0; q < n_group; ++q)
                  {
                    volume_column[k0 + q] =
                      J[q] * initial_volume_column[k0 + q];
                    J_of_group[q] = J[q] > 0 ? J[q] : 1;
                  }
              }
            else
              for (unsigned int q = 0; q < n_group; ++q)
                {
                  const unsigned int k = group_points[q];
                  for (unsigned int c = 0; c < 9; ++c)
                    if (dim == 3 || c == 0 || c == 1 || c == 3 || c == 4)
                      F_column[c][k] = F[c][q];
                  for (unsigned int c = 0; c < n_stress_entries; ++c)
                    stress_column[c][k] = outputs.cauchy_stress[c][q];
                  energy_column[k] = outputs.strain_energy_density[q];
                  volume_column[k] = J[q] * initial_volume_column[k];
                  // Inverted points are reported above; they give no speed.
                  J_of_group[q] = J[q] > 0 ? J[q] : 1;
                }
            for (unsigned int q = 0; q < n_group; ++q)
              if (!std::isfinite(outputs.strain_energy_density[q]) &&
                  local_failure.empty())
                {
                  const unsigned int k = group_points[q];
                  std::ostringstream message;
                  message << "stress of material point " << points.id[k]
                          << " at (" << points.position[k]
                          << ") is not finite (NaN or Inf)";
                  local_failure = message.str();
                }
            if (constitutive_models[m]->computes_wave_speed())
              for (unsigned int q = 0; q < n_group; ++q)
                wave_speed = std::max(wave_speed, outputs.wave_speed[q]);
            else
              wave_speed =
                std::max(wave_speed,
                         constitutive_models[m]->max_wave_speed(
                           parameters.materials[m].density,
                           ArrayView<const double>(J_of_group, n_group)));
          }
        if (with_forces)
          for (unsigned int k = batch_begin; k < batch_end; ++k)
            {
              // (with contact f^α0 of the point's material, Eq. 29)
              double *const *f_target =
                contact ? &f_alpha[supports.material[k] * dim] : f;
              if (supports.implicit_classic)
                {
                  const unsigned int b = k - batch_begin;
                  scatter_point_force(
                    k,
                    batch_node[b],
                    batch_S[b].data(),
                    batch_G[b].data(),
                    std::integral_constant<unsigned int, n_nodes>(),
                    force_columns,
                    gravity,
                    uniform_body_force,
                    f_target);
                }
              else
                support_of.visit(k,
                                 true,
                                 [&](const unsigned int *const   node,
                                     const double *const         S,
                                     const Tensor<1, dim> *const G,
                                     const auto                  n_entries)
                                   DEAL_II_ALWAYS_INLINE {
                                     scatter_point_force(k,
                                                         node,
                                                         S,
                                                         G,
                                                         n_entries,
                                                         force_columns,
                                                         gravity,
                                                         uniform_body_force,
                                                         f_target);
                                   });
            }
      }
    local_max_wave_speed = wave_speed;
    if (with_forces)
      {
        if (contact) // f = Σ_α f^α0
          centre_of_mass.set_to_sum(this->contact->material_fields(),
                                    false,
                                    false,
                                    true);
        centre_of_mass.force.compress(VectorOperation::add);
        if (contact)
          for (auto &material_field : this->contact->material_fields())
            material_field.force.compress(VectorOperation::add);
      }
  }



  template <int dim>
  void
  Simulator<dim>::sort_particles_into_cells()
  {
    TimerOutput::Scope timer(computing_timer, "sort points into cells");
    // The particle update set the reference positions of the points that
    // stayed in their cells. Each of the others gets the cell that now holds
    // it, searched around its old cell: a locally owned cell takes it in the
    // store, a ghost cell's owner receives it (one point-to-point exchange of
    // only these points), and the store puts its points back in cell order.
    // A point not found nearby or outside the mesh: deal.II's sort handles
    // every point (and reports lost points).
    // Mesh/Periodic directions: the box's length along each periodic axis.
    // A point that crosses a periodic face enters through the opposite one:
    // its position and initial position shift by the length (u = x − X
    // and F are kept).
    Tensor<1, dim> period;
    for (unsigned int d = 0; d < dim; ++d)
      if (parameters.mesh.periodic[d])
        period[d] =
          parameters.mesh.upper_corner[d] - parameters.mesh.lower_corner[d];
    const auto shift_point = [this](const unsigned int    k,
                                    const Tensor<1, dim> &shift) {
      points.position[k] += shift;
      for (unsigned int d = 0; d < dim; ++d)
        points.column(PropertyIndex<dim>::initial_position + d)[k] += shift[d];
    };
    auto full_sort = [&]() {
      points_that_left_their_cell.clear();
      if (parameters.mesh.any_periodic())
        for (unsigned int k = 0; k < points.n_points(); ++k)
          {
            Tensor<1, dim> shift;
            for (unsigned int d = 0; d < dim; ++d)
              if (period[d] > 0)
                {
                  const double x = points.position[k][d];
                  if (x < parameters.mesh.lower_corner[d])
                    shift[d] = period[d];
                  else if (x >= parameters.mesh.upper_corner[d])
                    shift[d] = -period[d];
                }
            if (shift.norm_square() > 0)
              shift_point(k, shift);
          }
      points_to_handler();
      particle_handler.sort_particles_into_subdomains_and_cells();
      points_from_handler();
    };
    if (!parameters.fast_point_sorting)
      {
        full_sort();
        return;
      }
    point_moves.clear();
    std::uint64_t n_sent         = 0;
    bool          need_full_sort = false;
    Point<dim>    center;
    for (unsigned int d = 0; d < dim; ++d)
      center[d] = 0.5;
    Assert(std::is_sorted(points_that_left_their_cell.begin(),
                          points_that_left_their_cell.end()),
           ExcInternalError());
    unsigned int cell_with_points = 0;
    for (const unsigned int k : points_that_left_their_cell)
      {
        // The points that left are listed in store order: the cell's place
        // follows with a cursor.
        while (points.cell_point_begin[cell_with_points + 1] <= k)
          ++cell_with_points;
        const auto       cell = points.cell_iterator(cell_with_points);
        const Point<dim> x    = points.position[k];

        // The new cell: across the face the point crossed, from neighbour
        // to neighbour (a corner takes two steps); where that meets a
        // boundary, a finer neighbour or an artificial cell, the cells
        // around the old cell's vertices.
        // Across a periodic face the walk goes on in the twin cell, with x
        // shifted by the period (x_walk).
        typename Triangulation<dim>::active_cell_iterator target;
        Point<dim>                                        xi;
        Point<dim>                                        x_walk = x;
        {
          auto       walk    = cell;
          Point<dim> xi_walk = GridTransfer<dim>::reference_point(
            transfer.cell_data(cell->active_cell_index()), x, center);
          for (unsigned int hop = 0; hop <= dim; ++hop)
            {
              unsigned int face = numbers::invalid_unsigned_int;
              for (unsigned int d = 0; d < dim; ++d)
                if (xi_walk[d] < -1e-12 || xi_walk[d] > 1 + 1e-12)
                  {
                    face = 2 * d + (xi_walk[d] > 1 ? 1 : 0);
                    break;
                  }
              if (face == numbers::invalid_unsigned_int)
                {
                  if (walk != cell)
                    {
                      target = walk;
                      xi     = xi_walk;
                    }
                  break;
                }
              if (walk->at_boundary(face))
                {
                  if (!walk->has_periodic_neighbor(face) ||
                      walk->periodic_neighbor(face)->has_children())
                    break;
                  x_walk[face / 2] +=
                    (face % 2 == 1 ? -1. : 1.) * period[face / 2];
                  walk = walk->periodic_neighbor(face);
                }
              else if (walk->neighbor(face)->has_children())
                break;
              else
                walk = walk->neighbor(face);
              if (walk->is_artificial())
                break;
              xi_walk = GridTransfer<dim>::reference_point(
                transfer.cell_data(walk->active_cell_index()), x_walk, center);
            }
          if (target.state() == IteratorState::valid && x_walk != x)
            shift_point(k, x_walk - x);
        }
        if (target.state() != IteratorState::valid)
          for (const unsigned int v : cell->vertex_indices())
            {
              for (const auto &other : vertex_to_cells[cell->vertex_index(v)])
                {
                  const auto candidate = vertex_to_cells.iterator(other);
                  if (candidate == cell || candidate->is_artificial())
                    continue;
                  xi = GridTransfer<dim>::reference_point(
                    transfer.cell_data(candidate->active_cell_index()),
                    x,
                    center);
                  if (GridTransfer<dim>::is_inside(xi))
                    {
                      target = candidate;
                      break;
                    }
                }
              if (target.state() == IteratorState::valid)
                break;
            }
        if (target.state() == IteratorState::valid)
          {
            point_moves.push_back({k, target, xi});
            if (!target->is_locally_owned())
              ++n_sent;
          }
        else
          need_full_sort = true;
      }
    // One reduction: does any rank need the full sort, how many points left
    // their cells and how many their rank, on all ranks (the same decision
    // on every rank).
    const std::uint64_t local_counts[3] = {need_full_sort ? 1u : 0u,
                                           points_that_left_their_cell.size(),
                                           n_sent};
    std::uint64_t global_counts[3] = {0, 0, 0};
    Utilities::MPI::sum(make_array_view(local_counts),
                        mpi_communicator,
                        make_array_view(global_counts));
    points_that_left_their_cell.clear();
    if (global_counts[0] != 0)
      {
        full_sort();
        return;
      }
    if (global_counts[1] == 0)
      return;

    // Per receiving rank, per point: id, x, the new cell's CellId (binary),
    // the properties.
    const unsigned int n_properties = points.n_properties();
    std::map<unsigned int, std::vector<double>> sent;
    for (const PointMove &move : point_moves)
      if (move.cell->is_locally_owned())
        points.move(move.k, move.cell, move.xi);
      else
        {
          std::vector<double> &buffer = sent[move.cell->subdomain_id()];
          buffer.push_back(points.id[move.k]);
          for (unsigned int d = 0; d < dim; ++d)
            buffer.push_back(points.position[move.k][d]);
          for (const unsigned int word :
               move.cell->id().template to_binary<dim>())
            buffer.push_back(word);
          const std::size_t first = buffer.size();
          buffer.resize(first + n_properties);
          points.copy_record(move.k, buffer.data() + first);
          points.remove(move.k);
        }
    // Only the points that change rank travel, to the owners of their new
    // cells. A new cell is owned or a ghost cell, so each rank exchanges
    // one message (empty if no point moves) with each owner of its ghost
    // cells: a neighbour exchange without collectives. With one ghost layer
    // the ghost owners are symmetric (a ghost cell touches an owned cell,
    // so that cell is a ghost cell on the other rank). The full sort covers
    // everything else.
    if (global_counts[2] != 0)
      {
        const std::vector<unsigned int> neighbours(
          triangulation.ghost_owners().begin(),
          triangulation.ghost_owners().end());
        const std::map<unsigned int, std::vector<double>> received =
          neighbour_exchange(mpi_communicator,
                             neighbours,
                             neighbours,
                             sent,
                             MPITags::point_exchange);
        const unsigned int record = 1 + dim + 4 + n_properties;
        for (const auto &from_rank : received)
          {
            const std::vector<double> &buffer = from_rank.second;
            AssertDimension(buffer.size() % record, 0);
            for (std::size_t r = 0; r < buffer.size(); r += record)
              {
                const double *const entry = buffer.data() + r;
                Point<dim>          x;
                for (unsigned int d = 0; d < dim; ++d)
                  x[d] = entry[1 + d];
                CellId::binary_type binary;
                for (unsigned int w = 0; w < 4; ++w)
                  binary[w] = static_cast<unsigned int>(entry[1 + dim + w]);
                const typename Triangulation<dim>::active_cell_iterator cell =
                  triangulation.create_cell_iterator(CellId(binary));
                Assert(cell->is_locally_owned(), ExcInternalError());
                const Point<dim> xi = GridTransfer<dim>::reference_point(
                  transfer.cell_data(cell->active_cell_index()), x, center);
                points.add(static_cast<types::particle_index>(entry[0]),
                           x,
                           xi,
                           cell,
                           entry + 1 + dim + 4);
              }
          }
      }
    points.rebin();
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
