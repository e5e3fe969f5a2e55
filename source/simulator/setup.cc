// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Set-up of a run: the background mesh, the DoFs and grid vectors, the
// material points of every body, the grid velocity conditions and the
// plugins.

#include <fmpm/simulator.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <fstream>
#include <map>

namespace fmpm
{
  template <int dim>
  void
  Simulator<dim>::make_grid()
  {
    const MeshParameters &mesh = parameters.mesh;
    if (mesh.type == "box")
      {
        Point<dim>                lower, upper;
        std::vector<unsigned int> subdivisions(dim);
        for (unsigned int d = 0; d < dim; ++d)
          {
            lower[d]        = mesh.lower_corner[d];
            upper[d]        = mesh.upper_corner[d];
            subdivisions[d] = mesh.subdivisions[d];
          }
        GridGenerator::subdivided_hyper_rectangle(
          triangulation, subdivisions, lower, upper, /*colorize=*/true);
      }
    else
      {
        GridIn<dim> grid_in;
        grid_in.attach_triangulation(triangulation);
        std::ifstream input(mesh.file_name);
        try
          {
            grid_in.read_msh(input);
          }
        catch (const ExceptionBase &e)
          {
            std::ostringstream message;
            e.print_info(message);
            AssertThrow(false,
                        ExcMessage("Mesh/File name = <" + mesh.file_name +
                                   "> is not a readable Gmsh mesh of "
                                   "quadrilaterals/hexahedra: " +
                                   message.str()));
          }
      }
    triangulation.refine_global(mesh.global_refinement);
  }



  template <int dim>
  void
  Simulator<dim>::setup_dofs()
  {
    dof_handler.distribute_dofs(fe);
    locally_owned_dofs = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant_dofs);

    // Only hanging-node constraints: velocity conditions are applied to the
    // nodal fields directly, as seed 000 §2.1 describes.
    constraints.clear();
    constraints.reinit(locally_relevant_dofs);
    DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    constraints.close();

    const auto partitioner =
      std::make_shared<Utilities::MPI::Partitioner>(locally_owned_dofs,
                                                    locally_relevant_dofs,
                                                    mpi_communicator);
    lumped_mass.reinit(partitioner);
    auto reinit_field = [&](GridVectorField &field) {
      field.reinit(dim);
      for (unsigned int d = 0; d < dim; ++d)
        field.block(d).reinit(partitioner);
      field.collect_sizes();
    };
    reinit_field(momentum);
    reinit_field(force);
    reinit_field(updated_momentum);
    for (auto &field : grid_fields)
      reinit_field(field);

    transfer.reinit(dof_handler,
                    constraints,
                    *partitioner,
                    shape_function != ShapeFunction::Type::classic);
    vertex_to_cells = GridTools::vertex_to_cell_map(triangulation);

    if (mass_matrix && mass_matrix->needs_full_mass_matrix())
      {
        TrilinosWrappers::SparsityPattern sparsity(locally_owned_dofs,
                                                   locally_owned_dofs,
                                                   locally_relevant_dofs,
                                                   mpi_communicator);
        DoFTools::make_sparsity_pattern(dof_handler,
                                        sparsity,
                                        constraints,
                                        false,
                                        Utilities::MPI::this_mpi_process(
                                          mpi_communicator));
        // GIMP/CPDI couple all nodes of the patch of a point's cell (the
        // cells sharing a vertex with it).
        if (shape_function != ShapeFunction::Type::classic)
          {
            std::vector<types::global_dof_index> patch_dofs;
            for (const auto &cell : triangulation.active_cell_iterators())
              if (cell->is_locally_owned())
                {
                  patch_dofs.clear();
                  for (const unsigned int other :
                       transfer.patch(cell->active_cell_index()))
                    for (const auto dof : transfer.cell_data(other).dof_index)
                      if (std::find(patch_dofs.begin(),
                                    patch_dofs.end(),
                                    dof) == patch_dofs.end())
                        patch_dofs.push_back(dof);
                  constraints.add_entries_local_to_global(patch_dofs,
                                                          sparsity,
                                                          false);
                }
          }
        sparsity.compress();
        full_mass_matrix.reinit(sparsity);
      }

    // The smallest edge length h_min for the Courant condition.
    double h_min = std::numeric_limits<double>::max();
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        h_min = std::min(h_min, cell->minimum_vertex_distance());
    minimum_cell_size = Utilities::MPI::min(h_min, mpi_communicator);
  }



  namespace
  {
    /** Whether @p x lies inside the body's shape. */
    template <int dim>
    bool
    inside_body(const BodyParameters &body, const Point<dim> &x)
    {
      if (body.shape == "box")
        {
          for (unsigned int d = 0; d < dim; ++d)
            if (std::abs(x[d] - body.center[d]) > body.half_lengths[d])
              return false;
          return true;
        }
      double r2 = 0;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const double a = (body.shape == "sphere") ? body.half_lengths[0] :
                                                      body.half_lengths[d];
          r2 += std::pow((x[d] - body.center[d]) / a, 2);
        }
      return r2 <= 1.0;
    }

    /** Axis-aligned bounding box of the body. */
    template <int dim>
    BoundingBox<dim>
    body_bounding_box(const BodyParameters &body)
    {
      Point<dim> lower, upper;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const double a = (body.shape == "sphere") ? body.half_lengths[0] :
                                                      body.half_lengths[d];
          lower[d]       = body.center[d] - a;
          upper[d]       = body.center[d] + a;
        }
      return BoundingBox<dim>(std::make_pair(lower, upper));
    }
  } // namespace



  template <int dim>
  void
  Simulator<dim>::create_material_points()
  {
    using Index                 = PropertyIndex<dim>;
    const unsigned int n_bodies = parameters.bodies.size();

    // One FEValues per distinct number of points per cell: the points are
    // the midpoints of a regular subdivision of the reference cell, their
    // volume the JxW of that midpoint rule.
    std::map<unsigned int, std::unique_ptr<FEValues<dim>>> fe_values_for_ppc;
    for (const auto &body : parameters.bodies)
      if (fe_values_for_ppc.find(body.points_per_cell) ==
          fe_values_for_ppc.end())
        fe_values_for_ppc[body.points_per_cell] =
          std::make_unique<FEValues<dim>>(mapping,
                                          fe,
                                          QIterated<dim>(QMidpoint<1>(),
                                                         body.points_per_cell),
                                          update_quadrature_points |
                                            update_JxW_values);

    // Initial velocity of each body as a function of position.
    std::vector<std::unique_ptr<FunctionParser<dim>>> initial_velocity;
    for (unsigned int b = 0; b < n_bodies; ++b)
      {
        const std::string where =
          numbered_subsection("Body", b) + "/Initial velocity";
        initial_velocity.push_back(std::make_unique<FunctionParser<dim>>(dim));
        try
          {
            initial_velocity.back()->initialize(
              FunctionParser<dim>::default_variable_names(),
              to_function_expressions(parameters.bodies[b].velocity_expression),
              parse_function_constants(parameters.bodies[b].function_constants,
                                       numbered_subsection("Body", b) +
                                         "/Function constants"));
          }
        catch (const ExceptionBase &e)
          {
            std::ostringstream message;
            e.print_info(message);
            AssertThrow(false,
                        ExcMessage(
                          where + " = <" +
                          parameters.bodies[b].velocity_expression +
                          "> is not " + std::to_string(dim) +
                          " numbers or expressions: " + message.str()));
          }
      }

    std::vector<BoundingBox<dim>> body_boxes;
    for (const auto &body : parameters.bodies)
      body_boxes.push_back(body_bounding_box<dim>(body));

    struct NewPoint
    {
      typename Triangulation<dim>::active_cell_iterator cell;
      Point<dim>                                        x;
      Point<dim>                                        xi;
      std::vector<double>                               properties;
    };
    std::vector<NewPoint> new_points;

    // Cells outer, bodies inner: the global order (and so the ids) is the
    // same on any number of ranks.
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const BoundingBox<dim> cell_box = cell->bounding_box();
          for (unsigned int b = 0; b < n_bodies; ++b)
            {
              const BodyParameters &body = parameters.bodies[b];
              if (cell_box.get_neighbor_type(body_boxes[b]) ==
                  NeighborType::not_neighbors)
                continue;
              FEValues<dim> &fe_values =
                *fe_values_for_ppc[body.points_per_cell];
              fe_values.reinit(cell);
              const Quadrature<dim> &quadrature = fe_values.get_quadrature();
              for (unsigned int q = 0; q < quadrature.size(); ++q)
                {
                  const Point<dim> &x = fe_values.quadrature_point(q);
                  if (!inside_body(body, x))
                    continue;
                  bool claimed = false;
                  for (unsigned int earlier = 0; earlier < b; ++earlier)
                    if (inside_body(parameters.bodies[earlier], x))
                      claimed = true;
                  if (claimed)
                    continue;

                  const MaterialParameters &material =
                    parameters.materials[body.material];
                  const double        volume = fe_values.JxW(q);
                  std::vector<double> p(particle_properties.n_properties(), 0.);
                  p[Index::mass]           = material.density * volume;
                  p[Index::volume]         = volume;
                  p[Index::initial_volume] = volume;
                  for (unsigned int d = 0; d < dim; ++d)
                    p[Index::velocity + d] = initial_velocity[b]->value(x, d);
                  for (unsigned int i = 0; i < 3; ++i)
                    p[Index::deformation_gradient + 4 * i] = 1.0;
                  p[Index::material_id] = body.material;
                  p[Index::body_id]     = b;
                  for (unsigned int d = 0; d < dim; ++d)
                    {
                      p[Index::initial_position + d] = x[d];
                      p[Index::initial_half_length + d] =
                        0.5 * cell->extent_in_direction(d) /
                        body.points_per_cell;
                    }
                  new_points.push_back(
                    NewPoint{cell, x, quadrature.point(q), std::move(p)});
                }
            }
        }

    // Globally unique ids: an exclusive prefix sum of the local counts.
    unsigned long long n_local = new_points.size(), first_id = 0;
    const int          ierr = MPI_Exscan(&n_local,
                                &first_id,
                                1,
                                MPI_UNSIGNED_LONG_LONG,
                                MPI_SUM,
                                mpi_communicator);
    AssertThrowMPI(ierr);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      first_id = 0;

    particle_handler.reserve(new_points.size());
    for (unsigned int i = 0; i < new_points.size(); ++i)
      particle_handler.insert_particle(new_points[i].x,
                                       new_points[i].xi,
                                       first_id + i,
                                       new_points[i].cell,
                                       make_array_view(
                                         new_points[i].properties));
    particle_handler.update_cached_numbers();

    // Every body must have produced points.
    std::vector<unsigned long long> points_per_body(n_bodies, 0);
    for (const auto &point : new_points)
      ++points_per_body[static_cast<unsigned int>(
        point.properties[Index::body_id])];
    Utilities::MPI::sum(points_per_body, mpi_communicator, points_per_body);
    for (unsigned int b = 0; b < n_bodies; ++b)
      AssertThrow(points_per_body[b] > 0,
                  ExcMessage(numbered_subsection("Body", b) +
                             " contains no material point: its shape lies "
                             "outside the mesh or is smaller than one point "
                             "spacing. Check its Center and Half lengths "
                             "against the Mesh subsection."));
  }



  template <int dim>
  void
  Simulator<dim>::setup_boundary_conditions()
  {
    node_conditions.clear();
    const auto                  &bc = parameters.boundary_conditions;
    std::set<types::boundary_id> mesh_ids;
    for (const auto id : triangulation.get_boundary_ids())
      mesh_ids.insert(id);
    for (const auto id : bc.fixed)
      AssertThrow(mesh_ids.count(id),
                  ExcMessage("Boundary conditions/Fixed boundary ids names "
                             "boundary id " +
                             std::to_string(id) +
                             ", which the mesh does not have."));
    for (const auto id : bc.roller)
      AssertThrow(mesh_ids.count(id),
                  ExcMessage("Boundary conditions/Roller boundary ids names "
                             "boundary id " +
                             std::to_string(id) +
                             ", which the mesh does not have."));

    const auto &partitioner = *lumped_mass.get_partitioner();
    // For each condition (boundary id) and owned node: the summed outward
    // face normals of the faces with that id around the node.
    std::map<std::pair<types::boundary_id, types::global_dof_index>,
             Tensor<1, dim>>
                                         normals;
    std::vector<types::global_dof_index> dofs(fe.dofs_per_cell);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          cell->get_dof_indices(dofs);
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              {
                const types::boundary_id id = cell->face(f)->boundary_id();
                const bool               is_fixed =
                  std::find(bc.fixed.begin(), bc.fixed.end(), id) !=
                  bc.fixed.end();
                const bool is_roller =
                  std::find(bc.roller.begin(), bc.roller.end(), id) !=
                  bc.roller.end();
                if (!is_fixed && !is_roller)
                  continue;
                // Outward unit normal of the (planar or nearly planar) face.
                const auto     face = cell->face(f);
                Tensor<1, dim> normal;
                if (dim == 2)
                  {
                    const Tensor<1, dim> t = face->vertex(1) - face->vertex(0);
                    normal[0]              = t[1];
                    normal[1]              = -t[0];
                  }
                else
                  {
                    const Tensor<1, dim> d1 = face->vertex(3) - face->vertex(0);
                    const Tensor<1, dim> d2 = face->vertex(2) - face->vertex(1);
                    Tensor<1, 3>         a, b;
                    for (unsigned int d = 0; d < dim; ++d)
                      {
                        a[d] = d1[d];
                        b[d] = d2[d];
                      }
                    const Tensor<1, 3> n = cross_product_3d(a, b);
                    for (unsigned int d = 0; d < dim; ++d)
                      normal[d] = n[d];
                  }
                if (normal * (face->center() - cell->center()) < 0)
                  normal = -normal;
                normal /= normal.norm();
                for (unsigned int v = 0; v < face->n_vertices(); ++v)
                  {
                    const types::global_dof_index dof =
                      face->vertex_dof_index(v, 0);
                    if (!locally_owned_dofs.is_element(dof))
                      continue;
                    const types::boundary_id key_id =
                      is_fixed ? numbers::invalid_boundary_id : id;
                    normals[std::make_pair(key_id, dof)] += normal;
                  }
              }
        }
    for (const auto &entry : normals)
      {
        NodeCondition condition;
        condition.local_index = partitioner.global_to_local(entry.first.second);
        condition.fixed_all =
          (entry.first.first == numbers::invalid_boundary_id);
        condition.normal = entry.second;
        if (!condition.fixed_all)
          condition.normal /= condition.normal.norm();
        node_conditions.push_back(condition);
      }

    // Components held at zero velocity on axis-aligned conditions: the full
    // mass matrix solves treat them as known (Dirichlet) values, the least
    // squares problem of seed 000 Eq. 1.49.
    zero_velocity_mask.resize(dim);
    for (unsigned int d = 0; d < dim; ++d)
      {
        zero_velocity_mask[d].reinit(lumped_mass.get_partitioner());
        zero_velocity_mask[d] = 0;
      }
    for (const auto &condition : node_conditions)
      for (unsigned int d = 0; d < dim; ++d)
        if (condition.fixed_all || std::abs(condition.normal[d]) > 1 - 1e-12)
          zero_velocity_mask[d].local_element(condition.local_index) = 1;
  }



  template <int dim>
  void
  Simulator<dim>::setup_plugins(ParameterHandler &prm)
  {
    for (unsigned int m = 0; m < parameters.materials.size(); ++m)
      {
        const std::string where = numbered_subsection("Material", m);
        prm.enter_subsection(where);
        constitutive_models.push_back(
          ConstitutiveModel::Registry<dim>::instance().create(
            parameters.materials[m].model_name, prm));
        prm.leave_subsection();
        constitutive_models.back()->check_parameters(
          where + "/" +
          ConstitutiveModel::Registry<dim>::subsection_name(
            parameters.materials[m].model_name));
      }

    prm.enter_subsection("Mass matrix");
    mass_matrix = MassMatrix::Registry<dim>::instance().create(
      parameters.method.mass_matrix, prm);
    prm.leave_subsection();
    mass_matrix->initialize_simulator(*this);

    prm.enter_subsection("Particle update");
    particle_update = ParticleUpdate::Registry<dim>::instance().create(
      parameters.method.particle_update, prm);
    prm.leave_subsection();

    if (!parameters.body_acceleration.empty())
      {
        auto function = std::make_unique<FunctionParser<dim>>(dim);
        try
          {
            function->initialize(
              FunctionParser<dim>::default_variable_names() + ",t",
              to_function_expressions(parameters.body_acceleration),
              parse_function_constants(parameters.body_acceleration_constants,
                                       "Body force/Function constants"),
              true);
          }
        catch (const ExceptionBase &e)
          {
            std::ostringstream message;
            e.print_info(message);
            AssertThrow(false,
                        ExcMessage(
                          "Body force/Acceleration = <" +
                          parameters.body_acceleration + "> is not " +
                          std::to_string(dim) +
                          " expressions in x, y, z, t: " + message.str()));
          }
        body_acceleration = std::move(function);
      }

    field_needed.fill(false);
    field_needed[ParticleUpdate::updated_velocity] = true;
    for (const auto field : particle_update->required_fields())
      field_needed[field] = true;
    // Grid damping needs S v; the dissipation measure S v and S a.
    if (parameters.method.grid_damping != 0)
      field_needed[ParticleUpdate::velocity] = true;
    if (parameters.output.track_dissipation)
      field_needed[ParticleUpdate::velocity] =
        field_needed[ParticleUpdate::acceleration] = true;
  }



  template <int dim>
  void
  Simulator<dim>::check_scene()
  {
    // Bodies must lie inside the mesh.
    const BoundingBox<dim> mesh_box =
      GridTools::compute_bounding_box(triangulation);
    for (unsigned int b = 0; b < parameters.bodies.size(); ++b)
      {
        const BoundingBox<dim> box =
          body_bounding_box<dim>(parameters.bodies[b]);
        const double tolerance = 1e-10 * mesh_box.side_length(0);
        for (unsigned int d = 0; d < dim; ++d)
          AssertThrow(
            box.lower_bound(d) >= mesh_box.lower_bound(d) - tolerance &&
              box.upper_bound(d) <= mesh_box.upper_bound(d) + tolerance,
            ExcMessage(
              numbered_subsection("Body", b) +
              " reaches outside the mesh in direction " + std::to_string(d) +
              ": the body spans [" + std::to_string(box.lower_bound(d)) + ", " +
              std::to_string(box.upper_bound(d)) + "] but the mesh spans [" +
              std::to_string(mesh_box.lower_bound(d)) + ", " +
              std::to_string(mesh_box.upper_bound(d)) +
              "]. Change its Center or Half lengths."));
      }

    // A fixed time step must be stable.
    const double stable = minimum_cell_size / max_signal_speed;
    AssertThrow(
      !parameters.time.check_stability || parameters.time.time_step <= stable,
      ExcMessage(
        "Time/Time step = " + std::to_string(parameters.time.time_step) +
        " s is above the stable limit h_min / (wave speed "
        "+ point speed) = " +
        std::to_string(stable) +
        " s of this scene. Choose a smaller time step, or "
        "set it to 0 and use Time/Courant number (or set Time/Check "
        "stability limit = false for a stability study)."));
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
