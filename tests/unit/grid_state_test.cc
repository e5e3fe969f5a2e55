// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The centre-of-mass field solve (GridState::compute) on a tiny grid of two
// points and four nodes (one empty), against values computed here by hand:
// the lumped fields m⁻¹p, m⁻¹p⁺, m⁻¹f (seed 000 Eq. 1.7), and the full-mass
// fields as the FMPM(k) partial sums z₁ = m⁻¹q, z_{j+1} = z_j + m⁻¹(q − m̃ z_j)
// (Eqs. 1.22-1.23) of q = p, p⁺, f; a field solved once per step is kept;
// a material's field (Contact::MaterialField) through the same solve gives
// the same bits.

#include <fmpm/contact/manager.h>
#include <fmpm/grid_state.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/mass_matrix/series.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <array>
#include <cmath>
#include <cstring>

#include "series_helpers.h"
#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using namespace fmpm::ParticleUpdate;

  constexpr unsigned int n_nodes  = 4; // per rank; node 3 empty
  constexpr unsigned int n_points = 2;
  constexpr double       dt       = 0.25;

  // S_pi of the two points at nodes 0-2, their masses and velocities.
  constexpr double S[n_points][3] = {{0.7, 0.3, 0.}, {0., 0.4, 0.6}};
  constexpr double M[n_points]    = {2., 3.};
  constexpr double V[n_points][3] = {{1., -2., 0.5}, {0.5, 1., -1.}};
  // Forces per node and component (f), and p⁺ = p + f Δt.
  constexpr double F[3][3] = {{0.3, -0.1, 0.2},
                              {1., 0.5, -0.4},
                              {-0.2, 0.7, 0.}};

  /** The FMPM(k) mass matrix of a fixed m̃ (the test's plugin): v =
   * m̃ₖ⁻¹p by the series of series.h; records the residual scale. */
  template <int dim>
  class SeriesMassMatrix : public fmpm::MassMatrix::Interface<dim>
  {
  public:
    SeriesMassMatrix(const TrilinosWrappers::SparseMatrix &m_tilde,
                     const fmpm::GridScalar               &m,
                     const unsigned int                    k)
      : m_tilde(m_tilde)
      , m(m)
      , k(k)
    {}

    void
    solve(const fmpm::GridVectorField &p,
          fmpm::GridVectorField       &v) const override
    {
      fmpm_tests::fmpm_inverse(m_tilde, m, p, v, k, 1e-12);
      ++n_solves;
    }

    void
    solve_from_guess(const fmpm::GridVectorField &p,
                     fmpm::GridVectorField       &v,
                     const double                 residual_scale) const override
    {
      last_residual_scale = residual_scale;
      solve(p, v);
    }

    mutable double       last_residual_scale = -1;
    mutable unsigned int n_solves            = 0;

  private:
    const TrilinosWrappers::SparseMatrix &m_tilde;
    const fmpm::GridScalar               &m;
    const unsigned int                    k;
  };

  template <int dim>
  struct TinyGrid
  {
    std::shared_ptr<const Utilities::MPI::Partitioner> partitioner;
    unsigned int                                       first = 0;
    TrilinosWrappers::SparseMatrix                     m_tilde;
    fmpm::GridState<dim>                               state;
    fmpm::FieldSolver<dim>                             solver;
    // By hand: m, m̃ (nodes 0-2), p, p⁺, f per node and component.
    std::array<double, n_nodes>                      m{};
    std::array<std::array<double, n_nodes>, n_nodes> m_tilde_hand{};
    std::array<std::array<double, dim>, n_nodes>     p{}, p_updated{}, f{};

    TinyGrid()
    {
      const unsigned int rank =
        Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
      const unsigned int n_ranks =
        Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
      first = rank * n_nodes;
      IndexSet owned(n_nodes * n_ranks);
      owned.add_range(first, first + n_nodes);
      partitioner =
        std::make_shared<Utilities::MPI::Partitioner>(owned,
                                                      owned,
                                                      MPI_COMM_WORLD);

      for (unsigned int q = 0; q < n_points; ++q)
        for (unsigned int i = 0; i < 3; ++i)
          {
            m[i] += M[q] * S[q][i];
            for (unsigned int d = 0; d < dim; ++d)
              p[i][d] += M[q] * S[q][i] * V[q][d];
            for (unsigned int j = 0; j < 3; ++j)
              m_tilde_hand[i][j] += M[q] * S[q][i] * S[q][j];
          }
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int d = 0; d < dim; ++d)
          {
            f[i][d]         = F[i][d];
            p_updated[i][d] = p[i][d] + F[i][d] * dt;
          }

      TrilinosWrappers::SparsityPattern sparsity(owned, MPI_COMM_WORLD);
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = 0; j < 3; ++j)
          sparsity.add(first + i, first + j);
      sparsity.compress();
      m_tilde.reinit(sparsity);
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = 0; j < 3; ++j)
          m_tilde.set(first + i, first + j, m_tilde_hand[i][j]);
      m_tilde.compress(VectorOperation::insert);

      state.reinit(partitioner, false);
      for (unsigned int i = 0; i < n_nodes; ++i)
        {
          state.mass.local_element(i) = m[i];
          for (unsigned int d = 0; d < dim; ++d)
            {
              state.momentum.block(d).local_element(i) = p[i][d];
              state.updated_momentum.block(d).local_element(i) =
                p_updated[i][d];
              state.force.block(d).local_element(i) = f[i][d];
            }
        }
      state.mass_floor  = 1e-12;
      solver.mass_floor = 1e-12;
      solver.t_begin    = 0;
      solver.t_end      = dt;
    }

    /** The FMPM(k) partial sum z_k of q, by hand. */
    std::array<std::array<double, dim>, n_nodes>
    series(const std::array<std::array<double, dim>, n_nodes> &q,
           const unsigned int                                  k) const
    {
      std::array<std::array<double, dim>, n_nodes> z{};
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int d = 0; d < dim; ++d)
          z[i][d] = q[i][d] / m[i];
      for (unsigned int j = 1; j < k; ++j)
        {
          auto next = z;
          for (unsigned int i = 0; i < 3; ++i)
            for (unsigned int d = 0; d < dim; ++d)
              {
                double m_tilde_z = 0;
                for (unsigned int l = 0; l < 3; ++l)
                  m_tilde_z += m_tilde_hand[i][l] * z[l][d];
                next[i][d] = z[i][d] + (q[i][d] - m_tilde_z) / m[i];
              }
          z = next;
        }
      return z;
    }

    void
    expect_field(const GridField                                     field,
                 const std::array<std::array<double, dim>, n_nodes> &hand) const
    {
      const fmpm::GridVectorField &v = state.fields[field];
      for (unsigned int i = 0; i < n_nodes; ++i)
        for (unsigned int d = 0; d < dim; ++d)
          EXPECT_NEAR(v.block(d).local_element(i),
                      hand[i][d],
                      1e-14 * (1 + std::abs(hand[i][d])))
            << "field " << field << ", node " << i << ", component " << d;
    }
  };



  template <int dim>
  void
  lumped_fields_are_m_inverse_q()
  {
    TinyGrid<dim>         grid;
    SeriesMassMatrix<dim> mass_matrix(grid.m_tilde, grid.state.mass, 3);
    const std::array<GridField, 3> fields = {
      {lumped_velocity, lumped_updated_velocity, lumped_acceleration}};
    const std::array<const std::array<std::array<double, dim>, n_nodes> *, 3>
      sources = {{&grid.p, &grid.p_updated, &grid.f}};
    for (unsigned int n = 0; n < 3; ++n)
      {
        grid.state.compute(fields[n], grid.solver, mass_matrix, dt);
        EXPECT_TRUE(grid.state.computed[fields[n]]);
        // k = 1: the lumped field; the empty node stays zero.
        grid.expect_field(fields[n], grid.series(*sources[n], 1));
      }
    EXPECT_EQ(mass_matrix.n_solves, 0u); // no full-mass solve
  }



  template <int dim>
  void
  full_mass_fields_are_fmpm_partial_sums()
  {
    for (const unsigned int k : {1u, 2u, 3u, 6u})
      {
        TinyGrid<dim>         grid;
        SeriesMassMatrix<dim> mass_matrix(grid.m_tilde, grid.state.mass, k);
        grid.state.compute(velocity, grid.solver, mass_matrix, dt);
        grid.expect_field(velocity, grid.series(grid.p, k));
        EXPECT_EQ(mass_matrix.last_residual_scale, 0.);
        grid.state.compute(updated_velocity, grid.solver, mass_matrix, dt);
        grid.expect_field(updated_velocity, grid.series(grid.p_updated, k));
        // a = m̃ₖ⁻¹f, as accurate in a Δt as v in p.
        grid.state.compute(acceleration, grid.solver, mass_matrix, dt);
        grid.expect_field(acceleration, grid.series(grid.f, k));
        EXPECT_DOUBLE_EQ(mass_matrix.last_residual_scale,
                         grid.state.momentum.l2_norm() / dt +
                           grid.state.force.l2_norm());
        EXPECT_EQ(mass_matrix.n_solves, 3u);

        // Solved once per step: new momenta do not change a computed field.
        grid.state.momentum *= 2.;
        grid.state.compute(velocity, grid.solver, mass_matrix, dt);
        EXPECT_EQ(mass_matrix.n_solves, 3u);
        grid.expect_field(velocity, grid.series(grid.p, k));
      }
  }



  template <int dim>
  void
  material_solve_gives_the_same_bits()
  {
    TinyGrid<dim>         grid;
    SeriesMassMatrix<dim> mass_matrix(grid.m_tilde, grid.state.mass, 2);
    fmpm::Contact::MaterialField<dim> material;
    material.reinit(grid.partitioner, true);
    material.mass             = grid.state.mass;
    material.momentum         = grid.state.momentum;
    material.updated_momentum = grid.state.updated_momentum;
    material.force            = grid.state.force;
    for (const GridField field : {lumped_velocity,
                                  lumped_updated_velocity,
                                  lumped_acceleration,
                                  velocity})
      {
        grid.state.compute(field, grid.solver, mass_matrix, dt);
        grid.solver.solve(
          material,
          field,
          [&](const fmpm::GridVectorField &q, fmpm::GridVectorField &target) {
            mass_matrix.solve(q, target);
          },
          false);
        EXPECT_TRUE(material.computed[field]);
        for (unsigned int d = 0; d < dim; ++d)
          EXPECT_EQ(std::memcmp(grid.state.fields[field].block(d).begin(),
                                material.fields[field].block(d).begin(),
                                n_nodes * sizeof(double)),
                    0)
            << "field " << field << ", component " << d;
      }
  }
} // namespace

TEST(GridState, LumpedFieldsAreMInverseQ2d)
{
  lumped_fields_are_m_inverse_q<2>();
}

TEST(GridState, LumpedFieldsAreMInverseQ3d)
{
  lumped_fields_are_m_inverse_q<3>();
}

TEST(GridState, FullMassFieldsAreFmpmPartialSums2d)
{
  full_mass_fields_are_fmpm_partial_sums<2>();
}

TEST(GridState, FullMassFieldsAreFmpmPartialSums3d)
{
  full_mass_fields_are_fmpm_partial_sums<3>();
}

TEST(GridState, MaterialSolveGivesTheSameBits2d)
{
  material_solve_gives_the_same_bits<2>();
}
