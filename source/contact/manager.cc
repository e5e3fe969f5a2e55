// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The contact manager: set-up, the material fields' conditions and
// momentum update, the point clouds of the contact nodes, history and
// summary figures.

#include <fmpm/contact/manager.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/material_points.h>
#include <fmpm/neighbour_exchange.h>
#include <fmpm/support_cache.h>
#include <fmpm/velocity_conditions.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>

namespace fmpm
{
  namespace Contact
  {
    template <int dim>
    void
    Manager<dim>::initialize()
    {
      const ::fmpm::Parameters &parameters  = this->get_parameters();
      const Parameters         &contact     = parameters.contact;
      const unsigned int        n_materials = parameters.size.n_materials;
      const MassMatrix::Interface<dim> &mass_matrix = this->get_mass_matrix();

      normal_method = create_normal_method<dim>(contact.normals_name);
      // DF: d(x) of each material from the half-length of its points (the
      // first body made of it; 2 points per cell if none).
      NormalSetup setup;
      setup.type = this->get_shape_function_type();
      setup.points_per_cell.assign(n_materials, 2);
      for (unsigned int a = 0; a < n_materials; ++a)
        for (const auto &body : parameters.bodies)
          if (body.material == a)
            {
              setup.points_per_cell[a] = body.points_per_cell;
              break;
            }
      normal_method->set_up(contact, setup);
      needs = normal_method->needs();

      // The exact solve: CG settings of the single-material one.
      material_exact_solve = mass_matrix.exact_solve();
      if (material_exact_solve)
        {
          AssertThrow(n_materials <= 32,
                      ExcMessage(
                        "'Mass matrix/Model name = full' with contact "
                        "supports up to 32 materials; this scene has " +
                        std::to_string(n_materials) + "."));
        }

      material_full_mass_needed =
        mass_matrix.order() > 1 || material_exact_solve.has_value();
      full_mass.resize(material_full_mass_needed ? n_materials : 0);

      increment_law = create_law<dim>(Law{"perfect", {}});
      laws.clear();
      laws.resize(n_materials * n_materials);
      needs_interface = false;
      for (unsigned int a = 0; a < n_materials; ++a)
        for (unsigned int b = a + 1; b < n_materials; ++b)
          {
            laws[a * n_materials + b] = create_law<dim>(contact.law(a, b));
            needs_interface =
              needs_interface || laws[a * n_materials + b]->interface_state();
          }
      // (The contact area of interface laws is measured in the local cell
      // size.)
      needs.cell_size = needs.cell_size || needs_interface;
    }



    template <int dim>
    void
    Manager<dim>::reinit()
    {
      const ::fmpm::Parameters         &parameters  = this->get_parameters();
      const MassMatrix::Interface<dim> &mass_matrix = this->get_mass_matrix();
      const DoFHandler<dim>            &dof_handler = this->get_dof_handler();
      geometry_valid                                = false;
      multimaterial_nodes_valid                     = false;
      delta_velocity_nodes.clear();
      recorded_nodes.clear();

      const auto partitioner = this->get_lumped_mass().get_partitioner();
      auto       reinit      = [&](GridVectorField &field) {
        field.reinit(dim);
        for (unsigned int d = 0; d < dim; ++d)
          field.block(d).reinit(partitioner);
        field.collect_sizes();
      };
      reinit(contact_normal);
      contact_separation.reinit(partitioner);
      fields.clear();
      fields.resize(parameters.size.n_materials);
      for (auto &material : fields)
        {
          material.reinit(partitioner, true);
          reinit(material.delta_velocity);
          if (mass_matrix.order() > 1)
            {
              reinit(material.series_product);
              reinit(material.series_rhs);
              if (parameters.contact.net_incremental)
                reinit(material.series_increment);
            }
          if (material_exact_solve)
            {
              material.full_mass_diagonal.reinit(partitioner);
              material.weak.reinit(partitioner);
            }
          if (needs.volume_gradients)
            reinit(material.volume_gradient);
          if (needs.positions)
            reinit(material.position_moment);
          if (needs_interface)
            {
              reinit(material.displacement_moment);
              material.volume.reinit(partitioner);
            }
        }
      if (material_exact_solve)
        {
          known_velocity_mask.resize(dim);
          known_velocity_value.resize(dim);
          for (unsigned int d = 0; d < dim; ++d)
            {
              known_velocity_mask[d].reinit(partitioner);
              known_velocity_value[d].reinit(partitioner);
            }
        }

      // The local cell size at a node: the smallest vertex distance of the
      // cells around it (separations are measured in cells, also on adapted
      // and unstructured meshes); DF also needs the node positions.
      if (needs.cell_size)
        {
          node_cell_size.reinit(partitioner);
          const double large = std::numeric_limits<double>::max();
          for (auto &value : node_cell_size)
            value = large;
          node_cell_size.update_ghost_values();
          if (needs.node_positions)
            reinit(node_position);
          std::vector<types::global_dof_index> dofs(
            dof_handler.get_fe().n_dofs_per_cell());
          for (const auto &cell : dof_handler.active_cell_iterators())
            if (cell->is_locally_owned())
              {
                const double h = cell->minimum_vertex_distance();
                cell->get_dof_indices(dofs);
                for (unsigned int v = 0; v < dofs.size(); ++v)
                  {
                    const unsigned int i =
                      partitioner->global_to_local(dofs[v]);
                    double &value = node_cell_size.local_element(i);
                    value         = std::min(value, h);
                    if (needs.node_positions) // FE_Q(1): dof v at vertex v
                      for (unsigned int d = 0; d < dim; ++d)
                        node_position.block(d).local_element(i) =
                          cell->vertex(v)[d];
                  }
              }
          node_cell_size.compress(VectorOperation::min);
          if (needs.node_positions)
            for (unsigned int d = 0; d < dim; ++d)
              node_position.block(d).compress(VectorOperation::insert);
        }
    }



    template <int dim>
    GeometrySink<dim> &
    Manager<dim>::reset_geometry_sink(const MaterialPoints<dim> &points,
                                      const unsigned char *const point_material)
    {
      geometry_sink.reset(fields,
                          needs,
                          needs_interface,
                          points,
                          point_material,
                          this->get_parameters().axisymmetric);
      return geometry_sink;
    }



    template <int dim>
    GeometrySink<dim> &
    Manager<dim>::begin_extrapolation(const MaterialPoints<dim> &points,
                                      const unsigned char *const point_material,
                                      const bool                 with_forces)
    {
      invalidate_geometry(true);
      for (auto &field : fields)
        {
          field.mass     = 0;
          field.momentum = 0;
          if (with_forces)
            field.force = 0;
        }
      if (material_full_mass_needed)
        for (auto &matrix : full_mass)
          matrix.clear();
      return reset_geometry_sink(points, point_material);
    }



    template <int dim>
    void
    Manager<dim>::finish_extrapolation(NodalField<dim> &total,
                                       const bool       with_forces)
    {
      total.set_to_sum(fields, true, true, with_forces);
      for (auto &field : fields)
        {
          field.mass.compress(VectorOperation::add);
          field.momentum.compress(VectorOperation::add);
          if (with_forces)
            field.force.compress(VectorOperation::add);
          GeometrySink<dim>::compress(field, needs, needs_interface);
          field.mass.update_ghost_values();
          field.computed.fill(false);
        }
    }



    template <int dim>
    GeometrySink<dim> &
    Manager<dim>::begin_re_extrapolation(
      const MaterialPoints<dim> &points,
      const unsigned char *const point_material)
    {
      for (auto &field : fields)
        field.momentum = 0;
      return reset_geometry_sink(points, point_material);
    }



    template <int dim>
    void
    Manager<dim>::finish_re_extrapolation(NodalField<dim> &total)
    {
      invalidate_geometry(false);
      total.set_to_sum(fields, false, true, false);
      for (auto &field : fields)
        {
          field.momentum.compress(VectorOperation::add);
          GeometrySink<dim>::compress(field, needs, needs_interface);
          field.computed.fill(false);
        }
    }



    template <int dim>
    void
    Manager<dim>::correct_extrapolated_momenta(const double t,
                                               const Stage  stage)
    {
      for (unsigned int a = 0; a < fields.size(); ++a)
        impose_material_conditions(a, fields[a].momentum, t);
      if (stage == Stage::re_extrapolated ||
          this->get_parameters().contact.corrections_per_step == 2)
        apply(stage);
      else
        for (auto &field : fields)
          field.momentum.update_ghost_values();
    }



    template <int dim>
    void
    Manager<dim>::update_momenta(const double dt, const double t_end)
    {
      for (unsigned int a = 0; a < fields.size(); ++a)
        {
          MaterialField<dim> &field = fields[a];
          set_scaled_sum(field.updated_momentum,
                         field.momentum,
                         dt,
                         field.force);
          impose_material_conditions(a, field.updated_momentum, t_end);
        }
    }



    template <int dim>
    std::pair<double, double>
    Manager<dim>::history_values()
    {
      const MPI_Comm comm = this->get_mpi_communicator();
      friction_work += Utilities::MPI::sum(local_friction_work, comm);
      local_friction_work = 0;
      return {friction_work,
              static_cast<double>(
                Utilities::MPI::sum(local_contact_nodes, comm))};
    }



    template <int dim>
    std::vector<std::pair<std::string, double>>
    Manager<dim>::summary_entries() const
    {
      auto entries = normal_method->statistics(this->get_mpi_communicator());
      if (material_solves > 0) // the same on every rank (CG is global)
        {
          entries.emplace_back("contact_cg_solves", material_solves);
          entries.emplace_back("contact_cg_iterations_mean",
                               static_cast<double>(material_solve_iterations) /
                                 material_solves);
          entries.emplace_back("contact_cg_failures", material_solve_failures);
        }
      return entries;
    }



    template <int dim>
    void
    Manager<dim>::impose_material_conditions(const unsigned int alpha,
                                             GridVectorField   &q,
                                             const double       t) const
    {
      const double                   mass_floor = this->get_mass_floor();
      const VelocityConditions<dim> &velocity_conditions =
        this->get_velocity_conditions();
      // The conditions act on every material field with that material's
      // lumped masses (contact requires the lumped mass matrix).
      const GridScalar                           &m = fields[alpha].mass;
      typename VelocityConditions<dim>::Operators operators;
      operators.lumped_mass = &m;
      operators.mass_floor  = mass_floor;
      operators.solve       = [&m, mass_floor](const GridVectorField &p,
                                         GridVectorField       &v) {
        MassMatrix::apply_lumped_inverse(m, p, v, mass_floor);
      };
      operators.forward = [&m](const GridVectorField &v, GridVectorField &p) {
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
            p.block(d).local_element(i) =
              m.local_element(i) * v.block(d).local_element(i);
      };
      operators.full_mass = operators.forward;
      velocity_conditions.impose_on_momenta(q, t, operators, nullptr);
    }



    template <int dim>
    void
    Manager<dim>::gather_point_clouds()
    {
      const GridScalar          &lumped_mass = this->get_lumped_mass();
      const SupportCache<dim>   &supports    = this->get_support_cache();
      const MaterialPoints<dim> &points      = this->get_material_points();
      const double               mass_floor  = this->get_mass_floor();
      const MPI_Comm     mpi_communicator    = this->get_mpi_communicator();
      TimerOutput::Scope timer(this->get_computing_timer(),
                               "contact: point clouds");
      using Index                    = PropertyIndex<dim>;
      const auto        &partitioner = *lumped_mass.get_partitioner();
      const unsigned int n_owned     = partitioner.locally_owned_size();
      const unsigned int n_local     = n_owned + partitioner.n_ghost_indices();
      const unsigned int n_materials = fields.size();
      const double       floor       = mass_floor;

      // Nodes (owned and ghost) that see 2+ materials: the ghost masses are
      // current after the extrapolation.
      if (!multimaterial_nodes_valid)
        find_multimaterial_nodes();
      std::vector<char> shared(n_local, 0);
      for (const unsigned int i : multimaterial_nodes)
        shared[i] = 1;
      for (unsigned int i = n_owned; i < n_local; ++i)
        {
          unsigned int count = 0;
          for (unsigned int a = 0; a < n_materials; ++a)
            count += fields[a].mass.local_element(i) > floor;
          shared[i] = count > 1;
        }
      // The owner of each ghost node (ghosts are numbered rank by rank).
      std::vector<unsigned int> ghost_owner;
      ghost_owner.reserve(partitioner.n_ghost_indices());
      for (const auto &[rank, count] : partitioner.ghost_targets())
        ghost_owner.insert(ghost_owner.end(), count, rank);

      std::vector<CloudPoint<dim>>                         owned_points;
      std::map<unsigned int, std::vector<CloudPoint<dim>>> sent;
      const GridTransfer<dim> &transfer = this->get_grid_transfer();
      const SupportReader<dim> support_of(supports,
                                          transfer,
                                          points.cell.data());
      // A point is in a node's cloud where S_ip > 1e-30: a support that
      // meets the node only at its edge, up to the round-off of the
      // position (a point on the lattice of support edges: the tails of
      // uGIMP and the B-splines go as ε², ε³, ε ~ 1e-16 cells), stays out
      // whichever way it rounds. S ≤ 1e-30 is an overlap below 1e-10
      // cells for the cubic tails, 1e-15 for the quadratic ones.
      constexpr double edge_round_off = 1e-30;
      for (unsigned int c = 0; c < points.n_cells(); ++c)
        {
          // Computed supports are the cell's nodes: a cell without a
          // shared node has no point in a cloud.
          if (supports.implicit_classic)
            {
              bool any_shared = false;
              for (const unsigned int i :
                   transfer.cell_data(points.cell_index[c]).local_index)
                any_shared = any_shared || shared[i];
              if (!any_shared)
                continue;
            }
          for (unsigned int k = points.cell_point_begin[c];
               k < points.cell_point_begin[c + 1];
               ++k)
            support_of.visit(
              k,
              false,
              [&](const unsigned int *const node,
                  const double *const       S,
                  const Tensor<1, dim> *,
                  const auto n_entries) {
                bool            filled = false;
                CloudPoint<dim> point{};
                for (unsigned int j = 0; j < n_entries; ++j)
                  {
                    const unsigned int i = node[j];
                    if (!shared[i] || !(S[j] > edge_round_off))
                      continue;
                    if (!filled)
                      {
                        const PointRecord P = points.record(k);
                        const Point<dim> &X = points.position[k];
                        Tensor<2, dim>    F;
                        for (unsigned int a = 0; a < dim; ++a)
                          for (unsigned int b = 0; b < dim; ++b)
                            F[a][b] =
                              P[Index::deformation_gradient + 3 * a + b];
                        const Tensor<2, dim> F_inverse = invert(F);
                        point.id                       = points.id[k];
                        point.material                 = supports.material[k];
                        for (unsigned int a = 0; a < dim; ++a)
                          {
                            point.position[a] = X[a];
                            point.initial_radii[a] =
                              P[Index::initial_half_length + a];
                            for (unsigned int b = 0; b < dim; ++b)
                              point.F_inverse[a * dim + b] = F_inverse[a][b];
                          }
                        filled = true;
                      }
                    point.node = partitioner.local_to_global(i);
                    if (i < n_owned)
                      owned_points.push_back(point);
                    else
                      sent[ghost_owner[i - n_owned]].push_back(point);
                  }
              });
        }
      // Each rank sends to the owners of its ghost nodes and receives from
      // the ranks that have its nodes as ghosts (the partitioner's import
      // targets): one message each way, possibly empty, no collective.
      std::vector<unsigned int> send_to, receive_from;
      for (const auto &[rank, count] : partitioner.ghost_targets())
        send_to.push_back(rank);
      for (const auto &[rank, count] : partitioner.import_targets())
        receive_from.push_back(rank);
      for (const auto &[rank, points] :
           neighbour_exchange(mpi_communicator,
                              send_to,
                              receive_from,
                              sent,
                              MPITags::contact_point_clouds))
        owned_points.insert(owned_points.end(), points.begin(), points.end());

      // Sort into the clouds of the owned nodes (counting sort).
      cloud_begin.assign(n_owned + 1, 0);
      for (const auto &point : owned_points)
        ++cloud_begin[partitioner.global_to_local(point.node) + 1];
      for (unsigned int i = 0; i < n_owned; ++i)
        cloud_begin[i + 1] += cloud_begin[i];
      cloud.resize(owned_points.size());
      std::vector<unsigned int> next(cloud_begin.begin(),
                                     cloud_begin.end() - 1);
      for (const auto &point : owned_points)
        cloud[next[partitioner.global_to_local(point.node)]++] = point;
      // The points of other ranks came after the rank's own: the clouds in
      // id order, the same on every number of ranks.
      for (unsigned int i = 0; i < n_owned; ++i)
        std::sort(cloud.begin() + cloud_begin[i],
                  cloud.begin() + cloud_begin[i + 1],
                  [](const CloudPoint<dim> &a, const CloudPoint<dim> &b) {
                    return a.id < b.id;
                  });
    }



    template class Manager<2>;
    template class Manager<3>;
  } // namespace Contact
} // namespace fmpm
