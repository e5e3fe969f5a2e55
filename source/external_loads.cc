// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/external_loads.h>
#include <fmpm/function_parser.h>
#include <fmpm/shape_function.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace fmpm
{
  template <int dim>
  void
  ExternalLoads<dim>::initialize(const Parameters        &parameters,
                                 ParticleProperties<dim> &properties)
  {
    for (unsigned int d = 0; d < dim; ++d)
      gravity_vector[d] = parameters.gravity[d];
    if (!parameters.body_acceleration.empty())
      {
        auto function = std::make_unique<FunctionParser<dim>>(dim);
        parse_function(
          *function,
          "Body force/Acceleration",
          parameters.body_acceleration,
          to_function_expressions(parameters.body_acceleration),
          FunctionParser<dim>::default_variable_names() + ",t",
          parse_function_constants(parameters.body_acceleration_constants,
                                   "Body force/Function constants"),
          true,
          std::to_string(dim) + " expressions in x, y" +
            (dim == 3 ? ", z" : "") + ", t");
        body_acceleration = std::move(function);
      }
    body_acceleration_at_initial_position =
      parameters.body_acceleration_at_initial_position;

    tractions    = parameters.boundary_conditions.tractions;
    axisymmetric = parameters.axisymmetric;
    if (!tractions.empty())
      traction_slot = properties.request("traction", 2);
    for (const auto &traction : tractions)
      (traction.on_face ? has_face_traction : has_point_tractions) = true;
    if (has_face_traction)
      AssertThrow(!ShapeFunction::is_bspline(
                    ShapeFunction::parse(parameters.method.shape_function)),
                  ExcMessage("Boundary conditions/Traction N/Distribution = "
                             "face needs a shape function on the linear grid: "
                             "Shape function/Type = classic, ugimp, cpgimp or "
                             "cpdi, not " +
                             parameters.method.shape_function + "."));
    for (unsigned int n = 0; n < tractions.size(); ++n)
      {
        const std::string where =
          "Boundary conditions/" + numbered_subsection("Traction", n);
        auto function = std::make_unique<FunctionParser<1>>(dim);
        parse_function(*function,
                       where + "/Traction",
                       tractions[n].traction,
                       to_function_expressions(tractions[n].traction),
                       "x,t",
                       parse_function_constants(tractions[n].constants,
                                                where + "/Function constants"),
                       true,
                       std::to_string(dim) + " expressions in t");
        traction_functions.push_back(std::move(function));
      }

    const auto &frame = parameters.rotating_frame;
    if (frame.enable)
      {
        angular_velocity = std::make_unique<FunctionParser<1>>(3);
        parse_function(*angular_velocity,
                       "Body force/Rotating frame/Angular velocity",
                       frame.angular_velocity,
                       to_function_expressions(frame.angular_velocity),
                       "x,t",
                       parse_function_constants(
                         frame.constants,
                         "Body force/Rotating frame/Function constants"),
                       true,
                       "3 expressions in t");
        for (unsigned int d = 0; d < dim; ++d)
          frame_center[d] = frame.center[d];
      }
  }



  template <int dim>
  void
  ExternalLoads<dim>::mark_traction_points(MaterialPoints<dim> &points) const
  {
    if (traction_slot == numbers::invalid_unsigned_int)
      return;
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const PointRecord p = points.record(k);
        const Point<dim>  X(
          get_vector<dim>(p, PropertyIndex<dim>::initial_position));
        for (unsigned int n = 0; n < tractions.size(); ++n)
          {
            const auto &traction = tractions[n];
            bool        inside   = true;
            for (unsigned int d = 0; d < dim; ++d)
              inside = inside && X[d] >= traction.box_lower[d] &&
                       X[d] <= traction.box_upper[d];
            if (!inside)
              continue;
            double area = 1;
            for (unsigned int d = 0; d < dim; ++d)
              if (d != traction.normal_axis)
                area *= 2 * p[PropertyIndex<dim>::initial_half_length + d];
            // Axisymmetric: the face area per radian, ∫ r dA over the face:
            // a face z = const 2 l_r r_p; a face r = const 2 l_z r_f, r_f
            // the point's side toward the traction box's centre.
            if (axisymmetric)
              {
                double face_r = X[0];
                if (traction.normal_axis == 0)
                  {
                    const double l = p[PropertyIndex<dim>::initial_half_length];
                    face_r += X[0] < 0.5 * (traction.box_lower[0] +
                                            traction.box_upper[0]) ?
                                l :
                                -l;
                  }
                area *= face_r;
              }
            p[traction_slot]     = n + 1;
            p[traction_slot + 1] = area;
          }
      }
  }



  template <int dim>
  void
  ExternalLoads<dim>::begin_step(const double t)
  {
    if (body_acceleration)
      body_acceleration->set_time(t);
    for (auto &traction : traction_functions)
      traction->set_time(t);
    if (angular_velocity)
      {
        // ω̇ by a central difference over ±δt around t.
        FunctionParser<1> &omega_function = *angular_velocity;
        omega_function.set_time(t);
        const double dt = 1e-6 * std::max(1.0, std::abs(t));
        for (unsigned int d = 0; d < 3; ++d)
          omega[d] = omega_function.value(Point<1>(), d);
        omega_function.set_time(t + dt);
        for (unsigned int d = 0; d < 3; ++d)
          omega_dot[d] = omega_function.value(Point<1>(), d);
        omega_function.set_time(t - dt);
        for (unsigned int d = 0; d < 3; ++d)
          omega_dot[d] =
            (omega_dot[d] - omega_function.value(Point<1>(), d)) / (2 * dt);
        omega_function.set_time(t);
      }
  }



  template <int dim>
  Tensor<1, dim>
  ExternalLoads<dim>::body_acceleration_at(
    const Point<dim>     &x,
    const Tensor<1, dim> &V,
    const Point<dim>     &expression_point) const
  {
    Tensor<1, dim> b = gravity_vector;
    if (body_acceleration)
      for (unsigned int d = 0; d < dim; ++d)
        b[d] += body_acceleration->value(expression_point, d);
    if (angular_velocity)
      {
        Tensor<1, 3> r, v;
        for (unsigned int d = 0; d < dim; ++d)
          {
            r[d] = x[d] - frame_center[d];
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
  ExternalLoads<dim>::traction_force(const MaterialPoints<dim> &points,
                                     const unsigned int         k) const
  {
    Tensor<1, dim> F;
    const int      index =
      static_cast<int>(points.column(traction_slot)[k] + 0.5) - 1;
    if (index < 0)
      return F;
    // F_p = t(t) A_p, the f_T term of Eq. 2.10 (at mid-step, like b).
    const double area = points.column(traction_slot + 1)[k];
    for (unsigned int d = 0; d < dim; ++d)
      F[d] = traction_functions[index]->value(Point<1>(), d) * area;
    return F;
  }



  template <int dim>
  Tensor<1, dim>
  ExternalLoads<dim>::acceleration(const MaterialPoints<dim> &points,
                                   const unsigned int         k)
  {
    using Index            = PropertyIndex<dim>;
    const PointRecord    p = points.record(k);
    const Point<dim>    &x = points.position[k];
    const Tensor<1, dim> V = get_vector<dim>(p, Index::velocity);
    Tensor<1, dim>       b =
      body_acceleration_at_initial_position ?
              body_acceleration_at(
          x, V, Point<dim>(get_vector<dim>(p, Index::initial_position))) :
              body_acceleration_at(x, V, x);
    if (has_point_tractions)
      {
        // The traction force as an acceleration, F_p / M_p (Eq. 2.10).
        const int index =
          static_cast<int>(points.column(traction_slot)[k] + 0.5) - 1;
        if (index >= 0 && tractions[index].on_face)
          return b;
        const Tensor<1, dim> F_p = traction_force(points, k);
        b += F_p / p[Index::mass];
        local_traction_power += F_p * V;
        local_traction_magnitude += F_p.norm();
      }
    return b;
  }



  template <int dim>
  void
  ExternalLoads<dim>::add_face_traction_forces(
    const MaterialPoints<dim> &points,
    const GridTransfer<dim>   &transfer,
    double *const *const       f)
  {
    if (!has_face_traction)
      return;
    using Index = PropertyIndex<dim>;
    // Gauss-Legendre with two points on each half of the face's
    // parameter range [-1, 1] along each of its directions: exact for the
    // r-weighted bilinear N_i where a half lies in one cell.
    constexpr unsigned int     n_pieces = 2;
    constexpr unsigned int     n_line   = 2 * n_pieces;
    std::array<double, n_line> s_line;
    const double               g = 1 / std::sqrt(3.);
    for (unsigned int q = 0; q < n_pieces; ++q)
      {
        const double centre = -1 + (2 * q + 1) / double(n_pieces);
        s_line[2 * q]       = centre - g / n_pieces;
        s_line[2 * q + 1]   = centre + g / n_pieces;
      }
    const double       weight_line = 1. / n_pieces;
    const unsigned int n_gauss     = dim == 2 ? n_line : n_line * n_line;

    const double *const slot = points.column(traction_slot);
    std::array<double, GridTransfer<dim>::n_nodes> N;
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const int index = static_cast<int>(slot[k] + 0.5) - 1;
        if (index < 0 || !tractions[index].on_face)
          continue;
        const TractionParameters &traction = tractions[index];
        const unsigned int        a        = traction.normal_axis;
        const PointRecord         p        = points.record(k);
        Tensor<1, dim>            t;
        for (unsigned int d = 0; d < dim; ++d)
          t[d] = traction_functions[index]->value(Point<1>(), d);
        Tensor<2, dim> F;
        for (unsigned int i = 0; i < dim; ++i)
          for (unsigned int j = 0; j < dim; ++j)
            F[i][j] = p[Index::deformation_gradient + 3 * i + j];
        // The face: the point's side toward the box's centre, and its
        // half edges T_j along the other axes, deformed by F.
        const double   X_a = p[Index::initial_position + a];
        Tensor<1, dim> offset;
        offset[a] =
          (X_a < 0.5 * (traction.box_lower[a] + traction.box_upper[a]) ? 1 :
                                                                         -1) *
          p[Index::initial_half_length + a];
        const Point<dim> centre = points.position[k] + F * offset;
        std::array<Tensor<1, dim>, dim - 1> T;
        for (unsigned int d = 0, j = 0; d < dim; ++d)
          if (d != a)
            {
              Tensor<1, dim> half_edge;
              half_edge[d] = p[Index::initial_half_length + d];
              T[j++]       = F * half_edge;
            }
        double jacobian;
        if constexpr (dim == 2)
          jacobian = T[0].norm();
        else
          jacobian = cross_product_3d(T[0], T[1]).norm();

        Tensor<1, dim> F_p;
        for (unsigned int q = 0; q < n_gauss; ++q)
          {
            Point<dim> x      = centre;
            double     weight = jacobian;
            for (unsigned int j = 0; j < dim - 1; ++j)
              {
                const unsigned int q_j = j == 0 ? q % n_line : q / n_line;
                x += s_line[q_j] * T[j];
                weight *= weight_line;
              }
            if (axisymmetric)
              weight *= x[0];
            typename GridTransfer<dim>::Location location;
            AssertThrow(
              transfer.locate(points.cell[k], x, points.cell[k], location) ==
                GridTransfer<dim>::LocateStatus::found,
              ExcMessage("Boundary conditions/Traction " +
                         std::to_string(index) +
                         "/Distribution = face: the face of a "
                         "loaded point at " +
                         Utilities::to_string(x[0]) +
                         ", ... lies outside its cell's patch "
                         "(with Shape function/Type = classic the "
                         "face must lie in the point's cell)."));
            GridTransfer<dim>::values(location.xi, N);
            const auto &cell = transfer.cell_data(location.cell);
            for (unsigned int i = 0; i < N.size(); ++i)
              for (unsigned int d = 0; d < dim; ++d)
                f[d][cell.local_index[i]] += N[i] * weight * t[d];
            F_p += weight * t;
          }
        local_traction_power += F_p * get_vector<dim>(p, Index::velocity);
        local_traction_magnitude += F_p.norm();
      }
  }



  template <int dim>
  void
  ExternalLoads<dim>::add_step_work(const double   wall_work,
                                    const double   dt,
                                    const double   mesh_diameter,
                                    const MPI_Comm communicator)
  {
    std::vector<double> traction = {local_traction_power,
                                    local_traction_magnitude};
    Utilities::MPI::sum(traction, communicator, traction);
    const double work    = wall_work + traction[0] * dt;
    local_traction_power = local_traction_magnitude = 0;
    external_work += work;
    // The work the tractions can do across the mesh bounds the growth.
    external_work_scale = std::max(external_work_scale + std::abs(work),
                                   traction[1] * mesh_diameter);
  }



  template class ExternalLoads<2>;
  template class ExternalLoads<3>;
} // namespace fmpm
