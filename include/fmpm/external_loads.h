// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_external_loads_h
#define fmpm_external_loads_h

#include <fmpm/grid_transfer.h>
#include <fmpm/material_points.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_properties.h>

#include <deal.II/base/function.h>
#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <array>
#include <memory>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The loads on the material points (seed 000 Eq. 2.10): gravity
   * g, the scene's body acceleration b(x, t), the terms of a rotating
   * frame and the tractions' forces F_p = t(t) A_p on the points of their
   * boxes, with the tractions' power and the external work.
   *
   * The Simulator calls initialize() once at set-up, mark_traction_points()
   * when the points are created, begin_step() at the start of each step
   * (every load at the middle of the step), acceleration() per point in the
   * force sums, and add_step_work() at the step's end.
   *
   * @tparam dim space dimension
   */
  template <int dim>
  class ExternalLoads
  {
  public:
    /**
     * @brief Read the loads of @p parameters: parse b(x, t), the traction
     * curves t(t) and the rotating frame's ω(t) (errors name the
     * parameter), and request the points' traction slots (index + 1, face
     * area) in @p properties if the scene has tractions.
     */
    void
    initialize(const Parameters        &parameters,
               ParticleProperties<dim> &properties);

    /** @brief Mark the points of @p points inside each traction box with
     * the traction's index + 1 and their face area (the product of their
     * initial side lengths across the face normal). */
    void
    mark_traction_points(MaterialPoints<dim> &points) const;

    /**
     * @brief Every load at time @p t (the middle of the step: second order
     * in time; first order at t^n, measured on the manufactured solution),
     * and the rotating frame's ω and ω̇ = dω/dt (a central difference) at
     * @p t, once for all points (ω depends on t only).
     */
    void
    begin_step(const double t);

    /** @brief Gravity g. Units: m/s². */
    const Tensor<1, dim> &
    gravity() const
    {
      return gravity_vector;
    }

    /** @brief Whether a point's body force depends on the point (b(x, t),
     * a rotating frame, tractions), not only on gravity. */
    bool
    has_point_body_force() const
    {
      return body_acceleration || angular_velocity || has_point_tractions;
    }

    /**
     * @brief Gravity, b(·, t) at @p expression_point (x, or X for
     * manufactured solutions) and the rotating frame's terms (seed 001,
     * computeParticleBodyForce): b = g − ω × (ω × r) − 2 ω × V − ω̇ × r with
     * r = x − the frame's centre, at a point at @p x moving with @p V.
     */
    Tensor<1, dim>
    body_acceleration_at(const Point<dim>     &x,
                         const Tensor<1, dim> &V,
                         const Point<dim>     &expression_point) const;

    /** @brief Traction force t(t) A_p of point @p k of @p points (zero if
     * it has none). Units: N. */
    Tensor<1, dim>
    traction_force(const MaterialPoints<dim> &points,
                   const unsigned int         k) const;

    /**
     * @brief The acceleration of point @p k of @p points: its body
     * acceleration plus its traction force over its mass (Eq. 2.10); adds
     * the traction's power F_p · V_p to this rank's sum of the step.
     */
    Tensor<1, dim>
    acceleration(const MaterialPoints<dim> &points, const unsigned int k);

    /**
     * @brief End of a step of length @p dt, when the scene has tractions or
     * moving walls: the work of the step, the walls' @p wall_work plus the
     * tractions' Σ F_p · V_p Δt (over all ranks of @p communicator), added
     * to work(); the tractions' Σ |F_p| times @p mesh_diameter bounds
     * work_scale() from below. Collective.
     */
    void
    add_step_work(const double   wall_work,
                  const double   dt,
                  const double   mesh_diameter,
                  const MPI_Comm communicator);

    /** @brief Whether a traction has Distribution = face. */
    bool
    has_face_tractions() const
    {
      return has_face_traction;
    }

    /**
     * @brief The nodal forces of the tractions with Distribution = face,
     * added to @p f[d] (indexed by the nodes' local index, ghosts
     * included; the caller compresses): f_i += ∫ t N_i dA over each loaded
     * point's face (per radian when axisymmetric: dA = r ds), two Gauss
     * points per half of the face along each of its directions, each
     * located from the point's cell in @p transfer. Adds Σ F_p · V_p to
     * the step's traction power, F_p the point's total face force.
     */
    void
    add_face_traction_forces(const MaterialPoints<dim> &points,
                             const GridTransfer<dim>   &transfer,
                             double *const *const       f);

    /** @brief Whether the scene has tractions. */
    bool
    has_tractions() const
    {
      return !traction_functions.empty();
    }

    /** @brief The work done on the material by the moving walls and the
     * tractions since the start (energy balance). Units: J. */
    double
    work() const
    {
      return external_work;
    }

    /** @brief Σ over steps of the work's |dW|, at least the work the
     * tractions can do across the mesh. Units: J. */
    double
    work_scale() const
    {
      return external_work_scale;
    }

    /** @brief Checkpoint the work and its scale (the loads themselves are
     * read from the scene again on resume). */
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &external_work &external_work_scale;
    }

  private:
    Tensor<1, dim> gravity_vector;
    /** b(x, t), or nullptr. */
    std::unique_ptr<Function<dim>> body_acceleration;
    bool body_acceleration_at_initial_position = false;
    /** ω(t) of the rotating frame, or nullptr, and the frame's centre. */
    std::unique_ptr<FunctionParser<1>> angular_velocity;
    Tensor<1, 3>                       frame_center;
    /** ω and ω̇ at the time of begin_step(). */
    Tensor<1, 3> omega, omega_dot;
    /** t(t) of each traction, its box and normal axis. */
    std::vector<std::unique_ptr<FunctionParser<1>>> traction_functions;
    std::vector<TractionParameters>                 tractions;
    /** Whether some traction has Distribution = point, some = face. */
    bool has_point_tractions = false;
    bool has_face_traction   = false;
    /** Axisymmetric: face areas per radian (r times the length). */
    bool axisymmetric = false;
    /** The first of the points' traction slots (index + 1, face area). */
    unsigned int traction_slot = numbers::invalid_unsigned_int;
    /** This rank's Σ F_p · V_p and Σ |F_p| in the current step. */
    double local_traction_power     = 0;
    double local_traction_magnitude = 0;
    double external_work            = 0;
    double external_work_scale      = 0;
  };
} // namespace fmpm

#endif
