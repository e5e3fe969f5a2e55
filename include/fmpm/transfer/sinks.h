// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_transfer_sinks_h
#define fmpm_transfer_sinks_h

#include <deal.II/base/config.h>
#include <fmpm/external_loads.h>
#include <fmpm/grid_transfer.h>
#include <fmpm/grid_vectors.h>
#include <fmpm/material_points.h>
#include <fmpm/particle_properties.h>
#include <fmpm/support_cache.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/base/tensor.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <algorithm>
#include <type_traits>
#include <vector>

namespace fmpm
{
  /**
   * @brief The sinks of the particle–grid passes: what one point adds to
   * grid vectors from its support entries j < n (node[j], S[j], G[j]).
   *
   * Each sink has point(k, node, S, G, n) (inlined, no virtual call); the
   * count n is an `unsigned int` for stored supports and a compile-time
   * constant for computed ones, so that S and G stay in registers. A sink
   * reads the store's columns through pointers taken once per pass.
   * Transfer::for_each_point() (point_loop.h) calls them; a sink with
   * begin_cell(c)/end_cell(c) is also told where each cell of points
   * begins and ends.
   */
  namespace Transfer
  {
    using namespace dealii;

    /**
     * @brief m += M S (with @p with_mass) and p += (M V) S (Eq. 1.6,
     * m = SᵀM, p = SᵀMV), over the point's entries in entry order.
     */
    template <int dim, bool with_mass = true>
    struct MassMomentumSink
    {
      /** Targets @p m (unused without mass) and @p p[d] (raw views of the
       * ghosted grid vectors); M and V from @p points. */
      MassMomentumSink(const MaterialPoints<dim> &points,
                       double *const              m,
                       double *const *const       p)
        : mass(points.column(PropertyIndex<dim>::mass))
        , m(m)
      {
        for (unsigned int d = 0; d < dim; ++d)
          {
            velocity[d] = points.column(PropertyIndex<dim>::velocity + d);
            this->p[d]  = p[d];
          }
      }

      template <typename Count>
      DEAL_II_ALWAYS_INLINE void
      point(const unsigned int        k,
            const unsigned int *const node,
            const double *const       S,
            const Tensor<1, dim> *,
            const Count n) const
      {
        const double M = mass[k];
        double       MV[dim];
        for (unsigned int d = 0; d < dim; ++d)
          MV[d] = M * velocity[d][k];
        for (unsigned int j = 0; j < n; ++j)
          {
            const unsigned int i = node[j];
            if constexpr (with_mass)
              m[i] += M * S[j];
            for (unsigned int d = 0; d < dim; ++d)
              p[d][i] += MV[d] * S[j];
          }
      }

      const double *mass;
      const double *velocity[dim];
      double       *m;
      double       *p[dim];
    };

    /**
     * @brief The nodal force (Eq. 2.11): f_a += M S b_a − V Σ_c σ_ac G_c
     * with the point's body acceleration b (tractions included; g unless
     * the loads depend on the point). Without b the body term is left out
     * (the same bits, M S ≥ 0).
     *
     * @tparam hoop axisymmetric (2D, per radian): also the hoop force
     * f_r −= V σ_θθ T on the radial component (Nairn and Guilkey 2015,
     * GIMP_Theory Eq. 5.13), T the support's hoop function in the
     * SupportCache (read_hoop_function()) for stored supports, S/r_p for
     * computed classic ones.
     */
    template <int dim, bool hoop = false>
    struct ForceSink
    {
      /** Targets @p f[d]; M, V and σ from @p points; b from @p loads. */
      ForceSink(const MaterialPoints<dim> &points,
                ExternalLoads<dim>        &loads,
                double *const *const       f)
        : points(&points)
        , loads(&loads)
        , mass(points.column(PropertyIndex<dim>::mass))
        , volume(points.column(PropertyIndex<dim>::volume))
        , gravity(loads.gravity())
        , uniform_body_force(!loads.has_point_body_force())
      {
        for (unsigned int c = 0; c < 6; ++c)
          stress[c] = points.column(PropertyIndex<dim>::stress + c);
        for (unsigned int d = 0; d < dim; ++d)
          this->f[d] = f[d];
      }

      template <typename Count>
      DEAL_II_ALWAYS_INLINE void
      point(const unsigned int          k,
            const unsigned int *const   node,
            const double *const         S,
            const Tensor<1, dim> *const G,
            const Count                 n) const
      {
        const double M = mass[k];
        const double V = volume[k];
        // The dim x dim block of σ from the six stress columns.
        double sigma[dim][dim];
        for (unsigned int c = 0; c < 6; ++c)
          if (stress_component_i[c] < dim && stress_component_j[c] < dim)
            sigma[stress_component_i[c]][stress_component_j[c]] =
              sigma[stress_component_j[c]][stress_component_i[c]] =
                stress[c][k];
        const Tensor<1, dim> b =
          uniform_body_force ? gravity : loads->acceleration(*points, k);
        if (b.norm_square() == 0)
          for (unsigned int j = 0; j < n; ++j)
            for (unsigned int a = 0; a < dim; ++a)
              {
                double f_a = 0.;
                for (unsigned int c = 0; c < dim; ++c)
                  f_a -= V * sigma[a][c] * G[j][c];
                f[a][node[j]] += f_a;
              }
        else
          for (unsigned int j = 0; j < n; ++j)
            for (unsigned int a = 0; a < dim; ++a)
              {
                double f_a = M * S[j] * b[a];
                for (unsigned int c = 0; c < dim; ++c)
                  f_a -= V * sigma[a][c] * G[j][c];
                f[a][node[j]] += f_a;
              }
        if constexpr (hoop)
          {
            const double V_sigma_hoop = V * stress[2][k];
            if constexpr (std::is_same_v<Count, unsigned int>)
              {
                // Stored: T_j at the index of S_j in the cache (read here:
                // the builder may grow the cache during the loop).
                const double *const T =
                  hoop_cache->T.data() + (S - hoop_cache->S.data());
                for (unsigned int j = 0; j < n; ++j)
                  f[0][node[j]] -= V_sigma_hoop * T[j];
              }
            else
              {
                // Computed classic supports: T_j = S_j / r_p (the bits
                // the builder stores).
                const double inverse_r = 1 / points->position[k][0];
                for (unsigned int j = 0; j < n; ++j)
                  f[0][node[j]] -= V_sigma_hoop * (S[j] * inverse_r);
              }
          }
      }

      /** The entries' hoop function T (hoop only). */
      void
      read_hoop_function(const SupportCache<dim> &cache)
      {
        hoop_cache = &cache;
      }

      const SupportCache<dim>   *hoop_cache = nullptr;
      const MaterialPoints<dim> *points;
      ExternalLoads<dim>        *loads;
      const double              *mass, *volume, *stress[6];
      Tensor<1, dim>             gravity;
      bool                       uniform_body_force;
      double                    *f[dim];
    };

    /**
     * @brief Routes a point to the sink of its material α (contact: m^α,
     * p^α, f^α of seed 004 Eqs. 5, 29); one sink per material, made once
     * per pass.
     */
    template <typename Sink>
    struct PerMaterial
    {
      /** @p material: each point's material index (SupportCache). */
      explicit PerMaterial(const unsigned char *const material)
        : material(material)
      {}

      template <typename Count, int dim>
      DEAL_II_ALWAYS_INLINE void
      point(const unsigned int          k,
            const unsigned int *const   node,
            const double *const         S,
            const Tensor<1, dim> *const G,
            const Count                 n) const
      {
        sinks[material[k]].point(k, node, S, G, n);
      }

      const unsigned char *material;
      std::vector<Sink>    sinks;
    };

    /**
     * @brief A sink switched on or off for a whole pass (e.g. the force
     * without forces): one predictable branch per point.
     */
    template <typename Sink>
    struct IfActive
    {
      IfActive(const Sink &sink, const bool active)
        : sink(sink)
        , active(active)
      {}

      template <typename Count, int dim>
      DEAL_II_ALWAYS_INLINE void
      point(const unsigned int          k,
            const unsigned int *const   node,
            const double *const         S,
            const Tensor<1, dim> *const G,
            const Count                 n) const
      {
        if (active)
          sink.point(k, node, S, G, n);
      }

      const Sink &sink;
      const bool  active;
    };

    /**
     * @brief The full mass matrix cell by cell, m̃_c = Σ_{p in c} M S Sᵀ
     * (Eq. 1.9), and with contact m̃^α_c of each material α (seed 004 Eq.
     * 37), over the union of the cell's points' supports: a dense local
     * matrix into a CellwiseMatrix or the assembled Trilinos matrix, or for
     * a large union (GIMP, CPDI) the points' supports themselves
     * (CellwiseMatrix::begin_factored_cell()).
     *
     * Computed supports (the cell's own nodes) are added point by point;
     * stored ones at the end of the cell from the cache (the cell's entries
     * are complete then, also when the loop builds them), in the same
     * order: point by point, entry by entry.
     */
    template <int dim>
    class FullMassCellSink
    {
    public:
      /** Where m̃ goes: @p cellwise or @p assembled (with @p partitioner to
       * name its rows) or neither; m̃^α into @p material (one per
       * material) or not. */
      struct Targets
      {
        CellwiseMatrix                    *cellwise    = nullptr;
        TrilinosWrappers::SparseMatrix    *assembled   = nullptr;
        const Utilities::MPI::Partitioner *partitioner = nullptr;
        std::vector<CellwiseMatrix>       *material    = nullptr;
      };

      /** @p n_local_nodes: the ghosted grid vectors' local size. */
      FullMassCellSink(const MaterialPoints<dim> &points,
                       const SupportCache<dim>   &supports,
                       const GridTransfer<dim>   &transfer,
                       const Targets             &targets,
                       const unsigned int         n_local_nodes)
        : points(points)
        , supports(supports)
        , transfer(transfer)
        , targets(targets)
        , mass(points.column(PropertyIndex<dim>::mass))
        , total(targets.cellwise != nullptr || targets.assembled != nullptr)
        , computed(supports.implicit_classic)
        , local_material(targets.material ? targets.material->size() : 0)
        , material_in_cell(local_material.size(), 0)
        , slot_of_node((targets.cellwise != nullptr ||
                        targets.assembled != nullptr ||
                        targets.material != nullptr) &&
                           !supports.implicit_classic ?
                         n_local_nodes :
                         0,
                       numbers::invalid_unsigned_int)
      {}

      /** Whether m̃ or m̃^α is formed at all. */
      bool
      active() const
      {
        return total || targets.material != nullptr;
      }

      void
      begin_cell(const unsigned int c)
      {
        if (computed && active())
          {
            n_cell_nodes = GridTransfer<dim>::n_nodes;
            cell_node =
              transfer.cell_data(points.cell_index[c]).local_index.data();
            if (total)
              local.assign(n_cell_nodes * n_cell_nodes, 0.);
          }
      }

      template <typename Count>
      DEAL_II_ALWAYS_INLINE void
      point(const unsigned int k,
            const unsigned int *,
            const double *const S,
            const Tensor<1, dim> *,
            const Count n)
      {
        // (Stored supports: at the cell's end.)
        if constexpr (!std::is_same_v<Count, unsigned int>)
          {
            if (total)
              add_dense(local, mass[k], n, S, [](const unsigned int j) {
                return j;
              });
            if (targets.material != nullptr)
              add_dense(material_matrix(k), mass[k], n, S, [](auto j) {
                return j;
              });
          }
      }

      void
      end_cell(const unsigned int c)
      {
        if (!active())
          return;
        bool factored_total = false, factored_material = false;
        if (!computed)
          stored_cell(c, factored_total, factored_material);
        if (targets.material != nullptr)
          for (unsigned int a = 0; a < material_in_cell.size(); ++a)
            if (material_in_cell[a])
              {
                if (!factored_material)
                  (*targets.material)[a].add_cell(n_cell_nodes,
                                                  cell_node,
                                                  local_material[a].data());
                material_in_cell[a] = 0;
              }
        if (!factored_total)
          add_total_cell();
      }

    private:
      /** row(place(i)) += M S_i S_j over the point's entries (Eq. 1.9). */
      template <typename Count, typename Place>
      DEAL_II_ALWAYS_INLINE void
      add_dense(std::vector<double> &matrix,
                const double         M,
                const Count          n,
                const double *const  S,
                const Place         &place) const
      {
        for (unsigned int i = 0; i < n; ++i)
          {
            const double MS_i = M * S[i];
            double      *row  = &matrix[place(i) * n_cell_nodes];
            for (unsigned int j = 0; j < n; ++j)
              row[place(j)] += MS_i * S[j];
          }
      }

      /** The local m̃^α of point @p k's material (zeroed at its first
       * point in the cell). */
      std::vector<double> &
      material_matrix(const unsigned int k)
      {
        const unsigned int alpha = supports.material[k];
        if (!material_in_cell[alpha])
          {
            local_material[alpha].assign(n_cell_nodes * n_cell_nodes, 0.);
            material_in_cell[alpha] = 1;
          }
        return local_material[alpha];
      }

      /** The cell's nodes (the union of its points' supports, in the order
       * of the entries), the place of each entry in them, and the cell's
       * points added. */
      void
      stored_cell(const unsigned int c,
                  bool              &factored_total,
                  bool              &factored_material)
      {
        const unsigned int first_point = points.cell_point_begin[c];
        const unsigned int end_point   = points.cell_point_begin[c + 1];
        const unsigned int first_entry = supports.support_begin[first_point];
        const unsigned int entry_end   = supports.support_begin[end_point];
        cell_nodes.clear();
        slot.resize(entry_end - first_entry);
        // Slots in the order of first appearance (a node's slot looked up
        // in slot_of_node, reset after the cell).
        for (unsigned int j = first_entry; j < entry_end; ++j)
          {
            unsigned int &place = slot_of_node[supports.node[j]];
            if (place == numbers::invalid_unsigned_int)
              {
                place = cell_nodes.size();
                cell_nodes.push_back(supports.node[j]);
              }
            slot[j - first_entry] = place;
          }
        for (const unsigned int node : cell_nodes)
          slot_of_node[node] = numbers::invalid_unsigned_int;
        cell_node    = cell_nodes.data();
        n_cell_nodes = cell_nodes.size();
        const bool factored =
          CellwiseMatrix::factored_is_cheaper(n_cell_nodes,
                                              entry_end - first_entry);
        factored_total    = factored && targets.cellwise != nullptr;
        factored_material = factored && targets.material != nullptr;
        if (factored_total)
          targets.cellwise->begin_factored_cell(n_cell_nodes, cell_node);
        else if (total)
          local.assign(n_cell_nodes * n_cell_nodes, 0.);
        for (unsigned int k = first_point; k < end_point; ++k)
          {
            const unsigned int        begin = supports.support_begin[k];
            const unsigned int        n = supports.support_begin[k + 1] - begin;
            const unsigned int *const entry_slot =
              slot.data() + (begin - first_entry);
            const double *const S     = supports.S.data() + begin;
            const double        M     = mass[k];
            const auto          place = [entry_slot](const unsigned int j) {
              return entry_slot[j];
            };
            if (factored_total)
              targets.cellwise->add_point(M, n, entry_slot, S);
            if (factored_material)
              {
                const unsigned int alpha         = supports.material[k];
                CellwiseMatrix    &m_tilde_alpha = (*targets.material)[alpha];
                if (!material_in_cell[alpha])
                  {
                    m_tilde_alpha.begin_factored_cell(n_cell_nodes, cell_node);
                    material_in_cell[alpha] = 1;
                  }
                m_tilde_alpha.add_point(M, n, entry_slot, S);
              }
            if (total && !factored_total)
              add_dense(local, M, n, S, place);
            if (targets.material != nullptr && !factored_material)
              add_dense(material_matrix(k), M, n, S, place);
          }
      }

      /** The cell's m̃ into the cell-wise or the assembled matrix. */
      void
      add_total_cell()
      {
        if (targets.cellwise != nullptr)
          targets.cellwise->add_cell(n_cell_nodes, cell_node, local.data());
        else if (targets.assembled != nullptr)
          {
            dofs.resize(n_cell_nodes);
            for (unsigned int i = 0; i < n_cell_nodes; ++i)
              dofs[i] = targets.partitioner->local_to_global(cell_node[i]);
            for (unsigned int i = 0; i < n_cell_nodes; ++i)
              targets.assembled->add(dofs[i],
                                     n_cell_nodes,
                                     dofs.data(),
                                     &local[i * n_cell_nodes]);
          }
      }

      const MaterialPoints<dim> &points;
      const SupportCache<dim>   &supports;
      const GridTransfer<dim>   &transfer;
      const Targets              targets;
      const double *const        mass;
      const bool                 total;
      const bool                 computed;

      unsigned int                     n_cell_nodes = 0;
      const unsigned int              *cell_node    = nullptr;
      std::vector<unsigned int>        cell_nodes, slot;
      std::vector<double>              local;
      std::vector<std::vector<double>> local_material;
      std::vector<char>                material_in_cell;
      /** Each local node's slot in the cell being added (invalid: none). */
      std::vector<unsigned int>            slot_of_node;
      std::vector<types::global_dof_index> dofs;
    };
  } // namespace Transfer
} // namespace fmpm

#endif
