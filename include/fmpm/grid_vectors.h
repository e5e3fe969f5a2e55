// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_grid_vectors_h
#define fmpm_grid_vectors_h

#include <deal.II/base/exceptions.h>
#include <deal.II/lac/la_parallel_block_vector.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <type_traits>
#include <vector>

#include <experimental/simd>

namespace fmpm
{
  /**
   * @brief Two doubles as one SIMD value (SSE2 on x86-64), for the grid
   * kernels that treat two components or two nodes at once: the portable
   * simd type of the C++ Parallelism TS 2. (deal.II's VectorizedArray<double,
   * 2> is defined only when deal.II itself is configured with SSE2 or wider
   * vectorization, DEAL_II_VECTORIZATION_WIDTH_IN_BITS >= 128, which the
   * Debian build of deal.II 9.4 is not.)
   */
  using DoublePair =
    std::experimental::simd<double,
                            std::experimental::simd_abi::deduce_t<double, 2>>;

  /** @brief The two doubles at @p x as one DoublePair. */
  inline DoublePair
  load_pair(const double *const x)
  {
    return DoublePair(x, std::experimental::element_aligned);
  }

  /** @brief Write @p value to the two doubles at @p x. */
  inline void
  store_pair(double *const x, const DoublePair &value)
  {
    value.copy_to(x, std::experimental::element_aligned);
  }

  /** A scalar nodal field, e.g. the lumped masses m. Ghosted. */
  using GridScalar = dealii::LinearAlgebra::distributed::Vector<double>;

  /**
   * A vector nodal field with one block per space direction, e.g. the
   * momenta p. All blocks share the scalar DoF layout, so the (scalar) mass
   * matrix applies to each block.
   */
  using GridVectorField =
    dealii::LinearAlgebra::distributed::BlockVector<double>;

  namespace internal
  {
    /** The largest cell of a Count: the constant, or 64 nodes. */
    template <typename Count>
    struct CellSize
    {
      static constexpr unsigned int value = 64;
    };
    template <unsigned int n>
    struct CellSize<std::integral_constant<unsigned int, n>>
    {
      static constexpr unsigned int value = n;
    };

    /**
     * A cell's local copy of its nodes' values for a product y = m̃_c x:
     * two components per DoublePair, so that one multiply serves both; the
     * third, in 3D, alone.
     */
    template <bool third, unsigned int size>
    struct CellNodeValues
    {
      DoublePair x[size], y[size];
      double     x2[third ? size : 1], y2[third ? size : 1];

      /** x from @p source at the cell's @p n nodes @p index; y = 0. */
      template <typename Count>
      DEAL_II_ALWAYS_INLINE void
      gather(const Count               n,
             const unsigned int *const index,
             const double *const      *source)
      {
        for (unsigned int j = 0; j < n; ++j)
          {
            x[j] = DoublePair(
              [&](const auto lane) { return source[lane][index[j]]; });
            y[j] = 0.;
            if constexpr (third)
              {
                x2[j] = source[2][index[j]];
                y2[j] = 0;
              }
          }
      }

      /** @p destination += y at the cell's nodes. */
      template <typename Count>
      DEAL_II_ALWAYS_INLINE void
      scatter(const Count               n,
              const unsigned int *const index,
              double *const            *destination) const
      {
        for (unsigned int i = 0; i < n; ++i)
          {
            destination[0][index[i]] += y[i][0];
            destination[1][index[i]] += y[i][1];
            if constexpr (third)
              destination[2][index[i]] += y2[i];
          }
      }
    };
  } // namespace internal

  /**
   * @brief The full mass matrix m̃ = SᵀMS kept as one dense local matrix per
   * cell with material points (seed 000 Eq. 1.9 before assembly): filling
   * it costs n² multiply-adds per point and no sparse-matrix insertion, and
   * m̃v is a gather-multiply-scatter over those cells. The local matrices
   * are symmetric and stored as their upper triangles. A cell's nodes are
   * the union of its points' supports: its own 4 or 8 nodes for classic
   * shape functions, more for GIMP/CPDI and where hanging nodes pass their
   * weights on. A cell whose union is large against its points' supports
   * (GIMP/CPDI) is kept instead as those supports, m̃_c = Σ_p M_p S_p S_pᵀ,
   * which a product applies point by point (factored_is_cheaper()). Used by
   * FMPM(k) and the exact solve.
   */
  class CellwiseMatrix
  {
  public:
    /** @brief Forget all cells; @p n is the default number of nodes of a
     * cell (add_cell() without a size). */
    void
    clear(const unsigned int n = 0)
    {
      nodes_per_cell = n;
      uniform_size   = 0;
      local_indices.clear();
      values.clear();
      cell_node_begin.assign(1, 0);
      cell_value_begin.assign(1, 0);
      factored_indices.clear();
      factored_node_begin.assign(1, 0);
      factored_point_begin.assign(1, 0);
      point_mass.clear();
      point_entries.clear();
      entry_slot.clear();
      entry_value.clear();
    }

    /**
     * @brief Append a cell: its @p n nodes' local indices and its symmetric
     * n x n matrix (row by row; the upper triangle is kept).
     */
    void
    add_cell(const unsigned int  n,
             const unsigned int *indices,
             const double       *cell_values)
    {
      uniform_size = (n_cells() == 0 || uniform_size == n) ? n : 0;
      local_indices.insert(local_indices.end(), indices, indices + n);
      for (unsigned int i = 0; i < n; ++i)
        values.insert(values.end(),
                      cell_values + i * n + i,
                      cell_values + (i + 1) * n);
      cell_node_begin.push_back(local_indices.size());
      cell_value_begin.push_back(values.size());
    }

    /** @brief add_cell() with the default number of nodes of clear(). */
    void
    add_cell(const unsigned int *indices, const double *cell_values)
    {
      add_cell(nodes_per_cell, indices, cell_values);
    }

    /**
     * @brief Whether a cell of @p n_nodes nodes whose points have
     * @p n_entries support entries in all is cheaper kept as its
     * points' supports (begin_factored_cell()): a product then costs 2
     * n_entries multiply-adds per component against n_nodes² for the dense
     * matrix (GIMP/CPDI unions; never for classic cells with their own nodes).
     */
    /** The most nodes of a cell kept as a dense matrix (4^3: GIMP/CPDI
     * patches, b2spline/b3spline unions); wider cells (b2gimp, b2cpdi in
     * 3D) are kept factored. */
    static constexpr unsigned int max_dense_nodes = 64;

    static bool
    factored_is_cheaper(const unsigned int n_nodes,
                        const unsigned int n_entries)
    {
      return n_nodes > max_dense_nodes || 2 * n_entries < n_nodes * n_nodes;
    }

    /**
     * @brief Append a cell kept as its points' supports, m̃_c = Σ_p M_p S_p
     * S_pᵀ (Eq. 1.9 before the sum over the cell's points is formed): its
     * @p n nodes' local indices; add_point() then adds each of its points.
     */
    void
    begin_factored_cell(const unsigned int n, const unsigned int *indices)
    {
      Assert(n <= 64, dealii::ExcInternalError());
      factored_indices.insert(factored_indices.end(), indices, indices + n);
      factored_node_begin.push_back(factored_indices.size());
      factored_point_begin.push_back(point_mass.size());
    }

    /**
     * @brief Add a point to the cell begun last: its mass @p M and its
     * @p n_entries shape function values @p S at the places @p slot of the
     * cell's nodes.
     */
    void
    add_point(const double        M,
              const unsigned int  n_entries,
              const unsigned int *slot,
              const double       *S)
    {
      Assert(n_entries < 256, dealii::ExcInternalError());
      point_mass.push_back(M);
      point_entries.push_back(n_entries);
      for (unsigned int j = 0; j < n_entries; ++j)
        {
          entry_slot.push_back(slot[j]);
          entry_value.push_back(S[j]);
        }
      ++factored_point_begin.back();
    }

    /** @brief Number of cells kept as dense matrices. */
    unsigned int
    n_cells() const
    {
      return cell_node_begin.size() - 1;
    }

    /** @brief Number of cells kept as their points' supports. */
    unsigned int
    n_factored_cells() const
    {
      return factored_node_begin.size() - 1;
    }

    /**
     * @brief dst = m̃ src for every component at once: one pass over the
     * cell matrices serves all blocks. Updates and then clears the ghost
     * values of @p src.
     */
    void
    vmult(GridVectorField &dst, const GridVectorField &src) const
    {
      const unsigned int n_blocks = src.n_blocks();
      Assert(n_blocks <= 3, dealii::ExcInternalError());
      src.update_ghost_values();
      dst                          = 0;
      const double *source[3]      = {};
      double       *destination[3] = {};
      for (unsigned int b = 0; b < n_blocks; ++b)
        {
          source[b]      = src.block(b).begin();
          destination[b] = dst.block(b).begin();
        }
      add_products(destination, source, n_blocks);
      dst.compress(dealii::VectorOperation::add);
      src.zero_out_ghost_values();
    }

    /** @brief The diagonal m̃ᵢᵢ on locally owned nodes. */
    void
    diagonal(GridScalar &dst) const
    {
      dst = 0;
      for (unsigned int c = 0; c < n_cells(); ++c)
        {
          const unsigned int  n = cell_node_begin[c + 1] - cell_node_begin[c];
          const unsigned int *index = &local_indices[cell_node_begin[c]];
          const double       *a     = &values[cell_value_begin[c]];
          for (unsigned int i = 0; i < n; a += n - i, ++i)
            dst.local_element(index[i]) += a[0];
        }
      const double *S     = entry_value.data();
      const auto   *place = entry_slot.data();
      for (unsigned int c = 0; c < n_factored_cells(); ++c)
        {
          const unsigned int *index = &factored_indices[factored_node_begin[c]];
          for (unsigned int q = factored_point_begin[c];
               q < factored_point_begin[c + 1];
               S += point_entries[q], place += point_entries[q], ++q)
            for (unsigned int e = 0; e < point_entries[q]; ++e)
              dst.local_element(index[place[e]]) += point_mass[q] * S[e] * S[e];
        }
      dst.compress(dealii::VectorOperation::add);
    }

  private:
    /** dst_b += m̃ src_b over the local cells for @p n_blocks components. */
    void
    add_products(double *const       *destination,
                 const double *const *source,
                 const unsigned int   n_blocks) const
    {
      // Classic Q1 cells: 4 nodes in 2D and 8 in 3D, one component each way.
      if (uniform_size == 4 && n_blocks == 2)
        add_products_paired<4, false>(destination, source);
      else if (uniform_size == 8 && n_blocks == 3)
        add_products_paired<8, true>(destination, source);
      else if (n_blocks == 2)
        add_products_paired_any_size<false>(destination, source);
      else if (n_blocks == 3)
        add_products_paired_any_size<true>(destination, source);
      else
        add_products_generic(destination, source, n_blocks);
      if (n_factored_cells() > 0)
        {
          if (n_blocks == 2)
            add_factored_products<false>(destination, source);
          else if (n_blocks == 3)
            add_factored_products<true>(destination, source);
          else
            add_factored_products_generic(destination, source, n_blocks);
        }
    }

    /**
     * The cells kept as supports: per point s = S_pᵀx (one DoublePair
     * for two components, as in add_cell_products_paired()), then
     * y += S_p M_p s, in the cell's local copy of its nodes; 1D one
     * component at a time.
     */
    template <bool third>
    void
    add_factored_products(double *const       *destination,
                          const double *const *source) const
    {
      internal::CellNodeValues<third, 64> local;
      auto         &x = local.x, &y = local.y, &x2 = local.x2, &y2 = local.y2;
      const double *S     = entry_value.data();
      const auto   *place = entry_slot.data();
      for (unsigned int c = 0; c < n_factored_cells(); ++c)
        {
          const unsigned int n =
            factored_node_begin[c + 1] - factored_node_begin[c];
          const unsigned int *index = &factored_indices[factored_node_begin[c]];
          local.gather(n, index, source);
          for (unsigned int q = factored_point_begin[c];
               q < factored_point_begin[c + 1];
               ++q)
            {
              const unsigned int n_entries = point_entries[q];
              DoublePair         s         = 0.;
              double             s2        = 0;
              for (unsigned int e = 0; e < n_entries; ++e)
                {
                  s += S[e] * x[place[e]];
                  if constexpr (third)
                    s2 += S[e] * x2[place[e]];
                }
              s *= point_mass[q];
              s2 *= point_mass[q];
              for (unsigned int e = 0; e < n_entries; ++e)
                {
                  y[place[e]] += S[e] * s;
                  if constexpr (third)
                    y2[place[e]] += S[e] * s2;
                }
              S += n_entries;
              place += n_entries;
            }
          local.scatter(n, index, destination);
        }
    }

    /** add_factored_products() one component at a time (1D). */
    void
    add_factored_products_generic(double *const       *destination,
                                  const double *const *source,
                                  const unsigned int   n_blocks) const
    {
      for (unsigned int b = 0; b < n_blocks; ++b)
        {
          const double *S     = entry_value.data();
          const auto   *place = entry_slot.data();
          for (unsigned int c = 0; c < n_factored_cells(); ++c)
            {
              const unsigned int *index =
                &factored_indices[factored_node_begin[c]];
              for (unsigned int q = factored_point_begin[c];
                   q < factored_point_begin[c + 1];
                   S += point_entries[q], place += point_entries[q], ++q)
                {
                  double s = 0;
                  for (unsigned int e = 0; e < point_entries[q]; ++e)
                    s += S[e] * source[b][index[place[e]]];
                  s *= point_mass[q];
                  for (unsigned int e = 0; e < point_entries[q]; ++e)
                    destination[b][index[place[e]]] += S[e] * s;
                }
            }
        }
    }

    /** Cells of any size (GIMP/CPDI supports, hanging nodes). */
    void
    add_products_generic(double *const       *destination,
                         const double *const *source,
                         const unsigned int   n_blocks) const
    {
      double x[3][max_dense_nodes], y[3][max_dense_nodes];
      for (unsigned int c = 0; c < n_cells(); ++c)
        {
          const unsigned int  n = cell_node_begin[c + 1] - cell_node_begin[c];
          const unsigned int *index = &local_indices[cell_node_begin[c]];
          const double       *a     = &values[cell_value_begin[c]];
          AssertIndexRange(n, max_dense_nodes + 1);
          for (unsigned int b = 0; b < n_blocks; ++b)
            for (unsigned int j = 0; j < n; ++j)
              {
                x[b][j] = source[b][index[j]];
                y[b][j] = 0;
              }
          for (unsigned int i = 0; i < n; a += n - i, ++i)
            for (unsigned int b = 0; b < n_blocks; ++b)
              {
                y[b][i] += a[0] * x[b][i];
                for (unsigned int j = i + 1; j < n; ++j)
                  {
                    y[b][i] += a[j - i] * x[b][j];
                    y[b][j] += a[j - i] * x[b][i];
                  }
              }
          for (unsigned int b = 0; b < n_blocks; ++b)
            for (unsigned int i = 0; i < n; ++i)
              destination[b][index[i]] += y[b][i];
        }
    }

    /**
     * The kernel for two components (and a third one if @p third): each
     * stored entry a_ij (i <= j) adds a_ij x_j to y_i and, off the diagonal,
     * a_ij x_i to y_j, on internal::CellNodeValues. Cells of @p n nodes (a
     * constant for uniform cells, so that the loops unroll), the same
     * operations per component as add_products_generic().
     */
    template <bool third, typename Count>
    DEAL_II_ALWAYS_INLINE void
    add_cell_products_paired(const Count               n,
                             const unsigned int *const index,
                             const double             *a,
                             double *const            *destination,
                             const double *const      *source) const
    {
      internal::CellNodeValues<third, internal::CellSize<Count>::value> local;
      auto &x = local.x, &y = local.y, &x2 = local.x2, &y2 = local.y2;
      local.gather(n, index, source);
      for (unsigned int i = 0; i < n; ++i)
        {
          y[i] += a[0] * x[i];
          if constexpr (third)
            y2[i] += a[0] * x2[i];
          for (unsigned int j = i + 1; j < n; ++j)
            {
              y[i] += a[j - i] * x[j];
              y[j] += a[j - i] * x[i];
              if constexpr (third)
                {
                  y2[i] += a[j - i] * x2[j];
                  y2[j] += a[j - i] * x2[i];
                }
            }
          a += n - i;
        }
      local.scatter(n, index, destination);
    }

    /** add_cell_products_paired() over cells of @p n nodes each. */
    template <unsigned int n, bool third>
    void
    add_products_paired(double *const       *destination,
                        const double *const *source) const
    {
      const unsigned int     n_cells = local_indices.size() / n;
      constexpr unsigned int n_upper = n * (n + 1) / 2;
      for (unsigned int c = 0; c < n_cells; ++c)
        add_cell_products_paired<third>(
          std::integral_constant<unsigned int, n>(),
          &local_indices[c * n],
          &values[c * n_upper],
          destination,
          source);
    }

    /** add_cell_products_paired() over cells of any size (GIMP/CPDI
     * supports, hanging nodes). */
    template <bool third>
    void
    add_products_paired_any_size(double *const       *destination,
                                 const double *const *source) const
    {
      for (unsigned int c = 0; c < n_cells(); ++c)
        {
          const unsigned int n = cell_node_begin[c + 1] - cell_node_begin[c];
          AssertIndexRange(n, max_dense_nodes + 1);
          add_cell_products_paired<third>(n,
                                          &local_indices[cell_node_begin[c]],
                                          &values[cell_value_begin[c]],
                                          destination,
                                          source);
        }
    }

    unsigned int nodes_per_cell = 0;
    /** The size of every cell if all have the same, else 0. */
    unsigned int              uniform_size = 0;
    std::vector<unsigned int> local_indices;
    std::vector<double>       values;
    /** Cell c's nodes and upper-triangle values start here. */
    std::vector<unsigned int> cell_node_begin{0};
    std::vector<std::size_t>  cell_value_begin{0};
    /** Cells kept as supports: cell c's nodes and points start at
     * factored_node_begin[c] and factored_point_begin[c]; point q's mass
     * point_mass[q] and its point_entries[q] entries (place among the
     * cell's nodes, S) after those of the points before it. */
    std::vector<unsigned int>  factored_indices;
    std::vector<unsigned int>  factored_node_begin{0};
    std::vector<unsigned int>  factored_point_begin{0};
    std::vector<double>        point_mass;
    std::vector<unsigned char> point_entries;
    std::vector<unsigned char> entry_slot;
    std::vector<double>        entry_value;
  };

  namespace internal
  {
    /**
     * o = a + s b, or (a + s b) c with @p scaled, over @p n entries of
     * distinct arrays: restrict-qualified and called with a constant count
     * for full blocks, so that GCC vectorizes it at -O2.
     */
    template <bool scaled, typename Count>
    inline void
    scaled_sum(const Count n,
               double *__restrict o,
               const double *__restrict a,
               const double s,
               const double *__restrict b,
               const double c)
    {
      for (unsigned int i = 0; i < n; ++i)
        o[i] = scaled ? (a[i] + s * b[i]) * c : a[i] + s * b[i];
    }
  } // namespace internal

  /**
   * @brief out = (a + s b) c on the owned entries in one pass (what deal.II's
   * copy, add and scale give in three, to the bit); the ghost entries are
   * updated if @p a's are, else left stale, as deal.II leaves them. @p out
   * is neither @p a nor @p b.
   */
  inline void
  set_scaled_sum(GridVectorField       &out,
                 const GridVectorField &a,
                 const double           s,
                 const GridVectorField &b,
                 const double           c = 1.)
  {
    for (unsigned int d = 0; d < out.n_blocks(); ++d)
      {
        const unsigned int     n      = out.block(d).locally_owned_size();
        double *const          o      = out.block(d).begin();
        const double *const    a_d    = a.block(d).begin();
        const double *const    b_d    = b.block(d).begin();
        constexpr unsigned int block  = 64;
        const unsigned int     n_full = n - n % block;
        const std::integral_constant<unsigned int, block> full;
        if (c == 1.)
          {
            for (unsigned int i = 0; i < n_full; i += block)
              internal::scaled_sum<false>(full, o + i, a_d + i, s, b_d + i, c);
            internal::scaled_sum<false>(
              n - n_full, o + n_full, a_d + n_full, s, b_d + n_full, c);
          }
        else
          {
            for (unsigned int i = 0; i < n_full; i += block)
              internal::scaled_sum<true>(full, o + i, a_d + i, s, b_d + i, c);
            internal::scaled_sum<true>(
              n - n_full, o + n_full, a_d + n_full, s, b_d + n_full, c);
          }
      }
    if (a.has_ghost_elements())
      out.update_ghost_values();
    else
      out.zero_out_ghost_values();
  }
} // namespace fmpm

#endif
