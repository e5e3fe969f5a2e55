// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Set-up of a run: the background mesh, the DoFs and grid vectors, the
// grid velocity conditions, the plugins and the scene's checks (the material
// points: point_setup.cc).

#include <fmpm/axisymmetric_shape_function.h>
#include <fmpm/bspline_ghosts.h>
#include <fmpm/function_parser.h>
#include <fmpm/geometry/body_shape.h>
#include <fmpm/geometry/mesh_body.h>
#include <fmpm/simulator.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>

namespace fmpm
{
  template <int dim>
  void
  Simulator<dim>::make_grid()
  {
    const MeshParameters &mesh = parameters.mesh;
    // The coarse mesh is built directly in the distributed triangulation,
    // or, when it must be distorted, in a serial one first: every rank then
    // distorts the same coarse mesh with the same seed.
    // Gmsh meshes are read into a serial triangulation too, so that a mesh
    // of triangles/tetrahedra is rejected with a message before p4est sees
    // it.
    const bool via_serial =
      mesh.distortion > 0 || mesh.type == MeshParameters::Type::gmsh;
    Triangulation<dim>  serial;
    Triangulation<dim> &coarse =
      via_serial ? serial : static_cast<Triangulation<dim> &>(triangulation);
    Point<dim> lower, upper;
    for (unsigned int d = 0; d < dim; ++d)
      {
        lower[d] = mesh.lower_corner[d];
        upper[d] = mesh.upper_corner[d];
      }
    if (mesh.type == MeshParameters::Type::box)
      {
        std::vector<unsigned int> subdivisions(dim);
        for (unsigned int d = 0; d < dim; ++d)
          subdivisions[d] = mesh.subdivisions[d];
        GridGenerator::subdivided_hyper_rectangle(
          coarse, subdivisions, lower, upper, /*colorize=*/true);
      }
    else if (mesh.type == MeshParameters::Type::ball)
      // Manifold 0 (the circle/sphere) on the boundary, transfinite
      // interpolation inside: refinement puts new boundary vertices on the
      // curve.
      GridGenerator::hyper_ball(coarse,
                                Point<dim>(0.5 * (lower + upper)),
                                0.5 * (upper[0] - lower[0]));
    else
      {
        GridIn<dim> grid_in;
        grid_in.attach_triangulation(coarse);
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
    AssertThrow(coarse.all_reference_cells_are_hyper_cube(),
                ExcMessage("Mesh/File name = <" + mesh.file_name +
                           "> has triangles or tetrahedra: fmpm's grid "
                           "transfer works on quadrilaterals and hexahedra "
                           "only (see README.md, Meshes)."));
    if (mesh.distortion > 0)
      GridTools::distort_random(mesh.distortion,
                                serial,
                                /*keep_boundary=*/true,
                                /*seed=*/20260);
    if (via_serial)
      triangulation.copy_triangulation(serial);
    // Mesh/Periodic directions: p4est joins the two faces across each
    // periodic axis of the box (before any refinement, also before a
    // checkpoint's refinement is loaded); setup_dofs() joins their nodes.
    if (mesh.any_periodic())
      {
        std::vector<GridTools::PeriodicFacePair<
          typename Triangulation<dim>::cell_iterator>>
          face_pairs;
        for (unsigned int d = 0; d < dim; ++d)
          if (mesh.periodic[d])
            GridTools::collect_periodic_faces(
              triangulation, 2 * d, 2 * d + 1, d, face_pairs);
        triangulation.add_periodicity(face_pairs);
      }
    // A resumed run loads the refinement from its checkpoint onto the
    // coarse mesh.
    if (!checkpoint_state.resume)
      triangulation.refine_global(mesh.global_refinement);
  }



  namespace
  {
    /** The sparsity of the full mass matrix m̃ (Eq. 1.9) into @p sparsity:
     * the nodes of each cell, and with @p patch_supports (GIMP, CPDI) all
     * nodes of the patch of a point's cell (the cells sharing a vertex
     * with it), with B-splines those within their reach. */
    template <int dim>
    void
    make_full_mass_sparsity(
      const DoFHandler<dim>                     &dof_handler,
      const AffineConstraints<double>           &constraints,
      const Utilities::MPI::Partitioner         &partitioner,
      const GridTransfer<dim>                   &transfer,
      const ShapeFunction::BSplineSupports<dim> &bspline_supports,
      const bool                                 patch_supports,
      TrilinosWrappers::SparsityPattern         &sparsity)
    {
      DoFTools::make_sparsity_pattern(dof_handler,
                                      sparsity,
                                      constraints,
                                      false,
                                      Utilities::MPI::this_mpi_process(
                                        dof_handler.get_communicator()));
      if (bspline_supports.active())
        {
          std::vector<unsigned int>            local_indices;
          std::vector<types::global_dof_index> reach_dofs;
          for (const auto &cell : dof_handler.active_cell_iterators())
            if (cell->is_locally_owned())
              {
                bspline_supports.vertices_in_reach(
                  transfer.cell_data(cell->active_cell_index()), local_indices);
                reach_dofs.clear();
                for (const unsigned int local : local_indices)
                  reach_dofs.push_back(partitioner.local_to_global(local));
                constraints.add_entries_local_to_global(reach_dofs,
                                                        sparsity,
                                                        false);
              }
        }
      else if (patch_supports)
        {
          std::vector<types::global_dof_index> patch_dofs;
          for (const auto &cell : dof_handler.active_cell_iterators())
            if (cell->is_locally_owned())
              {
                patch_dofs.clear();
                for (const unsigned int other :
                     transfer.patch(cell->active_cell_index()))
                  for (unsigned int i = 0; i < GridTransfer<dim>::n_nodes; ++i)
                    if (const auto dof =
                          transfer.dof_index(transfer.cell_data(other), i);
                        std::find(patch_dofs.begin(), patch_dofs.end(), dof) ==
                        patch_dofs.end())
                      patch_dofs.push_back(dof);
                constraints.add_entries_local_to_global(patch_dofs,
                                                        sparsity,
                                                        false);
              }
        }
    }
  } // namespace



  template <int dim>
  void
  Simulator<dim>::setup_dofs()
  {
    dof_handler.distribute_dofs(fe);
    const IndexSet locally_owned_dofs = dof_handler.locally_owned_dofs();
    IndexSet       locally_relevant_dofs;
    DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant_dofs);
    // b2cpdi corners up to a cell from the point reach vertices two cells
    // beyond its cell, one further than the ghost cells (b2gimp's boxes of
    // at most h/2 reach them only at that limit, to round-off): the
    // vertices there become ghost entries too.
    BSpline::VerticesBeyondGhostCells<dim> vertices_beyond_ghost_cells;
    if ((shape_function == ShapeFunction::Type::b2gimp ||
         shape_function == ShapeFunction::Type::b2cpdi) &&
        Utilities::MPI::n_mpi_processes(mpi_communicator) > 1)
      {
        vertices_beyond_ghost_cells = BSpline::vertices_beyond_ghost_cells(
          dof_handler, locally_relevant_dofs, 2, mpi_communicator);
        locally_relevant_dofs.add_indices(
          vertices_beyond_ghost_cells.index_set(dof_handler.n_dofs()));
      }

    // Only hanging-node and periodicity constraints: velocity conditions
    // are applied to the nodal fields directly, as seed 000 §2.1 describes.
    // A node of a periodic face is constrained to its twin on the opposite
    // face (weight 1): the supports give its share to the twin, so the
    // nodal sums of both sides add up there, and distribute() copies the
    // twin's values back, like a hanging node's.
    constraints.clear();
    constraints.reinit(locally_relevant_dofs);
    DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    for (unsigned int d = 0; d < dim; ++d)
      if (parameters.mesh.periodic[d])
        DoFTools::make_periodicity_constraints(
          dof_handler, 2 * d, 2 * d + 1, d, constraints);
    constraints.close();
    has_hanging_nodes =
      Utilities::MPI::max(constraints.n_constraints() > 0 ? 1u : 0u,
                          mpi_communicator) > 0;

    const auto partitioner =
      std::make_shared<Utilities::MPI::Partitioner>(locally_owned_dofs,
                                                    locally_relevant_dofs,
                                                    mpi_communicator);
    centre_of_mass.reinit(partitioner, false);
    for (unsigned int f = 0; f < ParticleUpdate::n_grid_fields; ++f)
      if (centre_of_mass.field_needed[f] ||
          centre_of_mass.lumped_step_fields[f] || contact)
        centre_of_mass.allocate(static_cast<ParticleUpdate::GridField>(f));

    {
      Point<dim>            lower_corner, upper_corner;
      std::array<bool, dim> periodic;
      for (unsigned int d = 0; d < dim; ++d)
        {
          lower_corner[d] = parameters.mesh.lower_corner[d];
          upper_corner[d] = parameters.mesh.upper_corner[d];
          periodic[d]     = parameters.mesh.periodic[d];
        }
      point_sort.reinit(
        triangulation, transfer, lower_corner, upper_corner, periodic);
    }
    transfer.reinit(dof_handler,
                    constraints,
                    *partitioner,
                    shape_function != ShapeFunction::Type::classic,
                    &point_sort.vertex_cells());
    gimp_patches.clear();
    gimp_patch_of_cell.clear();
    cpdi_patches.clear();
    cpdi_patch_of_cell.clear();
    bspline_supports.reinit(shape_function,
                            BSpline::parse_boundary(
                              parameters.method.bspline_boundary),
                            transfer,
                            triangulation.n_active_cells(),
                            mpi_communicator);
    {
      std::vector<unsigned int> local_indices;
      for (const types::global_dof_index dof : vertices_beyond_ghost_cells.dofs)
        local_indices.push_back(partitioner->global_to_local(dof));
      bspline_supports.add_vertices(vertices_beyond_ghost_cells.positions,
                                    local_indices);
    }
    // The locally owned cells in the order of the passes.
    std::vector<typename Triangulation<dim>::active_cell_iterator>
      owned_cells_in_id_order;
    owned_cells_in_id_order.reserve(
      triangulation.n_locally_owned_active_cells());
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        owned_cells_in_id_order.push_back(cell);
    // An adapted mesh's storage order depends on its history (a mesh loaded
    // from a checkpoint is stored afresh): sort by CellId so that the sums
    // onto nodes are the same after a resume. A mesh that is never adapted
    // keeps its storage order (the order of the points in memory: faster).
    if (parameters.refinement.adaptive())
      std::sort(owned_cells_in_id_order.begin(),
                owned_cells_in_id_order.end(),
                [](const auto &a, const auto &b) { return a->id() < b->id(); });
    points.set_cell_order(std::move(owned_cells_in_id_order),
                          triangulation.n_active_cells());
    setup_contact();

    if (mass_matrix && (mass_matrix->needs_full_mass_matrix() ||
                        velocity_conditions.needs_full_mass_matrix()))
      {
        TrilinosWrappers::SparsityPattern sparsity(locally_owned_dofs,
                                                   locally_owned_dofs,
                                                   locally_relevant_dofs,
                                                   mpi_communicator);
        make_full_mass_sparsity(dof_handler,
                                constraints,
                                *partitioner,
                                transfer,
                                bspline_supports,
                                shape_function != ShapeFunction::Type::classic,
                                sparsity);
        sparsity.compress();
        centre_of_mass.full_mass_matrix.reinit(sparsity);
      }

    // The smallest edge length h_min for the Courant condition.
    double h_min = std::numeric_limits<double>::max();
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        h_min = std::min(h_min, cell->minimum_vertex_distance());
    control.set_minimum_cell_size(Utilities::MPI::min(h_min, mpi_communicator));
  }



  template <int dim>
  void
  Simulator<dim>::setup_boundary_conditions()
  {
    velocity_conditions.setup_nodes(dof_handler,
                                    *centre_of_mass.mass.get_partitioner());
    centre_of_mass.known_velocity_mask.resize(dim);
    centre_of_mass.known_velocity_value.resize(dim);
    for (unsigned int d = 0; d < dim; ++d)
      if (known_velocities_read())
        {
          centre_of_mass.known_velocity_mask[d].reinit(
            centre_of_mass.mass.get_partitioner());
          centre_of_mass.known_velocity_value[d].reinit(
            centre_of_mass.mass.get_partitioner());
        }
      else
        {
          centre_of_mass.known_velocity_mask[d].reinit(0);
          centre_of_mass.known_velocity_value[d].reinit(0);
        }
    reactions.step_impulse.assign(velocity_conditions.labels().size(),
                                  Tensor<1, dim>());
    reactions.forces = reactions.step_impulse;

    // Tractions: the points inside each box carry the traction's index and
    // their face area.
    external_loads.mark_traction_points(points);
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
        // Materials of one model share its slots (request() returns the
        // offset of a name requested before).
        constitutive_models.back()->request_properties(particle_properties);
      }

    prm.enter_subsection("Mass matrix");
    mass_matrix = MassMatrix::Registry<dim>::instance().create(
      parameters.method.mass_matrix, prm);
    prm.leave_subsection();
    mass_matrix->initialize_simulator(*this);

    prm.enter_subsection("Particle update");
    particle_updates.configured =
      ParticleUpdate::Registry<dim>::instance().create(
        parameters.method.particle_update, prm);
    particle_updates.configured->set_strain_update(
      parameters.method.strain_update);
    if (mass_matrix->periodic())
      {
        particle_updates.lumped_step =
          ParticleUpdate::Registry<dim>::instance().create("flip", prm);
        particle_updates.lumped_step->set_strain_update(
          parameters.method.strain_update);
      }
    prm.leave_subsection();

    velocity_conditions.initialize(parameters, mpi_communicator);
    external_loads.initialize(parameters, particle_properties);

    // The method's measured critical Courant number caps the automatic time
    // step's (doc/studies/stability.md).
    {
      StabilityMethod method;
      const auto      fields = particle_updates.configured->required_fields();
      method.flip_type =
        std::find(fields.begin(), fields.end(), ParticleUpdate::acceleration) !=
        fields.end();
      method.strain_update = parameters.method.strain_update_scheme;
      method.lumped_strain_velocities =
        parameters.method.lumped_strain_velocities;
      method.position_update_psi =
        particle_updates.configured->position_update_psi();
      method.shape_function  = shape_function;
      method.bspline_padding = bspline_supports.active() &&
                               parameters.method.bspline_boundary == "padding";
      control.time_step_rule().set_method_limit(
        mass_matrix->stability_limit(method));
    }

    // v⁺ always (grid output, conditions); grid damping needs S v, the
    // dissipation measure S v and S a.
    std::array<bool, ParticleUpdate::n_grid_fields> always;
    always.fill(false);
    always[ParticleUpdate::updated_velocity] = true;
    if (parameters.method.grid_damping != 0)
      always[ParticleUpdate::velocity] = true;
    if (parameters.output.track_dissipation)
      always[ParticleUpdate::velocity] = always[ParticleUpdate::acceleration] =
        true;
    centre_of_mass.field_needed = centre_of_mass.lumped_step_fields = always;
    for (const auto field : particle_updates.configured->required_fields())
      centre_of_mass.field_needed[field] = true;
    if (particle_updates.lumped_step)
      for (const auto field : particle_updates.lumped_step->required_fields())
        centre_of_mass.lumped_step_fields[field] = true;
  }



  template <int dim>
  void
  Simulator<dim>::check_scene()
  {
    // Axisymmetric: the mesh lies at r >= 0.
    if constexpr (dim == 2)
      if (parameters.axisymmetric)
        ShapeFunction::Axisymmetric::check_mesh(triangulation, "Geometry");
    // Bodies must lie inside the mesh.
    const BoundingBox<dim> mesh_box =
      GridTools::compute_bounding_box(triangulation);
    const auto shapes = Geometry::create_body_shapes<dim>(parameters.bodies);
    for (unsigned int b = 0; b < parameters.bodies.size(); ++b)
      {
        const BoundingBox<dim> box       = shapes[b]->bounding_box();
        const double           tolerance = 1e-10 * mesh_box.side_length(0);
        for (unsigned int d = 0; d < dim; ++d)
          AssertThrow(
            !Geometry::is_bounded(box, d) ||
              (box.lower_bound(d) >= mesh_box.lower_bound(d) - tolerance &&
               box.upper_bound(d) <= mesh_box.upper_bound(d) + tolerance),
            ExcMessage(numbered_subsection("Body", b) +
                       " reaches outside the mesh in direction " +
                       std::to_string(d) + ": the body spans [" +
                       format_number(box.lower_bound(d), 6) + ", " +
                       format_number(box.upper_bound(d), 6) +
                       "] but the mesh spans [" +
                       format_number(mesh_box.lower_bound(d), 6) + ", " +
                       format_number(mesh_box.upper_bound(d), 6) +
                       "]. Change its Shape (or Center and Half lengths)."));
      }

    // Contact: every particle update with the lumped mass matrix, and
    // multimaterial XPIC(k)/FMPM(k) with the FMPM(k) mass matrix (seed 004
    // Eq. 37, seed 000 Eqs. 3.18, 3.22).
    if (parameters.contact.multimaterial && parameters.size.n_materials > 1)
      {
        const std::string &mass = parameters.method.mass_matrix;
        AssertThrow(mass_matrix->supports_multimaterial_contact(),
                    ExcMessage("Contact/Model name = multimaterial works with "
                               "'Mass matrix/Model name = lumped', 'fmpm' "
                               "(multimaterial XPIC(k)/FMPM(k)) or 'full' "
                               "(their exact limit); this scene has '" +
                               mass + "'."));
        AssertThrow(!mass_matrix->exact_solve() ||
                      parameters.contact.net_incremental,
                    ExcMessage(
                      "'Mass matrix/Model name = full' with contact is the "
                      "k -> infinity limit of net incremental contact; "
                      "'Contact/Contact in mass-matrix iterations = once "
                      "per step' has no contact left in that limit (the "
                      "series converges to the solve of the uncorrected "
                      "momenta, [Nairn2023-FMPM] Eq. 3.22). Set it to 'net "
                      "incremental', or use 'Mass matrix/Model name = fmpm' "
                      "with a finite Order."));
        AssertThrow(!mass_matrix->periodic(),
                    ExcMessage("Mass matrix/Fmpm/Period and Period time "
                               "(periodic FMPM(k)) are not available with "
                               "Contact/Model name = multimaterial: set "
                               "Period = 1 and Period time = 0."));
        AssertThrow(mass_matrix->increment_tolerance() == 0,
                    ExcMessage("Mass matrix/Fmpm/Increment tolerance (the "
                               "adaptive order) is not available with "
                               "Contact/Model name = multimaterial: set it "
                               "to 0 (the series of every material then has "
                               "'Order' terms)."));
        AssertThrow(!velocity_conditions.needs_full_mass_matrix(),
                    ExcMessage("Contact/Model name = multimaterial needs a "
                               "'Boundary conditions/Method' without the full "
                               "mass matrix (not collection)."));
      }

    // B-splines: a fixed lattice of equal boxes (setup_dofs() refuses
    // other meshes), and what they do not do yet.
    if (ShapeFunction::is_bspline(shape_function))
      {
        const std::string type =
          "Shape function/Type = " + parameters.method.shape_function;
        AssertThrow(!parameters.refinement.adaptive(),
                    ExcMessage(type + " needs a fixed mesh of equal boxes: "
                                      "set Mesh refinement/Strategy = none."));
        // The contact tests of 'average gradient' (delta_c = 0.92, 0.96)
        // and 'd fit' (the edge distance d(x)) are fitted to the hat
        // functions (seed 004 Eqs. 15-17), not to the wider B-splines.
        const std::string &normals = parameters.contact.normals_name;
        AssertThrow(!(parameters.contact.multimaterial &&
                      parameters.size.n_materials > 1) ||
                      (normals != "average gradient" && normals != "d fit"),
                    ExcMessage(type + " with Contact/Normals = " + normals +
                               ": its contact test is fitted to the linear "
                               "shape functions. Use 'logistic regression', "
                               "'contact position' (with your Critical "
                               "separation), 'velocity only' or "
                               "'specified'."));
        // The padding nodes are slaved to their mirrors inside the
        // mass-matrix solves of the centre-of-mass grid fields (in each
        // iterate of the FMPM(k) series and of the exact solve), as the
        // walls' known values of the constrained method are held there.
        // The velocity method holds the walls only after the solve
        // (measured on the padded bar: energy -5 % with FMPM(5), -1.6 %
        // exact); the methods that solve inside the imposition on momenta
        // (lumped, unlumped, collection), the consistent matrix and the
        // per-material solves of contact couple them unmirrored.
        const auto        &conditions = parameters.boundary_conditions;
        const std::string &mass       = parameters.method.mass_matrix;
        const bool         contact =
          parameters.contact.multimaterial && parameters.size.n_materials > 1;
        AssertThrow(parameters.method.bspline_boundary != "padding" ||
                      (conditions.fixed.empty() && conditions.roller.empty() &&
                       conditions.moving_walls.empty()) ||
                      mass == "lumped" ||
                      ((mass == "fmpm" || mass == "full") && !contact &&
                       conditions.method == "constrained"),
                    ExcMessage(
                      "Shape function/B-spline boundary = padding with "
                      "velocity conditions (Boundary conditions/Fixed "
                      "boundary ids, Roller boundary ids, Moving walls) "
                      "needs Mass matrix/Model name = lumped, or fmpm or "
                      "full with Boundary conditions/Method = constrained "
                      "and without multimaterial contact (this scene: " +
                      mass + ", " + conditions.method +
                      (contact ? ", contact" : "") +
                      "); use 'open knots' otherwise."));
      }

    // Periodic faces (Mesh/Periodic directions) carry no condition; what
    // is not available across them is refused.
    if (parameters.mesh.any_periodic())
      {
        const auto check_ids = [&](const std::vector<types::boundary_id> &ids,
                                   const std::string &where) {
          for (const types::boundary_id id : ids)
            AssertThrow(
              id >= 2 * dim || !parameters.mesh.periodic[id / 2],
              ExcMessage(where + " contains boundary id " + std::to_string(id) +
                         ", a face of the periodic "
                         "direction " +
                         std::string(1, 'x' + id / 2) +
                         " (Mesh/Periodic directions): the two faces are "
                         "one and carry no velocity condition. Remove the "
                         "id or the direction."));
        };
        const auto &conditions = parameters.boundary_conditions;
        check_ids(conditions.fixed, "Boundary conditions/Fixed boundary ids");
        check_ids(conditions.roller, "Boundary conditions/Roller boundary ids");
        for (unsigned int w = 0; w < conditions.moving_walls.size(); ++w)
          check_ids(conditions.moving_walls[w].boundary_ids,
                    "Boundary conditions/" +
                      numbered_subsection("Moving wall", w) + "/Boundary ids");
        AssertThrow(shape_function == ShapeFunction::Type::classic,
                    ExcMessage("Mesh/Periodic directions works with 'Shape "
                               "function/Type = classic' only (GIMP and "
                               "CPDI supports that cross a periodic face "
                               "are not joined yet); this scene has '" +
                               parameters.method.shape_function + "'."));
        AssertThrow(!(parameters.contact.multimaterial &&
                      parameters.size.n_materials > 1),
                    ExcMessage("Mesh/Periodic directions is not available "
                               "with Contact/Model name = multimaterial (the "
                               "contact geometry reads point positions, "
                               "which jump across a periodic face)."));
        AssertThrow(!parameters.refinement.adaptive(),
                    ExcMessage("Mesh/Periodic directions is not available "
                               "with mesh adaptation: set Mesh "
                               "refinement/Strategy = none."));
      }

    // A fixed time step must be stable.
    const std::string unstable = control.time_step_rule().check_fixed_time_step(
      control.signal_speed(), control.minimum_cell_size(), false);
    AssertThrow(unstable.empty(), ExcMessage(unstable));
  }



  template <int dim>
  void
  Simulator<dim>::setup_contact()
  {
    if (contact)
      contact->reinit();
  }



  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
