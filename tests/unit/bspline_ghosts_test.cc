// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks fmpm::BSpline::vertices_beyond_ghost_cells() on one and two ranks
// (unit/BSplineGhosts.mpirun=2): the vertices found are the ones within two
// cells of the owned cells that are not locally relevant, at the positions
// of their DoFs; with them as further ghost entries every b2gimp and b2cpdi
// support of a point anywhere in an owned cell (domains up to half a cell,
// CPDI corners up to a cell away) finds all its vertices and is complete
// (Σ S = 1, Σ S x_i = x, Σ G = 0, Σ G ⊗ x_i = I with the nodes' true
// positions), while without them some b2cpdi supports on two ranks miss a
// vertex (b2gimp's boxes of less than a cell reach one cell only).

#include <fmpm/bspline_ghosts.h>
#include <fmpm/bspline_supports.h>
#include <fmpm/grid_transfer.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/affine_constraints.h>

#include <array>
#include <map>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using fmpm::BSpline::Boundary;
  using fmpm::ShapeFunction::Status;
  using fmpm::ShapeFunction::Type;

  template <typename T>
  class BSplineGhostsTest : public ::testing::Test
  {};
  template <int d>
  using Dim        = std::integral_constant<int, d>;
  using Dimensions = ::testing::Types<Dim<2>, Dim<3>>;
  TYPED_TEST_SUITE(BSplineGhostsTest, Dimensions);

  TYPED_TEST(BSplineGhostsTest, SupportsFindEveryVertexTwoCellsAway)
  {
    constexpr int      dim     = TypeParam::value;
    const MPI_Comm     comm    = MPI_COMM_WORLD;
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);

    // A box of 6 x 7 (x 5) cells of 0.3 x 0.25 (x 0.2), refined once.
    parallel::distributed::Triangulation<dim> triangulation(comm);
    std::vector<unsigned int>                 subdivisions;
    Point<dim>                                lower, upper;
    for (unsigned int d = 0; d < dim; ++d)
      {
        subdivisions.push_back(6 + d - (d == 2 ? 3 : 0));
        lower[d] = -0.5 + 0.1 * d;
        upper[d] = lower[d] + (0.6 - 0.1 * d) * subdivisions[d];
      }
    GridGenerator::subdivided_hyper_rectangle(triangulation,
                                              subdivisions,
                                              lower,
                                              upper);
    triangulation.refine_global(1);
    FE_Q<dim>       fe(1);
    DoFHandler<dim> dof_handler(triangulation);
    dof_handler.distribute_dofs(fe);
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);

    // Every DoF's position, from its owner.
    std::map<types::global_dof_index, Point<dim>> owned_points, positions;
    {
      std::map<types::global_dof_index, Point<dim>> points;
      DoFTools::map_dofs_to_support_points(MappingQ<dim>(1),
                                           dof_handler,
                                           points);
      for (const auto &[dof, x] : points)
        if (dof_handler.locally_owned_dofs().is_element(dof))
          owned_points[dof] = x;
      for (const auto &part : Utilities::MPI::all_gather(comm, owned_points))
        positions.insert(part.begin(), part.end());
      ASSERT_EQ(positions.size(), dof_handler.n_dofs());
    }

    const auto beyond = fmpm::BSpline::vertices_beyond_ghost_cells(dof_handler,
                                                                   relevant,
                                                                   2,
                                                                   comm);
    ASSERT_EQ(beyond.dofs.size(), beyond.positions.size());
    if (n_ranks == 1)
      {
        EXPECT_TRUE(beyond.dofs.empty());
      }
    // Not relevant, at their DoF's position, within two cells of an owned
    // cell (and every vertex that is: none missing).
    const double h[3] = {(upper[0] - lower[0]) / (2 * subdivisions[0]),
                         (upper[1] - lower[1]) / (2 * subdivisions[1]),
                         dim > 2 ? (upper[dim - 1] - lower[dim - 1]) /
                                     (2 * subdivisions[dim - 1]) :
                                   1.};
    std::vector<types::global_dof_index> expected;
    for (const auto &[dof, x] : positions)
      {
        if (relevant.is_element(dof))
          continue;
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              bool near = true;
              for (unsigned int d = 0; d < dim; ++d)
                near = near && x[d] > cell->vertex(0)[d] - 2.5 * h[d] &&
                       x[d] < cell->vertex(0)[d] + 3.5 * h[d];
              if (near)
                {
                  expected.push_back(dof);
                  break;
                }
            }
      }
    EXPECT_EQ(beyond.dofs, expected);
    for (unsigned int v = 0; v < beyond.dofs.size(); ++v)
      EXPECT_LT((beyond.positions[v] - positions[beyond.dofs[v]]).norm(),
                1e-12);
    const unsigned int n_beyond =
      Utilities::MPI::sum<unsigned int>(beyond.dofs.size(), comm);
    if (n_ranks > 1)
      {
        EXPECT_GT(n_beyond, 0u);
      }

    for (const bool with_beyond : {true, false})
      {
        IndexSet ghosts = relevant;
        if (with_beyond)
          ghosts.add_indices(beyond.index_set(dof_handler.n_dofs()));
        AffineConstraints<double> constraints;
        constraints.reinit(ghosts);
        constraints.close();
        const Utilities::MPI::Partitioner partitioner(
          dof_handler.locally_owned_dofs(), ghosts, comm);
        fmpm::GridTransfer<dim> transfer;
        transfer.reinit(dof_handler, constraints, partitioner);
        std::vector<Point<dim>> node_position(partitioner.locally_owned_size() +
                                              partitioner.n_ghost_indices());
        for (unsigned int i = 0; i < node_position.size(); ++i)
          node_position[i] = positions[partitioner.local_to_global(i)];

        for (const Type type : {Type::b2gimp, Type::b2cpdi})
          for (const Boundary boundary :
               {Boundary::open_knots, Boundary::padding})
            {
              fmpm::ShapeFunction::BSplineSupports<dim> supports;
              supports.reinit(
                type, boundary, transfer, triangulation.n_active_cells(), comm);
              if (with_beyond)
                {
                  std::vector<unsigned int> local;
                  for (const auto dof : beyond.dofs)
                    local.push_back(partitioner.global_to_local(dof));
                  supports.add_vertices(beyond.positions, local);
                }
              // Points near the corners and the centre of every owned
              // cell, domains of 0.45 cells, F stretching and shearing
              // them (CPDI corners up to 0.99 cells away).
              unsigned int   n_ok = 0, n_missing = 0;
              double         largest_defect = 0;
              const double   fractions[3]   = {0.02, 0.5, 0.98};
              Tensor<1, dim> l0;
              Tensor<2, dim> F;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  l0[d]   = 0.45 * h[d];
                  F[d][d] = 2;
                }
              F[0][1] = 0.2 * h[0] / h[1];
              for (const auto &cell : triangulation.active_cell_iterators())
                if (cell->is_locally_owned())
                  for (unsigned int q = 0; q < (dim == 2 ? 9u : 27u); ++q)
                    {
                      Point<dim>   x;
                      unsigned int rest = q;
                      for (unsigned int d = 0; d < dim; ++d)
                        {
                          x[d] =
                            cell->vertex(0)[d] + fractions[rest % 3] * h[d];
                          rest /= 3;
                        }
                      constexpr unsigned int n_max =
                        fmpm::ShapeFunction::BSplineSupports<
                          dim>::max_support_size;
                      unsigned int   node[n_max], count = 0;
                      double         S[n_max];
                      Tensor<1, dim> G[n_max];
                      const Status   status =
                        supports.support(x, F, l0, 0, node, S, G, count);
                      if (status == Status::in_padding_layer &&
                          boundary == Boundary::padding)
                        continue;
                      if (status == Status::vertex_not_on_rank)
                        {
                          ++n_missing;
                          continue;
                        }
                      ASSERT_EQ(status, Status::ok) << x;
                      ++n_ok;
                      double         sum_S = 0;
                      Tensor<1, dim> sum_Sx, sum_G;
                      Tensor<2, dim> sum_Gx;
                      for (unsigned int e = 0; e < count; ++e)
                        {
                          const Point<dim> &xi = node_position[node[e]];
                          sum_S += S[e];
                          sum_Sx += S[e] * xi;
                          sum_G += G[e];
                          sum_Gx += outer_product(xi, G[e]);
                        }
                      largest_defect = std::max(
                        largest_defect,
                        std::abs(sum_S - 1) + (sum_Sx - x).norm() +
                          sum_G.norm() / h[0] +
                          (sum_Gx - unit_symmetric_tensor<dim>()).norm());
                    }
              EXPECT_GT(n_ok, 0u);
              EXPECT_LT(largest_defect, 1e-11);
              const unsigned int all_missing =
                Utilities::MPI::sum(n_missing, comm);
              // Without them b2cpdi misses vertices on two ranks (corners
              // a cell away reach two cells); b2gimp does not: its box
              // x ± l, l < h/2, in [i − 1/2, i + 3/2] for a point in cell
              // [i, i + 1], meets the supports (j − 3/2, j + 3/2) of the
              // vertices i − 1 ... i + 2 only.
              const bool misses =
                !with_beyond && n_ranks > 1 && type == Type::b2cpdi;
              if (misses)
                {
                  EXPECT_GT(all_missing, 0u);
                }
              else
                {
                  EXPECT_EQ(all_missing, 0u)
                    << fmpm::ShapeFunction::parameter_name(type);
                }
            }
      }
  }
} // namespace
