// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The particle-grid passes of the time step: extrapolations to the grid
// (Sᵀ, Gᵀ), the particle update (S) and the strain update (G), and the
// re-sorting of moved points into cells.

#include <fmpm/simulator.h>

#include <cmath>
#include <sstream>

namespace fmpm
{
  namespace
  {
    /**
     * Add a cell's nodal contributions to a ghosted grid vector: directly
     * when no hanging node touches the cell, else through the constraints
     * (condensation of the particle-to-grid result).
     */
    template <int dim, typename CellData>
    inline void
    add_to_grid(const CellData                             &cell,
                const double                               *values,
                LinearAlgebra::distributed::Vector<double> &vector,
                const AffineConstraints<double>            &constraints)
    {
      constexpr unsigned int n = GeometryInfo<dim>::vertices_per_cell;
      if (!cell.has_constraints)
        for (unsigned int i = 0; i < n; ++i)
          vector.local_element(cell.local_index[i]) += values[i];
      else
        {
          Vector<double>                       local(values, values + n);
          std::vector<types::global_dof_index> dofs(cell.dof_index.begin(),
                                                    cell.dof_index.end());
          constraints.distribute_local_to_global(local, dofs, vector);
        }
    }

    /**
     * Add a value to one node of a point's support (GIMP/CPDI): directly,
     * or for a hanging node to the nodes it is constrained to.
     */
    template <int dim>
    inline void
    add_to_grid(const ShapeFunction::Node<dim>             &node,
                const double                                value,
                LinearAlgebra::distributed::Vector<double> &vector,
                const AffineConstraints<double>            &constraints)
    {
      if (!node.constrained)
        vector.local_element(node.local_index) += value;
      else
        for (const auto &entry : *constraints.get_constraint_entries(node.dof))
          vector(entry.first) += entry.second * value;
    }

    /**
     * The force component @p a one point gives its node (Eq. 2.11):
     * M S b_a − V Σ_b σ_ab G_b, with @p MS = M S and the point's body
     * acceleration (tractions included) @p b.
     */
    template <int dim, typename Stress>
    inline double
    nodal_force(const unsigned int    a,
                const double          MS,
                const Tensor<1, dim> &b,
                const double          V,
                const Stress         &sigma,
                const Tensor<1, dim> &G)
    {
      double f = MS * b[a];
      for (unsigned int c = 0; c < dim; ++c)
        f -= V * sigma[a][c] * G[c];
      return f;
    }

    /** A 3x3 tensor with the dim x dim block @p t (plane strain in 2D). */
    template <int dim>
    inline Tensor<2, 3>
    embed(const Tensor<2, dim> &t)
    {
      Tensor<2, 3> result;
      for (unsigned int i = 0; i < dim; ++i)
        for (unsigned int j = 0; j < dim; ++j)
          result[i][j] = t[i][j];
      return result;
    }
  } // namespace



  template <int dim>
  Tensor<2, 3>
  Simulator<dim>::deformation_gradient_increment(const Tensor<2, 3> &L,
                                                 const double        dt) const
  {
    // F^{n+1} = ΔF F^n with ΔF ≈ exp(L Δt) for a velocity gradient constant
    // over the step (seed 001, computeDeformationGradientFromVelocity).
    const Tensor<2, 3> I      = unit_symmetric_tensor<3>();
    const Tensor<2, 3> L_dt   = L * dt;
    const std::string &update = parameters.method.deformation_gradient_update;
    if (update == "first order")
      return I + L_dt;
    if (update == "cayley")
      return invert(I - 0.5 * L_dt) * (I + 0.5 * L_dt);
    if (update == "taylor")
      {
        Tensor<2, 3> term = I, sum = I;
        for (unsigned int k = 1; k <= parameters.method.taylor_terms; ++k)
          {
            term = term * L_dt / static_cast<double>(k);
            sum += term;
          }
        return sum;
      }
    // subcycle: first-order substeps with |L Δt_sub| below the bound.
    const unsigned int n_sub =
      std::max(1u,
               static_cast<unsigned int>(std::ceil(
                 L_dt.norm() / parameters.method.subcycle_strain_increment)));
    const Tensor<2, 3> step   = I + L_dt / static_cast<double>(n_sub);
    Tensor<2, 3>       result = I;
    for (unsigned int k = 0; k < n_sub; ++k)
      result = step * result;
    return result;
  }



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
  Simulator<dim>::traction_force_of(
    const ArrayView<const double> &properties) const
  {
    Tensor<1, dim> F;
    const int      index =
      static_cast<int>(properties[traction_index_slot] + 0.5) - 1;
    if (index < 0)
      return F;
    // F_p = t(t) A_p, the f_T term of Eq. 2.10 (at mid-step, like b).
    const double area = properties[traction_index_slot + 1];
    for (unsigned int d = 0; d < dim; ++d)
      F[d] = traction_functions[index]->value(Point<1>(), d) * area;
    return F;
  }



  template <int dim>
  Tensor<1, dim>
  Simulator<dim>::external_acceleration(const ArrayView<const double> &p,
                                        const Point<dim>              &x,
                                        const Tensor<1, dim>          &gravity)
  {
    using Index            = PropertyIndex<dim>;
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
        const Tensor<1, dim> F_p = traction_force_of(p);
        b += F_p / p[Index::mass];
        local_traction_power += F_p * V;
        local_traction_magnitude += F_p.norm();
      }
    return b;
  }



  template <int dim>
  void
  Simulator<dim>::compute_supports()
  {
    TimerOutput::Scope timer(computing_timer, "shape functions");
    using Index = PropertyIndex<dim>;
    support_offsets.clear();
    support_nodes.clear();
    support_offsets.reserve(particle_handler.n_locally_owned_particles() + 1);
    support_offsets.push_back(0);
    std::vector<ShapeFunction::Node<dim>> support;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        for (const auto &particle : particle_handler.particles_in_cell(cell))
          {
            const auto     p = particle.get_properties();
            Tensor<2, dim> F;
            Tensor<1, dim> l0;
            for (unsigned int a = 0; a < dim; ++a)
              {
                l0[a] = p[Index::initial_half_length + a];
                for (unsigned int b = 0; b < dim; ++b)
                  F[a][b] = p[Index::deformation_gradient + 3 * a + b];
              }
            const ShapeFunction::Status status =
              ShapeFunction::compute_support(shape_function,
                                             transfer,
                                             cell->active_cell_index(),
                                             particle.get_location(),
                                             F,
                                             l0,
                                             support);
            if (status != ShapeFunction::Status::ok)
              {
                if (local_failure.empty())
                  {
                    std::ostringstream message;
                    message
                      << "the domain of material point " << particle.get_id()
                      << " at (" << particle.get_location() << ") "
                      << (status == ShapeFunction::Status::outside_mesh ?
                            "reaches outside the mesh by more than half a "
                            "cell" :
                            "reaches beyond the cells that share a vertex "
                            "with its cell (one layer of neighbour or ghost "
                            "cells)")
                      << " (Shape function/Type = "
                      << parameters.method.shape_function
                      << "): use smaller points (more Points per cell), a "
                         "coarser mesh there, or classic shape functions";
                    local_failure = message.str();
                  }
                // Carry on with the classic weights; the step fails.
                ShapeFunction::compute_support(ShapeFunction::Type::classic,
                                               transfer,
                                               cell->active_cell_index(),
                                               particle.get_location(),
                                               F,
                                               l0,
                                               support);
              }
            support_nodes.insert(support_nodes.end(),
                                 support.begin(),
                                 support.end());
            support_offsets.push_back(support_nodes.size());
          }
      }
  }



  template <int dim>
  void
  Simulator<dim>::particles_to_grid(const bool with_forces)
  {
    TimerOutput::Scope timer(computing_timer, "particles to grid");
    using Index              = PropertyIndex<dim>;
    constexpr unsigned int n = GridTransfer<dim>::n_nodes;

    // m̃ as cell-wise matrices where the mass matrix accepts them and the
    // cell's nodes are its DoFs (no hanging nodes, classic shape
    // functions); else the assembled sparse matrix.
    use_cellwise_full_mass = mass_matrix->needs_full_mass_matrix() &&
                             mass_matrix->accepts_cellwise_full_mass_matrix() &&
                             !velocity_conditions.needs_full_mass_matrix() &&
                             !has_hanging_nodes &&
                             shape_function == ShapeFunction::Type::classic;
    const bool assemble_full =
      !use_cellwise_full_mass && (mass_matrix->needs_full_mass_matrix() ||
                                  velocity_conditions.needs_full_mass_matrix());
    lumped_mass = 0;
    momentum    = 0;
    if (with_forces)
      force = 0;
    if (assemble_full)
      full_mass_matrix = 0;
    if (use_cellwise_full_mass)
      cellwise_full_mass.clear(n);

    Tensor<1, dim> gravity;
    for (unsigned int d = 0; d < dim; ++d)
      gravity[d] = parameters.gravity[d];

    std::array<double, n>                S;
    std::array<Tensor<1, dim>, n>        G;
    double                               cell_mass[n];
    double                               cell_momentum[dim][n];
    double                               cell_force[dim][n];
    FullMatrix<double>                   cell_full_mass(n, n);
    std::vector<types::global_dof_index> dofs(n);

    // GIMP/CPDI: every point scatters to its own support (S̄, Ḡ).
    unsigned int point = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        if (shape_function == ShapeFunction::Type::classic)
          break;
        if (!cell->is_locally_owned())
          continue;
        for (const auto &particle : particle_handler.particles_in_cell(cell))
          {
            const auto         p     = particle.get_properties();
            const double       M     = p[Index::mass];
            const unsigned int begin = support_offsets[point];
            const unsigned int end   = support_offsets[point + 1];
            ++point;
            Tensor<1, dim>        body_force;
            SymmetricTensor<2, 3> sigma;
            const double          V = p[Index::volume];
            if (with_forces)
              {
                body_force =
                  external_acceleration(p, particle.get_location(), gravity);
                sigma = get_symmetric_tensor3(p, Index::stress);
              }
            for (unsigned int k = begin; k < end; ++k)
              {
                const auto  &node = support_nodes[k];
                const double MS   = M * node.S;
                add_to_grid<dim>(node, MS, lumped_mass, constraints);
                for (unsigned int d = 0; d < dim; ++d)
                  add_to_grid<dim>(node,
                                   MS * p[Index::velocity + d],
                                   momentum.block(d),
                                   constraints);
                if (with_forces)
                  for (unsigned int a = 0; a < dim; ++a)
                    add_to_grid<dim>(
                      node,
                      nodal_force<dim>(a, MS, body_force, V, sigma, node.G),
                      force.block(a),
                      constraints);
              }
            if (assemble_full ||
                use_cellwise_full_mass) // m̃ = SᵀMS (1.9) over the support
              {
                const unsigned int n_support = end - begin;
                cell_full_mass.reinit(n_support, n_support);
                dofs.resize(n_support);
                for (unsigned int i = 0; i < n_support; ++i)
                  {
                    dofs[i] = support_nodes[begin + i].dof;
                    for (unsigned int j = 0; j < n_support; ++j)
                      cell_full_mass(i, j) = M * support_nodes[begin + i].S *
                                             support_nodes[begin + j].S;
                  }
                constraints.distribute_local_to_global(cell_full_mass,
                                                       dofs,
                                                       full_mass_matrix);
              }
          }
      }

    for (const auto &cell : triangulation.active_cell_iterators())
      {
        if (shape_function != ShapeFunction::Type::classic)
          break;
        if (!cell->is_locally_owned())
          continue;
        const auto particles = particle_handler.particles_in_cell(cell);
        if (particles.begin() == particles.end())
          continue;
        const auto &data = transfer.cell_data(cell->active_cell_index());

        std::fill(cell_mass, cell_mass + n, 0.);
        for (unsigned int d = 0; d < dim; ++d)
          {
            std::fill(cell_momentum[d], cell_momentum[d] + n, 0.);
            std::fill(cell_force[d], cell_force[d] + n, 0.);
          }
        if (assemble_full || use_cellwise_full_mass)
          cell_full_mass = 0;

        for (const auto &particle : particles)
          {
            const auto   p = particle.get_properties();
            const double M = p[Index::mass];
            if (with_forces)
              GridTransfer<dim>::values_and_gradients(
                data, particle.get_reference_location(), S, G);
            else
              GridTransfer<dim>::values(particle.get_reference_location(), S);

            for (unsigned int i = 0; i < n; ++i)
              {
                const double MS = M * S[i];
                cell_mass[i] += MS; // m = SᵀM (Eq. 1.6)
                for (unsigned int d = 0; d < dim; ++d)
                  cell_momentum[d][i] += MS * p[Index::velocity + d]; // p = SᵀP
              }
            if (assemble_full || use_cellwise_full_mass) // m̃ = SᵀMS (1.9)
              for (unsigned int i = 0; i < n; ++i)
                for (unsigned int j = 0; j < n; ++j)
                  cell_full_mass(i, j) += M * S[i] * S[j];

            if (with_forces)
              {
                // f = −Σ V_p σ_p G_p + Σ S_p (M_p b + F_p)  (Eq. 2.11,
                // τ/ρ₀ M = σ V; F_p the traction force)
                const Tensor<1, dim> body_force =
                  external_acceleration(p, particle.get_location(), gravity);
                const double V = p[Index::volume];
                double       sigma[dim][dim];
                for (unsigned int a = 0; a < dim; ++a)
                  for (unsigned int b = 0; b < dim; ++b)
                    sigma[a][b] = 0;
                {
                  const SymmetricTensor<2, 3> s =
                    get_symmetric_tensor3(p, Index::stress);
                  for (unsigned int a = 0; a < dim; ++a)
                    for (unsigned int b = 0; b < dim; ++b)
                      sigma[a][b] = s[a][b];
                }
                for (unsigned int i = 0; i < n; ++i)
                  for (unsigned int a = 0; a < dim; ++a)
                    cell_force[a][i] +=
                      nodal_force<dim>(a, M * S[i], body_force, V, sigma, G[i]);
              }
          }

        add_to_grid<dim>(data, cell_mass, lumped_mass, constraints);
        for (unsigned int d = 0; d < dim; ++d)
          add_to_grid<dim>(data,
                           cell_momentum[d],
                           momentum.block(d),
                           constraints);
        if (with_forces)
          for (unsigned int d = 0; d < dim; ++d)
            add_to_grid<dim>(data, cell_force[d], force.block(d), constraints);
        if (assemble_full)
          {
            std::copy(data.dof_index.begin(),
                      data.dof_index.end(),
                      dofs.begin());
            constraints.distribute_local_to_global(cell_full_mass,
                                                   dofs,
                                                   full_mass_matrix);
          }
        if (use_cellwise_full_mass)
          cellwise_full_mass.add_cell(data.local_index.data(),
                                      &cell_full_mass(0, 0));
      }

    lumped_mass.compress(VectorOperation::add);
    momentum.compress(VectorOperation::add);
    if (with_forces)
      force.compress(VectorOperation::add);
    if (assemble_full)
      full_mass_matrix.compress(VectorOperation::add);
    lumped_mass.update_ghost_values();
    mass_matrix->setup();
  }



  template <int dim>
  void
  Simulator<dim>::compute_forces()
  {
    TimerOutput::Scope timer(computing_timer, "particles to grid");
    using Index              = PropertyIndex<dim>;
    constexpr unsigned int n = GridTransfer<dim>::n_nodes;
    force                    = 0;
    Tensor<1, dim> gravity;
    for (unsigned int d = 0; d < dim; ++d)
      gravity[d] = parameters.gravity[d];

    std::array<double, n>         S;
    std::array<Tensor<1, dim>, n> G;
    double                        cell_force[dim][n];
    unsigned int                  point = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        if (shape_function == ShapeFunction::Type::classic)
          break;
        if (!cell->is_locally_owned())
          continue;
        for (const auto &particle : particle_handler.particles_in_cell(cell))
          {
            const auto                  p = particle.get_properties();
            const double                M = p[Index::mass];
            const double                V = p[Index::volume];
            const SymmetricTensor<2, 3> sigma =
              get_symmetric_tensor3(p, Index::stress);
            const Tensor<1, dim> body_force =
              external_acceleration(p, particle.get_location(), gravity);
            for (unsigned int k = support_offsets[point];
                 k < support_offsets[point + 1];
                 ++k)
              {
                const auto &node = support_nodes[k];
                for (unsigned int a = 0; a < dim; ++a)
                  add_to_grid<dim>(
                    node,
                    nodal_force<dim>(
                      a, M * node.S, body_force, V, sigma, node.G),
                    force.block(a),
                    constraints);
              }
            ++point;
          }
      }
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        if (shape_function != ShapeFunction::Type::classic)
          break;
        if (!cell->is_locally_owned())
          continue;
        const auto particles = particle_handler.particles_in_cell(cell);
        if (particles.begin() == particles.end())
          continue;
        const auto &data = transfer.cell_data(cell->active_cell_index());
        for (unsigned int d = 0; d < dim; ++d)
          std::fill(cell_force[d], cell_force[d] + n, 0.);
        for (const auto &particle : particles)
          {
            const auto p = particle.get_properties();
            GridTransfer<dim>::values_and_gradients(
              data, particle.get_reference_location(), S, G);
            const double                M = p[Index::mass];
            const double                V = p[Index::volume];
            const SymmetricTensor<2, 3> sigma =
              get_symmetric_tensor3(p, Index::stress);
            const Tensor<1, dim> body_force =
              external_acceleration(p, particle.get_location(), gravity);
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int a = 0; a < dim; ++a)
                cell_force[a][i] +=
                  nodal_force<dim>(a, M * S[i], body_force, V, sigma, G[i]);
          }
        for (unsigned int d = 0; d < dim; ++d)
          add_to_grid<dim>(data, cell_force[d], force.block(d), constraints);
      }
    force.compress(VectorOperation::add);
  }



  template <int dim>
  void
  Simulator<dim>::update_particles()
  {
    TimerOutput::Scope timer(computing_timer, "particle update");
    using Index              = PropertyIndex<dim>;
    constexpr unsigned int n = GridTransfer<dim>::n_nodes;

    std::vector<unsigned int> fields;
    for (unsigned int f = 0; f < ParticleUpdate::n_grid_fields; ++f)
      if (field_needed[f])
        fields.push_back(f);

    ParticleUpdate::Batch<dim> batch;
    batch.time_step = time_step;
    new_reference_locations.clear();
    new_reference_locations.reserve(
      particle_handler.n_locally_owned_particles());
    Point<dim> outside_marker;
    for (unsigned int d = 0; d < dim; ++d)
      outside_marker[d] = -1;
    const bool   track_dissipation = parameters.output.track_dissipation;
    const double grid_damping      = parameters.method.grid_damping;
    const double particle_damping  = parameters.method.particle_damping;
    std::vector<Tensor<1, dim>> old_velocity, damping_velocity;
    std::vector<Point<dim>>     old_position;
    std::array<double, n>       S;
    double                      speed = 0;
    const bool   has_moving_walls     = velocity_conditions.has_moving_boxes();
    const bool   classic     = (shape_function == ShapeFunction::Type::classic);
    unsigned int first_point = 0; // of the cell, in traversal order

    for (const auto &cell : triangulation.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        const auto         particles = particle_handler.particles_in_cell(cell);
        const unsigned int n_points =
          particle_handler.n_particles_in_cell(cell);
        if (n_points == 0)
          continue;
        const auto &data = transfer.cell_data(cell->active_cell_index());
        batch.resize(n_points);
        const unsigned int cell_first_point = first_point;
        first_point += n_points;

        // Gather: V, X and the requested fields extrapolated with S.
        unsigned int q = 0;
        for (const auto &particle : particles)
          {
            const auto p      = particle.get_properties();
            batch.velocity[q] = get_vector<dim>(p, Index::velocity);
            batch.position[q] = particle.get_location();
            if (!classic)
              {
                // S̄ of the point's support (GIMP/CPDI).
                const unsigned int begin =
                  support_offsets[cell_first_point + q];
                const unsigned int end =
                  support_offsets[cell_first_point + q + 1];
                for (const unsigned int f : fields)
                  {
                    Tensor<1, dim> value;
                    for (unsigned int d = 0; d < dim; ++d)
                      {
                        const auto &block = grid_fields[f].block(d);
                        double      sum   = 0;
                        for (unsigned int k = begin; k < end; ++k)
                          sum +=
                            support_nodes[k].S *
                            block.local_element(support_nodes[k].local_index);
                        value[d] = sum;
                      }
                    batch.grid[f][q] = value;
                  }
                ++q;
                continue;
              }
            GridTransfer<dim>::values(particle.get_reference_location(), S);
            for (const unsigned int f : fields)
              {
                Tensor<1, dim> value;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    const auto &block = grid_fields[f].block(d);
                    double      sum   = 0;
                    for (unsigned int i = 0; i < n; ++i)
                      sum += S[i] * block.local_element(data.local_index[i]);
                    value[d] = sum;
                  }
                batch.grid[f][q] = value;
              }
            ++q;
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

        particle_update->update(batch);

        // Damping (seed 003 Eqs. 1.21-1.25): the acceleration loses
        // A_damp = α_g S v + α_p V^(n); V^(n+1) -= A_damp Δt and, the
        // effective velocity being unchanged, X^(n+1) -= A_damp Δt²/2.
        if (grid_damping != 0 || particle_damping != 0)
          for (unsigned int p = 0; p < n_points; ++p)
            {
              Tensor<1, dim> A_damp;
              if (grid_damping != 0)
                A_damp +=
                  grid_damping * batch.grid[ParticleUpdate::velocity][p];
              if (particle_damping != 0)
                A_damp += particle_damping * (*V_n)[p];
              batch.velocity[p] -= A_damp * time_step;
              batch.position[p] -= A_damp * (0.5 * time_step * time_step);
            }

        // Energy dissipated compared with non-dissipative FLIP (seed 003
        // Eqs. 1.44-1.45): M [A_g→p Δt·(V_g→p + A_g→p Δt/2) − ΔV·ΔX/Δt].
        if (track_dissipation)
          {
            unsigned int p_index = 0;
            for (const auto &particle : particles)
              {
                const double         M = particle.get_properties()[Index::mass];
                const Tensor<1, dim> a_dt =
                  batch.grid[ParticleUpdate::acceleration][p_index] * time_step;
                const Tensor<1, dim> &v_g =
                  batch.grid[ParticleUpdate::velocity][p_index];
                const Tensor<1, dim> dV =
                  batch.velocity[p_index] - old_velocity[p_index];
                const Tensor<1, dim> dX_dt =
                  (batch.position[p_index] - old_position[p_index]) / time_step;
                local_dissipation +=
                  M * (a_dt * (v_g + 0.5 * a_dt) - dV * dX_dt);
                ++p_index;
              }
          }

        // Scatter the new V and X.
        q = 0;
        for (auto particle_iterator = particles.begin();
             particle_iterator != particles.end();
             ++particle_iterator)
          {
            auto                 &particle = *particle_iterator;
            const Tensor<1, dim> &V        = batch.velocity[q];
            const double          V2       = V * V;
            if (!std::isfinite(V2) && local_failure.empty())
              {
                std::ostringstream message;
                message << "velocity of material point " << particle.get_id()
                        << " at (" << particle.get_location()
                        << ") is not finite (NaN or Inf)";
                local_failure = message.str();
              }
            speed = std::max(speed, std::sqrt(V2));
            set_vector<dim>(particle.get_properties(), Index::velocity, V);
            // Points do not enter a moving wall's box.
            if (has_moving_walls)
              velocity_conditions.push_out_of_walls(batch.position[q]);
            // The new reference location, set after the strain update (which
            // still uses the shape functions of the step's start); only
            // points that left their cell need sorting.
            const Point<dim> xi = GridTransfer<dim>::reference_point(
              data, batch.position[q], particle.get_reference_location());
            particle.set_location(batch.position[q]);
            if (GridTransfer<dim>::is_inside(xi))
              new_reference_locations.push_back(xi);
            else
              {
                new_reference_locations.push_back(outside_marker);
                points_that_left_their_cell.push_back(particle_iterator);
              }
            ++q;
          }
      }
    local_max_point_speed = speed;
  }



  template <int dim>
  void
  Simulator<dim>::update_stresses(const GridVectorField &v, const double dt)
  {
    TimerOutput::Scope timer(computing_timer, "stress update");
    using Index                        = PropertyIndex<dim>;
    constexpr unsigned int n           = GridTransfer<dim>::n_nodes;
    const unsigned int     n_materials = constitutive_models.size();

    std::array<double, n>                  S;
    std::array<Tensor<1, dim>, n>          G;
    ConstitutiveModel::StressUpdateInputs  inputs;
    ConstitutiveModel::StressUpdateOutputs outputs;
    inputs.time_step  = dt;
    double wave_speed = 0;

    // Points of one cell, grouped by material for the batched model call.
    std::vector<
      std::vector<typename Particles::ParticleHandler<dim>::particle_iterator>>
      by_material(n_materials);
    // The index of each point of by_material in traversal order (supports).
    std::vector<std::vector<unsigned int>> point_index(n_materials);
    const bool   classic = (shape_function == ShapeFunction::Type::classic);
    unsigned int point   = 0;

    for (const auto &cell : triangulation.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        const auto particles = particle_handler.particles_in_cell(cell);
        if (particles.begin() == particles.end())
          continue;
        const auto &data = transfer.cell_data(cell->active_cell_index());
        for (auto &group : by_material)
          group.clear();
        for (auto &group : point_index)
          group.clear();
        for (auto particle = particles.begin(); particle != particles.end();
             ++particle)
          {
            const unsigned int m =
              n_materials == 1 ?
                0 :
                static_cast<unsigned int>(
                  particle->get_properties()[Index::material_id]);
            by_material[m].push_back(particle);
            point_index[m].push_back(point++);
          }

        for (unsigned int m = 0; m < n_materials; ++m)
          {
            const auto &group = by_material[m];
            if (group.empty())
              continue;
            inputs.resize(group.size());
            outputs.resize(group.size());
            for (unsigned int q = 0; q < group.size(); ++q)
              {
                auto       particle = group[q];
                const auto p        = particle->get_properties();
                // ∇v = Σ_i v_i ⊗ G_pi (Eq. 2.7, 2.18)
                Tensor<2, dim> grad_v;
                if (classic)
                  {
                    GridTransfer<dim>::values_and_gradients(
                      data, particle->get_reference_location(), S, G);
                    for (unsigned int i = 0; i < n; ++i)
                      for (unsigned int a = 0; a < dim; ++a)
                        {
                          const double v_ia =
                            v.block(a).local_element(data.local_index[i]);
                          for (unsigned int b = 0; b < dim; ++b)
                            grad_v[a][b] += v_ia * G[i][b];
                        }
                  }
                else // Ḡ of the point's support (GIMP/CPDI)
                  for (unsigned int k = support_offsets[point_index[m][q]];
                       k < support_offsets[point_index[m][q] + 1];
                       ++k)
                    for (unsigned int a = 0; a < dim; ++a)
                      {
                        const double v_ia = v.block(a).local_element(
                          support_nodes[k].local_index);
                        for (unsigned int b = 0; b < dim; ++b)
                          grad_v[a][b] += v_ia * support_nodes[k].G[b];
                      }
                const Tensor<2, 3> L = embed<dim>(grad_v);
                const Tensor<2, 3> F_old =
                  get_tensor3(p, Index::deformation_gradient);
                const Tensor<2, 3> F =
                  deformation_gradient_increment(L, dt) * F_old;
                inputs.deformation_gradient[q] = F;
                inputs.velocity_gradient[q]    = L;
                inputs.properties[q]           = p;
                const double J                 = determinant(F);
                if (!(J > 0) && local_failure.empty())
                  {
                    std::ostringstream message;
                    message
                      << "material point " << particle->get_id() << " at ("
                      << particle->get_location()
                      << ") has an inverted deformation gradient, J = " << J;
                    local_failure = message.str();
                  }
              }

            constitutive_models[m]->update_stress(inputs, outputs);

            const double density = parameters.materials[m].density;
            for (unsigned int q = 0; q < group.size(); ++q)
              {
                auto         particle = group[q];
                const auto   p        = particle->get_properties();
                const double J = determinant(inputs.deformation_gradient[q]);
                set_tensor3(p,
                            Index::deformation_gradient,
                            inputs.deformation_gradient[q]);
                set_symmetric_tensor3(p,
                                      Index::stress,
                                      outputs.cauchy_stress[q]);
                p[Index::strain_energy_density] =
                  outputs.strain_energy_density[q];
                p[Index::volume] = J * p[Index::initial_volume];
                if (J > 0)
                  wave_speed =
                    std::max(wave_speed,
                             constitutive_models[m]->wave_speed(density, J));
                if (!std::isfinite(outputs.strain_energy_density[q]) &&
                    local_failure.empty())
                  {
                    std::ostringstream message;
                    message << "stress of material point " << group[q]->get_id()
                            << " at (" << group[q]->get_location()
                            << ") is not finite (NaN or Inf)";
                    local_failure = message.str();
                  }
              }
          }
      }
    local_max_wave_speed = wave_speed;
  }



  template <int dim>
  void
  Simulator<dim>::sort_particles_into_cells()
  {
    TimerOutput::Scope timer(computing_timer, "sort points into cells");
    // The particle update kept the reference locations of the points that
    // stayed in their cells. Move the others to the locally owned cell that
    // now holds them, searching the cells around the old cell's vertices. If
    // a point went to another rank's cell, or could not be found nearby, or
    // left the mesh, deal.II's full sort handles every point (and reports
    // lost points).
    if (Utilities::MPI::n_mpi_processes(mpi_communicator) > 1)
      {
        points_that_left_their_cell.clear();
        particle_handler.sort_particles_into_subdomains_and_cells();
        return;
      }
    struct Move
    {
      typename Triangulation<dim>::active_cell_iterator cell;
      Point<dim>                                        x, xi;
      types::particle_index                             id;
      std::vector<double>                               properties;
    };
    // Points that stayed in their cell: the reference locations computed in
    // the particle update (same traversal order).
    {
      unsigned int index = 0;
      for (const auto &cell : triangulation.active_cell_iterators())
        if (cell->is_locally_owned())
          for (auto &particle : particle_handler.particles_in_cell(cell))
            {
              const Point<dim> &xi = new_reference_locations[index++];
              if (xi[0] != -1)
                particle.set_reference_location(xi);
            }
    }

    std::vector<Move> moves;
    bool              need_full_sort = false;
    Point<dim>        center;
    for (unsigned int d = 0; d < dim; ++d)
      center[d] = 0.5;
    for (const auto &particle : points_that_left_their_cell)
      {
        const auto       old_cell = particle->get_surrounding_cell();
        const Point<dim> x        = particle->get_location();
        bool             found    = false;
        for (const unsigned int v : old_cell->vertex_indices())
          {
            for (const auto &candidate :
                 vertex_to_cells[old_cell->vertex_index(v)])
              {
                if (candidate == old_cell || !candidate->is_locally_owned())
                  continue;
                const Point<dim> xi = GridTransfer<dim>::reference_point(
                  transfer.cell_data(candidate->active_cell_index()),
                  x,
                  center);
                if (GridTransfer<dim>::is_inside(xi))
                  {
                    const auto p = particle->get_properties();
                    moves.push_back(
                      Move{candidate,
                           x,
                           xi,
                           particle->get_id(),
                           std::vector<double>(p.begin(), p.end())});
                    found = true;
                    break;
                  }
              }
            if (found)
              break;
          }
        if (!found)
          need_full_sort = true;
      }
    // One reduction: does any rank need the full sort, did any rank move
    // points (then the handler's cached counts must be updated, together).
    const unsigned int local_flags[2] = {need_full_sort ? 1u : 0u,
                                         moves.empty() ? 0u : 1u};
    unsigned int global_flags[2] = {0, 0};
    Utilities::MPI::max(make_array_view(local_flags),
                        mpi_communicator,
                        make_array_view(global_flags));
    // On several ranks deal.II's sort also exchanges the points that changed
    // rank; mixing it with local moves is not safe in deal.II 9.4, so the
    // fast path is used on one rank only (see doc/benchmarks.md).
    if (global_flags[0] != 0 || !parameters.fast_point_sorting ||
        Utilities::MPI::n_mpi_processes(mpi_communicator) > 1)
      particle_handler.sort_particles_into_subdomains_and_cells();
    else if (global_flags[1] != 0)
      {
        if (!points_that_left_their_cell.empty())
          particle_handler.remove_particles(points_that_left_their_cell);
        for (const auto &move : moves)
          particle_handler.insert_particle(move.x,
                                           move.xi,
                                           move.id,
                                           move.cell,
                                           make_array_view(move.properties));
        particle_handler.update_cached_numbers();
      }
    points_that_left_their_cell.clear();
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
