// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The diagnostics of a run: the global statistics of the points (energies,
// momentum, reference errors, per-material sums), the energy check, and
// where a failure happened.

#include <fmpm/function_parser.h>
#include <fmpm/simulator.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

namespace fmpm
{
  template <int dim>
  GlobalStatistics<dim>
  Simulator<dim>::compute_statistics() const
  {
    TimerOutput::Scope timer(computing_timer, "statistics");
    using Index = PropertyIndex<dim>;
    GlobalStatistics<dim> s;
    Tensor<1, dim>        gravity;
    for (unsigned int d = 0; d < dim; ++d)
      gravity[d] = parameters.gravity[d];

    std::unique_ptr<FunctionParser<dim>> reference_velocity,
      reference_displacement;
    if (parameters.reference.enable)
      {
        const auto constants =
          parse_function_constants(parameters.reference.constants,
                                   "Reference solution/Function constants");
        reference_velocity         = std::make_unique<FunctionParser<dim>>(dim);
        reference_displacement     = std::make_unique<FunctionParser<dim>>(dim);
        const std::string expected = std::to_string(dim) +
                                     " expressions in x, y" +
                                     (dim == 3 ? ", z" : "") + ", t";
        parse_function(*reference_velocity,
                       "Reference solution/Velocity",
                       parameters.reference.velocity,
                       to_function_expressions(parameters.reference.velocity),
                       FunctionParser<dim>::default_variable_names() + ",t",
                       constants,
                       true,
                       expected);
        parse_function(*reference_displacement,
                       "Reference solution/Displacement",
                       parameters.reference.displacement,
                       to_function_expressions(
                         parameters.reference.displacement),
                       FunctionParser<dim>::default_variable_names() + ",t",
                       constants,
                       true,
                       expected);
        reference_velocity->set_time(control.time());
        reference_displacement->set_time(control.time());
      }

    // In the store's order: cell by cell in the order of the cells' ids
    // (CellId) on adapted meshes, by id in a cell. Neither depends on the
    // history of the points' moves, and a resumed run shares it (bitwise
    // equal sums).
    const unsigned int n_materials = parameters.size.n_materials;
    const unsigned int stride      = GlobalStatistics<dim>::material_stride();
    if (n_materials > 1)
      s.per_material.assign(n_materials * stride, 0.);
    constexpr unsigned int stress_slots[6] = {0, 1, 3, 2, 4, 5};
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const PointRecord    p = points.record(k);
        const double         M = p[Index::mass];
        const Tensor<1, dim> V = get_vector<dim>(p, Index::velocity);
        const Point<dim>    &x = points.position[k];
        if (n_materials > 1)
          {
            double *const sums =
              &s.per_material[static_cast<unsigned int>(p[Index::material_id]) *
                              stride];
            const double volume = p[Index::volume];
            sums[0] += M;
            for (unsigned int d = 0; d < dim; ++d)
              sums[1 + d] += M * V[d];
            sums[1 + dim] += volume;
            // 2D: xx, yy, xy = stored slots 0, 1, 3.
            for (unsigned int c = 0; c < GlobalStatistics<dim>::n_stress; ++c)
              sums[2 + dim + c] +=
                volume * p[Index::stress + (dim == 2 ? stress_slots[c] : c)];
            sums[stride - 2] += 0.5 * M * V * V;
            sums[stride - 1] +=
              p[Index::initial_volume] * p[Index::strain_energy_density];
          }
        s.mass += M;
        s.momentum += M * V;
        s.kinetic_energy += 0.5 * M * V * V;
        s.strain_energy +=
          p[Index::initial_volume] * p[Index::strain_energy_density];
        // Gravity's potential energy relative to the initial configuration
        // (independent of where the origin lies): -Σ M g·(x - X).
        const Point<dim> X(get_vector<dim>(p, Index::initial_position));
        s.potential_energy -= M * (gravity * (x - X));
        if (reference_velocity)
          {
            Tensor<1, dim> v_ref, u_ref;
            for (unsigned int d = 0; d < dim; ++d)
              {
                v_ref[d] = reference_velocity->value(X, d);
                u_ref[d] = reference_displacement->value(X, d);
              }
            const Tensor<1, dim> u = x - X;
            s.velocity_error_squared += M * (V - v_ref).norm_square();
            s.velocity_reference_squared += M * v_ref.norm_square();
            s.displacement_error_squared += M * (u - u_ref).norm_square();
            s.displacement_reference_squared += M * u_ref.norm_square();
          }
      }
    // The energy stored in imperfect interfaces (their springs) at the last
    // correction of the updated momenta.
    if (contact)
      s.strain_energy += contact->local_interface_energy();

    // One reduction for all sums.
    std::vector<double> values = {s.mass,
                                  s.kinetic_energy,
                                  s.strain_energy,
                                  s.potential_energy,
                                  s.velocity_error_squared,
                                  s.velocity_reference_squared,
                                  s.displacement_error_squared,
                                  s.displacement_reference_squared};
    for (unsigned int d = 0; d < dim; ++d)
      values.push_back(s.momentum[d]);
    values.insert(values.end(), s.per_material.begin(), s.per_material.end());
    Utilities::MPI::sum(values, mpi_communicator, values);
    std::copy(values.end() - s.per_material.size(),
              values.end(),
              s.per_material.begin());
    s.mass                           = values[0];
    s.kinetic_energy                 = values[1];
    s.strain_energy                  = values[2];
    s.potential_energy               = values[3];
    s.velocity_error_squared         = values[4];
    s.velocity_reference_squared     = values[5];
    s.displacement_error_squared     = values[6];
    s.displacement_reference_squared = values[7];
    for (unsigned int d = 0; d < dim; ++d)
      s.momentum[d] = values[8 + d];
    return s;
  }



  template <int dim>
  void
  Simulator<dim>::check_energy(const GlobalStatistics<dim> &statistics)
  {
    TimerOutput::Scope timer(computing_timer, "statistics");
    const double       E = statistics.total_energy();
    // Energies are measured from the initial state; gravity's potential
    // energy makes the reference the initial total, which may be of any
    // sign, so the bound is on the growth relative to the initial kinetic +
    // strain energy scale. A moving wall that starts to drive material at
    // rest gives it of order ½ M v_w² in the first steps, when its work so
    // far is still small: that is a scale too.
    const double wall_speed =
      velocity_conditions.fastest_wall_speed(control.time());
    const double scale = std::max(
      {energy_balance.error_scale(statistics, external_loads.work_scale()),
       energy_balance.growth_scale(),
       0.5 * statistics.mass * wall_speed * wall_speed});
    if (!std::isfinite(E))
      throw SimulationFailure("total energy is not finite (NaN or Inf)",
                              control.step_number(),
                              control.time());
    const double E0 = energy_balance.initial_total_energy();
    if (E - E0 - external_loads.work() >
        (parameters.failure.energy_growth_limit - 1) * scale)
      {
        std::ostringstream message;
        message << "total energy grew from " << E0 << " to " << E
                << " J (external work " << external_loads.work()
                << " J), past Failure detection/Energy growth limit = "
                << parameters.failure.energy_growth_limit << "; "
                << fastest_point();
        throw SimulationFailure(message.str(),
                                control.step_number(),
                                control.time());
      }
    // Kinetic and strain energy are not negative: the balance cannot fall
    // by more than the initial energy, gravity's reach, the gross external
    // work and a wall's drive put in. (The error scale's energy exchanged
    // is left out: an unstable run inflates it as the energy goes wrong.)
    const double available =
      std::max({energy_balance.growth_scale(),
                external_loads.work_scale(),
                0.5 * statistics.mass * wall_speed * wall_speed});
    if (E - E0 - external_loads.work() <
        -(parameters.failure.energy_growth_limit - 1) * available)
      {
        std::ostringstream message;
        message << "total energy fell from " << E0 << " to " << E
                << " J (kinetic " << statistics.kinetic_energy << ", strain "
                << statistics.strain_energy << ", external work "
                << external_loads.work()
                << " J): a loss larger than Failure detection/Energy "
                   "growth limit - 1 = "
                << parameters.failure.energy_growth_limit - 1
                << " times all the energy the run was given (the kinetic "
                   "and strain energies cannot be negative: an unstable "
                   "step); "
                << fastest_point();
        throw SimulationFailure(message.str(),
                                control.step_number(),
                                control.time());
      }
    const double kinetic_limit = parameters.failure.kinetic_energy_limit;
    if (kinetic_limit > 0 && statistics.kinetic_energy > kinetic_limit)
      throw SimulationFailure(
        "kinetic energy " + format_number(statistics.kinetic_energy, 6) +
          " J is above Failure detection/Kinetic energy limit = " +
          format_number(kinetic_limit) + " J (total energy " +
          format_number(E, 6) + " J, external work " +
          format_number(external_loads.work(), 6) + " J); " + fastest_point(),
        control.step_number(),
        control.time());
  }



  template <int dim>
  std::string
  Simulator<dim>::failure_location_hint(const SimulationFailure &failure) const
  {
    const FailedPoint &point = failure.point;
    // 1. A point that left the mesh of a box through a face with a velocity
    //    condition (boundary ids 2d, 2d + 1 of direction d).
    if (point.cause == FailedPoint::Cause::left_mesh)
      {
        Point<dim> x;
        for (unsigned int d = 0; d < dim; ++d)
          x[d] = point.position[d];
        if (parameters.mesh.type != MeshParameters::Type::box)
          return "";
        const auto                  &bc = parameters.boundary_conditions;
        std::set<types::boundary_id> held(bc.fixed.begin(), bc.fixed.end());
        held.insert(bc.roller.begin(), bc.roller.end());
        for (const auto &wall : bc.moving_walls)
          held.insert(wall.boundary_ids.begin(), wall.boundary_ids.end());
        for (unsigned int d = 0; d < dim; ++d)
          for (const unsigned int side : {0u, 1u})
            {
              const double face = side == 0 ? parameters.mesh.lower_corner[d] :
                                              parameters.mesh.upper_corner[d];
              const bool   beyond = side == 0 ? x[d] < face : x[d] > face;
              const types::boundary_id id_of_face = 2 * d + side;
              if (beyond && held.count(id_of_face) > 0)
                // FMPM's, XPIC's and PIC midpoint's position updates read
                // the point's own velocity when psi > 0 (seed 000 Table 2.1,
                // Eq. 2.28).
                return "Where: the point crossed boundary id " +
                       std::to_string(id_of_face) +
                       ", which has a velocity condition: the condition holds "
                       "the grid velocity at the boundary's nodes, not the "
                       "points. A position update that moves a point also "
                       "with its own velocity ('Position update psi' > 0 in "
                       "'Particle update/Fmpm', '/Xpic' or '/Pic midpoint') "
                       "can carry it through; with psi = 0 the points move "
                       "with the grid velocity.";
            }
        return "";
      }

    if (point.cause != FailedPoint::Cause::inverted &&
        point.cause != FailedPoint::Cause::model_failure)
      return "";

    // 2. An inverted or failed point: how full the nodes of its cell are.
    //    A node inside a body holds about ρ₀ times the measure of a cell
    //    (each of its 2^dim cells gives it 1/2^dim); a node at a free face
    //    about half of that, at a free corner a quarter.
    using Index     = PropertyIndex<dim>;
    double min_fill = -1;
    int    body     = -1;
    for (unsigned int c = 0; c < points.n_cells(); ++c)
      for (unsigned int k = points.cell_point_begin[c];
           k < points.cell_point_begin[c + 1];
           ++k)
        if (points.id[k] == point.id)
          {
            const PointRecord p   = points.record(k);
            const double density0 = p[Index::mass] / p[Index::initial_volume];
            const auto  &cell     = points.cell_iterator(c);
            std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
            typename DoFHandler<dim>::active_cell_iterator dof_cell(
              &triangulation, cell->level(), cell->index(), &dof_handler);
            dof_cell->get_dof_indices(dofs);
            min_fill = std::numeric_limits<double>::max();
            for (const auto dof : dofs)
              min_fill = std::min(min_fill,
                                  centre_of_mass.mass(dof) /
                                    (density0 * cell->measure()));
            body = static_cast<int>(p[Index::body_id]);
          }
    min_fill = Utilities::MPI::max(min_fill, mpi_communicator);
    body     = Utilities::MPI::max(body, mpi_communicator);
    if (min_fill < 0 || min_fill >= 0.75)
      return "";
    std::string hint =
      "Where: the point is at a free " +
      std::string(min_fill < 0.375 ? "corner" : "surface") + " of Body " +
      std::to_string(body) + " (the lightest node of its cell holds " +
      format_number(100 * min_fill, 2) +
      " % of the mass of a node inside the body). The nodes there rest on "
      "few points, so their velocities and the deformation they give the "
      "point are the least accurate of the body: the likely cause is the "
      "resolution of the edge, not the time step. Likely remedies: more "
      "'Points per cell' or a finer mesh";
    if (!parameters.method.lumped_strain_velocities && mass_matrix->order() > 1)
      hint += ", or 'Time/Strain update mass matrix = lumped' (the lumped "
              "velocity p/m of a node is an average of its points' "
              "velocities; the series of the mass matrix '" +
              parameters.method.mass_matrix +
              "' can amplify the momenta of nearly empty nodes)";
    return hint + ".";
  }



  template <int dim>
  std::string
  Simulator<dim>::fastest_point() const
  {
    using Index          = PropertyIndex<dim>;
    double      speed    = -1;
    std::string location = "no material points";
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const PointRecord p = points.record(k);
        const double      v = get_vector<dim>(p, Index::velocity).norm();
        if (v > speed)
          {
            speed = v;
            std::ostringstream text;
            text << "the fastest material point, " << points.id[k]
                 << " of Body " << static_cast<unsigned int>(p[Index::body_id])
                 << ", moves at " << format_number(v, 6) << " m/s at position ("
                 << points.position[k] << ")";
            location = text.str();
          }
      }
    const auto speeds = Utilities::MPI::all_gather(mpi_communicator, speed);
    const auto locations =
      Utilities::MPI::all_gather(mpi_communicator, location);
    return locations[std::max_element(speeds.begin(), speeds.end()) -
                     speeds.begin()];
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
