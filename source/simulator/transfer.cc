// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The particle-grid passes of the time step: the support cache (S, G of
// every point, once per step), extrapolations to the grid (Sᵀ, Gᵀ), the
// particle update (S) and the strain update (G, with the kinematics of
// transfer/kinematics.h), and the re-sorting of moved points into cells
// (PointSort). Every pass loops over the support cache.

#include <fmpm/simulator.h>
#include <fmpm/transfer/kinematics.h>
#include <fmpm/transfer/sinks.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace fmpm
{
  namespace
  {
    /** Points per batch of the strain update (constitutive model calls). */
    constexpr unsigned int stress_batch_size =
      ConstitutiveModel::StressUpdateInputs::capacity;
  } // namespace



  template <int dim>
  template <typename... Text>
  void
  Simulator<dim>::report_point_failure(const unsigned int       k,
                                       const FailedPoint::Cause cause,
                                       const Text &...text)
  {
    if (!local_failure.empty())
      return;
    std::ostringstream message;
    switch (cause)
      {
        case FailedPoint::Cause::support_outside_patch:
          message << "the domain of ";
          break;
        case FailedPoint::Cause::velocity_not_finite:
          message << "velocity of ";
          break;
        case FailedPoint::Cause::stress_not_finite:
          message << "stress of ";
          break;
        default:
          break;
      }
    message << "material point " << points.id[k] << " at ("
            << points.position[k] << ") ";
    (message << ... << text);
    local_failure            = message.str();
    local_failed_point.cause = cause;
    local_failed_point.id    = points.id[k];
    for (unsigned int d = 0; d < dim; ++d)
      local_failed_point.position[d] = points.position[k][d];
  }



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
  Simulator<dim>::update_particles()
  {
    TimerOutput::Scope timer(computing_timer, "particle update");
    using Index = PropertyIndex<dim>;

    unsigned int fields[ParticleUpdate::n_grid_fields];
    unsigned int n_fields = 0;
    using FieldViews      = std::array<std::array<const double *, dim>,
                                  ParticleUpdate::n_grid_fields>;
    // The fields of the centre of mass, or with contact of each material
    // (the point reads its material's field, Eq. 32).
    const bool              contact = contact_active();
    std::vector<FieldViews> views(
      contact ? this->contact->material_fields().size() : 1);
    const auto &needed = active_fields();
    for (unsigned int f = 0; f < ParticleUpdate::n_grid_fields; ++f)
      if (needed[f])
        {
          fields[n_fields++] = f;
          for (unsigned int a = 0; a < views.size(); ++a)
            for (unsigned int d = 0; d < dim; ++d)
              views[a][f][d] =
                (contact ? this->contact->material_fields()[a].fields[f] :
                           centre_of_mass.fields[f])
                  .block(d)
                  .begin();
        }

    // Periodic FMPM(k): FLIP in the lumped steps between the series.
    ParticleUpdate::Interface<dim> &update = active_update();
    ParticleUpdate::Batch<dim>      batch;
    batch.time_step = control.time_step();
    point_sort.clear();
    const bool   track_dissipation = parameters.output.track_dissipation;
    const double grid_damping      = parameters.method.grid_damping;
    const double particle_damping  = parameters.method.particle_damping;
    std::vector<Tensor<1, dim>> old_velocity, damping_velocity;
    std::vector<Point<dim>>     old_position;
    double                      max_V2 = 0;
    const bool has_moving_walls        = velocity_conditions.has_moving_boxes();
    SupportReader<dim> support_of(supports, transfer, points.cell.data());
    double            *velocity_column[dim];
    for (unsigned int d = 0; d < dim; ++d)
      velocity_column[d] = points.column(Index::velocity + d);
    const double *const mass_column = points.column(Index::mass);
    // USL+/USAVG+: p = SᵀMV^{n+1} in this sweep, into momentum_target[d]
    // (with contact p^α of the point's material α: [α dim + d], and what
    // the normals and laws read of the moved points).
    const bool re_extrapolate = re_extrapolates_in_particle_update();
    Contact::GeometrySink<dim>        no_contact_geometry;
    const Contact::GeometrySink<dim> &contact_geometry =
      re_extrapolate && contact ? this->contact->begin_geometry(points) :
                                  no_contact_geometry;
    double *p[dim] = {};
    if (re_extrapolate && !contact)
      {
        centre_of_mass.momentum = 0;
        for (unsigned int d = 0; d < dim; ++d)
          p[d] = centre_of_mass.momentum.block(d).begin();
      }
    const Transfer::MassMomentumSink<dim, false> momentum(points, nullptr, p);
    Transfer::PerMaterial<Transfer::MassMomentumSink<dim, false>>
      material_momentum(supports.material.data());
    if (re_extrapolate && contact)
      for (auto &field : this->contact->material_fields())
        {
          field.momentum = 0;
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = field.momentum.block(d).begin();
          material_momentum.sinks.emplace_back(points, nullptr, p);
        }

    // Point k's share of p = SᵀMV^{n+1} (Eq. 5 with contact) and of the
    // contact geometry once its V and X are final (in the store): the
    // operations of particles_to_grid().
    const auto re_extrapolate_point =
      [&](const unsigned int k, const auto &data) DEAL_II_ALWAYS_INLINE {
        support_of.visit(
          k,
          data,
          contact_geometry.needs_gradients(),
          [&](const unsigned int *const   node,
              const double *const         S,
              const Tensor<1, dim> *const G,
              const auto                  n_entries) DEAL_II_ALWAYS_INLINE {
            if (contact)
              {
                material_momentum.point(k, node, S, G, n_entries);
                contact_geometry.add_point(
                  k, supports.material[k], node, S, G, n_entries);
              }
            else
              momentum.point(k, node, S, G, n_entries);
          });
      };

    // One batch per cell with points (the plugin's virtual call per batch).
    for (unsigned int c = 0; c < points.n_cells(); ++c)
      {
        const unsigned int first_point = points.cell_point_begin[c];
        const unsigned int n_points =
          points.cell_point_begin[c + 1] - first_point;
        const auto &data = transfer.cell_data(points.cell_index[c]);
        batch.resize(n_points);

        // Gather: V, X and the requested fields extrapolated with S.
        for (unsigned int q = 0; q < n_points; ++q)
          {
            const unsigned int k = first_point + q;
            for (unsigned int d = 0; d < dim; ++d)
              batch.velocity[q][d] = velocity_column[d][k];
            batch.position[q] = points.position[k];
            const FieldViews &field_values =
              views[contact ? supports.material[k] : 0];
            support_of.visit(
              k,
              data,
              false,
              [&](const unsigned int *const node,
                  const double *const       S,
                  const Tensor<1, dim> *,
                  const auto n_entries) {
                for (unsigned int field = 0; field < n_fields; ++field)
                  {
                    const unsigned int f = fields[field];
                    Kinematics::interpolate<dim>(node,
                                                 S,
                                                 0,
                                                 n_entries,
                                                 field_values[f].data(),
                                                 batch.grid[f][q]);
                  }
              });
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

        update.update(batch);

        // Damping (seed 003 Eqs. 1.21-1.25): the acceleration loses
        // A_damp = α_g S v + α_p V^(n); V^(n+1) -= A_damp Δt and, the
        // effective velocity being unchanged, X^(n+1) -= A_damp Δt²/2.
        if (grid_damping != 0 || particle_damping != 0)
          for (unsigned int q = 0; q < n_points; ++q)
            {
              Tensor<1, dim> A_damp;
              if (grid_damping != 0)
                A_damp +=
                  grid_damping * batch.grid[ParticleUpdate::velocity][q];
              if (particle_damping != 0)
                A_damp += particle_damping * (*V_n)[q];
              batch.velocity[q] -= A_damp * control.time_step();
              batch.position[q] -=
                A_damp * (0.5 * control.time_step() * control.time_step());
            }

        // Energy dissipated compared with non-dissipative FLIP (seed 003
        // Eqs. 1.44-1.45): M [A_g→p Δt·(V_g→p + A_g→p Δt/2) − ΔV·ΔX/Δt].
        if (track_dissipation)
          for (unsigned int q = 0; q < n_points; ++q)
            {
              const double         M = mass_column[first_point + q];
              const Tensor<1, dim> a_dt =
                batch.grid[ParticleUpdate::acceleration][q] *
                control.time_step();
              const Tensor<1, dim> &v_g =
                batch.grid[ParticleUpdate::velocity][q];
              const Tensor<1, dim> dV = batch.velocity[q] - old_velocity[q];
              const Tensor<1, dim> dX_dt =
                (batch.position[q] - old_position[q]) / control.time_step();
              local_dissipation += M * (a_dt * (v_g + 0.5 * a_dt) - dV * dX_dt);
            }

        // Scatter the new V and X, and the new reference location of each
        // point still in its cell (the batch has read its supports; later
        // passes of the step read the support cache's copy of ξ); the
        // others are re-binned at the step's end.
        for (unsigned int q = 0; q < n_points; ++q)
          {
            const unsigned int    k  = first_point + q;
            const Tensor<1, dim> &V  = batch.velocity[q];
            const double          V2 = V * V;
            if (!std::isfinite(V2))
              report_point_failure(k,
                                   FailedPoint::Cause::velocity_not_finite,
                                   "is not finite (NaN or Inf)");
            max_V2 = std::max(max_V2, V2);
            for (unsigned int d = 0; d < dim; ++d)
              velocity_column[d][k] = V[d];
            // Points do not enter a moving wall's box.
            if (has_moving_walls)
              velocity_conditions.push_out_of_walls(batch.position[q]);
            points.position[k] = batch.position[q];
            if (re_extrapolate)
              re_extrapolate_point(k, data);
            const Point<dim> xi =
              GridTransfer<dim>::reference_point(data,
                                                 batch.position[q],
                                                 points.reference_position[k]);
            if (GridTransfer<dim>::is_inside(xi))
              points.reference_position[k] = xi;
            else
              point_sort.left_cell(k);
          }
      }
    local_max_point_speed = std::sqrt(max_V2);
  }



  template <int dim>
  void
  Simulator<dim>::update_stresses(const ParticleUpdate::GridField field,
                                  const double                    dt,
                                  const bool                      with_forces)
  {
    // The velocities of the centre of mass, or with contact of the group's
    // material (Eq. 28); their solves time themselves.
    const bool contact = contact_active();
    if (contact)
      this->contact->compute_field(field);
    else
      compute_field(field);
    TimerOutput::Scope timer(computing_timer, "stress update");
    using Index                                 = PropertyIndex<dim>;
    const unsigned int              n_materials = constitutive_models.size();
    const DeformationGradientUpdate F_update =
      parameters.method.deformation_gradient_update;
    // The batch's entry arrays (zero: in 2D the out-of-plane entries stay
    // so).
    ConstitutiveModel::StressUpdateInputs  inputs;
    ConstitutiveModel::StressUpdateOutputs outputs;
    inputs.time_step = dt;
    Kinematics::BatchEntries dF, F_gathered;
    double                   wave_speed = 0;
    const double            *v_a[dim];
    auto                     view_velocities = [&](const GridVectorField &v) {
      for (unsigned int a = 0; a < dim; ++a)
        v_a[a] = v.block(a).begin();
    };
    view_velocities(centre_of_mass.fields[field]);
    SupportReader<dim> support_of(supports, transfer, points.cell.data());
    // Computed supports: S and G of the batch's points (by place in the
    // batch).
    constexpr unsigned int              n_nodes = GridTransfer<dim>::n_nodes;
    std::array<double, n_nodes>         batch_S[stress_batch_size];
    std::array<Tensor<1, dim>, n_nodes> batch_G[stress_batch_size];
    const unsigned int                 *batch_node[stress_batch_size];

    // USF/USAVG: f (and with contact f^α0, Eq. 29) from the new stresses
    // in this sweep, each batch's points in the store's order once their
    // stresses are updated.
    // (With contact f is set from the f^α0 after the sweep.)
    if (with_forces && !contact)
      centre_of_mass.force = 0;
    double *f[dim];
    for (unsigned int d = 0; d < dim; ++d)
      f[d] = centre_of_mass.force.block(d).begin();
    const Transfer::ForceSink<dim> force(points, external_loads, f);
    Transfer::PerMaterial<Transfer::ForceSink<dim>> material_force(
      supports.material.data());
    if (with_forces && contact)
      for (auto &material_field : this->contact->material_fields())
        {
          material_field.force = 0;
          double *f_alpha[dim];
          for (unsigned int d = 0; d < dim; ++d)
            f_alpha[d] = material_field.force.block(d).begin();
          material_force.sinks.emplace_back(points, external_loads, f_alpha);
        }

    // Cell sizes (Eq. 52's Δx) only for models that read them, by active
    // cell index for the cells with points.
    bool needs_cell_size = false;
    for (const auto &model : constitutive_models)
      needs_cell_size = needs_cell_size || model->needs_cell_size();
    if (needs_cell_size)
      {
        cell_size_by_index.resize(triangulation.n_active_cells());
        for (unsigned int c = 0; c < points.n_cells(); ++c)
          cell_size_by_index[points.cell_index[c]] =
            points.cell_iterator(c)->minimum_vertex_distance();
      }

    // Points of a batch grouped by material for the model call (one group
    // when the scene has one material).
    std::vector<std::vector<unsigned int>> by_material(n_materials);
    for (auto &group : by_material)
      group.reserve(stress_batch_size);
    unsigned int group_points[stress_batch_size];
    double       J_of_group[stress_batch_size];
    // F (row major) and σ in the store. In 2D (plane strain) only the 2x2
    // block and F_33 of F, and σ_xx, σ_yy, σ_zz, σ_xy are stored: the other
    // entries are zero and are not written.
    double                *F_column[9], *stress_column[6];
    constexpr unsigned int n_stress_entries = dim == 3 ? 6 : 4;
    for (unsigned int c = 0; c < 9; ++c)
      F_column[c] = points.column(Index::deformation_gradient + c);
    for (unsigned int c = 0; c < 6; ++c)
      stress_column[c] = points.column(Index::stress + c);
    double *const energy_column = points.column(Index::strain_energy_density);
    double *const volume_column = points.column(Index::volume);
    const double *const initial_volume_column =
      points.column(Index::initial_volume);

    for (unsigned int batch_begin = 0; batch_begin < supports.n_points();
         batch_begin += stress_batch_size)
      {
        const unsigned int batch_end =
          std::min(batch_begin + stress_batch_size, supports.n_points());
        if (n_materials > 1)
          {
            for (unsigned int m = 0; m < n_materials; ++m)
              by_material[m].clear();
            for (unsigned int k = batch_begin; k < batch_end; ++k)
              by_material[supports.material[k]].push_back(k);
          }

        for (unsigned int m = 0; m < n_materials; ++m)
          {
            const unsigned int n_group = n_materials == 1 ?
                                           batch_end - batch_begin :
                                           by_material[m].size();
            if (n_group == 0)
              continue;
            if (n_materials == 1)
              std::iota(group_points, group_points + n_group, batch_begin);
            else
              std::copy(by_material[m].begin(),
                        by_material[m].end(),
                        group_points);
            // (one material: the batch, stored one after another)
            const unsigned int k0 = group_points[0];
            const bool         contiguous =
              group_points[n_group - 1] == k0 + n_group - 1;
            if (contact)
              view_velocities(
                this->contact->material_fields()[m].fields[field]);
            inputs.resize(n_group);
            inputs.reference_density = parameters.materials[m].density;
            if (constitutive_models[m]->needs_cell_size())
              for (unsigned int q = 0; q < n_group; ++q)
                inputs.cell_size[q] =
                  cell_size_by_index[points.cell[group_points[q]]];
            // L = ∇v = Σ_i v_i ⊗ G_pi (Eqs. 2.7, 2.18), plane strain in 2D;
            // σ^n, W^n and the history slots if the model reads them.
            for (unsigned int q = 0; q < n_group; ++q)
              {
                const unsigned int k = group_points[q];
                if (supports.implicit_classic)
                  {
                    // Computed once for L and the forces.
                    const unsigned int b = k - batch_begin;
                    const auto &cell     = transfer.cell_data(points.cell[k]);
                    support_of.compute(k, cell, true, batch_S[b], batch_G[b]);
                    batch_node[b] = cell.local_index.data();
                    Kinematics::velocity_gradient<dim>(
                      batch_node[b],
                      batch_G[b].data(),
                      0,
                      std::integral_constant<unsigned int, n_nodes>(),
                      v_a,
                      inputs.velocity_gradient,
                      q);
                  }
                else
                  support_of.visit(k,
                                   true,
                                   [&](const unsigned int *const node,
                                       const double *,
                                       const Tensor<1, dim> *const G,
                                       const auto                  n_entries) {
                                     Kinematics::velocity_gradient<dim>(
                                       node,
                                       G,
                                       0,
                                       n_entries,
                                       v_a,
                                       inputs.velocity_gradient,
                                       q);
                                   });
              }
            if (constitutive_models[m]->reads_old_state())
              {
                if (contiguous)
                  {
                    for (unsigned int c = 0; c < n_stress_entries; ++c)
                      std::copy(stress_column[c] + k0,
                                stress_column[c] + k0 + n_group,
                                inputs.old_stress[c]);
                    std::copy(energy_column + k0,
                              energy_column + k0 + n_group,
                              inputs.old_strain_energy_density);
                  }
                else
                  for (unsigned int q = 0; q < n_group; ++q)
                    {
                      const unsigned int k = group_points[q];
                      for (unsigned int c = 0; c < n_stress_entries; ++c)
                        inputs.old_stress[c][q] = stress_column[c][k];
                      inputs.old_strain_energy_density[q] = energy_column[k];
                    }
                for (unsigned int q = 0; q < n_group; ++q)
                  inputs.properties[q] = points.record(group_points[q]);
              }
            if (constitutive_models[m]->needs_old_volume_ratio())
              for (unsigned int q = 0; q < n_group; ++q)
                inputs.old_volume_ratio[q] =
                  volume_column[group_points[q]] /
                  initial_volume_column[group_points[q]];
            auto &F = inputs.deformation_gradient;
            auto &J = inputs.volume_ratio;
            if (F_update == DeformationGradientUpdate::cayley)
              {
                // F^n: the store's columns, or gathered for a group spread
                // over the batch (several materials).
                std::array<const double *, 9> F_old;
                for (unsigned int c = 0; c < 9; ++c)
                  if (contiguous)
                    F_old[c] = F_column[c] + k0;
                  else
                    {
                      for (unsigned int q = 0; q < n_group; ++q)
                        F_gathered[c][q] = F_column[c][group_points[q]];
                      F_old[c] = F_gathered[c];
                    }
                Kinematics::cayley_update<dim>(
                  n_group, dt, inputs.velocity_gradient, F_old, F, J);
              }
            else
              {
                Kinematics::increments<dim>(F_update,
                                            parameters.method,
                                            inputs.velocity_gradient,
                                            dt,
                                            n_group,
                                            dF);
                // F^{n+1} = ΔF F^n and J = det F^{n+1} (the operations of
                // deal.II's Tensor product and determinant()); in 2D on the
                // 2x2 block, F_33 kept (plane strain).
                for (unsigned int q = 0; q < n_group; ++q)
                  {
                    const unsigned int k = group_points[q];
                    if constexpr (dim == 2)
                      {
                        const double a = F_column[0][k], b = F_column[1][k],
                                     c = F_column[3][k], e = F_column[4][k];
                        F[0][q] = dF[0][q] * a + dF[1][q] * c;
                        F[1][q] = dF[0][q] * b + dF[1][q] * e;
                        F[3][q] = dF[3][q] * a + dF[4][q] * c;
                        F[4][q] = dF[3][q] * b + dF[4][q] * e;
                        F[8][q] = F_column[8][k];
                      }
                    else
                      for (unsigned int a = 0; a < 3; ++a)
                        for (unsigned int b = 0; b < 3; ++b)
                          F[3 * a + b][q] =
                            dF[3 * a][q] * F_column[b][k] +
                            dF[3 * a + 1][q] * F_column[3 + b][k] +
                            dF[3 * a + 2][q] * F_column[6 + b][k];
                  }
                for (unsigned int q = 0; q < n_group; ++q)
                  if constexpr (dim == 2)
                    // The same value without the plane-strain zeros' products.
                    J[q] = F[0][q] * (F[4][q] * F[8][q]) -
                           F[1][q] * (F[3][q] * F[8][q]);
                  else
                    {
                      const double C0 = F[4][q] * F[8][q] - F[5][q] * F[7][q];
                      const double C1 = F[5][q] * F[6][q] - F[3][q] * F[8][q];
                      const double C2 = F[3][q] * F[7][q] - F[4][q] * F[6][q];
                      J[q] = F[0][q] * C0 + F[1][q] * C1 + F[2][q] * C2;
                    }
              }
            for (unsigned int q = 0; q < n_group; ++q)
              if (!(J[q] > 0))
                report_point_failure(group_points[q],
                                     FailedPoint::Cause::inverted,
                                     "has an inverted deformation gradient, "
                                     "J = ",
                                     J[q]);

            outputs.failed_point = -1;
            constitutive_models[m]->update_stress(inputs, outputs);
            if (outputs.failed_point >= 0)
              report_point_failure(group_points[outputs.failed_point],
                                   FailedPoint::Cause::model_failure,
                                   outputs.failure);

            // F, σ, W and V = J V0 into the store (in 2D the plane-strain
            // zero entries are not stored; F_33 is unchanged).
            if (contiguous)
              {
                for (unsigned int c = 0; c < 9; ++c)
                  if (dim == 3 || c == 0 || c == 1 || c == 3 || c == 4)
                    std::copy(F[c], F[c] + n_group, F_column[c] + k0);
                for (unsigned int c = 0; c < n_stress_entries; ++c)
                  std::copy(outputs.cauchy_stress[c],
                            outputs.cauchy_stress[c] + n_group,
                            stress_column[c] + k0);
                std::copy(outputs.strain_energy_density,
                          outputs.strain_energy_density + n_group,
                          energy_column + k0);
                for (unsigned int q = 0; q < n_group; ++q)
                  {
                    volume_column[k0 + q] =
                      J[q] * initial_volume_column[k0 + q];
                    J_of_group[q] = J[q] > 0 ? J[q] : 1;
                  }
              }
            else
              for (unsigned int q = 0; q < n_group; ++q)
                {
                  const unsigned int k = group_points[q];
                  for (unsigned int c = 0; c < 9; ++c)
                    if (dim == 3 || c == 0 || c == 1 || c == 3 || c == 4)
                      F_column[c][k] = F[c][q];
                  for (unsigned int c = 0; c < n_stress_entries; ++c)
                    stress_column[c][k] = outputs.cauchy_stress[c][q];
                  energy_column[k] = outputs.strain_energy_density[q];
                  volume_column[k] = J[q] * initial_volume_column[k];
                  // Inverted points are reported above; they give no speed.
                  J_of_group[q] = J[q] > 0 ? J[q] : 1;
                }
            for (unsigned int q = 0; q < n_group; ++q)
              if (!std::isfinite(outputs.strain_energy_density[q]))
                report_point_failure(group_points[q],
                                     FailedPoint::Cause::stress_not_finite,
                                     "is not finite (NaN or Inf)");
            if (constitutive_models[m]->computes_wave_speed())
              for (unsigned int q = 0; q < n_group; ++q)
                wave_speed = std::max(wave_speed, outputs.wave_speed[q]);
            else
              wave_speed =
                std::max(wave_speed,
                         constitutive_models[m]->max_wave_speed(
                           parameters.materials[m].density,
                           ArrayView<const double>(J_of_group, n_group)));
          }
        // f of the batch's points from their new stresses, in the
        // store's order (with contact f^α0 of the point's material, Eq.
        // 29).
        if (with_forces)
          for (unsigned int k = batch_begin; k < batch_end; ++k)
            {
              auto add_force = [&](const unsigned int *const   node,
                                   const double *const         S,
                                   const Tensor<1, dim> *const G,
                                   const auto n_entries) DEAL_II_ALWAYS_INLINE {
                if (contact)
                  material_force.point(k, node, S, G, n_entries);
                else
                  force.point(k, node, S, G, n_entries);
              };
              if (supports.implicit_classic)
                {
                  const unsigned int b = k - batch_begin;
                  add_force(batch_node[b],
                            batch_S[b].data(),
                            batch_G[b].data(),
                            std::integral_constant<unsigned int, n_nodes>());
                }
              else
                support_of.visit(k, true, add_force);
            }
      }
    local_max_wave_speed = wave_speed;
    if (with_forces)
      {
        if (contact) // f = Σ_α f^α0
          centre_of_mass.set_to_sum(this->contact->material_fields(),
                                    false,
                                    false,
                                    true);
        centre_of_mass.force.compress(VectorOperation::add);
        if (contact)
          for (auto &material_field : this->contact->material_fields())
            material_field.force.compress(VectorOperation::add);
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
