// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/external_loads.h>
#include <fmpm/function_parser.h>

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
    if (!traction_functions.empty())
      {
        // The traction force as an acceleration, F_p / M_p (Eq. 2.10).
        const Tensor<1, dim> F_p = traction_force(points, k);
        b += F_p / p[Index::mass];
        local_traction_power += F_p * V;
        local_traction_magnitude += F_p.norm();
      }
    return b;
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
