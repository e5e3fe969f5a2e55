// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_support_cache_h
#define fmpm_support_cache_h

#include <fmpm/grid_transfer.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include <algorithm>
#include <array>
#include <type_traits>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief Every locally owned material point of this step and its support:
   * the nodes i with S_ip and G_ip (seed 000 Eqs. 1.1, 2.8; S̄, Ḡ of seed 001
   * for GIMP/CPDI).
   *
   * Built once per step, at the positions of the step's start and in cell
   * order, for every shape function. Every pass of the step reads it
   * (through SupportReader): m, p, f and m̃ to the grid (Sᵀ, Gᵀ), the strain
   * update (G), the particle update (S) and the USL+/USAVG+
   * re-extrapolation. Classic supports on affine cells are computed from ξ
   * instead of stored (implicit_classic).
   *
   * Hanging nodes are resolved here: a constrained node i with
   * v_i = Σ_j c_ij v_j passes its weights to its masters (S_jp += c_ij S_ip,
   * G_jp += c_ij G_ip), so that every entry is a free node. Sᵀ through the
   * cache is then the condensed extrapolation and S the interpolation of
   * the distributed field, with no constraint logic in any pass.
   *
   * Point k of the cache is point k of the MaterialPoints store (its
   * cells and cell ranges are the store's) until the points are re-binned
   * at the end of the step.
   *
   * @tparam dim space dimension
   */
  template <int dim>
  struct SupportCache
  {
    /**
     * Classic shape functions with every cell of the points affine and free
     * of hanging nodes: no entry is stored. A pass computes S_ip and G_ip of
     * the cell's nodes from the point's reference location at the step's start
     * when it reads them, with the operations that would have filled the
     * entries (the same bits).
     */
    bool implicit_classic = false;
    /** ξ_p at the step's start (implicit classic supports only): the
     * store's own ξ when no pass after the particle update (which moves
     * it) reads the supports, else reference_position_copy. */
    const Point<dim>       *reference_position = nullptr;
    unsigned int            n_implicit_points  = 0;
    std::vector<Point<dim>> reference_position_copy;

    /** @name Per point, in the order of the point store */
    /** @{ */
    /** Material index of the point (filled with several materials only). */
    std::vector<unsigned char> material;
    /** The point's support is entries [support_begin[k], support_begin[k+1]).
     */
    std::vector<unsigned int> support_begin;
    /** @} */

    /** @name Per support entry
     * The first n_stored entries of each array; the arrays keep their size
     * from step to step (entries are written in place, make_room()).
     */
    /** @{ */
    /** Number of stored entries. */
    std::size_t n_stored = 0;
    /** Local index of the node in the ghosted grid vectors. */
    std::vector<unsigned int> node;
    /** S_ip. */
    std::vector<double> S;
    /** G_ip = ∇S_i(x_p). Units: 1/m. */
    std::vector<Tensor<1, dim>> G;
    /** T_ip, the hoop function of axisymmetric runs (at the index of S_ip;
     * sized by Transfer::SupportBuilder in those runs only, else empty).
     * Units: 1/m. */
    std::vector<double> T;
    /** @} */

    /** @brief Number of cached points. */
    unsigned int
    n_points() const
    {
      if (implicit_classic)
        return n_implicit_points;
      return support_begin.empty() ? 0 : support_begin.size() - 1;
    }

    /** @brief Number of support entries (computed or stored). */
    std::size_t
    n_entries(const unsigned int entries_per_implicit_point) const
    {
      return implicit_classic ?
               std::size_t(entries_per_implicit_point) * n_points() :
               n_stored;
    }

    /** @brief Forget everything (keeps the memory). */
    void
    clear()
    {
      implicit_classic   = false;
      reference_position = nullptr;
      n_implicit_points  = 0;
      reference_position_copy.clear();
      material.clear();
      support_begin.assign(1, 0);
      n_stored = 0;
    }

    /** @brief Make room for @p n_more entries after the stored ones. */
    void
    make_room(const std::size_t n_more)
    {
      if (n_stored + n_more > node.size())
        {
          const std::size_t size = std::max(n_stored + n_more, 2 * node.size());
          node.resize(size);
          S.resize(size);
          G.resize(size);
        }
    }

    /** @brief Store an entry (after make_room()). */
    void
    append(const unsigned int    local_index,
           const double          S_ip,
           const Tensor<1, dim> &G_ip)
    {
      node[n_stored] = local_index;
      S[n_stored]    = S_ip;
      G[n_stored]    = G_ip;
      ++n_stored;
    }

    /**
     * @brief Append a support entry for node @p local_index to the point
     * being built, merging it with an entry for the same node added since
     * @p first (a master reached directly and through a hanging node).
     */
    void
    add_entry(const unsigned int    first,
              const unsigned int    local_index,
              const double          S_ip,
              const Tensor<1, dim> &G_ip)
    {
      for (std::size_t k = first; k < n_stored; ++k)
        if (node[k] == local_index)
          {
            S[k] += S_ip;
            G[k] += G_ip;
            return;
          }
      make_room(1);
      append(local_index, S_ip, G_ip);
    }

    /** @brief Bytes held (capacity), for the benchmark's memory figure. */
    std::size_t
    memory_consumption() const
    {
      return reference_position_copy.capacity() * sizeof(Point<dim>) +
             material.capacity() +
             (support_begin.capacity() + node.capacity()) *
               sizeof(unsigned int) +
             (S.capacity() + T.capacity()) * sizeof(double) +
             G.capacity() * sizeof(Tensor<1, dim>);
    }
  };

  /**
   * @brief A point's support entries as the passes read them: from the
   * cache, or for implicit classic supports computed from ξ_p at the
   * step's start on its affine cell (GridTransfer::values_and_gradients:
   * S = Π(1 − ξ | ξ), G = J⁻ᵀ∇̂S, the same operations).
   *
   * visit() calls body(node, S, G, n) with the entries j < n; for computed
   * entries n is a compile-time constant, so that S and G stay in
   * registers.
   */
  template <int dim>
  class SupportReader
  {
  public:
    using CellData = typename GridTransfer<dim>::CellData;
    static constexpr unsigned int n_nodes = GridTransfer<dim>::n_nodes;

    /** @p point_cell: the active cell index of each point (the store's). */
    SupportReader(const SupportCache<dim>  &cache,
                  const GridTransfer<dim>  &transfer,
                  const unsigned int *const point_cell)
      : cache(cache)
      , transfer(transfer)
      , point_cell(point_cell)
    {}

    /** Point @p k's entries, G only if @p with_gradients; @p cell is the
     * data of the point's cell. */
    template <typename Body>
    DEAL_II_ALWAYS_INLINE void
    visit(const unsigned int k,
          const CellData    &cell,
          const bool         with_gradients,
          const Body        &body) const
    {
      if (!cache.implicit_classic)
        visit_cached(k, body);
      else
        visit_computed(k, cell, with_gradients, body);
    }

    /** Point @p k's entries (its cell looked up). */
    template <typename Body>
    DEAL_II_ALWAYS_INLINE void
    visit(const unsigned int k,
          const bool         with_gradients,
          const Body        &body) const
    {
      if (!cache.implicit_classic)
        visit_cached(k, body);
      else
        visit_computed(k,
                       transfer.cell_data(point_cell[k]),
                       with_gradients,
                       body);
    }

    /** Point @p k's computed entries (implicit classic supports only). */
    DEAL_II_ALWAYS_INLINE void
    compute(const unsigned int                   k,
            const CellData                      &cell,
            const bool                           with_gradients,
            std::array<double, n_nodes>         &S,
            std::array<Tensor<1, dim>, n_nodes> &G) const
    {
      const Point<dim> &xi = cache.reference_position[k];
      GridTransfer<dim>::values(xi, S);
      if (with_gradients)
        {
          GridTransfer<dim>::reference_gradients(xi, G);
          // G_i = J⁻ᵀ ∇̂S_i, summed as deal.II's Tensor product does.
          double A[dim][dim];
          for (unsigned int a = 0; a < dim; ++a)
            for (unsigned int b = 0; b < dim; ++b)
              A[a][b] = cell.inverse_jacobian_transpose[a][b];
          for (unsigned int i = 0; i < n_nodes; ++i)
            {
              double g[dim];
              for (unsigned int b = 0; b < dim; ++b)
                g[b] = G[i][b];
              for (unsigned int a = 0; a < dim; ++a)
                {
                  double sum = A[a][0] * g[0];
                  for (unsigned int b = 1; b < dim; ++b)
                    sum += A[a][b] * g[b];
                  G[i][a] = sum;
                }
            }
        }
    }

  private:
    template <typename Body>
    DEAL_II_ALWAYS_INLINE void
    visit_cached(const unsigned int k, const Body &body) const
    {
      const unsigned int begin = cache.support_begin[k];
      body(cache.node.data() + begin,
           cache.S.data() + begin,
           cache.G.data() + begin,
           cache.support_begin[k + 1] - begin);
    }

    template <typename Body>
    DEAL_II_ALWAYS_INLINE void
    visit_computed(const unsigned int k,
                   const CellData    &cell,
                   const bool         with_gradients,
                   const Body        &body) const
    {
      std::array<double, n_nodes>         S;
      std::array<Tensor<1, dim>, n_nodes> G;
      compute(k, cell, with_gradients, S, G);
      body(cell.local_index.data(),
           S.data(),
           G.data(),
           std::integral_constant<unsigned int, n_nodes>());
    }

    const SupportCache<dim>  &cache;
    const GridTransfer<dim>  &transfer;
    const unsigned int *const point_cell;
  };
} // namespace fmpm

#endif
