// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The support cache of the step: S and G of every point (seed 000 Eqs. 1.1,
// 2.8; S̄, Ḡ of seed 001 for GIMP/CPDI), built by Transfer::SupportBuilder in
// the loop of the first pass that reads them (the extrapolation), or
// computed in each pass for classic shape functions on affine cells.

#include <fmpm/axisymmetric_bspline.h>
#include <fmpm/simulator.h>
#include <fmpm/simulator.templates.h>
#include <fmpm/transfer/support_builder.h>

#include <sstream>

namespace fmpm
{
  namespace Transfer
  {
    template <int dim>
    SupportBuilder<dim>::SupportBuilder(
      SupportCache<dim>                         &cache,
      const MaterialPoints<dim>                 &points,
      const GridTransfer<dim>                   &transfer,
      const AffineConstraints<double>           &constraints,
      const Utilities::MPI::Partitioner         &partitioner,
      const ShapeFunction::Type                  shape_function,
      const double                               cpdi_critical_radius,
      const unsigned int                         n_active_cells,
      const Patches                             &patches,
      const ShapeFunction::BSplineSupports<dim> *bsplines,
      const bool                                 axisymmetric)
      : cache(cache)
      , points(points)
      , transfer(transfer)
      , constraints(constraints)
      , partitioner(partitioner)
      , shape_function(shape_function)
      , cpdi_critical_radius(cpdi_critical_radius)
      , patches(patches)
      , bsplines(bsplines)
      , classic(shape_function == ShapeFunction::Type::classic)
      , gimp(shape_function == ShapeFunction::Type::ugimp ||
             shape_function == ShapeFunction::Type::cpgimp)
      , cpdi(shape_function == ShapeFunction::Type::cpdi)
      , axisymmetric(axisymmetric)
    {
      Assert(!axisymmetric || dim == 2,
             ExcMessage("Axisymmetric supports: 2D only."));
      using Index                 = PropertyIndex<dim>;
      const unsigned int n_points = points.n_points();
      // (GIMP on a uniform patch: at most 3^dim nodes per point.)
      cache.support_begin.resize(n_points + 1);
      cache.make_room((gimp ? Utilities::pow(3, dim) : n) * n_points);
      if (axisymmetric)
        cache.T.resize(cache.node.size());
      support_end = cache.support_begin.data() + 1;
      for (unsigned int a = 0; a < dim; ++a)
        {
          l0_column[a] = points.column(Index::initial_half_length + a);
          for (unsigned int b = 0; b < dim; ++b)
            F_column[a][b] =
              points.column(Index::deformation_gradient + 3 * a + b);
        }
      if (gimp)
        patches.gimp_of_cell.resize(n_active_cells,
                                    numbers::invalid_unsigned_int);
      if (cpdi)
        patches.cpdi_of_cell.resize(n_active_cells,
                                    numbers::invalid_unsigned_int);
    }



    template <int dim>
    void
    SupportBuilder<dim>::begin_cell(const unsigned int cell_number)
    {
      c    = points.cell_index[cell_number];
      data = &transfer.cell_data(c);
      if (gimp && data->uniform_patch)
        {
          // (Built once per cell, kept across steps.)
          if (patches.gimp_of_cell[c] == numbers::invalid_unsigned_int)
            {
              patches.gimp_of_cell[c] = patches.gimp.size();
              patches.gimp.emplace_back();
              patches.gimp.back().reinit(transfer, c);
            }
          gimp_patch = &patches.gimp[patches.gimp_of_cell[c]];
        }
      if constexpr (dim == 2)
        if (axisymmetric)
          {
            // The axisymmetric closed forms read the same planes.
            axisymmetric_gimp_patch_ready = gimp && data->uniform_patch;
            if (axisymmetric_gimp_patch_ready)
              axisymmetric_gimp_patch.reinit(gimp_patch->planes());
            return;
          }
      cpdi_patch = nullptr;
      if (cpdi && data->uniform_patch)
        {
          if (patches.cpdi_of_cell[c] == numbers::invalid_unsigned_int)
            {
              patches.cpdi_of_cell[c] = patches.cpdi.size();
              patches.cpdi.emplace_back();
              patches.cpdi.back().reinit(transfer, c);
            }
          if (patches.cpdi[patches.cpdi_of_cell[c]].applies())
            cpdi_patch = &patches.cpdi[patches.cpdi_of_cell[c]];
        }
    }



    template <int dim>
    void
    SupportBuilder<dim>::build(const unsigned int k)
    {
      const unsigned int first = cache.n_stored;
      if (axisymmetric)
        build_axisymmetric(first, k);
      else if (classic)
        build_classic(first, k);
      else if (bsplines != nullptr)
        build_bspline(k);
      else
        build_general(first, k);
      support_end[k] = cache.n_stored;
    }



    template <int dim>
    void
    SupportBuilder<dim>::build_bspline(const unsigned int k)
    {
      // (b2spline and b3spline read neither F nor l⁰.)
      Tensor<2, dim> F;
      Tensor<1, dim> l0;
      if (shape_function == ShapeFunction::Type::b2gimp ||
          shape_function == ShapeFunction::Type::b2cpdi)
        for (unsigned int a = 0; a < dim; ++a)
          l0[a] = l0_column[a][k];
      if (shape_function == ShapeFunction::Type::b2cpdi)
        for (unsigned int a = 0; a < dim; ++a)
          for (unsigned int b = 0; b < dim; ++b)
            F[a][b] = F_column[a][b][k];
      const std::size_t first = cache.n_stored;
      cache.make_room(bsplines->max_support_size);
      unsigned int                count;
      const ShapeFunction::Status status =
        bsplines->support(points.position[k],
                          F,
                          l0,
                          cpdi_critical_radius,
                          cache.node.data() + first,
                          cache.S.data() + first,
                          cache.G.data() + first,
                          count);
      if (status != ShapeFunction::Status::ok)
        {
          if (failed_point == numbers::invalid_unsigned_int)
            {
              failed_point = k;
              failure      = status;
            }
          count = 0; // (the step fails)
        }
      cache.n_stored += count;
    }



    template <int dim>
    void
    SupportBuilder<dim>::add_node(const unsigned int            first,
                                  const unsigned int            local_index,
                                  const types::global_dof_index dof,
                                  const bool                    constrained,
                                  const double                  S_ip,
                                  const Tensor<1, dim>         &G_ip)
    {
      if (!constrained)
        cache.add_entry(first, local_index, S_ip, G_ip);
      else
        for (const auto &entry : *constraints.get_constraint_entries(dof))
          cache.add_entry(first,
                          partitioner.global_to_local(entry.first),
                          entry.second * S_ip,
                          entry.second * G_ip);
    }



    template <int dim>
    void
    SupportBuilder<dim>::build_classic(const unsigned int first,
                                       const unsigned int k)
    {
      GridTransfer<dim>::values_and_gradients(*data,
                                              points.reference_position[k],
                                              S,
                                              G);
      if (!data->has_constraints)
        {
          cache.make_room(n);
          for (unsigned int i = 0; i < n; ++i)
            cache.append(data->local_index[i], S[i], G[i]);
        }
      else
        for (unsigned int i = 0; i < n; ++i)
          add_node(first,
                   data->local_index[i],
                   transfer.dof_index(*data, i),
                   data->constrained_nodes & (1u << i),
                   S[i],
                   G[i]);
    }



    template <int dim>
    void
    SupportBuilder<dim>::build_general(const unsigned int first,
                                       const unsigned int k)
    {
      const Point<dim> &location = points.position[k];
      Tensor<2, dim>    F;
      Tensor<1, dim>    l0, l;
      for (unsigned int a = 0; a < dim; ++a)
        {
          l0[a] = l0_column[a][k];
          l[a]  = l0_column[a][k];
        }
      // (uGIMP reads no F.)
      if (shape_function != ShapeFunction::Type::ugimp)
        for (unsigned int a = 0; a < dim; ++a)
          for (unsigned int b = 0; b < dim; ++b)
            F[a][b] = F_column[a][b][k];
      // GIMP's closed forms on a uniform patch from the cell's planes
      // (built once per cell), else the general support.
      if (shape_function == ShapeFunction::Type::cpgimp)
        l = ShapeFunction::gimp_half_lengths(shape_function, F, l0);
      // No hanging nodes on a uniform patch: straight into the cache.
      if (gimp && data->uniform_patch)
        {
          cache.make_room(Utilities::pow(4, dim));
          unsigned int *const   node_out = cache.node.data() + first;
          double *const         S_out    = cache.S.data() + first;
          Tensor<1, dim> *const G_out    = cache.G.data() + first;
          unsigned int          count    = 0;
          if (gimp_patch->for_each_node_if_applies(
                location,
                l,
                [&](const unsigned int local_index,
                    const types::global_dof_index,
                    const double          S_ip,
                    const Tensor<1, dim> &G_ip) {
                  node_out[count] = local_index;
                  S_out[count]    = S_ip;
                  G_out[count]    = G_ip;
                  ++count;
                }))
            {
              cache.n_stored += count;
              return;
            }
        }
      // CPDI on a uniform patch: the corners' cells found arithmetically
      // (the general path's bits).
      if (cpdi_patch != nullptr)
        {
          cache.make_room(
            ShapeFunction::UniformCpdiPatch<dim>::max_support_size);
          const unsigned int count =
            cpdi_patch->support(transfer,
                                location,
                                F,
                                l0,
                                cpdi_critical_radius,
                                cache.node.data() + first,
                                cache.S.data() + first,
                                cache.G.data() + first);
          if (count > 0)
            {
              cache.n_stored += count;
              return;
            }
        }
      if (shape_function == ShapeFunction::Type::ugimp)
        for (unsigned int a = 0; a < dim; ++a)
          for (unsigned int b = 0; b < dim; ++b)
            F[a][b] = F_column[a][b][k];
      const ShapeFunction::Status status =
        ShapeFunction::compute_support(shape_function,
                                       transfer,
                                       c,
                                       location,
                                       F,
                                       l0,
                                       support,
                                       true,
                                       cpdi_critical_radius);
      if (status != ShapeFunction::Status::ok)
        {
          if (failed_point == numbers::invalid_unsigned_int)
            {
              failed_point = k;
              failure      = status;
            }
          // Carry on with the classic weights; the step fails.
          ShapeFunction::compute_support(ShapeFunction::Type::classic,
                                         transfer,
                                         c,
                                         location,
                                         F,
                                         l0,
                                         support);
        }
      // compute_support() names each node once: only the masters of
      // hanging nodes can repeat a node.
      bool any_constrained = false;
      for (const auto &node : support)
        any_constrained = any_constrained || node.constrained;
      if (!any_constrained)
        {
          cache.make_room(support.size());
          for (const auto &node : support)
            cache.append(node.local_index, node.S, node.G);
        }
      else
        for (const auto &node : support)
          add_node(first,
                   node.local_index,
                   node.dof,
                   node.constrained,
                   node.S,
                   node.G);
    }

    template <int dim>
    void
    SupportBuilder<dim>::add_axisymmetric_node(
      const unsigned int            first,
      const unsigned int            local_index,
      const types::global_dof_index dof,
      const bool                    constrained,
      const double                  S_ip,
      const Tensor<1, dim>         &G_ip,
      const double                  T_ip)
    {
      const auto add = [&](const unsigned int i, const double weight) {
        for (std::size_t j = first; j < cache.n_stored; ++j)
          if (cache.node[j] == i)
            {
              cache.S[j] += weight * S_ip;
              cache.G[j] += weight * G_ip;
              cache.T[j] += weight * T_ip;
              return;
            }
        cache.make_room(1);
        if (cache.T.size() < cache.node.size())
          cache.T.resize(cache.node.size());
        cache.T[cache.n_stored] = weight * T_ip;
        cache.append(i, weight * S_ip, weight * G_ip);
      };
      if (!constrained)
        add(local_index, 1.);
      else
        for (const auto &entry : *constraints.get_constraint_entries(dof))
          add(partitioner.global_to_local(entry.first), entry.second);
    }



    template <int dim>
    void
    SupportBuilder<dim>::build_axisymmetric_bspline(const unsigned int first,
                                                    const unsigned int k)
    {
      if constexpr (dim == 2)
        {
          const Point<dim> &x = points.position[k];
          if (!(x[0] > 0))
            {
              if (failed_point == numbers::invalid_unsigned_int)
                {
                  failed_point = k;
                  axisymmetric_failure =
                    ShapeFunction::Axisymmetric::Status::on_axis;
                }
              return;
            }
          Tensor<2, dim> F;
          Tensor<1, dim> l0;
          for (unsigned int a = 0; a < dim; ++a)
            {
              l0[a] = l0_column[a][k];
              for (unsigned int b = 0; b < dim; ++b)
                F[a][b] = F_column[a][b][k];
            }
          cache.make_room(bsplines->max_support_size);
          if (cache.T.size() < cache.node.size())
            cache.T.resize(cache.node.size());
          unsigned int                count  = 0;
          ShapeFunction::Status       status = ShapeFunction::Status::ok;
          const ShapeFunction::Status support_status =
            ShapeFunction::Axisymmetric::bspline_support(
              shape_function,
              bsplines->get_lattice(),
              x,
              F,
              l0,
              cpdi_critical_radius,
              [&](const std::array<int, 2> &index,
                  const double              S_ip,
                  const Tensor<1, 2>       &G_ip,
                  const double              T_ip) {
                const unsigned int local = bsplines->vertex_local_index(index);
                if (local == numbers::invalid_unsigned_int)
                  {
                    status = ShapeFunction::Status::vertex_not_on_rank;
                    return;
                  }
                cache.node[first + count] = local;
                cache.S[first + count]    = S_ip;
                cache.G[first + count]    = G_ip;
                cache.T[first + count]    = T_ip;
                ++count;
              });
          if (support_status != ShapeFunction::Status::ok)
            status = support_status;
          if (status != ShapeFunction::Status::ok)
            {
              if (failed_point == numbers::invalid_unsigned_int)
                {
                  failed_point = k;
                  failure      = status;
                }
              count = 0; // (the step fails)
            }
          cache.n_stored += count;
        }
      else
        {
          (void)first;
          (void)k;
        }
    }



    template <int dim>
    void
    SupportBuilder<dim>::build_axisymmetric(const unsigned int first,
                                            const unsigned int k)
    {
      if constexpr (dim == 2)
        {
          namespace Axisymmetric = ShapeFunction::Axisymmetric;
          const Point<dim> &x    = points.position[k];
          if (bsplines != nullptr)
            {
              build_axisymmetric_bspline(first, k);
              return;
            }
          if (classic)
            {
              // S, G of build_classic() (from ξ), T = S/r_p.
              if (!(x[0] > 0))
                {
                  if (failed_point == numbers::invalid_unsigned_int)
                    {
                      failed_point         = k;
                      axisymmetric_failure = Axisymmetric::Status::on_axis;
                    }
                  return;
                }
              GridTransfer<dim>::values_and_gradients(
                *data, points.reference_position[k], S, G);
              const double inverse_r = 1 / x[0];
              if (!data->has_constraints)
                {
                  // The cell's nodes, straight into the cache.
                  cache.make_room(n);
                  if (cache.T.size() < cache.node.size())
                    cache.T.resize(cache.node.size());
                  double *const T_out = cache.T.data() + first;
                  for (unsigned int i = 0; i < n; ++i)
                    {
                      T_out[i] = S[i] * inverse_r;
                      cache.append(data->local_index[i], S[i], G[i]);
                    }
                  return;
                }
              for (unsigned int i = 0; i < n; ++i)
                add_axisymmetric_node(first,
                                      data->local_index[i],
                                      transfer.dof_index(*data, i),
                                      data->constrained_nodes & (1u << i),
                                      S[i],
                                      G[i],
                                      S[i] * inverse_r);
              return;
            }
          Tensor<2, dim> F;
          Tensor<1, dim> l0;
          for (unsigned int a = 0; a < dim; ++a)
            {
              l0[a] = l0_column[a][k];
              for (unsigned int b = 0; b < dim; ++b)
                F[a][b] = F_column[a][b][k];
            }
          // GIMP on a uniform patch: the closed forms of the cell's patch
          // (no hanging nodes), straight into the cache.
          if (axisymmetric_gimp_patch_ready)
            {
              const Tensor<1, dim> l =
                ShapeFunction::gimp_half_lengths(shape_function, F, l0);
              cache.make_room(16);
              if (cache.T.size() < cache.node.size())
                cache.T.resize(cache.node.size());
              unsigned int *const   node_out = cache.node.data() + first;
              double *const         S_out    = cache.S.data() + first;
              Tensor<1, dim> *const G_out    = cache.G.data() + first;
              double *const         T_out    = cache.T.data() + first;
              unsigned int          count    = 0;
              if (axisymmetric_gimp_patch.for_each_node_if_applies(
                    x,
                    l,
                    [&](const unsigned int local_index,
                        const types::global_dof_index,
                        const double          S_ip,
                        const Tensor<1, dim> &G_ip,
                        const double          T_ip) {
                      node_out[count] = local_index;
                      S_out[count]    = S_ip;
                      G_out[count]    = G_ip;
                      T_out[count]    = T_ip;
                      ++count;
                    }))
                {
                  cache.n_stored += count;
                  return;
                }
            }
          const Axisymmetric::Status status = Axisymmetric::compute_support(
            shape_function, transfer, c, x, F, l0, axisymmetric_support);
          if (status != Axisymmetric::Status::ok)
            {
              if (failed_point == numbers::invalid_unsigned_int)
                {
                  failed_point         = k;
                  axisymmetric_failure = status;
                }
              return; // (the step fails)
            }
          // compute_support() names each node once: without constrained
          // nodes (no masters to merge) the entries go straight into the
          // cache, as add_axisymmetric_node() would store them.
          bool any_constrained = false;
          for (const auto &node : axisymmetric_support)
            any_constrained = any_constrained || node.constrained;
          if (!any_constrained)
            {
              const unsigned int n = axisymmetric_support.size();
              cache.make_room(n);
              if (cache.T.size() < cache.node.size())
                cache.T.resize(cache.node.size());
              unsigned int *const   node_out = cache.node.data() + first;
              double *const         S_out    = cache.S.data() + first;
              Tensor<1, dim> *const G_out    = cache.G.data() + first;
              double *const         T_out    = cache.T.data() + first;
              for (unsigned int i = 0; i < n; ++i)
                {
                  const auto &node = axisymmetric_support[i];
                  node_out[i]      = node.local_index;
                  S_out[i]         = node.S;
                  G_out[i]         = node.G;
                  T_out[i]         = node.T;
                }
              cache.n_stored += n;
              return;
            }
          for (const auto &node : axisymmetric_support)
            add_axisymmetric_node(first,
                                  node.local_index,
                                  node.dof,
                                  node.constrained,
                                  node.S,
                                  node.G,
                                  node.T);
        }
      else
        {
          (void)first;
          (void)k;
        }
    }

    template class SupportBuilder<2>;
    template class SupportBuilder<3>;
  } // namespace Transfer



  template <int dim>
  void
  Simulator<dim>::prepare_supports()
  {
    using Index = PropertyIndex<dim>;
    supports.clear();
    const unsigned int n_points = points.n_points();
    if (n_points == 0)
      return;
    if (constitutive_models.size() > 1)
      {
        const double *const material_id = points.column(Index::material_id);
        supports.material.resize(n_points);
        for (unsigned int k = 0; k < n_points; ++k)
          supports.material[k] = static_cast<unsigned char>(material_id[k]);
      }

    // Classic on affine cells without hanging nodes: the passes compute the
    // entries from the step's ξ (Transfer::ComputedSupports).
    // (Axisymmetric: T = S/r_p from the computed S and the step's r_p,
    // with USF only: after the particle update x_p has moved.)
    if (shape_function != ShapeFunction::Type::classic ||
        (parameters.axisymmetric &&
         parameters.method.strain_update_scheme.update_last))
      return;
    bool affine_without_hanging_nodes = true;
    for (unsigned int c = 0; c < points.n_cells(); ++c)
      {
        const auto &data             = transfer.cell_data(points.cell_index[c]);
        affine_without_hanging_nodes = affine_without_hanging_nodes &&
                                       data.is_affine && !data.has_constraints;
      }
    if (!affine_without_hanging_nodes)
      return;
    supports.implicit_classic  = true;
    supports.n_implicit_points = n_points;
    if (parameters.method.strain_update_scheme.update_last)
      {
        supports.reference_position_copy = points.reference_position;
        supports.reference_position = supports.reference_position_copy.data();
      }
    else
      supports.reference_position = points.reference_position.data();
  }



  template <int dim>
  Transfer::SupportBuilder<dim>
  Simulator<dim>::support_builder()
  {
    return Transfer::SupportBuilder<dim>(
      supports,
      points,
      transfer,
      constraints,
      *centre_of_mass.mass.get_partitioner(),
      shape_function,
      parameters.method.cpdi_critical_radius,
      triangulation.n_active_cells(),
      {gimp_patches, gimp_patch_of_cell, cpdi_patches, cpdi_patch_of_cell},
      bspline_supports.active() ? &bspline_supports : nullptr,
      parameters.axisymmetric);
  }



  template <int dim>
  void
  Simulator<dim>::report_support_failure(
    const Transfer::SupportBuilder<dim> &builder)
  {
    if (builder.failed_point == numbers::invalid_unsigned_int)
      return;
    std::ostringstream text;
    using AxisymmetricStatus = ShapeFunction::Axisymmetric::Status;
    if (builder.axisymmetric_failure != AxisymmetricStatus::ok)
      text << (builder.axisymmetric_failure == AxisymmetricStatus::on_axis ?
                 "lies on or across the axis r = 0 (Geometry = "
                 "axisymmetric): no hoop term there" :
               builder.axisymmetric_failure ==
                   AxisymmetricStatus::needs_axis_aligned_cells ?
                 "needs axis-aligned cells for axisymmetric GIMP" :
               builder.axisymmetric_failure ==
                   AxisymmetricStatus::outside_mesh ?
                 "reaches outside the mesh by more than half a cell" :
                 "reaches beyond the cells that share a vertex with its cell")
           << " (Shape function/Type = " << parameters.method.shape_function
           << ", Geometry = axisymmetric)";
    else if (bspline_supports.active())
      text << ShapeFunction::BSplineSupports<dim>::explain(builder.failure)
           << " (Shape function/Type = " << parameters.method.shape_function
           << ")";
    else
      text << (builder.failure == ShapeFunction::Status::outside_mesh ?
                 "reaches outside the mesh by more than half a cell" :
                 "reaches beyond the cells that share a vertex with its cell "
                 "(one layer of neighbour or ghost cells)")
           << " (Shape function/Type = " << parameters.method.shape_function
           << "): use smaller points (more Points per cell), a coarser mesh "
              "there, classic shape functions, or for CPDI a Shape "
              "function/CPDI critical radius of at most 1";
    report_point_failure(builder.failed_point,
                         FailedPoint::Cause::support_outside_patch,
                         text.str());
  }



  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
