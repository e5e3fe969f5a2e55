// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_grid_vectors_h
#define fmpm_grid_vectors_h

#include <deal.II/lac/la_parallel_block_vector.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <vector>

namespace fmpm
{
  /** A scalar nodal field, e.g. the lumped masses m. Ghosted. */
  using GridScalar = dealii::LinearAlgebra::distributed::Vector<double>;

  /**
   * A vector nodal field with one block per space direction, e.g. the
   * momenta p. All blocks share the scalar DoF layout, so the (scalar) mass
   * matrix applies to each block.
   */
  using GridVectorField =
    dealii::LinearAlgebra::distributed::BlockVector<double>;

  /**
   * @brief The full mass matrix m̃ = SᵀMS kept as one dense local matrix per
   * cell with material points (seed 000 Eq. 1.9 before assembly): filling
   * it costs n² multiply-adds per point and no sparse-matrix insertion, and
   * m̃v is a gather-multiply-scatter over those cells. Used by FMPM(k) on
   * meshes without hanging nodes.
   */
  class CellwiseMatrix
  {
  public:
    /** @brief Forget all cells; @p n is the number of nodes per cell. */
    void
    clear(const unsigned int n)
    {
      nodes_per_cell = n;
      local_indices.clear();
      values.clear();
    }

    /** @brief Append a cell: its nodes' local indices and n x n values. */
    void
    add_cell(const unsigned int *indices, const double *cell_values)
    {
      local_indices.insert(local_indices.end(),
                           indices,
                           indices + nodes_per_cell);
      values.insert(values.end(),
                    cell_values,
                    cell_values + nodes_per_cell * nodes_per_cell);
    }

    /** @brief dst = m̃ src; @p src needs its ghost values. */
    void
    vmult(GridScalar &dst, const GridScalar &src) const
    {
      dst                        = 0;
      const unsigned int n       = nodes_per_cell;
      const unsigned int n_cells = n == 0 ? 0 : local_indices.size() / n;
      for (unsigned int c = 0; c < n_cells; ++c)
        {
          const unsigned int *index = &local_indices[c * n];
          const double       *A     = &values[c * n * n];
          for (unsigned int i = 0; i < n; ++i)
            {
              double sum = 0;
              for (unsigned int j = 0; j < n; ++j)
                sum += A[i * n + j] * src.local_element(index[j]);
              dst.local_element(index[i]) += sum;
            }
        }
      dst.compress(dealii::VectorOperation::add);
    }

  private:
    unsigned int              nodes_per_cell = 0;
    std::vector<unsigned int> local_indices;
    std::vector<double>       values;
  };
} // namespace fmpm

#endif
