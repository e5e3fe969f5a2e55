// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_transfer_point_loop_h
#define fmpm_transfer_point_loop_h

#include <fmpm/grid_transfer.h>
#include <fmpm/material_points.h>
#include <fmpm/support_cache.h>

#include <array>
#include <type_traits>
#include <utility>

namespace fmpm
{
  namespace Transfer
  {
    using namespace dealii;

    /**
     * @brief Support reader of for_each_point(): the entries stored in the
     * SupportCache (n an `unsigned int`).
     */
    template <int dim>
    class StoredSupports
    {
    public:
      explicit StoredSupports(const SupportCache<dim> &cache)
        : cache(cache)
      {}

      void
      begin_cell(const unsigned int)
      {}

      /** body(node, S, G, n) with point @p k's entries j < n. */
      template <typename Body>
      DEAL_II_ALWAYS_INLINE void
      visit(const unsigned int k, const Body &body) const
      {
        const unsigned int begin = cache.support_begin[k];
        body(cache.node.data() + begin,
             cache.S.data() + begin,
             cache.G.data() + begin,
             cache.support_begin[k + 1] - begin);
      }

    private:
      const SupportCache<dim> &cache;
    };

    /**
     * @brief Support reader of for_each_point(): implicit classic supports
     * computed from ξ on the point's affine cell (SupportReader::compute(),
     * the bits of stored entries); n is a compile-time constant, so that S
     * and G stay in registers.
     */
    template <int dim>
    class ComputedSupports
    {
    public:
      static constexpr unsigned int n_nodes = GridTransfer<dim>::n_nodes;

      /** G only if @p with_gradients. */
      ComputedSupports(const SupportCache<dim>   &cache,
                       const GridTransfer<dim>   &transfer,
                       const MaterialPoints<dim> &points,
                       const bool                 with_gradients)
        : reader(cache, transfer, points.cell.data())
        , transfer(transfer)
        , points(points)
        , with_gradients(with_gradients)
      {}

      void
      begin_cell(const unsigned int cell_number)
      {
        cell = &transfer.cell_data(points.cell_index[cell_number]);
      }

      template <typename Body>
      DEAL_II_ALWAYS_INLINE void
      visit(const unsigned int k, const Body &body) const
      {
        std::array<double, n_nodes>         S;
        std::array<Tensor<1, dim>, n_nodes> G;
        reader.compute(k, *cell, with_gradients, S, G);
        body(cell->local_index.data(),
             S.data(),
             G.data(),
             std::integral_constant<unsigned int, n_nodes>());
      }

    private:
      const SupportReader<dim>                    reader;
      const GridTransfer<dim>                    &transfer;
      const MaterialPoints<dim>                  &points;
      const bool                                  with_gradients;
      const typename GridTransfer<dim>::CellData *cell = nullptr;
    };

    namespace internal
    {
      template <typename Sink, typename = void>
      struct HasCellHooks : std::false_type
      {};
      template <typename Sink>
      struct HasCellHooks<
        Sink,
        std::void_t<decltype(std::declval<Sink &>().end_cell(0u))>>
        : std::true_type
      {};
    } // namespace internal

    /**
     * @brief One pass over the points of @p points in the store's order
     * (cell by cell, cell_point_begin), reading each point's support
     * entries from @p supports and handing them to every sink in turn:
     * sink.point(k, node, S, G, n), and sink.begin_cell(c) /
     * sink.end_cell(c) around each cell where a sink has them. Sinks and
     * reader are inlined: no virtual call per point.
     *
     * A reader has begin_cell(c) and visit(k, body) (StoredSupports,
     * ComputedSupports, or a reader that builds the supports as it goes).
     */
    template <int dim, typename Supports, typename... Sinks>
    void
    for_each_point(const MaterialPoints<dim> &points,
                   Supports                  &supports,
                   Sinks &...sinks)
    {
      for (unsigned int c = 0; c < points.n_cells(); ++c)
        {
          supports.begin_cell(c);
          (
            [&](auto &sink) {
              if constexpr (internal::HasCellHooks<
                              std::decay_t<decltype(sink)>>::value)
                sink.begin_cell(c);
            }(sinks),
            ...);
          for (unsigned int k = points.cell_point_begin[c];
               k < points.cell_point_begin[c + 1];
               ++k)
            supports.visit(k,
                           [&](const unsigned int *const   node,
                               const double *const         S,
                               const Tensor<1, dim> *const G,
                               const auto n) DEAL_II_ALWAYS_INLINE {
                             (sinks.point(k, node, S, G, n), ...);
                           });
          (
            [&](auto &sink) {
              if constexpr (internal::HasCellHooks<
                              std::decay_t<decltype(sink)>>::value)
                sink.end_cell(c);
            }(sinks),
            ...);
        }
    }
  } // namespace Transfer
} // namespace fmpm

#endif
