// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The mass-matrix identities of seed 000 on a random cloud of material
// points: FMPM(k) computed as Jacobi-Richardson sweeps on the assembled
// m̃ = SᵀMS equals the XPIC(k) recursion through the particles (Eqs. 2.4-2.6)
// and the XPIC projection P_k V = (I − (I − SS⁺)^k) V = S m̃ₖ⁻¹ p
// (Eqs. 1.32-1.36); ‖m̃ₖ⁻¹p − m̃⁻¹p‖ decreases monotonically in k; the
// CG solve of the exact full mass matrix meets its tolerance.

#include <fmpm/grid_transfer.h>
#include <fmpm/grid_vectors.h>
#include <fmpm/mass_matrix/full_solve.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/mass_matrix/series.h>

#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <random>

#include "series_helpers.h"
#include <gtest/gtest.h>

namespace
{
  using namespace dealii;

  /** A random cloud of points on a small mesh with S, M, m, m̃, p. */
  template <int dim>
  struct Cloud
  {
    static constexpr unsigned int n_nodes = fmpm::GridTransfer<dim>::n_nodes;

    parallel::distributed::Triangulation<dim>    triangulation{MPI_COMM_WORLD};
    FE_Q<dim>                                    fe{1};
    DoFHandler<dim>                              dof_handler{triangulation};
    std::shared_ptr<Utilities::MPI::Partitioner> partitioner;
    // Per point: its nodes (local indices), S_pi, mass, velocity.
    std::vector<std::array<unsigned int, n_nodes>> nodes;
    std::vector<std::array<double, n_nodes>>       S;
    std::vector<double>                            M;
    std::vector<Tensor<1, dim>>                    V;
    fmpm::GridScalar                               m;
    fmpm::GridVectorField                          p;
    TrilinosWrappers::SparseMatrix                 m_tilde;

    Cloud(const unsigned int refinement, const unsigned int points_per_cell)
    {
      GridGenerator::hyper_cube(triangulation);
      triangulation.refine_global(refinement);
      dof_handler.distribute_dofs(fe);
      IndexSet relevant;
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      partitioner = std::make_shared<Utilities::MPI::Partitioner>(
        dof_handler.locally_owned_dofs(), relevant, MPI_COMM_WORLD);
      AffineConstraints<double> constraints;
      constraints.close();
      fmpm::GridTransfer<dim> transfer;
      transfer.reinit(dof_handler, constraints, *partitioner);

      std::mt19937                           rng(42);
      std::uniform_real_distribution<double> unit(0, 1);
      for (const auto &cell : dof_handler.active_cell_iterators())
        for (unsigned int q = 0; q < points_per_cell; ++q)
          {
            Point<dim> xi;
            for (unsigned int d = 0; d < dim; ++d)
              xi[d] = unit(rng);
            std::array<double, n_nodes> s;
            fmpm::GridTransfer<dim>::values(xi, s);
            S.push_back(s);
            nodes.push_back(
              transfer.cell_data(cell->active_cell_index()).local_index);
            M.push_back(0.5 + unit(rng));
            Tensor<1, dim> v;
            for (unsigned int d = 0; d < dim; ++d)
              v[d] = 2 * unit(rng) - 1;
            V.push_back(v);
          }

      m.reinit(partitioner);
      p.reinit(dim);
      for (unsigned int d = 0; d < dim; ++d)
        p.block(d).reinit(partitioner);
      p.collect_sizes();
      TrilinosWrappers::SparsityPattern sparsity(
        dof_handler.locally_owned_dofs(), MPI_COMM_WORLD);
      DoFTools::make_sparsity_pattern(dof_handler, sparsity);
      sparsity.compress();
      m_tilde.reinit(sparsity);
      for (unsigned int q = 0; q < S.size(); ++q)
        for (unsigned int i = 0; i < n_nodes; ++i)
          {
            m.local_element(nodes[q][i]) += M[q] * S[q][i]; // m = SᵀM
            for (unsigned int d = 0; d < dim; ++d)
              p.block(d).local_element(nodes[q][i]) += M[q] * S[q][i] * V[q][d];
            for (unsigned int j = 0; j < n_nodes; ++j) // m̃ = SᵀMS
              m_tilde.add(nodes[q][i], nodes[q][j], M[q] * S[q][i] * S[q][j]);
          }
      m_tilde.compress(VectorOperation::add);
    }

    fmpm::GridVectorField
    new_field() const
    {
      fmpm::GridVectorField v(p);
      v = 0;
      return v;
    }

    /** m̃ as cell matrices: here one "cell" per point, M S Sᵀ. */
    fmpm::CellwiseMatrix
    cellwise_matrix() const
    {
      fmpm::CellwiseMatrix                  matrix;
      std::array<double, n_nodes * n_nodes> local;
      matrix.clear(n_nodes);
      for (unsigned int q = 0; q < S.size(); ++q)
        {
          for (unsigned int i = 0; i < n_nodes; ++i)
            for (unsigned int j = 0; j < n_nodes; ++j)
              local[i * n_nodes + j] = M[q] * S[q][i] * S[q][j];
          matrix.add_cell(nodes[q].data(), local.data());
        }
      return matrix;
    }

    /**
     * m̃ with every other mesh cell kept as its points' supports
     * (CellwiseMatrix::begin_factored_cell()), its nodes listed in reverse,
     * the other cells as dense matrices summed over their points.
     */
    fmpm::CellwiseMatrix
    mixed_cellwise_matrix() const
    {
      fmpm::CellwiseMatrix                  matrix;
      std::array<double, n_nodes * n_nodes> local;
      std::array<unsigned int, n_nodes>     reversed, slot;
      matrix.clear(n_nodes);
      bool factored = false;
      for (unsigned int first = 0, end = 0; first < S.size(); first = end)
        {
          end = first;
          while (end < S.size() && nodes[end] == nodes[first])
            ++end;
          if (factored)
            {
              for (unsigned int i = 0; i < n_nodes; ++i)
                {
                  reversed[n_nodes - 1 - i] = nodes[first][i];
                  slot[i]                   = n_nodes - 1 - i;
                }
              matrix.begin_factored_cell(n_nodes, reversed.data());
              for (unsigned int q = first; q < end; ++q)
                matrix.add_point(M[q], n_nodes, slot.data(), S[q].data());
            }
          else
            {
              local.fill(0.);
              for (unsigned int q = first; q < end; ++q)
                for (unsigned int i = 0; i < n_nodes; ++i)
                  for (unsigned int j = 0; j < n_nodes; ++j)
                    local[i * n_nodes + j] += M[q] * S[q][i] * S[q][j];
              matrix.add_cell(nodes[first].data(), local.data());
            }
          factored = !factored;
        }
      EXPECT_GT(matrix.n_factored_cells(), 1u);
      EXPECT_GT(matrix.n_cells(), 1u);
      return matrix;
    }

    /** S w: a grid field extrapolated to the points. */
    std::vector<Tensor<1, dim>>
    to_points(const fmpm::GridVectorField &w) const
    {
      std::vector<Tensor<1, dim>> result(S.size());
      for (unsigned int q = 0; q < S.size(); ++q)
        for (unsigned int i = 0; i < n_nodes; ++i)
          for (unsigned int d = 0; d < dim; ++d)
            result[q][d] += S[q][i] * w.block(d).local_element(nodes[q][i]);
      return result;
    }

    /** S⁺W = m⁻¹SᵀMW: point values to the grid (Eq. 1.7). */
    fmpm::GridVectorField
    to_grid(const std::vector<Tensor<1, dim>> &W) const
    {
      fmpm::GridVectorField result = new_field();
      for (unsigned int q = 0; q < S.size(); ++q)
        for (unsigned int i = 0; i < n_nodes; ++i)
          for (unsigned int d = 0; d < dim; ++d)
            result.block(d).local_element(nodes[q][i]) +=
              M[q] * S[q][i] * W[q][d] / m.local_element(nodes[q][i]);
      return result;
    }
  };

  double
  difference(const fmpm::GridVectorField &a, const fmpm::GridVectorField &b)
  {
    fmpm::GridVectorField c(a);
    c -= b;
    return c.l2_norm();
  }
} // namespace



// Jacobi-Richardson sweeps on m̃ (the code's form) = XPIC(k)'s recursion
// through the particles, Eqs. 2.4-2.6, to round-off, for k = 1..8.
TEST(MassMatrix, FmpmSweepsEqualXpicRecursion)
{
  Cloud<2> cloud(3, 5);
  for (unsigned int k = 1; k <= 8; ++k)
    {
      fmpm::GridVectorField v_code = cloud.new_field();
      fmpm_tests::fmpm_inverse(cloud.m_tilde, cloud.m, cloud.p, v_code, k, 0);

      // v = Σ_ℓ v_ℓ, v_1 = k v^(L), v_ℓ = (C_kℓ/C_k,ℓ−1) S⁺S v_{ℓ−1} with
      // C_kℓ = (−1)^(ℓ+1) binom(k, ℓ) (Eq. 1.30), so the ratio is
      // −(k − ℓ + 1)/ℓ. (Eq. 2.6 prints the denominator as k; the binomial
      // ratio, which this test confirms, has ℓ.)
      fmpm::GridVectorField v_L = cloud.new_field();
      fmpm::MassMatrix::apply_lumped_inverse(cloud.m, cloud.p, v_L, 0);
      fmpm::GridVectorField v_l(v_L), v_xpic(v_L);
      v_l *= k;
      v_xpic = v_l;
      for (unsigned int l = 2; l <= k; ++l)
        {
          v_l = cloud.to_grid(cloud.to_points(v_l));
          v_l *= -static_cast<double>(k - l + 1) / l;
          v_xpic += v_l;
        }
      EXPECT_LT(difference(v_code, v_xpic), 1e-12 * v_xpic.l2_norm())
        << "k = " << k;
    }
}



// The XPIC(k) projection of the point velocities, P_k V = (I − (I −
// SS⁺)^k) V (Eq. 1.32), equals S m̃ₖ⁻¹ p (Eq. 1.36).
TEST(MassMatrix, XpicProjectionEqualsFmpmVelocity)
{
  Cloud<2> cloud(3, 4);
  for (const unsigned int k : {1u, 2u, 3u, 5u})
    {
      std::vector<Tensor<1, 2>> residual = cloud.V; // (I − SS⁺)^j V
      for (unsigned int j = 0; j < k; ++j)
        {
          const auto smoothed = cloud.to_points(cloud.to_grid(residual));
          for (unsigned int q = 0; q < residual.size(); ++q)
            residual[q] -= smoothed[q];
        }
      fmpm::GridVectorField v = cloud.new_field();
      fmpm_tests::fmpm_inverse(cloud.m_tilde, cloud.m, cloud.p, v, k, 0);
      const auto S_v       = cloud.to_points(v);
      double     max_error = 0, max_value = 0;
      for (unsigned int q = 0; q < S_v.size(); ++q)
        {
          max_error =
            std::max(max_error, (cloud.V[q] - residual[q] - S_v[q]).norm());
          max_value = std::max(max_value, S_v[q].norm());
        }
      EXPECT_LT(max_error, 1e-12 * max_value) << "k = " << k;
    }
}



// On a well-resolved cloud (m̃ invertible), ‖m̃ₖ⁻¹p − m̃⁻¹p‖ decreases
// monotonically in k, and the CG solve meets its tolerance and the dense
// solution.
TEST(MassMatrix, SeriesConvergesToExactSolve)
{
  Cloud<2>           cloud(2, 9);
  const unsigned int n = cloud.m.size();
  FullMatrix<double> dense(n, n);
  for (unsigned int i = 0; i < n; ++i)
    for (unsigned int j = 0; j < n; ++j)
      dense(i, j) = cloud.m_tilde.el(i, j);
  dense.gauss_jordan();
  fmpm::GridVectorField v_exact = cloud.new_field();
  for (unsigned int d = 0; d < 2; ++d)
    {
      Vector<double> rhs(n), solution(n);
      for (unsigned int i = 0; i < n; ++i)
        rhs(i) = cloud.p.block(d).local_element(i);
      dense.vmult(solution, rhs);
      for (unsigned int i = 0; i < n; ++i)
        v_exact.block(d).local_element(i) = solution(i);
    }

  double previous = std::numeric_limits<double>::max();
  for (unsigned int k = 1; k <= 30; ++k)
    {
      fmpm::GridVectorField v = cloud.new_field();
      fmpm_tests::fmpm_inverse(cloud.m_tilde, cloud.m, cloud.p, v, k, 0);
      const double error = difference(v, v_exact);
      EXPECT_LT(error, previous) << "k = " << k;
      previous = error;
    }
  EXPECT_LT(previous, 0.1 * v_exact.l2_norm());

  // The exact solve, with m̃ assembled and as cell matrices, from the
  // lumped start and from a warm start: m̃ v = p to the tolerance.
  const fmpm::CellwiseMatrix cellwise = cloud.cellwise_matrix();
  fmpm::GridScalar           diagonal(cloud.m), no_weak(cloud.m);
  no_weak = 0;
  for (unsigned int i = 0; i < diagonal.locally_owned_size(); ++i)
    diagonal.local_element(i) = cloud.m_tilde.diag_element(i);
  fmpm::MassMatrix::FullMassSolveSettings settings;
  settings.tolerance = 1e-10;
  // Solves with @p matrix; returns the CG iterations.
  const auto check_solve = [&](const auto &matrix, const bool warm_start) {
    fmpm::GridVectorField v = cloud.new_field();
    if (warm_start) // v_exact, perturbed by 1 %
      for (unsigned int d = 0; d < 2; ++d)
        for (unsigned int i = 0; i < v.block(d).locally_owned_size(); ++i)
          v.block(d).local_element(i) =
            v_exact.block(d).local_element(i) * (1 + 0.01 * std::sin(i));
    const auto result = fmpm::MassMatrix::solve_full_mass_system(matrix,
                                                                 diagonal,
                                                                 cloud.m,
                                                                 nullptr,
                                                                 no_weak,
                                                                 cloud.p,
                                                                 v,
                                                                 warm_start,
                                                                 settings);
    EXPECT_TRUE(result.converged);
    EXPECT_GT(result.iterations, 1u);
    fmpm::GridVectorField residual = cloud.new_field();
    for (unsigned int d = 0; d < 2; ++d)
      cloud.m_tilde.vmult(residual.block(d), v.block(d));
    residual -= cloud.p;
    EXPECT_LE(residual.l2_norm(), 1e-10 * cloud.p.l2_norm());
    EXPECT_LT(difference(v, v_exact), 1e-7 * v_exact.l2_norm());
    return result.iterations;
  };
  for (const bool warm_start : {false, true})
    {
      SCOPED_TRACE(warm_start ? "warm start" : "lumped start");
      EXPECT_EQ(check_solve(cloud.m_tilde, warm_start),
                check_solve(cellwise, warm_start));
    }
  // The warm start saves iterations.
  EXPECT_LT(check_solve(cellwise, true), check_solve(cellwise, false));
}



// Known (held) nodes: the constrained solve keeps their values and solves
// the other rows with them given; FMPM(k) sweeps keep masked components at
// zero.
TEST(MassMatrix, HeldNodesStayAtTheirValues)
{
  Cloud<2>                      cloud(3, 5);
  std::vector<fmpm::GridScalar> masks(2, cloud.m);
  fmpm::GridVectorField         v = cloud.new_field();
  fmpm::GridScalar              diagonal(cloud.m), no_weak(cloud.m);
  no_weak = 0;
  for (unsigned int i = 0; i < diagonal.locally_owned_size(); ++i)
    diagonal.local_element(i) = cloud.m_tilde.diag_element(i);
  // Component 0 holds every 7th node at 0.25, component 1 every 5th at −1.
  for (unsigned int d = 0; d < 2; ++d)
    {
      masks[d] = 0;
      for (unsigned int i = 0; i < cloud.m.size(); i += (d == 0 ? 7 : 5))
        {
          masks[d].local_element(i)   = 1;
          v.block(d).local_element(i) = d == 0 ? 0.25 : -1.;
        }
    }
  fmpm::MassMatrix::FullMassSolveSettings settings;
  settings.tolerance = 1e-12;
  fmpm::MassMatrix::solve_full_mass_system(cloud.m_tilde,
                                           diagonal,
                                           cloud.m,
                                           &masks,
                                           no_weak,
                                           cloud.p,
                                           v,
                                           false,
                                           settings);
  for (unsigned int d = 0; d < 2; ++d)
    {
      fmpm::GridScalar residual(cloud.m);
      cloud.m_tilde.vmult(residual, v.block(d));
      residual -= cloud.p.block(d);
      for (unsigned int i = 0; i < cloud.m.size(); ++i)
        {
          if (masks[d].local_element(i) != 0)
            {
              EXPECT_EQ(v.block(d).local_element(i), d == 0 ? 0.25 : -1.);
            }
          else
            {
              EXPECT_LT(std::abs(residual.local_element(i)),
                        1e-9 * cloud.p.l2_norm());
            }
        }
    }
  const fmpm::GridScalar &known = masks[0];

  std::vector<fmpm::GridScalar> mask(2, known);
  fmpm::GridVectorField         w = cloud.new_field();
  fmpm_tests::fmpm_inverse(cloud.m_tilde, cloud.m, cloud.p, w, 4, 0, &mask);
  for (unsigned int i = 0; i < cloud.m.size(); ++i)
    {
      if (known.local_element(i) != 0)
        {
          EXPECT_EQ(w.block(1).local_element(i), 0.0);
        }
    }
}



// The cell-wise form of m̃ (one dense local matrix per cell, the fast path
// of FMPM(k)) equals the assembled sparse matrix: m̃v and the FMPM(k)
// velocities agree to round-off.
namespace
{
  /** m̃ x for all components: cell-wise kernels against the sparse matrix. */
  template <int dim>
  void
  check_cellwise_products(const Cloud<dim> &cloud, const bool mixed)
  {
    const fmpm::CellwiseMatrix cellwise =
      mixed ? cloud.mixed_cellwise_matrix() : cloud.cellwise_matrix();
    fmpm::GridVectorField x = cloud.new_field(), y_sparse = x, y_cellwise = x;
    for (unsigned int d = 0; d < dim; ++d)
      for (unsigned int i = 0; i < x.block(d).locally_owned_size(); ++i)
        x.block(d).local_element(i) = std::sin(1.7 * i + 0.3 + d);
    for (unsigned int d = 0; d < dim; ++d)
      cloud.m_tilde.vmult(y_sparse.block(d), x.block(d));
    fmpm::MassMatrix::apply_full_mass(cellwise, y_cellwise, x);
    EXPECT_LT(difference(y_sparse, y_cellwise), 1e-13 * y_sparse.l2_norm())
      << dim << "D";
    fmpm::GridScalar diagonal(cloud.m);
    cellwise.diagonal(diagonal);
    for (unsigned int i = 0; i < diagonal.locally_owned_size(); ++i)
      EXPECT_NEAR(diagonal.local_element(i),
                  cloud.m_tilde.diag_element(i),
                  1e-14 * cloud.m.linfty_norm());
  }
} // namespace



TEST(MassMatrix, CellwiseMatrixEqualsAssembledMatrix)
{
  for (const bool mixed : {false, true})
    {
      check_cellwise_products(Cloud<2>(3, 3), mixed);
      check_cellwise_products(Cloud<3>(2, 2), mixed);
    }

  Cloud<2>                   cloud(3, 3);
  const fmpm::CellwiseMatrix cellwise = cloud.cellwise_matrix();

  for (const unsigned int k : {2u, 5u})
    {
      fmpm::GridVectorField v_sparse   = cloud.new_field();
      fmpm::GridVectorField v_cellwise = cloud.new_field();
      fmpm_tests::fmpm_inverse(
        cloud.m_tilde, cloud.m, cloud.p, v_sparse, k, 1e-300);
      fmpm_tests::fmpm_inverse(
        cellwise, cloud.m, cloud.p, v_cellwise, k, 1e-300);
      EXPECT_LT(difference(v_sparse, v_cellwise), 1e-12 * v_sparse.l2_norm())
        << "k = " << k;
    }
}



// Adaptive order: with a tolerance the series stops after the first sweep
// whose increment ‖v_ℓ − v_{ℓ−1}‖ is at most the tolerance times ‖v_1‖,
// and its result is FMPM(ℓ) bit for bit; every earlier increment is above
// the tolerance; tolerance 0 runs all k terms.
TEST(MassMatrix, AdaptiveOrderStopsAtTheTolerance)
{
  Cloud<2>   cloud(3, 5);
  const auto fmpm = [&](const unsigned int k,
                        const double       tolerance,
                        unsigned int      *used = nullptr) {
    fmpm::GridVectorField v     = cloud.new_field();
    const unsigned int    order = fmpm_tests::fmpm_inverse(
      cloud.m_tilde, cloud.m, cloud.p, v, k, 0, nullptr, nullptr, tolerance);
    if (used)
      *used = order;
    return v;
  };
  const double v1             = fmpm(1, 0).l2_norm();
  unsigned int previous_order = 1;
  for (const double tolerance : {1e-1, 1e-2, 1e-3, 1e-4})
    {
      unsigned int                order = 0;
      const fmpm::GridVectorField v     = fmpm(200, tolerance, &order);
      EXPECT_GT(order, 1u) << tolerance;
      EXPECT_LT(order, 200u) << tolerance;
      EXPECT_GE(order, previous_order) << tolerance;
      previous_order = order;
      EXPECT_EQ(difference(v, fmpm(order, 0)), 0.) << tolerance;
      EXPECT_LE(difference(fmpm(order, 0), fmpm(order - 1, 0)),
                tolerance * v1 * (1 + 1e-12))
        << tolerance;
      for (unsigned int l = 2; l < order; ++l)
        EXPECT_GT(difference(fmpm(l, 0), fmpm(l - 1, 0)), tolerance * v1)
          << tolerance << " l = " << l;
    }
  unsigned int order = 0;
  fmpm(7, 0, &order);
  EXPECT_EQ(order, 7u);
}



// A node set by a hook after every sweep (a padding node from its mirror)
// and marked untested leaves the adaptive order's test: with a right-hand
// side that gives it a large increment in every sweep, the series still
// stops where the other nodes' increment falls below the tolerance, with
// FMPM(ℓ) bit for bit; counted, that increment never lets it stop.
TEST(MassMatrix, AdaptiveOrderSkipsUntestedNodes)
{
  Cloud<2>              cloud(3, 5);
  const unsigned int    padding = 0, mirror = 1;
  fmpm::GridVectorField p = cloud.p;
  for (unsigned int d = 0; d < 2; ++d)
    p.block(d).local_element(padding) += 1e3 * p.l2_norm();
  fmpm::GridScalar untested(cloud.m);
  untested                        = 0;
  untested.local_element(padding) = 1;
  const auto set_padding          = [&](fmpm::GridVectorField &v) {
    for (unsigned int d = 0; d < 2; ++d)
      v.block(d).local_element(padding) = -v.block(d).local_element(mirror);
  };
  const auto series = [&](const unsigned int      k,
                          const double            tolerance,
                          const fmpm::GridScalar *skipped,
                          unsigned int           &order) {
    fmpm::GridVectorField v = cloud.new_field();
    fmpm::MassMatrix::apply_lumped_inverse(cloud.m, p, v, 0);
    set_padding(v);
    fmpm::GridVectorField m_tilde_v(v);
    order = fmpm::MassMatrix::fmpm_series(
      [&](const std::vector<fmpm::GridVectorField *> &in,
          const std::vector<fmpm::GridVectorField *> &out) {
        fmpm::MassMatrix::apply_full_mass(cloud.m_tilde, *out[0], *in[0]);
      },
      {fmpm::MassMatrix::SeriesField{&cloud.m, &p, &v, nullptr, skipped}},
      {&m_tilde_v},
      k,
      0,
      tolerance,
      fmpm::MassMatrix::SeriesHooks{nullptr, [&](const unsigned int) {
                                      set_padding(v);
                                    }});
    return v;
  };
  // The increment of sweep ℓ without the padding node.
  const auto tested_increment = [&](const unsigned int l) {
    unsigned int                used = 0;
    const fmpm::GridVectorField a    = series(l, 0, nullptr, used);
    const fmpm::GridVectorField b    = series(l - 1, 0, nullptr, used);
    double                      sum  = 0;
    for (unsigned int d = 0; d < 2; ++d)
      for (unsigned int i = 0; i < cloud.m.locally_owned_size(); ++i)
        if (i != padding)
          sum +=
            std::pow(a.block(d).local_element(i) - b.block(d).local_element(i),
                     2);
    return std::sqrt(sum);
  };
  unsigned int                used      = 0;
  fmpm::GridVectorField       v1        = series(1, 0, nullptr, used);
  const double                z1        = v1.l2_norm();
  const double                tolerance = 1e-3;
  unsigned int                order     = 0;
  const fmpm::GridVectorField v = series(200, tolerance, &untested, order);
  EXPECT_GT(order, 2u);
  EXPECT_LT(order, 200u);
  EXPECT_EQ(difference(v, series(order, 0, nullptr, used)), 0.);
  EXPECT_LE(tested_increment(order), tolerance * z1);
  EXPECT_GT(tested_increment(order - 1), tolerance * z1);
  series(200, tolerance, nullptr, order);
  EXPECT_EQ(order, 200u);
}



// Systems solved together (materials in contact, seed 004): split a cloud's
// points into two materials. Sharing the unknown at every node gives both
// the velocity of the whole cloud (m̃¹ + m̃²) v = p¹ + p²; sharing none gives
// each its own solve; sharing some leaves equal velocities and opposite
// residuals there, zero residuals elsewhere and Σ m v = Σ p.
TEST(MassMatrix, SharedNodesCoupleTheSystemsOfMaterials)
{
  Cloud<2>           cloud(2, 9);
  const unsigned int n = cloud.m.locally_owned_size();
  // Material a: the points q with q % 2 == a.
  struct Material
  {
    fmpm::CellwiseMatrix                K;
    fmpm::GridScalar                    m, diagonal, weak;
    fmpm::GridVectorField               p, v;
    fmpm::MassMatrix::FullMassWorkspace workspace;
  };
  std::vector<Material>  materials(2);
  constexpr unsigned int n_nodes = Cloud<2>::n_nodes;
  for (unsigned int a = 0; a < 2; ++a)
    {
      Material &material = materials[a];
      material.m         = cloud.m;
      material.m         = 0;
      material.p         = cloud.new_field();
      material.v         = cloud.new_field();
      material.K.clear(n_nodes);
      std::array<double, n_nodes * n_nodes> local;
      for (unsigned int q = a; q < cloud.S.size(); q += 2)
        {
          for (unsigned int i = 0; i < n_nodes; ++i)
            {
              material.m.local_element(cloud.nodes[q][i]) +=
                cloud.M[q] * cloud.S[q][i];
              for (unsigned int d = 0; d < 2; ++d)
                material.p.block(d).local_element(cloud.nodes[q][i]) +=
                  cloud.M[q] * cloud.S[q][i] * cloud.V[q][d];
              for (unsigned int j = 0; j < n_nodes; ++j)
                local[i * n_nodes + j] =
                  cloud.M[q] * cloud.S[q][i] * cloud.S[q][j];
            }
          material.K.add_cell(cloud.nodes[q].data(), local.data());
        }
      material.diagonal = cloud.m;
      material.K.diagonal(material.diagonal);
      material.weak = cloud.m;
      material.weak = 0;
    }
  const auto systems = [&]() {
    std::vector<fmpm::MassMatrix::FullMassSystem<fmpm::CellwiseMatrix>> list;
    for (Material &material : materials)
      list.push_back({&material.K,
                      &material.diagonal,
                      &material.m,
                      &material.weak,
                      &material.p,
                      &material.v,
                      &material.workspace});
    return list;
  };
  fmpm::MassMatrix::FullMassSolveSettings settings;
  settings.tolerance = 1e-12;
  // Starts from m⁻¹p, at shared nodes from the common (m¹ + m²)⁻¹(p¹ + p²)
  // (the corrections are shared, not the values).
  const auto solve = [&](const fmpm::MassMatrix::SharedNodes &shared) {
    std::vector<bool> is_shared(n, false);
    for (const auto &[i, group] : shared)
      is_shared[i] = true;
    for (unsigned int d = 0; d < 2; ++d)
      for (unsigned int i = 0; i < n; ++i)
        for (Material &material : materials)
          {
            const double m_i = is_shared[i] ? cloud.m.local_element(i) :
                                              material.m.local_element(i);
            const double p_i = is_shared[i] ?
                                 cloud.p.block(d).local_element(i) :
                                 material.p.block(d).local_element(i);
            material.v.block(d).local_element(i) = m_i > 0 ? p_i / m_i : 0.;
          }
    const auto result = fmpm::MassMatrix::solve_full_mass_systems(
      systems(),
      shared,
      nullptr,
      fmpm::MassMatrix::FullMassStart::given,
      settings);
    EXPECT_TRUE(result.converged);
    EXPECT_GT(result.iterations, 1u);
  };

  // The whole cloud, solved alone.
  const fmpm::CellwiseMatrix cellwise = cloud.cellwise_matrix();
  fmpm::GridScalar           diagonal(cloud.m), no_weak(cloud.m);
  no_weak = 0;
  cellwise.diagonal(diagonal);
  fmpm::GridVectorField v_whole = cloud.new_field();
  fmpm::MassMatrix::solve_full_mass_system(cellwise,
                                           diagonal,
                                           cloud.m,
                                           nullptr,
                                           no_weak,
                                           cloud.p,
                                           v_whole,
                                           false,
                                           settings);
  fmpm::MassMatrix::SharedNodes everywhere;
  for (unsigned int i = 0; i < n; ++i)
    everywhere.emplace_back(i, 3u);
  solve(everywhere);
  for (const Material &material : materials)
    EXPECT_LT(difference(material.v, v_whole), 1e-8 * v_whole.l2_norm());

  // No shared nodes: each material's own solve.
  solve({});
  for (Material &material : materials)
    {
      fmpm::GridVectorField v_alone = cloud.new_field();
      fmpm::MassMatrix::solve_full_mass_system(material.K,
                                               material.diagonal,
                                               material.m,
                                               nullptr,
                                               material.weak,
                                               material.p,
                                               v_alone,
                                               false,
                                               settings);
      EXPECT_LT(difference(material.v, v_alone), 1e-8 * v_alone.l2_norm());
    }

  // Every third node shared.
  fmpm::MassMatrix::SharedNodes some;
  std::vector<bool>             is_shared(n, false);
  for (unsigned int i = 0; i < n; i += 3)
    {
      some.emplace_back(i, 3u);
      is_shared[i] = true;
    }
  solve(some);
  std::vector<fmpm::GridVectorField> residual(2, cloud.new_field());
  double                             p_norm = 0;
  for (unsigned int a = 0; a < 2; ++a)
    {
      materials[a].K.vmult(residual[a], materials[a].v);
      residual[a].sadd(-1., 1., materials[a].p);
      p_norm += materials[a].p.norm_sqr();
    }
  p_norm = std::sqrt(p_norm);
  for (unsigned int d = 0; d < 2; ++d)
    {
      double momentum = 0;
      for (unsigned int i = 0; i < n; ++i)
        {
          const double r_0 = residual[0].block(d).local_element(i),
                       r_1 = residual[1].block(d).local_element(i);
          if (is_shared[i])
            {
              EXPECT_NEAR(materials[0].v.block(d).local_element(i),
                          materials[1].v.block(d).local_element(i),
                          1e-12 * v_whole.l2_norm());
              EXPECT_LT(std::abs(r_0 + r_1), 1e-10 * p_norm);
            }
          else
            {
              EXPECT_LT(std::abs(r_0), 1e-10 * p_norm);
              EXPECT_LT(std::abs(r_1), 1e-10 * p_norm);
            }
          for (const Material &material : materials)
            momentum += material.p.block(d).local_element(i) -
                        material.m.local_element(i) *
                          material.v.block(d).local_element(i);
        }
      EXPECT_LT(std::abs(momentum), 1e-13 * p_norm);
    }
  // Contact forces remain at the shared nodes: the materials differ.
  double force = 0;
  for (const auto &[i, group] : some)
    force += std::abs(residual[0].block(0).local_element(i));
  EXPECT_GT(force, 1e-3 * p_norm);
}
