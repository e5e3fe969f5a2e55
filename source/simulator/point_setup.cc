// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The material points of the scene's bodies at set-up, and their initial
// stress (geostatic, or given as functions of position).

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
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace fmpm
{
  namespace
  {
    /** The stress components a scene gives: xx, yy, xy in 2D (plane
     * strain: σ_zz follows from ε_zz = 0), all six in 3D; as stored
     * slots. */
    template <int dim>
    std::vector<unsigned int>
    given_stress_components()
    {
      return dim == 2 ? std::vector<unsigned int>{0, 1, 3} :
                        std::vector<unsigned int>{0, 1, 2, 3, 4, 5};
    }



    /**
     * The symmetric stretch F = I + ε at which a material's model gives a
     * point a stress: the model's stress at F, its tangent at F = I (by
     * finite differences, inverted: the compliance) and the Newton
     * iterations from it.
     */
    template <int dim>
    class PrestrainSolver
    {
    public:
      PrestrainSolver(const ConstitutiveModel::Interface<dim> &model,
                      const double                             density,
                      const unsigned int                       n_properties)
        : model(model)
        , given(given_stress_components<dim>())
        , n(given.size())
        , scratch(n_properties)
        , scratch_columns(make_array_view(scratch))
        , compliance(n, n)
      {
        inputs.time_step         = 1;
        inputs.reference_density = density;
        inputs.resize(1);
        inputs.old_volume_ratio[0] = 1;
      }

      PrestrainSolver(const PrestrainSolver &) = delete;

      /** The model's stress at the symmetric stretch F = I + ε (given
       * components @p strain), reached from the unstressed state of
       * @p record in one step (L = ε, Δt = 1); returns F. */
      Tensor<2, 3>
      stress_at(const Vector<double> &strain, const PointRecord &record)
      {
        Tensor<2, 3> epsilon;
        for (unsigned int a = 0; a < n; ++a)
          {
            const unsigned int i = stress_component_i[given[a]],
                               j = stress_component_j[given[a]];
            epsilon[i][j] = epsilon[j][i] = strain[a];
          }
        const Tensor<2, 3> F = unit_symmetric_tensor<3>() + epsilon;
        inputs.set_deformation_gradient(0, F);
        inputs.set_velocity_gradient(0, epsilon);
        inputs.set_old_stress(0, SymmetricTensor<2, 3>());
        inputs.old_strain_energy_density[0] = 0;
        inputs.properties[0]                = record;
        outputs.failed_point                = -1;
        model.update_stress(inputs, outputs);
        return F;
      }

      /** The tangent at F = I from the state @p fresh of a fresh point of
       * the body (F = I, no stress, the model's initial history); returns
       * whether it is singular. */
      bool
      compute_tangent(const std::vector<double> &fresh)
      {
        const double h = 1e-7;
        for (unsigned int a = 0; a < n; ++a)
          {
            Vector<double> strain(n);
            strain[a] = h;
            scratch   = fresh;
            stress_at(strain, scratch_columns.record());
            for (unsigned int c = 0; c < n; ++c)
              compliance(c, a) = outputs.cauchy_stress[given[c]][0] / h;
          }
        tangent_scale = 0;
        for (unsigned int a = 0; a < n; ++a)
          tangent_scale = std::max(tangent_scale, std::abs(compliance(a, a)));
        return !(tangent_scale > 0 && std::abs(compliance.determinant()) >
                                        1e-10 * std::pow(tangent_scale, n));
      }

      /** The tangent becomes the compliance of the Newton iterations. */
      void
      invert_tangent()
      {
        compliance.gauss_jordan();
      }

      /** Newton iterations for the strain at which the model gives point
       * @p p the stress @p target; on convergence the point takes F, the
       * stress, the strain energy and the volume there. Returns whether
       * they converged. */
      bool
      prestrain(const PointRecord &p, const Vector<double> &target)
      {
        Vector<double> strain(n), residual(n), correction(n);
        compliance.vmult(strain, target);
        const double tolerance =
          1e-12 * (target.linfty_norm() + 1e-6 * tangent_scale);
        bool converged = false;
        for (unsigned int iteration = 0; iteration < 50 && !converged;
             ++iteration)
          {
            for (unsigned int s = 0; s < scratch.size(); ++s)
              scratch[s] = p[s];
            stress_at(strain, scratch_columns.record());
            for (unsigned int c = 0; c < n; ++c)
              residual[c] = target[c] - outputs.cauchy_stress[given[c]][0];
            converged =
              outputs.failed_point < 0 && residual.linfty_norm() <= tolerance;
            if (!converged)
              {
                compliance.vmult(correction, residual);
                strain += correction;
              }
          }
        if (!converged)
          return false;
        // The converged strain, now on the point's own state.
        using Index          = PropertyIndex<dim>;
        const Tensor<2, 3> F = stress_at(strain, p);
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int c = 0; c < 3; ++c)
            if (dim == 3 || (a < 2) == (c < 2))
              p[Index::deformation_gradient + 3 * a + c] = F[a][c];
        for (unsigned int c = 0; c < (dim == 3 ? 6 : 4); ++c)
          p[Index::stress + c] = outputs.cauchy_stress[c][0];
        p[Index::strain_energy_density] = outputs.strain_energy_density[0];
        p[Index::volume] = determinant(F) * p[Index::initial_volume];
        return true;
      }

    private:
      const ConstitutiveModel::Interface<dim> &model;
      const std::vector<unsigned int>          given;
      const unsigned int                       n;
      ConstitutiveModel::StressUpdateInputs    inputs;
      ConstitutiveModel::StressUpdateOutputs   outputs;
      /** A point's state the iterations work on. */
      std::vector<double> scratch;
      RecordColumns       scratch_columns;
      FullMatrix<double>  compliance;
      double              tangent_scale = 0;
    };



    /** Parse Body @p b's Initial stress (@p where) into @p function. */
    template <int dim>
    void
    parse_initial_stress(FunctionParser<dim> &function,
                         const Parameters    &parameters,
                         const unsigned int   b,
                         const std::string   &where)
    {
      const BodyParameters &body = parameters.bodies[b];
      parse_function(function,
                     where,
                     body.initial_stress_expression,
                     body.initial_stress_expression,
                     FunctionParser<dim>::default_variable_names(),
                     parse_function_constants(body.function_constants,
                                              numbered_subsection("Body", b) +
                                                "/Function constants"),
                     false,
                     std::to_string(function.n_components) +
                       " expressions in x, y" + (dim == 3 ? ", z" : "") +
                       " separated by ';' (" +
                       (dim == 2 ? "xx; yy; xy" : "xx; yy; zz; xy; xz; yz") +
                       ")");
    }



    /**
     * The 'Initial stress' functions of the bodies: each point starts
     * pre-strained by the symmetric stretch F = I + ε at which its model
     * gives the stress (Newton iterations on the model's tangent at F = I),
     * with the model's stress, strain energy and history at that state.
     */
    template <int dim>
    void
    initialize_stress_from_functions(
      const Parameters &parameters,
      const std::vector<std::unique_ptr<ConstitutiveModel::Interface<dim>>>
                          &constitutive_models,
      const unsigned int   n_properties,
      MaterialPoints<dim> &points,
      const MPI_Comm       communicator)
    {
      using Index          = PropertyIndex<dim>;
      const unsigned int n = given_stress_components<dim>().size();
      for (unsigned int b = 0; b < parameters.bodies.size(); ++b)
        {
          const BodyParameters &body = parameters.bodies[b];
          if (body.initial_stress_expression.find_first_not_of(" \t") ==
              std::string::npos)
            continue;
          const std::string where =
            numbered_subsection("Body", b) + "/Initial stress";
          FunctionParser<dim> stress_function(n);
          parse_initial_stress(stress_function, parameters, b, where);

          const unsigned int   material = body.material;
          PrestrainSolver<dim> solver(*constitutive_models[material],
                                      parameters.materials[material].density,
                                      n_properties);

          // A failure (a model that cannot hold the stress, a point it
          // cannot reach) stops every rank with its message.
          std::string  failure;
          unsigned int first = 0;
          while (first < points.n_points() &&
                 static_cast<unsigned int>(
                   points.record(first)[Index::body_id]) != b)
            ++first;
          std::vector<double> fresh(n_properties, 0.);
          if (first < points.n_points())
            for (unsigned int s = 0; s < n_properties; ++s)
              fresh[s] = points.record(first)[s];
          const bool singular = solver.compute_tangent(fresh);
          if (first < points.n_points() && singular)
            failure = where + ": the model of Material " +
                      std::to_string(material) +
                      " cannot hold a general stress at rest (its "
                      "stiffness at zero strain is singular, e.g. "
                      "a fluid without shear modulus): give the "
                      "body no 'Initial stress' or another material.";
          else if (first < points.n_points())
            solver.invert_tangent();

          Vector<double> values(n);
          for (unsigned int k = first; k < points.n_points() && failure.empty();
               ++k)
            {
              const PointRecord p = points.record(k);
              if (static_cast<unsigned int>(p[Index::body_id]) != b)
                continue;
              Point<dim> x;
              for (unsigned int d = 0; d < dim; ++d)
                x[d] = p[Index::initial_position + d];
              stress_function.vector_value(x, values);
              if (!solver.prestrain(p, values))
                {
                  std::ostringstream position;
                  position << x;
                  failure = where + ": the model of Material " +
                            std::to_string(material) +
                            " reaches no strain with the given stress at the "
                            "point at (" +
                            position.str() +
                            ") (it exceeds the model's range, e.g. its "
                            "yield stress or a tension it cannot hold).";
                }
            }
          for (const std::string &message :
               Utilities::MPI::all_gather(communicator, failure))
            AssertThrow(message.empty(), ExcMessage(message));
        }
    }



    /** The Initial velocity of each body as functions of position. */
    template <int dim>
    std::vector<std::unique_ptr<FunctionParser<dim>>>
    parse_initial_velocities(const Parameters &parameters)
    {
      std::vector<std::unique_ptr<FunctionParser<dim>>> initial_velocity;
      for (unsigned int b = 0; b < parameters.bodies.size(); ++b)
        {
          const std::string where =
            numbered_subsection("Body", b) + "/Initial velocity";
          initial_velocity.push_back(
            std::make_unique<FunctionParser<dim>>(dim));
          parse_function(
            *initial_velocity.back(),
            where,
            parameters.bodies[b].velocity_expression,
            to_function_expressions(parameters.bodies[b].velocity_expression),
            FunctionParser<dim>::default_variable_names(),
            parse_function_constants(parameters.bodies[b].function_constants,
                                     numbered_subsection("Body", b) +
                                       "/Function constants"),
            false,
            std::to_string(dim) + " numbers or expressions in x, y" +
              (dim == 3 ? ", z" : ""));
        }
      return initial_velocity;
    }



    /** One FEValues per distinct number of points per cell: the points are
     * the midpoints of a regular subdivision of the reference cell, their
     * volume the JxW of that midpoint rule. */
    template <int dim>
    std::map<unsigned int, std::unique_ptr<FEValues<dim>>>
    regular_point_values(const Parameters         &parameters,
                         const Mapping<dim>       &mapping,
                         const FiniteElement<dim> &fe)
    {
      std::map<unsigned int, std::unique_ptr<FEValues<dim>>> fe_values;
      for (const auto &body : parameters.bodies)
        if (fe_values.find(body.points_per_cell) == fe_values.end())
          fe_values[body.points_per_cell] = std::make_unique<FEValues<dim>>(
            mapping,
            fe,
            QIterated<dim>(QMidpoint<1>(), body.points_per_cell),
            update_quadrature_points | update_JxW_values);
      return fe_values;
    }



    /** Warn of the points of body b not created because they lie inside an
     * earlier body e (@p n_overlapping[b n_bodies + e], summed over the
     * ranks). */
    void
    warn_of_overlapping_bodies(
      const std::vector<unsigned long long> &n_overlapping,
      const unsigned int                     n_bodies)
    {
      for (unsigned int b = 0; b < n_bodies; ++b)
        for (unsigned int earlier = 0; earlier < b; ++earlier)
          if (n_overlapping[b * n_bodies + earlier] > 0)
            std::cerr << "fmpm: warning: " << numbered_subsection("Body", b)
                      << " overlaps " << numbered_subsection("Body", earlier)
                      << ": " << n_overlapping[b * n_bodies + earlier]
                      << " of its points lie inside "
                      << numbered_subsection("Body", earlier)
                      << " and are not created (overlapping bodies keep the "
                         "earlier body's points)."
                      << std::endl;
    }



    /** The cells with new points, in creation order, and their counts. */
    template <int dim>
    using CellRuns =
      std::vector<std::pair<typename Triangulation<dim>::active_cell_iterator,
                            unsigned int>>;



    /** The ids of the new points on a mesh that is not adapted: the order
     * of the active cells of a serial run, coarse cell by coarse cell, and
     * within a coarse cell in the order of its children. p4est partitions
     * each coarse cell's children in that order, rank after rank, but
     * orders the coarse cells its own way (in 3D not as deal.II does): so
     * every coarse cell's first id is the sum of the points of the coarse
     * cells before it (on all ranks) and of its own points on the ranks
     * before this one. */
    template <int dim>
    void
    number_points_by_coarse_cell(const CellRuns<dim> &cell_runs,
                                 const unsigned int   n_coarse,
                                 const MPI_Comm       communicator,
                                 std::vector<types::particle_index> &ids)
    {
      std::vector<unsigned long long> local_count(n_coarse, 0);
      std::vector<unsigned int>       coarse_index(cell_runs.size());
      for (unsigned int r = 0; r < cell_runs.size(); ++r)
        {
          typename Triangulation<dim>::cell_iterator coarse =
            cell_runs[r].first;
          while (coarse->level() > 0)
            coarse = coarse->parent();
          coarse_index[r] = coarse->index();
          local_count[coarse_index[r]] += cell_runs[r].second;
        }
      std::vector<unsigned long long> on_earlier_ranks(n_coarse, 0);
      const int                       ierr = MPI_Exscan(local_count.data(),
                                  on_earlier_ranks.data(),
                                  n_coarse,
                                  MPI_UNSIGNED_LONG_LONG,
                                  MPI_SUM,
                                  communicator);
      AssertThrowMPI(ierr);
      // MPI_Exscan leaves rank 0's result undefined.
      if (Utilities::MPI::this_mpi_process(communicator) == 0)
        std::fill(on_earlier_ranks.begin(), on_earlier_ranks.end(), 0);
      std::vector<unsigned long long> total(n_coarse);
      Utilities::MPI::sum(local_count, communicator, total);
      std::vector<unsigned long long> next_id(n_coarse);
      unsigned long long              before = 0;
      for (unsigned int c = 0; c < n_coarse; ++c)
        {
          next_id[c] = before + on_earlier_ranks[c];
          before += total[c];
        }
      unsigned int i = 0;
      for (unsigned int r = 0; r < cell_runs.size(); ++r)
        for (unsigned int j = 0; j < cell_runs[r].second; ++j)
          ids[i++] = next_id[coarse_index[r]]++;
    }



    /** The ids of the new points on an adapted mesh, which has no order of
     * cells as a serial run's: every rank learns the number of points of
     * every cell (by CellId) and numbers the cells in the order of their
     * CellId strings, the points of a cell in creation order (the points
     * of a cell are consecutive in the store). */
    template <int dim>
    void
    number_points_by_cell_id(const CellRuns<dim>                &cell_runs,
                             const MPI_Comm                      communicator,
                             std::vector<types::particle_index> &ids)
    {
      std::vector<std::pair<std::string, unsigned int>> cell_counts;
      for (const auto &run : cell_runs)
        cell_counts.emplace_back(run.first->id().to_string(), run.second);
      std::vector<std::pair<std::string, unsigned int>> all_counts;
      for (const auto &rank_counts :
           Utilities::MPI::all_gather(communicator, cell_counts))
        all_counts.insert(all_counts.end(),
                          rank_counts.begin(),
                          rank_counts.end());
      std::sort(all_counts.begin(), all_counts.end());
      std::map<std::string, unsigned long long> first_id_of_cell;
      unsigned long long                        next = 0;
      for (const auto &entry : all_counts)
        {
          first_id_of_cell[entry.first] = next;
          next += entry.second;
        }
      unsigned int i = 0;
      for (unsigned int r = 0; r < cell_runs.size(); ++r)
        {
          unsigned long long id = first_id_of_cell[cell_counts[r].first];
          for (unsigned int j = 0; j < cell_runs[r].second; ++j)
            ids[i++] = id++;
        }
    }



    /** Every body must have produced points (@p points_per_body on this
     * rank). */
    void
    check_every_body_has_points(std::vector<unsigned long long> points_per_body,
                                const MPI_Comm                  communicator)
    {
      Utilities::MPI::sum(points_per_body, communicator, points_per_body);
      for (unsigned int b = 0; b < points_per_body.size(); ++b)
        AssertThrow(points_per_body[b] > 0,
                    ExcMessage(numbered_subsection("Body", b) +
                               " contains no material point: its shape lies "
                               "outside the mesh or is smaller than one point "
                               "spacing. Check its Center and Half lengths "
                               "against the Mesh subsection."));
    }



    /** The record @p p of a new point of body @p b at @p x in @p cell, of
     * volume @p volume, at rest in its reference state. @p half_length < 0:
     * the point's share of a regular subdivision of its cell. Axisymmetric:
     * volume and mass per radian, V_p = ∫_Ωp r dA = A_p r_p (GIMP_Theory
     * Eq. 5.4), for a GIMP box (@p gimp_box) cut at the axis the part at
     * r >= 0, A_p ((r_p + l_r)² − max(r_p − l_r, 0)²) / (4 l_r). */
    template <int dim, typename CellIterator>
    void
    set_initial_record(std::vector<double>       &p,
                       const Parameters          &parameters,
                       const unsigned int         b,
                       const FunctionParser<dim> &initial_velocity,
                       const CellIterator        &cell,
                       const Point<dim>          &x,
                       const double               area,
                       const double               half_length,
                       const bool                 gimp_box)
    {
      using Index                        = PropertyIndex<dim>;
      const BodyParameters     &body     = parameters.bodies[b];
      const MaterialParameters &material = parameters.materials[body.material];
      std::fill(p.begin(), p.end(), 0.);
      for (unsigned int d = 0; d < dim; ++d)
        {
          p[Index::initial_position + d] = x[d];
          p[Index::initial_half_length + d] =
            half_length < 0 ?
              0.5 * cell->extent_in_direction(d) / body.points_per_cell :
              half_length;
        }
      double volume = area;
      if (parameters.axisymmetric)
        {
          const double r = x[0], l = p[Index::initial_half_length];
          volume *= gimp_box && r < l ? (r + l) * (r + l) / (4 * l) : r;
        }
      p[Index::mass]           = material.density * volume;
      p[Index::volume]         = volume;
      p[Index::initial_volume] = volume;
      for (unsigned int d = 0; d < dim; ++d)
        p[Index::velocity + d] = initial_velocity.value(x, d);
      for (unsigned int i = 0; i < 3; ++i)
        p[Index::deformation_gradient + 4 * i] = 1.0;
      p[Index::material_id] = body.material;
      p[Index::body_id]     = b;
    }
  } // namespace



  template <int dim>
  void
  Simulator<dim>::create_material_points()
  {
    const unsigned int n_bodies = parameters.bodies.size();

    std::map<unsigned int, std::unique_ptr<FEValues<dim>>> fe_values_for_ppc =
      regular_point_values(parameters, mapping, fe);
    const std::vector<std::unique_ptr<FunctionParser<dim>>> initial_velocity =
      parse_initial_velocities<dim>(parameters);

    const auto shapes = Geometry::create_body_shapes<dim>(parameters.bodies);
    std::vector<BoundingBox<dim>> body_boxes;
    for (const auto &shape : shapes)
      body_boxes.push_back(shape->bounding_box());

    // Two passes over the same points: the first counts them (the store is
    // then allocated once, at its size), the second writes each point
    // straight into the store. Cells outer, bodies inner: the global order
    // (and so the ids) is the same on any number of ranks. A point inside
    // an earlier body belongs to that body: the first pass counts the
    // points of body b left to an earlier body e at [b n_bodies + e].
    std::vector<unsigned long long> n_overlapping(n_bodies * n_bodies, 0);
    bool                            count_overlaps = true;
    std::vector<std::pair<unsigned int, Point<dim>>> mesh_points;
    const auto for_each_new_point = [&](const auto &on_point) {
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
                // A body from a volume mesh brings its own points; the
                // others keep the regular points inside their shape.
                const auto on_candidate = [&](const Point<dim> &x,
                                              const Point<dim> &reference,
                                              const double      volume,
                                              const double      half_length) {
                  unsigned int earlier = 0;
                  while (earlier < b && !shapes[earlier]->inside(x))
                    ++earlier;
                  if (earlier < b)
                    {
                      if (count_overlaps)
                        ++n_overlapping[b * n_bodies + earlier];
                      return;
                    }
                  on_point(cell, b, x, reference, volume, half_length);
                };
                if (body.from_mesh)
                  {
                    const auto &region =
                      static_cast<const Geometry::MeshRegion<dim> &>(
                        *shapes[b]);
                    mesh_points.clear();
                    region.points_in_cell(cell, mapping, mesh_points);
                    for (const auto &[index, reference] : mesh_points)
                      on_candidate(region.positions[index],
                                   reference,
                                   region.volumes[index],
                                   0.5 *
                                     std::pow(region.volumes[index], 1. / dim));
                    continue;
                  }
                FEValues<dim> &fe_values =
                  *fe_values_for_ppc[body.points_per_cell];
                fe_values.reinit(cell);
                const Quadrature<dim> &quadrature = fe_values.get_quadrature();
                for (unsigned int q = 0; q < quadrature.size(); ++q)
                  if (shapes[b]->inside(fe_values.quadrature_point(q)))
                    on_candidate(fe_values.quadrature_point(q),
                                 quadrature.point(q),
                                 fe_values.JxW(q),
                                 -1);
              }
          }
    };
    unsigned int n_new_points = 0;
    for_each_new_point([&](const auto &,
                           const unsigned int,
                           const Point<dim> &,
                           const Point<dim> &,
                           const double,
                           const double) { ++n_new_points; });
    count_overlaps = false;
    Utilities::MPI::sum(n_overlapping, mpi_communicator, n_overlapping);
    if (!parameters.test_mode &&
        Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      warn_of_overlapping_bodies(n_overlapping, n_bodies);

    // The points go straight into the store (not through the handler);
    // their ids are set below, before the store is put in cell order.
    points.initialize(particle_properties.n_properties(),
                      MaterialPoints<dim>::plane_strain_zero_slots(),
                      MaterialPoints<dim>::invariant_core_slots(
                        parameters.axisymmetric));
    points.reserve(n_new_points);
    CellRuns<dim>                   cell_runs;
    std::vector<unsigned long long> points_per_body(n_bodies, 0);
    std::vector<double>             p(particle_properties.n_properties());
    const bool gimp_box = shape_function == ShapeFunction::Type::ugimp ||
                          shape_function == ShapeFunction::Type::cpgimp ||
                          shape_function == ShapeFunction::Type::b2gimp;
    for_each_new_point([&](const auto        &cell,
                           const unsigned int b,
                           const Point<dim>  &x,
                           const Point<dim>  &reference,
                           const double       volume,
                           const double       half_length) {
      set_initial_record(p,
                         parameters,
                         b,
                         *initial_velocity[b],
                         cell,
                         x,
                         volume,
                         half_length,
                         gimp_box);
      points.add(0, x, reference, cell, p.data());
      if (cell_runs.empty() || cell_runs.back().first != cell)
        cell_runs.emplace_back(cell, 0);
      ++cell_runs.back().second;
      ++points_per_body[b];
    });

    // Globally unique ids, the same on any number of ranks.
    if (!parameters.refinement.adaptive())
      number_points_by_coarse_cell<dim>(cell_runs,
                                        triangulation.n_cells(0),
                                        mpi_communicator,
                                        points.id);
    else
      number_points_by_cell_id<dim>(cell_runs, mpi_communicator, points.id);

    check_every_body_has_points(points_per_body, mpi_communicator);
    points.rebin();
    counters.n_material_points =
      Utilities::MPI::sum<unsigned long long>(points.n_points(),
                                              mpi_communicator);
  }



  template <int dim>
  void
  Simulator<dim>::initialize_stress_from_gravity()
  {
    using Index = PropertyIndex<dim>;
    initialize_stress_from_functions(parameters,
                                     constitutive_models,
                                     particle_properties.n_properties(),
                                     points,
                                     mpi_communicator);
    Tensor<1, dim> g;
    for (unsigned int d = 0; d < dim; ++d)
      g[d] = parameters.gravity[d];
    for (unsigned int b = 0; b < parameters.bodies.size(); ++b)
      {
        if (!parameters.bodies[b].initial_stress_from_gravity)
          continue;
        AssertThrow(g.norm() > 0,
                    ExcMessage(numbered_subsection("Body", b) +
                               "/Initial stress from gravity = true needs a "
                               "non-zero Body force/Gravity."));
        const Tensor<1, dim> down = g / g.norm();
        // The top surface: the smallest ĝ·x over the body's point domains.
        double top = std::numeric_limits<double>::max();
        for (unsigned int k = 0; k < points.n_points(); ++k)
          {
            const PointRecord p = points.record(k);
            if (static_cast<unsigned int>(p[Index::body_id]) != b)
              continue;
            double half = 0;
            for (unsigned int d = 0; d < dim; ++d)
              half += std::abs(down[d]) * p[Index::initial_half_length + d];
            top = std::min(top, down * points.position[k] - half);
          }
        top = Utilities::MPI::min(top, mpi_communicator);

        // Uniaxial strain along ĝ, ε = σ_gg / M with the constrained
        // modulus M = ρ c_p², so that σ_gg = −ρ|g| depth; the model gives
        // the lateral stresses (ν/(1−ν) σ_gg for linear elasticity).
        const unsigned int material = parameters.bodies[b].material;
        const double       density  = parameters.materials[material].density;
        const double       c =
          constitutive_models[material]->wave_speed(density, 1.0);
        const double                           M = density * c * c;
        ConstitutiveModel::StressUpdateInputs  inputs;
        ConstitutiveModel::StressUpdateOutputs outputs;
        inputs.time_step         = 1;
        inputs.reference_density = density;
        inputs.resize(1);
        for (unsigned int k = 0; k < points.n_points(); ++k)
          {
            const PointRecord p = points.record(k);
            if (static_cast<unsigned int>(p[Index::body_id]) != b)
              continue;
            const double depth   = down * points.position[k] - top;
            const double epsilon = -density * g.norm() * depth / M;
            Tensor<2, 3> strain;
            for (unsigned int i = 0; i < dim; ++i)
              for (unsigned int j = 0; j < dim; ++j)
                strain[i][j] = epsilon * down[i] * down[j];
            const Tensor<2, 3> F = unit_symmetric_tensor<3>() + strain;
            inputs.set_deformation_gradient(0, F);
            inputs.set_velocity_gradient(0, strain);
            inputs.set_old_stress(0, get_symmetric_tensor3(p, Index::stress));
            inputs.old_strain_energy_density[0] =
              p[Index::strain_energy_density];
            inputs.old_volume_ratio[0] =
              p[Index::volume] / p[Index::initial_volume];
            inputs.properties[0] = p;
            constitutive_models[material]->update_stress(inputs, outputs);
            // (In 2D the plane-strain zero entries are not stored.)
            for (unsigned int a = 0; a < 3; ++a)
              for (unsigned int c = 0; c < 3; ++c)
                if (dim == 3 || (a < 2) == (c < 2))
                  p[Index::deformation_gradient + 3 * a + c] = F[a][c];
            for (unsigned int c = 0; c < (dim == 3 ? 6 : 4); ++c)
              p[Index::stress + c] = outputs.cauchy_stress[c][0];
            p[Index::strain_energy_density] = outputs.strain_energy_density[0];
            p[Index::volume] = determinant(F) * p[Index::initial_volume];
          }
      }
  }



  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
