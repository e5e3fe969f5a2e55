// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/function_parser.h>
#include <fmpm/shape_function.h>
#include <fmpm/velocity_conditions.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace fmpm
{
  namespace
  {
    /** Whether @p expression names one of @p variables (as a whole
     * identifier: 't' is in 'v*t', not in 'sqrt(t0)'). */
    bool
    names_any(const std::string &expression, const std::string &variables)
    {
      const std::vector<std::string> names =
        Utilities::split_string_list(variables, ',');
      std::string::size_type i = 0;
      while (i < expression.size())
        {
          const char c = expression[i];
          if (std::isalpha(static_cast<unsigned char>(c)) || c == '_')
            {
              std::string::size_type j = i + 1;
              while (j < expression.size() &&
                     (std::isalnum(static_cast<unsigned char>(expression[j])) ||
                      expression[j] == '_'))
                ++j;
              if (std::find(names.begin(),
                            names.end(),
                            expression.substr(i, j - i)) != names.end())
                return true;
              i = j;
            }
          else if (std::isdigit(static_cast<unsigned char>(c)) || c == '.')
            {
              // A number, with its exponent (1e-3 names no 'e').
              std::string::size_type j = i + 1;
              while (j < expression.size() &&
                     (std::isalnum(static_cast<unsigned char>(expression[j])) ||
                      expression[j] == '.' ||
                      ((expression[j] == '-' || expression[j] == '+') &&
                       (expression[j - 1] == 'e' || expression[j - 1] == 'E'))))
                ++j;
              i = j;
            }
          else
            ++i;
        }
      return false;
    }

    /** A FunctionParser in x, y(, z), t of @p expression; @p what names the
     * entry in the error message. */
    template <int dim>
    std::unique_ptr<FunctionParser<dim>>
    parse_in_x_and_t(const std::string &expression,
                     const std::string &constants,
                     const std::string &where,
                     const std::string &what)
    {
      auto function = std::make_unique<FunctionParser<dim>>(1);
      parse_function(*function,
                     where + "/" + what,
                     expression,
                     expression,
                     FunctionParser<dim>::default_variable_names() + ",t",
                     parse_function_constants(constants,
                                              where + "/Function constants"),
                     true,
                     "a valid expression in " +
                       FunctionParser<dim>::default_variable_names() + ", t");
      return function;
    }
  } // namespace



  template <int dim>
  unsigned int
  VelocityConditions<dim>::label_index(const std::string &label)
  {
    const auto found =
      std::find(source_labels.begin(), source_labels.end(), label);
    if (found != source_labels.end())
      return found - source_labels.begin();
    source_labels.push_back(label);
    return source_labels.size() - 1;
  }



  template <int dim>
  void
  VelocityConditions<dim>::initialize(const Parameters &parameters,
                                      MPI_Comm          communicator)
  {
    mpi_communicator                       = communicator;
    const auto                         &bc = parameters.boundary_conditions;
    const std::map<std::string, Method> methods = {
      {"constrained", Method::constrained},
      {"lumped", Method::lumped},
      {"velocity", Method::velocity},
      {"unlumped 1", Method::unlumped_1},
      {"unlumped 2", Method::unlumped_2},
      {"collection full", Method::collection_full},
      {"collection partial", Method::collection_partial}};
    method        = methods.at(bc.method);
    padding_layer = parameters.method.bspline_boundary == "padding" &&
                    ShapeFunction::is_bspline(
                      ShapeFunction::parse(parameters.method.shape_function));
    fixed  = bc.fixed;
    roller = bc.roller;
    walls  = bc.moving_walls;
    source_labels.clear();
    for (const auto &wall : walls)
      for (const auto id : wall.boundary_ids)
        label_index(std::to_string(id));
    for (const auto id : fixed)
      label_index(std::to_string(id));
    for (const auto id : roller)
      label_index(std::to_string(id));
    for (unsigned int w = 0; w < walls.size(); ++w)
      if (walls[w].boundary_ids.empty())
        label_index("wall" + std::to_string(w));

    wall_velocity.clear();
    wall_region.clear();
    wall_displacement.assign(walls.size(), 0.);
    velocity_in_x.assign(walls.size(), false);
    velocity_in_t.assign(walls.size(), false);
    constant_velocity.assign(walls.size(), 0.);
    any_velocity_in_x = false;
    moving_nodes      = false;
    const std::string space_variables =
      FunctionParser<dim>::default_variable_names();
    for (unsigned int w = 0; w < walls.size(); ++w)
      {
        const std::string where =
          "Boundary conditions/" + numbered_subsection("Moving wall", w);
        wall_velocity.push_back(parse_in_x_and_t<dim>(
          walls[w].velocity, walls[w].constants, where, "Velocity"));
        velocity_in_x[w]  = names_any(walls[w].velocity, space_variables);
        velocity_in_t[w]  = names_any(walls[w].velocity, "t");
        any_velocity_in_x = any_velocity_in_x || velocity_in_x[w];
        if (!velocity_in_x[w] && !velocity_in_t[w])
          constant_velocity[w] = wall_velocity[w]->value(Point<dim>());
        const bool is_box =
          walls[w].boundary_ids.empty() && walls[w].region.empty();
        // A box moves rigidly: one velocity for all of it.
        AssertThrow(!is_box || !velocity_in_x[w],
                    ExcMessage(where + "/Velocity = <" + walls[w].velocity +
                               "> depends on the position, but a wall given "
                               "by 'Box lower/upper corner' moves as a "
                               "whole: its velocity may depend on t only. "
                               "Give the wall by 'Boundary ids' or "
                               "'Region' for a velocity that varies in "
                               "space."));
        if (is_box && (velocity_in_t[w] || constant_velocity[w] != 0))
          moving_nodes = true;
        AssertThrow(!padding_layer || walls[w].boundary_ids.empty() ||
                      !velocity_in_x[w],
                    ExcMessage(where + "/Velocity = <" + walls[w].velocity +
                               "> depends on the position: with Shape "
                               "function/B-spline boundary = padding a wall "
                               "on boundary ids moves as a whole (its "
                               "velocity may depend on t only); use 'open "
                               "knots'."));

        std::unique_ptr<FunctionParser<dim>> region;
        if (!walls[w].region.empty())
          {
            region = parse_in_x_and_t<dim>(walls[w].region,
                                           walls[w].constants,
                                           where,
                                           "Region");
            if (names_any(walls[w].region, "t"))
              moving_nodes = true;
          }
        wall_region.push_back(std::move(region));
      }

    fixed_region.reset();
    if (!bc.fixed_region.empty())
      {
        fixed_region       = parse_in_x_and_t<dim>(bc.fixed_region,
                                             "",
                                             "Boundary conditions",
                                             "Fixed region");
        fixed_region_label = label_index("fixed_region");
        if (names_any(bc.fixed_region, "t"))
          moving_nodes = true;
      }
    // Axisymmetric: the nodes on the axis r = 0 hold v_r = 0.
    axis       = parameters.axisymmetric;
    axis_label = axis ? label_index("axis") : 0;
    for (auto &values : cached_values)
      values.clear();
    cached_time.fill(std::numeric_limits<double>::quiet_NaN());
  }



  template <int dim>
  bool
  VelocityConditions<dim>::has_moving_boxes() const
  {
    for (const auto &wall : walls)
      if (wall.boundary_ids.empty() && wall.region.empty())
        return true;
    return false;
  }



  template <int dim>
  double
  VelocityConditions<dim>::fastest_wall_speed(const double t) const
  {
    double fastest = 0;
    for (unsigned int w = 0; w < walls.size(); ++w)
      if (!velocity_in_x[w])
        {
          wall_velocity[w]->set_time(t);
          fastest =
            std::max(fastest, std::abs(wall_velocity[w]->value(Point<dim>())));
        }
    if (any_velocity_in_x)
      {
        const std::vector<double> &values = values_at(t);
        for (unsigned int b = 0; b < conditions.size(); ++b)
          if (conditions[b].wall >= 0 && velocity_in_x[conditions[b].wall])
            fastest = std::max(fastest, std::abs(values[b]));
        fastest = Utilities::MPI::max(fastest, mpi_communicator);
      }
    return fastest;
  }



  template <int dim>
  double
  VelocityConditions<dim>::wall_work(
    const std::vector<Tensor<1, dim>> &reactions,
    const double                       t,
    const double                       dt) const
  {
    double work = 0;
    for (unsigned int w = 0; w < walls.size(); ++w)
      if (!velocity_in_x[w])
        {
          Tensor<1, dim> direction;
          for (unsigned int d = 0; d < dim; ++d)
            direction[d] = walls[w].direction[d];
          wall_velocity[w]->set_time(t + 0.5 * dt);
          const double             v = wall_velocity[w]->value(Point<dim>());
          std::vector<std::string> wall_labels;
          for (const auto id : walls[w].boundary_ids)
            wall_labels.push_back(std::to_string(id));
          if (walls[w].boundary_ids.empty())
            wall_labels.push_back("wall" + std::to_string(w));
          for (const auto &label : wall_labels)
            {
              const unsigned int s =
                std::find(source_labels.begin(), source_labels.end(), label) -
                source_labels.begin();
              if (s < reactions.size())
                work += (reactions[s] * direction) * v * dt;
            }
        }
    if (any_velocity_in_x)
      {
        // Σ_b Δp_b v_b(t + Δt/2): the force on each node times its own
        // velocity.
        double local_work = 0;
        for (unsigned int b = 0; b < conditions.size(); ++b)
          {
            const int w = conditions[b].wall;
            if (w >= 0 && velocity_in_x[w])
              local_work += condition_impulse[b] *
                            wall_value(w, conditions[b], t + 0.5 * dt);
          }
        work += Utilities::MPI::sum(local_work, mpi_communicator);
        std::fill(condition_impulse.begin(), condition_impulse.end(), 0.);
      }
    return work;
  }



  template <int dim>
  double
  VelocityConditions<dim>::wall_value(const unsigned int   w,
                                      const NodeCondition &c,
                                      const double         t) const
  {
    if (!velocity_in_x[w] && !velocity_in_t[w])
      return constant_velocity[w];
    wall_velocity[w]->set_time(t);
    return wall_velocity[w]->value(
      velocity_in_x[w] ? node_position[c.local_index] : Point<dim>());
  }



  template <int dim>
  const std::vector<double> &
  VelocityConditions<dim>::values_at(const double t) const
  {
    for (unsigned int s = 0; s < cached_time.size(); ++s)
      if (cached_time[s] == t && cached_values[s].size() == conditions.size())
        {
          last_cache_slot = s;
          return cached_values[s];
        }
    // The slot written least recently, never the one returned last (two
    // calls in a row may hold both).
    unsigned int s = next_cache_slot;
    if (s == last_cache_slot)
      s = (s + 1) % cached_time.size();
    next_cache_slot             = (s + 1) % cached_time.size();
    last_cache_slot             = s;
    std::vector<double> &values = cached_values[s];
    cached_time[s]              = t;
    // v_w once per wall unless it depends on x, then per node.
    std::vector<double> uniform(walls.size());
    for (unsigned int w = 0; w < walls.size(); ++w)
      if (!velocity_in_x[w])
        uniform[w] = wall_value(w, NodeCondition{}, t);
    values.resize(conditions.size());
    for (unsigned int b = 0; b < conditions.size(); ++b)
      {
        const int w = conditions[b].wall;
        values[b]   = w < 0             ? 0. :
                      !velocity_in_x[w] ? uniform[w] :
                                          wall_value(w, conditions[b], t);
      }
    return values;
  }



  template <int dim>
  void
  VelocityConditions<dim>::advance_walls(const double t, const double dt)
  {
    // The displacement moves box walls, whose velocity depends on t only.
    for (unsigned int w = 0; w < walls.size(); ++w)
      if (!velocity_in_x[w])
        {
          wall_velocity[w]->set_time(t + 0.5 * dt);
          wall_displacement[w] += wall_velocity[w]->value(Point<dim>()) * dt;
        }
  }



  template <int dim>
  bool
  VelocityConditions<dim>::is_inside_box(const unsigned int w,
                                         const Point<dim>  &x) const
  {
    const auto &wall = walls[w];
    if (!wall.boundary_ids.empty() || !wall.region.empty())
      return false;
    for (unsigned int d = 0; d < dim; ++d)
      {
        const double shift = wall.direction[d] * wall_displacement[w];
        if (x[d] < wall.box_lower[d] + shift - 1e-12 ||
            x[d] > wall.box_upper[d] + shift + 1e-12)
          return false;
      }
    return true;
  }



  template <int dim>
  bool
  VelocityConditions<dim>::push_out_of_walls(Point<dim> &x) const
  {
    bool moved = false;
    for (unsigned int w = 0; w < walls.size(); ++w)
      if (is_inside_box(w, x))
        {
          // Out along n̂ through the nearer of the two faces across n̂ (the
          // side the point came from): the smallest and largest n̂ · corner
          // of the moved box.
          const auto &wall  = walls[w];
          double      front = 0, back = 0, along = 0;
          for (unsigned int d = 0; d < dim; ++d)
            {
              const double shift = wall.direction[d] * wall_displacement[w];
              const double low   = wall.box_lower[d] + shift;
              const double high  = wall.box_upper[d] + shift;
              front += wall.direction[d] * (wall.direction[d] > 0 ? high : low);
              back += wall.direction[d] * (wall.direction[d] > 0 ? low : high);
              along += wall.direction[d] * x[d];
            }
          const double target = (front - along < along - back) ? front : back;
          for (unsigned int d = 0; d < dim; ++d)
            x[d] += (target - along) * wall.direction[d];
          moved = true;
        }
    return moved;
  }



  template <int dim>
  void
  VelocityConditions<dim>::add_node_condition(
    std::vector<std::vector<NodeCondition>> &per_node,
    const NodeCondition                     &candidate)
  {
    auto          &list       = per_node[candidate.local_index];
    Tensor<1, dim> r          = candidate.normal;
    bool           orthogonal = true;
    for (const auto &existing : list)
      {
        const double projection = r * existing.normal;
        if (std::abs(projection) > 1e-10)
          orthogonal = false;
        r -= projection * existing.normal;
      }
    if (r.norm() < 1e-8)
      return; // already held by the node's other conditions
    // A direction that is neither new nor orthogonal to a prescribed
    // non-zero velocity would need a combination of values.
    bool any_moving = candidate.wall >= 0;
    for (const auto &existing : list)
      any_moving = any_moving || existing.wall >= 0;
    AssertThrow(orthogonal || !any_moving,
                ExcMessage("A moving wall and another velocity condition "
                           "meet at a node with directions that are neither "
                           "equal nor orthogonal; give the moving wall a "
                           "direction along or across the other condition."));
    NodeCondition accepted = candidate;
    accepted.normal        = r / r.norm();
    list.push_back(accepted);
  }



  template <int dim>
  void
  VelocityConditions<dim>::setup_nodes(
    const DoFHandler<dim>             &dof_handler,
    const Utilities::MPI::Partitioner &partitioner)
  {
    dof_handler_pointer           = &dof_handler;
    partitioner_pointer           = &partitioner;
    const auto     &triangulation = dof_handler.get_triangulation();
    const IndexSet &owned         = partitioner.locally_owned_range();

    std::set<types::boundary_id> mesh_ids;
    for (const auto id : triangulation.get_boundary_ids())
      mesh_ids.insert(id);
    auto check_id = [&](const types::boundary_id id, const std::string &where) {
      AssertThrow(mesh_ids.count(id),
                  ExcMessage("Boundary conditions/" + where +
                             " names boundary id " + std::to_string(id) +
                             ", which the mesh does not have."));
    };
    for (const auto id : fixed)
      check_id(id, "Fixed boundary ids");
    for (const auto id : roller)
      check_id(id, "Roller boundary ids");
    for (unsigned int w = 0; w < walls.size(); ++w)
      for (const auto id : walls[w].boundary_ids)
        check_id(id, numbered_subsection("Moving wall", w) + "/Boundary ids");

    // Per (boundary id, owned node): summed outward unit face normals.
    std::map<std::pair<types::boundary_id, unsigned int>, Tensor<1, dim>>
      normals;
    // Padding layer: the cell at boundary face f is a padding cell; its
    // opposite face lies on the wall, whose nodes carry the conditions
    // (with the face's normal), and the boundary face's node mirrors the
    // node across the wall, the far node of the neighbour cell.
    std::map<std::pair<types::boundary_id, unsigned int>,
             std::pair<unsigned int, Tensor<1, dim>>>
                                 padding;
    std::set<types::boundary_id> held_ids(fixed.begin(), fixed.end());
    held_ids.insert(roller.begin(), roller.end());
    for (const auto &wall : walls)
      held_ids.insert(wall.boundary_ids.begin(), wall.boundary_ids.end());
    auto add_padding_cell = [&](const auto        &cell,
                                const unsigned int f,
                                auto              &normals_out) {
      const unsigned int axis = f / 2;
      Tensor<1, dim>     normal;
      normal[axis]                = (f % 2 == 0) ? -1. : 1.;
      const unsigned int opposite = f ^ 1;
      AssertThrow(!cell->at_boundary(opposite) &&
                    !cell->neighbor(opposite)->is_artificial(),
                  ExcMessage("Shape function/B-spline boundary = padding "
                             "with velocity conditions needs at least three "
                             "cells across the mesh and the mirror nodes "
                             "two cells inside the boundary on each rank."));
      const auto id = cell->face(f)->boundary_id();
      if (!held_ids.count(id))
        return;
      const auto &inner = cell->neighbor(opposite);
      for (unsigned int i = 0; i < GeometryInfo<dim>::vertices_per_face; ++i)
        {
          const auto wall_dof = cell->vertex_dof_index(
            GeometryInfo<dim>::face_to_cell_vertices(opposite, i), 0);
          if (owned.is_element(wall_dof))
            normals_out[std::make_pair(
              id, partitioner.global_to_local(wall_dof))] += normal;
          const auto padding_dof = cell->vertex_dof_index(
            GeometryInfo<dim>::face_to_cell_vertices(f, i), 0);
          const auto mirror_dof = inner->vertex_dof_index(
            GeometryInfo<dim>::face_to_cell_vertices(opposite, i), 0);
          if (owned.is_element(padding_dof))
            {
              AssertThrow(owned.is_element(mirror_dof) ||
                            partitioner.is_ghost_entry(mirror_dof),
                          ExcMessage("B-spline boundary = padding: the "
                                     "mirror node of a padding node is "
                                     "not in this rank's ghost layer."));
              padding[std::make_pair(
                id, partitioner.global_to_local(padding_dof))] =
                std::make_pair(partitioner.global_to_local(mirror_dof), normal);
            }
        }
    };
    const unsigned int n_owned = partitioner.locally_owned_size();
    // The nodes' positions only for walls given by a region or box, for
    // velocities in x, and for a fixed region.
    const bool needs_positions =
      any_velocity_in_x || fixed_region || axis ||
      std::any_of(walls.begin(), walls.end(), [](const auto &wall) {
        return wall.boundary_ids.empty();
      });
    node_position.assign(needs_positions ? n_owned : 0, Point<dim>());
    node_position.shrink_to_fit();
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          if (needs_positions)
            for (const unsigned int v : cell->vertex_indices())
              {
                const auto dof = cell->vertex_dof_index(v, 0);
                if (owned.is_element(dof))
                  node_position[partitioner.global_to_local(dof)] =
                    cell->vertex(v);
              }
          for (const unsigned int f : cell->face_indices())
            if (padding_layer && cell->face(f)->at_boundary())
              add_padding_cell(cell, f, normals);
            else if (cell->face(f)->at_boundary())
              {
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
                    const auto dof = face->vertex_dof_index(v, 0);
                    if (owned.is_element(dof))
                      normals[std::make_pair(face->boundary_id(),
                                             partitioner.global_to_local(
                                               dof))] += normal;
                  }
              }
        }

    boundary_normals.assign(normals.begin(), normals.end());
    padding_nodes.assign(padding.begin(), padding.end());
    build_conditions();
  }



  template <int dim>
  void
  VelocityConditions<dim>::move_nodes(const double t)
  {
    current_time = t;
    build_conditions();
  }



  template <int dim>
  void
  VelocityConditions<dim>::build_conditions()
  {
    const unsigned int n_owned = partitioner_pointer->locally_owned_size();
    const auto        &normals = boundary_normals;
    // Candidates in priority order: moving walls, fixed, roller.
    std::vector<std::vector<NodeCondition>> per_node(n_owned);
    auto label_of = [&](const std::string &label) {
      return static_cast<unsigned int>(
        std::find(source_labels.begin(), source_labels.end(), label) -
        source_labels.begin());
    };
    for (unsigned int w = 0; w < walls.size(); ++w)
      {
        Tensor<1, dim> direction;
        for (unsigned int d = 0; d < dim; ++d)
          direction[d] = walls[w].direction[d];
        if (walls[w].boundary_ids.empty())
          {
            const unsigned int source = label_of("wall" + std::to_string(w));
            if (wall_region[w])
              wall_region[w]->set_time(current_time);
            for (unsigned int i = 0; i < n_owned; ++i)
              if (wall_region[w] ? wall_region[w]->value(node_position[i]) > 0 :
                                   is_inside_box(w, node_position[i]))
                add_node_condition(
                  per_node,
                  NodeCondition{i, direction, source, static_cast<int>(w)});
          }
        else
          for (const auto &entry : normals)
            if (std::find(walls[w].boundary_ids.begin(),
                          walls[w].boundary_ids.end(),
                          entry.first.first) != walls[w].boundary_ids.end())
              add_node_condition(per_node,
                                 NodeCondition{entry.first.second,
                                               direction,
                                               label_of(std::to_string(
                                                 entry.first.first)),
                                               static_cast<int>(w)});
      }
    if (fixed_region)
      {
        fixed_region->set_time(current_time);
        for (unsigned int i = 0; i < n_owned; ++i)
          if (fixed_region->value(node_position[i]) > 0)
            for (unsigned int d = 0; d < dim; ++d)
              add_node_condition(per_node,
                                 NodeCondition{i,
                                               Point<dim>::unit_vector(d),
                                               fixed_region_label,
                                               -1});
      }
    for (const auto &entry : normals)
      if (std::find(fixed.begin(), fixed.end(), entry.first.first) !=
          fixed.end())
        for (unsigned int d = 0; d < dim; ++d)
          add_node_condition(per_node,
                             NodeCondition{entry.first.second,
                                           Point<dim>::unit_vector(d),
                                           label_of(
                                             std::to_string(entry.first.first)),
                                           -1});
    for (const auto &entry : normals)
      if (std::find(roller.begin(), roller.end(), entry.first.first) !=
          roller.end())
        add_node_condition(per_node,
                           NodeCondition{entry.first.second,
                                         entry.second / entry.second.norm(),
                                         label_of(
                                           std::to_string(entry.first.first)),
                                         -1});

    if (axis)
      for (unsigned int i = 0; i < n_owned; ++i)
        if (node_position[i][0] <= 0)
          add_node_condition(
            per_node,
            NodeCondition{i, Point<dim>::unit_vector(0), axis_label, -1});

    // Padding layer: the directions each wall holds at its padding nodes
    // (moving walls, fixed, roller, orthonormalized in that order).
    mirrors.clear();
    for (const auto &entry : padding_nodes)
      {
        const types::boundary_id id = entry.first.first;
        PaddingMirror            mirror;
        mirror.padding = entry.first.second;
        mirror.mirror  = entry.second.first;
        mirror.source  = label_of(std::to_string(id));
        auto hold      = [&](Tensor<1, dim> n, const int wall) {
          for (const auto &existing : mirror.directions)
            n -= (n * existing) * existing;
          if (n.norm() > 1e-8)
            {
              mirror.directions.push_back(n / n.norm());
              mirror.direction_wall.push_back(wall);
            }
        };
        for (unsigned int w = 0; w < walls.size(); ++w)
          if (std::find(walls[w].boundary_ids.begin(),
                        walls[w].boundary_ids.end(),
                        id) != walls[w].boundary_ids.end())
            {
              Tensor<1, dim> direction;
              for (unsigned int d = 0; d < dim; ++d)
                direction[d] = walls[w].direction[d];
              hold(direction, static_cast<int>(w));
            }
        if (std::find(fixed.begin(), fixed.end(), id) != fixed.end())
          for (unsigned int d = 0; d < dim; ++d)
            hold(Point<dim>::unit_vector(d), -1);
        if (std::find(roller.begin(), roller.end(), id) != roller.end())
          hold(entry.second.second, -1);
        if (!mirror.directions.empty())
          mirrors.push_back(mirror);
      }

    conditions.clear();
    for (const auto &list : per_node)
      conditions.insert(conditions.end(), list.begin(), list.end());
    for (auto &values : cached_values)
      values.clear();
    cached_time.fill(std::numeric_limits<double>::quiet_NaN());
    condition_impulse.assign(any_velocity_in_x ? conditions.size() : 0, 0.);
  }



  template class VelocityConditions<2>;
  template class VelocityConditions<3>;
} // namespace fmpm
