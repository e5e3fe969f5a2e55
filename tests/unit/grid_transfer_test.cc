// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks fmpm::GridTransfer<dim> (dim = 2, 3): the reference shape functions
// and gradients against FE_Q<dim>(1); partition of unity, sum of gradients
// zero and exact reproduction of linear fields (including x itself, whose
// gradient is I) on a Cartesian, a sheared (parallelogram) and a randomly
// distorted (non-affine) mesh; S and G against deal.II's FE_Q<dim>(1) +
// MappingQ<dim>(1) through FEValues (pins the vertex/DoF ordering and the
// cached inverse Jacobian); the cached vertices and DoF indices; the
// is_affine flag; and has_constraints next to hanging nodes.

#include <fmpm/grid_transfer.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/partitioner.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/affine_constraints.h>

#include <array>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;

  constexpr double value_tolerance = 1e-12;
  // Gradients scale with 1/h (h ~ 0.2 - 0.5 here).
  constexpr double gradient_tolerance = 1e-11;

  enum class MeshKind
  {
    cartesian,
    sheared,
    distorted
  };

  /** Random points strictly inside the reference cell. */
  template <int dim>
  std::vector<Point<dim>>
  random_reference_points(const unsigned int n, const unsigned int seed)
  {
    std::mt19937                           generator(seed);
    std::uniform_real_distribution<double> uniform(0.02, 0.98);
    std::vector<Point<dim>>                points(n);
    for (auto &p : points)
      for (unsigned int d = 0; d < dim; ++d)
        p[d] = uniform(generator);
    return points;
  }

  /**
   * A p::d::Triangulation with an FE_Q(1) DoFHandler, hanging-node
   * constraints, the Partitioner and a GridTransfer, as the Simulator sets
   * them up.
   */
  template <int dim>
  struct TransferSetup
  {
    TransferSetup()
      : triangulation(MPI_COMM_WORLD)
      , fe(1)
      , dof_handler(triangulation)
    {}

    /** Non-square box with 3 cells per direction (irregular spacing). */
    void
    make_mesh(const MeshKind kind)
    {
      const std::array<double, 3>              low{{0.1, -0.2, 0.3}};
      const std::array<std::vector<double>, 3> steps{
        {{0.3, 0.5, 0.2}, {0.4, 0.25, 0.35}, {0.2, 0.45, 0.3}}};
      Point<dim>                       lower, upper;
      std::vector<std::vector<double>> step_sizes(dim);
      for (unsigned int d = 0; d < dim; ++d)
        {
          lower[d]      = low[d];
          upper[d]      = low[d];
          step_sizes[d] = steps[d];
          for (const double h : steps[d])
            upper[d] += h;
        }
      GridGenerator::subdivided_hyper_rectangle(triangulation,
                                                step_sizes,
                                                lower,
                                                upper);
      if (kind == MeshKind::sheared)
        {
          // x -> M x + c with a full (non-symmetric) M: parallelograms.
          Tensor<2, dim> M;
          for (unsigned int i = 0; i < dim; ++i)
            for (unsigned int j = 0; j < dim; ++j)
              M[i][j] = (i == j) ? 1.0 + 0.1 * i : 0.15 * (i + 1) - 0.1 * j;
          Tensor<1, dim> c;
          for (unsigned int d = 0; d < dim; ++d)
            c[d] = 0.05 * (d + 1);
          GridTools::transform(
            [&](const Point<dim> &p) { return Point<dim>(M * p + c); },
            triangulation);
        }
      else if (kind == MeshKind::distorted)
        GridTools::distort_random(0.25, triangulation, false, 4242);
    }

    void
    setup()
    {
      dof_handler.distribute_dofs(fe);
      const IndexSet locally_owned_dofs = dof_handler.locally_owned_dofs();
      IndexSet       locally_relevant_dofs;
      DoFTools::extract_locally_relevant_dofs(dof_handler,
                                              locally_relevant_dofs);
      constraints.clear();
      constraints.reinit(locally_relevant_dofs);
      DoFTools::make_hanging_node_constraints(dof_handler, constraints);
      constraints.close();
      partitioner =
        std::make_shared<Utilities::MPI::Partitioner>(locally_owned_dofs,
                                                      locally_relevant_dofs,
                                                      MPI_COMM_WORLD);
      transfer.reinit(dof_handler, constraints, *partitioner);
    }

    parallel::distributed::Triangulation<dim>    triangulation;
    FE_Q<dim>                                    fe;
    DoFHandler<dim>                              dof_handler;
    AffineConstraints<double>                    constraints;
    std::shared_ptr<Utilities::MPI::Partitioner> partitioner;
    fmpm::GridTransfer<dim>                      transfer;
  };

  template <typename T>
  class GridTransferTest : public ::testing::Test
  {};

  template <int d>
  using Dim        = std::integral_constant<int, d>;
  using Dimensions = ::testing::Types<Dim<2>, Dim<3>>;
  TYPED_TEST_SUITE(GridTransferTest, Dimensions);



  // The static reference functions equal FE_Q<dim>(1) on the unit cell,
  // and S_i(vertex j) = delta_ij (DoF i sits on vertex i).
  TYPED_TEST(GridTransferTest, ReferenceFunctionsMatchFEQ1)
  {
    constexpr int dim    = TypeParam::value;
    using Transfer       = fmpm::GridTransfer<dim>;
    constexpr unsigned n = Transfer::n_nodes;
    const FE_Q<dim>    fe(1);
    ASSERT_EQ(fe.n_dofs_per_cell(), n);

    std::array<double, n>         S;
    std::array<Tensor<1, dim>, n> dS;
    for (unsigned int j = 0; j < n; ++j)
      {
        const Point<dim> vertex = GeometryInfo<dim>::unit_cell_vertex(j);
        Transfer::values(vertex, S);
        for (unsigned int i = 0; i < n; ++i)
          EXPECT_NEAR(S[i], i == j ? 1.0 : 0.0, value_tolerance)
            << "vertex " << j << " node " << i;
      }

    for (const Point<dim> &xi : random_reference_points<dim>(20, 1 + dim))
      {
        Transfer::values(xi, S);
        Transfer::reference_gradients(xi, dS);
        double         sum_S = 0;
        Tensor<1, dim> sum_dS;
        for (unsigned int i = 0; i < n; ++i)
          {
            EXPECT_NEAR(S[i], fe.shape_value(i, xi), value_tolerance)
              << "node " << i << " at " << xi;
            const Tensor<1, dim> expected = fe.shape_grad(i, xi);
            for (unsigned int d = 0; d < dim; ++d)
              EXPECT_NEAR(dS[i][d], expected[d], value_tolerance)
                << "node " << i << " component " << d << " at " << xi;
            sum_S += S[i];
            sum_dS += dS[i];
          }
        EXPECT_NEAR(sum_S, 1.0, value_tolerance);
        EXPECT_NEAR(sum_dS.norm(), 0.0, value_tolerance);
      }
  }



  /**
   * On every cell of a mesh of kind @p kind, at random reference points:
   * partition of unity, sum of gradients zero, exact reproduction of x and
   * of a general linear field, and S, G, x(xi) equal to what FEValues with
   * FE_Q(1) and MappingQ(1) gives. Also the cached vertices and DoFs.
   */
  template <int dim>
  void
  check_mesh(const MeshKind kind)
  {
    using Transfer       = fmpm::GridTransfer<dim>;
    constexpr unsigned n = Transfer::n_nodes;

    TransferSetup<dim> setup;
    setup.make_mesh(kind);
    setup.setup();

    const std::vector<Point<dim>> points = random_reference_points<dim>(6, 7);
    const MappingQ<dim>           mapping(1);
    FEValues<dim>                 fe_values(mapping,
                            setup.fe,
                            Quadrature<dim>(points),
                            update_values | update_gradients |
                              update_quadrature_points);

    // A general (non-symmetric) linear field u(x) = A x + b.
    Tensor<2, dim> A;
    Tensor<1, dim> b;
    for (unsigned int i = 0; i < dim; ++i)
      {
        b[i] = 0.3 - 0.7 * i;
        for (unsigned int j = 0; j < dim; ++j)
          A[i][j] = 1.0 + 0.5 * i - 1.3 * j + 0.2 * i * j;
      }
    const Tensor<2, dim> identity = unit_symmetric_tensor<dim>();

    unsigned int                         n_non_affine = 0;
    unsigned int                         n_cells      = 0;
    std::vector<types::global_dof_index> dofs(n);
    std::array<double, n>                S;
    std::array<Tensor<1, dim>, n>        G;
    for (const auto &cell : setup.dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        ++n_cells;
        const auto &data = setup.transfer.cell_data(cell->active_cell_index());
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < n; ++i)
          {
            EXPECT_EQ(setup.transfer.dof_index(data, i), dofs[i]);
            EXPECT_EQ(data.local_index[i],
                      setup.partitioner->global_to_local(dofs[i]));
            EXPECT_LT((data.vertex[i] - cell->vertex(i)).norm(), 1e-14);
          }
        EXPECT_FALSE(data.has_constraints);
        if (kind != MeshKind::distorted)
          {
            EXPECT_TRUE(data.is_affine) << "cell " << cell->active_cell_index();
          }
        if (!data.is_affine)
          ++n_non_affine;

        fe_values.reinit(cell);
        for (unsigned int q = 0; q < points.size(); ++q)
          {
            const Point<dim> &xi = points[q];
            Transfer::values_and_gradients(data, xi, S, G);

            const Point<dim> x = mapping.transform_unit_to_real_cell(cell, xi);
            double           sum_S = 0;
            Tensor<1, dim>   sum_G;
            Point<dim>       x_h;
            Tensor<2, dim>   grad_x, grad_u;
            Tensor<1, dim>   u_h;
            for (unsigned int i = 0; i < n; ++i)
              {
                const Point<dim>    &x_i = cell->vertex(i);
                const Tensor<1, dim> u_i = A * x_i + b;
                sum_S += S[i];
                sum_G += G[i];
                x_h += S[i] * x_i;
                u_h += S[i] * u_i;
                grad_x += outer_product(x_i, G[i]);
                grad_u += outer_product(u_i, G[i]);

                EXPECT_NEAR(S[i], fe_values.shape_value(i, q), value_tolerance)
                  << "cell " << cell->active_cell_index() << " node " << i;
                EXPECT_LT((G[i] - fe_values.shape_grad(i, q)).norm(),
                          gradient_tolerance)
                  << "cell " << cell->active_cell_index() << " node " << i
                  << ": G = " << G[i]
                  << ", FEValues: " << fe_values.shape_grad(i, q);
              }
            EXPECT_NEAR(sum_S, 1.0, value_tolerance);
            EXPECT_LT(sum_G.norm(), gradient_tolerance);
            EXPECT_LT((x_h - x).norm(), value_tolerance)
              << "x_h = " << x_h << ", mapped point " << x;
            EXPECT_LT((x_h - fe_values.quadrature_point(q)).norm(),
                      value_tolerance);
            EXPECT_LT((u_h - (A * x + b)).norm(), 1e-11);
            EXPECT_LT((grad_x - identity).norm(), 1e-11)
              << "sum_i x_i (x) G_i = " << grad_x;
            EXPECT_LT((grad_u - A).norm(), 1e-11)
              << "sum_i u_i (x) G_i = " << grad_u << ", A = " << A;
          }
      }
    EXPECT_EQ(n_cells, Utilities::pow(3u, dim));
    if (kind == MeshKind::distorted)
      EXPECT_GT(n_non_affine, 0u);
    else
      EXPECT_EQ(n_non_affine, 0u);
  }



  TYPED_TEST(GridTransferTest, CartesianMesh)
  {
    check_mesh<TypeParam::value>(MeshKind::cartesian);
  }



  // Parallelograms: affine, but with a full Jacobian, so the cached inverse
  // Jacobian transpose is used and a missing transpose shows.
  TYPED_TEST(GridTransferTest, ShearedMesh)
  {
    check_mesh<TypeParam::value>(MeshKind::sheared);
  }



  TYPED_TEST(GridTransferTest, DistortedMesh)
  {
    check_mesh<TypeParam::value>(MeshKind::distorted);
  }



  // Refine the centre cell once: exactly its 2^dim children have a
  // constrained (hanging) DoF; no other cell has one.
  TYPED_TEST(GridTransferTest, HasConstraintsNextToHangingNodes)
  {
    constexpr int      dim = TypeParam::value;
    TransferSetup<dim> setup;
    setup.make_mesh(MeshKind::cartesian);
    Point<dim> center;
    for (const auto &cell : setup.triangulation.active_cell_iterators())
      center += cell->center() / setup.triangulation.n_active_cells();
    for (const auto &cell : setup.triangulation.active_cell_iterators())
      if (cell->point_inside(center))
        {
          cell->set_refine_flag();
          break;
        }
    setup.triangulation.execute_coarsening_and_refinement();
    ASSERT_EQ(setup.triangulation.n_active_cells(),
              Utilities::pow(3u, dim) - 1 + Utilities::pow(2u, dim));
    setup.setup();
    ASSERT_GT(setup.constraints.n_constraints(), 0u);

    unsigned int n_with_constraints = 0;
    for (const auto &cell : setup.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          bool next_to_coarser = false;
          for (const unsigned int f : cell->face_indices())
            if (!cell->at_boundary(f) && cell->neighbor_is_coarser(f))
              next_to_coarser = true;
          const auto &data =
            setup.transfer.cell_data(cell->active_cell_index());
          EXPECT_EQ(data.has_constraints, next_to_coarser)
            << "cell " << cell->active_cell_index() << " on level "
            << cell->level();
          EXPECT_TRUE(data.is_affine);
          if (data.has_constraints)
            ++n_with_constraints;
        }
    EXPECT_EQ(n_with_constraints, Utilities::pow(2u, dim));
  }
} // namespace
