// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The particle-grid passes of the time step: the support cache (S, G of
// every point, once per step), extrapolations to the grid (Sᵀ, Gᵀ) and the
// re-sorting of moved points into cells (PointSort); the strain update is in
// stress_update.cc, the particle update in point_update.cc. Every pass loops
// over the support cache.

#include <fmpm/simulator.h>
#include <fmpm/simulator.templates.h>
#include <fmpm/transfer/sinks.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace fmpm
{
  template <int dim>
  void
  Simulator<dim>::compute_supports(const bool extrapolate)
  {
    TimerOutput::Scope timer(computing_timer, "shape functions");
    using Index              = PropertyIndex<dim>;
    constexpr unsigned int n = GridTransfer<dim>::n_nodes;
    supports.clear();
    supports_extrapolated       = false;
    const unsigned int n_points = points.n_points();
    if (n_points == 0)
      return;
    const bool classic = (shape_function == ShapeFunction::Type::classic);
    const bool multiple_materials   = constitutive_models.size() > 1;
    const double *const material_id = points.column(Index::material_id);
    if (multiple_materials)
      {
        supports.material.resize(n_points);
        for (unsigned int k = 0; k < n_points; ++k)
          supports.material[k] = static_cast<unsigned char>(material_id[k]);
      }

    // Classic on affine cells without hanging nodes: the passes compute the
    // entries from the step's ξ (SupportReader).
    if (classic)
      {
        bool affine_without_hanging_nodes = true;
        for (unsigned int c = 0; c < points.n_cells(); ++c)
          {
            const auto &data = transfer.cell_data(points.cell_index[c]);
            affine_without_hanging_nodes = affine_without_hanging_nodes &&
                                           data.is_affine &&
                                           !data.has_constraints;
          }
        if (affine_without_hanging_nodes)
          {
            supports.implicit_classic  = true;
            supports.n_implicit_points = n_points;
            if (parameters.method.strain_update_scheme.update_last)
              {
                supports.reference_position_copy = points.reference_position;
                supports.reference_position =
                  supports.reference_position_copy.data();
              }
            else
              supports.reference_position = points.reference_position.data();
            return;
          }
      }

    // (GIMP on a uniform patch: at most 3^dim nodes per point.)
    const bool gimp = (shape_function == ShapeFunction::Type::ugimp ||
                       shape_function == ShapeFunction::Type::cpgimp);
    supports.support_begin.resize(n_points + 1);
    supports.make_room((gimp ? Utilities::pow(3, dim) : n) * n_points);
    unsigned int *const support_end = supports.support_begin.data() + 1;

    // m = SᵀM, p = SᵀMV of each point once its entries are stored.
    const bool extrapolate_here = extrapolate && extrapolates_with_supports();
    double    *m = nullptr, *p[dim] = {};
    if (extrapolate_here)
      {
        centre_of_mass.mass     = 0;
        centre_of_mass.momentum = 0;
        m                       = centre_of_mass.mass.begin();
        for (unsigned int d = 0; d < dim; ++d)
          p[d] = centre_of_mass.momentum.block(d).begin();
        supports_extrapolated = true;
      }
    const Transfer::MassMomentumSink<dim> mass_momentum(points, m, p);
    auto extrapolate_point = [&](const unsigned int k,
                                 const std::size_t  first) {
      mass_momentum.point(k,
                          supports.node.data() + first,
                          supports.S.data() + first,
                          nullptr,
                          supports.n_stored - first);
    };
    const auto   &partitioner = *centre_of_mass.mass.get_partitioner();
    const double *F_column[dim][dim], *l0_column[dim];
    for (unsigned int a = 0; a < dim; ++a)
      {
        l0_column[a] = points.column(Index::initial_half_length + a);
        for (unsigned int b = 0; b < dim; ++b)
          F_column[a][b] =
            points.column(Index::deformation_gradient + 3 * a + b);
      }

    // B-splines on the mesh's lattice (no hanging nodes).
    if (bspline_supports.active())
      {
        for (unsigned int k = 0; k < n_points; ++k)
          {
            Tensor<2, dim> F;
            Tensor<1, dim> l0;
            for (unsigned int a = 0; a < dim; ++a)
              {
                l0[a] = l0_column[a][k];
                for (unsigned int b = 0; b < dim; ++b)
                  F[a][b] = F_column[a][b][k];
              }
            const std::size_t first = supports.n_stored;
            supports.make_room(bspline_supports.max_support_size);
            unsigned int                count;
            const ShapeFunction::Status status =
              bspline_supports.support(points.position[k],
                                       F,
                                       l0,
                                       parameters.method.cpdi_critical_radius,
                                       supports.node.data() + first,
                                       supports.S.data() + first,
                                       supports.G.data() + first,
                                       count);
            if (status != ShapeFunction::Status::ok)
              {
                report_point_failure(
                  k,
                  FailedPoint::Cause::support_outside_patch,
                  ShapeFunction::BSplineSupports<dim>::explain(status),
                  " (Shape function/Type = ",
                  parameters.method.shape_function,
                  ")");
                count = 0; // (the step fails)
              }
            supports.n_stored += count;
            support_end[k] = supports.n_stored;
            if (extrapolate_here)
              extrapolate_point(k, first);
          }
        return;
      }

    // A node of a support: itself, or for a hanging node its masters with
    // the constraint weights (S_jp += c_ij S_ip).
    auto add_node = [&](const unsigned int            first,
                        const unsigned int            local_index,
                        const types::global_dof_index dof,
                        const bool                    constrained,
                        const double                  S,
                        const Tensor<1, dim>         &G) {
      if (!constrained)
        supports.add_entry(first, local_index, S, G);
      else
        for (const auto &entry : *constraints.get_constraint_entries(dof))
          supports.add_entry(first,
                             partitioner.global_to_local(entry.first),
                             entry.second * S,
                             entry.second * G);
    };

    std::array<double, n>                 S;
    std::array<Tensor<1, dim>, n>         G;
    std::vector<ShapeFunction::Node<dim>> support;
    if (gimp)
      gimp_patch_of_cell.resize(triangulation.n_active_cells(),
                                numbers::invalid_unsigned_int);
    const ShapeFunction::UniformGimpPatch<dim> *gimp_patch = nullptr;
    const bool cpdi = (shape_function == ShapeFunction::Type::cpdi);
    if (cpdi)
      cpdi_patch_of_cell.resize(triangulation.n_active_cells(),
                                numbers::invalid_unsigned_int);
    const ShapeFunction::UniformCpdiPatch<dim> *cpdi_patch = nullptr;
    // The points in the store's order: cell by cell (cells in the order of
    // their ids, so that the sums over points onto nodes do not depend on
    // the mesh's storage order, which a mesh loaded from a checkpoint does
    // not share: bitwise resumes), by id in a cell.
    for (unsigned int cell_number = 0; cell_number < points.n_cells();
         ++cell_number)
      {
        const unsigned int c    = points.cell_index[cell_number];
        const auto        &data = transfer.cell_data(c);
        if (gimp && data.uniform_patch)
          {
            if (gimp_patch_of_cell[c] == numbers::invalid_unsigned_int)
              {
                gimp_patch_of_cell[c] = gimp_patches.size();
                gimp_patches.emplace_back();
                gimp_patches.back().reinit(transfer, c);
              }
            gimp_patch = &gimp_patches[gimp_patch_of_cell[c]];
          }
        cpdi_patch = nullptr;
        if (cpdi && data.uniform_patch)
          {
            if (cpdi_patch_of_cell[c] == numbers::invalid_unsigned_int)
              {
                cpdi_patch_of_cell[c] = cpdi_patches.size();
                cpdi_patches.emplace_back();
                cpdi_patches.back().reinit(transfer, c);
              }
            if (cpdi_patches[cpdi_patch_of_cell[c]].applies())
              cpdi_patch = &cpdi_patches[cpdi_patch_of_cell[c]];
          }
        for (unsigned int k = points.cell_point_begin[cell_number];
             k < points.cell_point_begin[cell_number + 1];
             ++k)
          {
            const Point<dim>  &location = points.position[k];
            const unsigned int first    = supports.n_stored;
            if (classic)
              {
                GridTransfer<dim>::values_and_gradients(
                  data, points.reference_position[k], S, G);
                if (!data.has_constraints)
                  {
                    supports.make_room(n);
                    for (unsigned int i = 0; i < n; ++i)
                      supports.append(data.local_index[i], S[i], G[i]);
                  }
                else
                  for (unsigned int i = 0; i < n; ++i)
                    add_node(first,
                             data.local_index[i],
                             transfer.dof_index(data, i),
                             data.constrained_nodes & (1u << i),
                             S[i],
                             G[i]);
              }
            else
              {
                Tensor<2, dim> F;
                Tensor<1, dim> l0, l;
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
                // GIMP's closed forms on a uniform patch from the cell's
                // planes (built once per cell), else the general support.
                ShapeFunction::Status status = ShapeFunction::Status::ok;
                if (shape_function == ShapeFunction::Type::cpgimp)
                  l = ShapeFunction::gimp_half_lengths(shape_function, F, l0);
                // No hanging nodes on a uniform patch: straight into the
                // cache.
                if (gimp && data.uniform_patch)
                  {
                    supports.make_room(Utilities::pow(4, dim));
                    unsigned int *const node_out = supports.node.data() + first;
                    double *const       S_out    = supports.S.data() + first;
                    Tensor<1, dim> *const G_out  = supports.G.data() + first;
                    unsigned int          count  = 0;
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
                        supports.n_stored += count;
                        support_end[k] = supports.n_stored;
                        if (extrapolate_here)
                          extrapolate_point(k, first);
                        continue;
                      }
                  }
                // CPDI on a uniform patch: the corners' cells found
                // arithmetically (the general path's bits).
                if (cpdi_patch != nullptr)
                  {
                    supports.make_room(
                      ShapeFunction::UniformCpdiPatch<dim>::max_support_size);
                    const unsigned int count = cpdi_patch->support(
                      transfer,
                      location,
                      F,
                      l0,
                      parameters.method.cpdi_critical_radius,
                      supports.node.data() + first,
                      supports.S.data() + first,
                      supports.G.data() + first);
                    if (count > 0)
                      {
                        supports.n_stored += count;
                        support_end[k] = supports.n_stored;
                        if (extrapolate_here)
                          extrapolate_point(k, first);
                        continue;
                      }
                  }
                if (shape_function == ShapeFunction::Type::ugimp)
                  for (unsigned int a = 0; a < dim; ++a)
                    for (unsigned int b = 0; b < dim; ++b)
                      F[a][b] = F_column[a][b][k];
                status = ShapeFunction::compute_support(
                  shape_function,
                  transfer,
                  c,
                  location,
                  F,
                  l0,
                  support,
                  true,
                  parameters.method.cpdi_critical_radius);
                if (status != ShapeFunction::Status::ok)
                  {
                    report_point_failure(
                      k,
                      FailedPoint::Cause::support_outside_patch,
                      status == ShapeFunction::Status::outside_mesh ?
                        "reaches outside the mesh by more than half a "
                        "cell" :
                        "reaches beyond the cells that share a vertex "
                        "with its cell (one layer of neighbour or "
                        "ghost cells)",
                      " (Shape function/Type = ",
                      parameters.method.shape_function,
                      "): use smaller points (more Points per cell), "
                      "a coarser mesh there, classic shape "
                      "functions, or for CPDI a Shape function/CPDI "
                      "critical radius of at most 1");
                    // Carry on with the classic weights; the step fails.
                    ShapeFunction::compute_support(ShapeFunction::Type::classic,
                                                   transfer,
                                                   c,
                                                   location,
                                                   F,
                                                   l0,
                                                   support);
                  }
                // compute_support() names each node once: only the masters
                // of hanging nodes can repeat a node.
                bool any_constrained = false;
                for (const auto &node : support)
                  any_constrained = any_constrained || node.constrained;
                if (!any_constrained)
                  {
                    supports.make_room(support.size());
                    for (const auto &node : support)
                      supports.append(node.local_index, node.S, node.G);
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
            support_end[k] = supports.n_stored;
            if (extrapolate_here)
              extrapolate_point(k, first);
          }
      }
  }



  template <int dim>
  void
  Simulator<dim>::particles_to_grid(const bool with_forces)
  {
    TimerOutput::Scope timer(computing_timer, "particles to grid");
    using Index = PropertyIndex<dim>;
    // m and p extrapolated by compute_supports() (one field, no forces, no
    // m̃): only the ghosts to add.
    const bool extrapolated = supports_extrapolated;
    supports_extrapolated   = false;

    // m̃ as cell-wise matrices where the mass matrix accepts them, else the
    // assembled sparse matrix (the collection BC methods need its entries).
    use_cellwise_full_mass = mass_matrix->needs_full_mass_matrix() &&
                             mass_matrix->accepts_cellwise_full_mass_matrix() &&
                             !velocity_conditions.needs_full_mass_matrix();
    const bool assemble_full =
      !use_cellwise_full_mass && (mass_matrix->needs_full_mass_matrix() ||
                                  velocity_conditions.needs_full_mass_matrix());
    const bool with_full_mass = use_cellwise_full_mass || assemble_full;
    // (With contact m, p and f are set from the material fields after the
    // sweep.)
    const bool contact = contact_active();
    if (!contact && !extrapolated)
      {
        centre_of_mass.mass     = 0;
        centre_of_mass.momentum = 0;
        if (with_forces)
          centre_of_mass.force = 0;
      }
    if (assemble_full)
      full_mass_matrix = 0;
    if (with_full_mass && use_cellwise_full_mass)
      cellwise_full_mass.clear();

    // Per-material fields (contact): m^α, p^α0, f^α0, g^α, Σ S M X.
    if (contact)
      this->contact->invalidate_geometry(true);
    std::vector<Contact::MaterialField<dim>>  no_material_fields;
    std::vector<Contact::MaterialField<dim>> &material_fields =
      contact ? this->contact->material_fields() : no_material_fields;
    const unsigned int n_materials = material_fields.size();
    // m̃^α = Σ_{p∈α} S M Sᵀ (seed 004 Eq. 37) as local matrices of the cells
    // with points of α, for the multimaterial series and exact solve.
    const bool material_full_mass =
      contact && this->contact->needs_material_full_mass();
    std::vector<CellwiseMatrix> *const material_full_mass_matrices =
      material_full_mass ? &this->contact->material_full_mass() : nullptr;
    if (material_full_mass)
      for (auto &matrix : *material_full_mass_matrices)
        matrix.clear();
    std::vector<double *> m_alpha(n_materials), p_alpha(n_materials * dim),
      f_alpha(n_materials * dim);
    Contact::GeometrySink<dim>        no_contact_geometry;
    const Contact::GeometrySink<dim> &contact_geometry =
      contact ? this->contact->begin_geometry(points) : no_contact_geometry;
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        Contact::MaterialField<dim> &field = material_fields[a];
        field.mass                         = 0;
        field.momentum                     = 0;
        if (with_forces)
          field.force = 0;
        m_alpha[a] = field.mass.begin();
        for (unsigned int d = 0; d < dim; ++d)
          {
            p_alpha[a * dim + d] = field.momentum.block(d).begin();
            f_alpha[a * dim + d] = field.force.block(d).begin();
          }
      }

    const auto &partitioner = *centre_of_mass.mass.get_partitioner();

    // Raw views of the ghosted grid vectors (owned and ghost entries).
    double *const m = centre_of_mass.mass.begin();
    double       *p[dim], *f[dim];
    for (unsigned int d = 0; d < dim; ++d)
      {
        p[d] = centre_of_mass.momentum.block(d).begin();
        f[d] = centre_of_mass.force.block(d).begin();
      }
    // The sinks of m, p (Sᵀ) and f (Gᵀ, body force) of the centre of mass
    // or, with contact, of the point's material (Eqs. 5, 29).
    const Transfer::MassMomentumSink<dim> mass_momentum(points, m, p);
    const Transfer::ForceSink<dim>        force(points, external_loads, f);
    Transfer::PerMaterial<Transfer::MassMomentumSink<dim>>
      material_mass_momentum(supports.material.data());
    Transfer::PerMaterial<Transfer::ForceSink<dim>> material_force(
      supports.material.data());
    for (unsigned int a = 0; a < n_materials; ++a)
      {
        material_mass_momentum.sinks.emplace_back(points,
                                                  m_alpha[a],
                                                  &p_alpha[a * dim]);
        material_force.sinks.emplace_back(points,
                                          external_loads,
                                          &f_alpha[a * dim]);
      }
    const unsigned int *const cached_node = supports.node.data();
    const SupportReader<dim> support_of(supports, transfer, points.cell.data());
    // (M of the points for m̃)
    const double *const mass_column = points.column(Index::mass);
    // m̃ of one cell over the union of its points' supports: the nodes, and
    // the place in them of each support entry of the cell's points.
    std::vector<unsigned int>        cell_nodes, slot;
    std::vector<double>              local_full_mass;
    std::vector<std::vector<double>> local_material_mass(
      material_full_mass ? n_materials : 0);
    std::vector<char> material_in_cell(material_full_mass ? n_materials : 0);
    std::vector<types::global_dof_index> dofs;
    // A cell's m̃ (local_full_mass over its n nodes) into the cell-wise or
    // the assembled matrix.
    auto add_cell_full_mass = [&](const unsigned int        n,
                                  const unsigned int *const nodes) {
      if (with_full_mass && use_cellwise_full_mass)
        cellwise_full_mass.add_cell(n, nodes, local_full_mass.data());
      else if (assemble_full)
        {
          dofs.resize(n);
          for (unsigned int i = 0; i < n; ++i)
            dofs[i] = partitioner.local_to_global(nodes[i]);
          for (unsigned int i = 0; i < n; ++i)
            full_mass_matrix.add(dofs[i],
                                 n,
                                 dofs.data(),
                                 &local_full_mass[i * n]);
        }
    };

    // Per point: the entries j of its support (computed: the cell's nodes;
    // stored: the cache's), at place place_of(j) of the cell's nodes.
    const bool with_gradients =
      with_forces || contact_geometry.needs_gradients();
    for (unsigned int c = 0; c < (extrapolated ? 0 : points.n_cells()); ++c)
      {
        if (supports.implicit_classic && !contact)
          {
            // Computed supports, one velocity field (the general loop below
            // keeps fewer values in registers): the cell's nodes for all its
            // points, m̃ over them.
            constexpr unsigned int n = GridTransfer<dim>::n_nodes;
            const auto &cell_data    = transfer.cell_data(points.cell_index[c]);
            const std::array<unsigned int, n> &cell_node =
              cell_data.local_index;
            if (with_full_mass)
              local_full_mass.assign(n * n, 0.);
            for (unsigned int k = points.cell_point_begin[c];
                 k < points.cell_point_begin[c + 1];
                 ++k)
              {
                std::array<double, n>         S_k;
                std::array<Tensor<1, dim>, n> G_k;
                support_of.compute(k, cell_data, with_forces, S_k, G_k);
                const std::integral_constant<unsigned int, n> n_entries;
                mass_momentum.point(
                  k, cell_node.data(), S_k.data(), G_k.data(), n_entries);
                if (with_forces)
                  force.point(
                    k, cell_node.data(), S_k.data(), G_k.data(), n_entries);
                const double M = mass_column[k];
                if (with_full_mass) // m̃ = SᵀMS (1.9)
                  for (unsigned int i = 0; i < n; ++i)
                    {
                      const double MS_i = M * S_k[i];
                      for (unsigned int j = 0; j < n; ++j)
                        local_full_mass[i * n + j] += MS_i * S_k[j];
                    }
              }
            add_cell_full_mass(n, cell_node.data());
            continue;
          }
        const auto        &cell_data = transfer.cell_data(points.cell_index[c]);
        const unsigned int first_point = points.cell_point_begin[c];
        const unsigned int end_point   = points.cell_point_begin[c + 1];
        // m̃ of the cell over the union of its points' supports: computed
        // supports have the cell's nodes, in the order of the entries.
        const unsigned int *cell_node_list = cell_data.local_index.data();
        unsigned int        n_cell_nodes   = GridTransfer<dim>::n_nodes;
        unsigned int        first_entry    = 0;
        if (!supports.implicit_classic)
          {
            first_entry = supports.support_begin[first_point];
            if (with_full_mass || material_full_mass)
              {
                const unsigned int entry_end =
                  supports.support_begin[end_point];
                cell_nodes.clear();
                slot.resize(entry_end - first_entry);
                for (unsigned int j = first_entry; j < entry_end; ++j)
                  {
                    const auto place      = std::find(cell_nodes.begin(),
                                                 cell_nodes.end(),
                                                 cached_node[j]);
                    slot[j - first_entry] = place - cell_nodes.begin();
                    if (place == cell_nodes.end())
                      cell_nodes.push_back(cached_node[j]);
                  }
                cell_node_list = cell_nodes.data();
                n_cell_nodes   = cell_nodes.size();
              }
          }
        // A large union against the points' supports (GIMP, CPDI): m̃ of
        // the cell kept as those supports.
        const bool factored =
          !supports.implicit_classic &&
          CellwiseMatrix::factored_is_cheaper(
            n_cell_nodes, supports.support_begin[end_point] - first_entry);
        const bool factored_total =
          factored && with_full_mass && use_cellwise_full_mass;
        const bool factored_material = factored && material_full_mass;
        if (factored_total)
          cellwise_full_mass.begin_factored_cell(n_cell_nodes, cell_node_list);
        else if (with_full_mass)
          local_full_mass.assign(n_cell_nodes * n_cell_nodes, 0.);
        for (unsigned int k = first_point; k < end_point; ++k)
          support_of.visit(
            k,
            cell_data,
            with_gradients,
            [&](const unsigned int *const   node,
                const double *const         S,
                const Tensor<1, dim> *const G,
                const auto                  n_entries) DEAL_II_ALWAYS_INLINE {
              constexpr bool computed =
                !std::is_same_v<std::decay_t<decltype(n_entries)>,
                                unsigned int>;
              const unsigned int *const entry_slot =
                computed ?
                  nullptr :
                  slot.data() + (supports.support_begin[k] - first_entry);
              auto place_of = [&](const unsigned int j) {
                if constexpr (computed)
                  return j;
                else
                  return entry_slot[j];
              };
              const double M = mass_column[k];
              // m = SᵀM (Eq. 1.6), p = SᵀMV, f = −Σ V σ G + Σ S (M b + F)
              // (Eq. 2.11, τ/ρ₀ M = σ V; F the traction force); with
              // contact m^α, p^α0, f^α0 of the point's material (Eqs. 5,
              // 29) and its geometry (Eq. 11), m and p their sums after the
              // sweep.
              if (!contact)
                {
                  mass_momentum.point(k, node, S, G, n_entries);
                  if (with_forces)
                    force.point(k, node, S, G, n_entries);
                }
              else
                {
                  if (with_forces)
                    material_force.point(k, node, S, G, n_entries);
                  material_mass_momentum.point(k, node, S, G, n_entries);
                  contact_geometry.add_point(
                    k, supports.material[k], node, S, G, n_entries);
                }
              if constexpr (!computed)
                {
                  if (factored_total)
                    cellwise_full_mass.add_point(M, n_entries, entry_slot, S);
                  if (factored_material)
                    {
                      const unsigned int alpha = supports.material[k];
                      CellwiseMatrix    &m_tilde_alpha =
                        (*material_full_mass_matrices)[alpha];
                      if (!material_in_cell[alpha])
                        {
                          m_tilde_alpha.begin_factored_cell(n_cell_nodes,
                                                            cell_node_list);
                          material_in_cell[alpha] = 1;
                        }
                      m_tilde_alpha.add_point(M, n_entries, entry_slot, S);
                    }
                }
              if (with_full_mass && !factored_total) // m̃ = SᵀMS (1.9)
                for (unsigned int i = 0; i < n_entries; ++i)
                  {
                    const double MS_i = M * S[i];
                    double *row = &local_full_mass[place_of(i) * n_cell_nodes];
                    for (unsigned int j = 0; j < n_entries; ++j)
                      row[place_of(j)] += MS_i * S[j];
                  }
              if (material_full_mass && !factored_material) // m̃^α of α
                {
                  const unsigned int   alpha = supports.material[k];
                  std::vector<double> &local = local_material_mass[alpha];
                  if (!material_in_cell[alpha])
                    {
                      local.assign(n_cell_nodes * n_cell_nodes, 0.);
                      material_in_cell[alpha] = 1;
                    }
                  for (unsigned int i = 0; i < n_entries; ++i)
                    {
                      const double MS_i = M * S[i];
                      double      *row  = &local[place_of(i) * n_cell_nodes];
                      for (unsigned int j = 0; j < n_entries; ++j)
                        row[place_of(j)] += MS_i * S[j];
                    }
                }
            });
        if (material_full_mass)
          for (unsigned int a = 0; a < n_materials; ++a)
            if (material_in_cell[a])
              {
                if (!factored_material)
                  (*material_full_mass_matrices)[a].add_cell(
                    n_cell_nodes,
                    cell_node_list,
                    local_material_mass[a].data());
                material_in_cell[a] = 0;
              }
        if (!factored_total)
          add_cell_full_mass(n_cell_nodes, cell_node_list);
      }

    if (contact)
      {
        // m = Σ_α m^α, p = Σ_α p^α, f = Σ_α f^α0.
        centre_of_mass.set_to_sum(material_fields, true, true, with_forces);
      }
    centre_of_mass.mass.compress(VectorOperation::add);
    centre_of_mass.momentum.compress(VectorOperation::add);
    if (with_forces)
      centre_of_mass.force.compress(VectorOperation::add);
    if (assemble_full)
      full_mass_matrix.compress(VectorOperation::add);
    centre_of_mass.mass.update_ghost_values();
    for (auto &field : material_fields)
      {
        field.mass.compress(VectorOperation::add);
        field.momentum.compress(VectorOperation::add);
        if (with_forces)
          field.force.compress(VectorOperation::add);
        this->contact->compress_geometry(field);
        field.mass.update_ghost_values();
        field.computed.fill(false);
      }
    mass_matrix->setup();
  }



  template <int dim>
  bool
  Simulator<dim>::re_extrapolates_in_particle_update() const
  {
    return parameters.method.strain_update_scheme.update_last &&
           parameters.method.strain_update_scheme.re_extrapolate;
  }



  template <int dim>
  void
  Simulator<dim>::finish_re_extrapolation()
  {
    // The tail of the re-extrapolation the particle update made: with
    // contact p = Σ_α p^α (Eq. 6); the ghosts added (with contact also of
    // g^α, Σ S M X, u^α, V^α where read).
    TimerOutput::Scope timer(computing_timer, "particles to grid");
    if (contact_active())
      {
        this->contact->invalidate_geometry(false);
        centre_of_mass.set_to_sum(this->contact->material_fields(),
                                  false,
                                  true,
                                  false);
      }
    centre_of_mass.momentum.compress(VectorOperation::add);
    if (contact_active())
      for (auto &field : this->contact->material_fields())
        {
          field.momentum.compress(VectorOperation::add);
          this->contact->compress_geometry(field);
          field.computed.fill(false);
        }
  }



  template <int dim>
  void
  Simulator<dim>::sort_particles_into_cells()
  {
    TimerOutput::Scope timer(computing_timer, "sort points into cells");
    // The points that left their cells, to their new cells nearby (on this
    // rank or their new owner's); else deal.II's sort of every point (a
    // point not found nearby or outside the mesh: it reports lost points).
    if (parameters.fast_point_sorting && point_sort.sort(points))
      return;
    point_sort.prepare_full_sort(points);
    points_to_handler();
    particle_handler.sort_particles_into_subdomains_and_cells();
    points_from_handler();
  }

  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
