// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_grid_vectors_h
#define fmpm_grid_vectors_h

#include <deal.II/lac/la_parallel_block_vector.h>
#include <deal.II/lac/la_parallel_vector.h>

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
} // namespace fmpm

#endif
