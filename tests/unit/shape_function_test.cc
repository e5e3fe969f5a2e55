// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks the effective shape functions of fmpm::ShapeFunction (seed 001,
// "Shape functions for MPM, GIMP, and CPDI") for dim = 2, 3: partition of
// unity, sum of gradients zero and exact linear fields (value at the point
// and gradient) at random points on uniform, randomly distorted and
// hanging-node meshes for every type; GIMP's closed forms against the split
// quadrature on uniform cells; the classic weights at the centre when a
// domain lies inside one cell; the split quadrature against brute-force
// sampling on distorted and hanging-node meshes; domains that reach too far
// are reported; and whole runs that conserve momentum with each type.

#include <fmpm/grid_transfer.h>
#include <fmpm/parameters.h>
#include <fmpm/shape_function.h>
#include <fmpm/simulator.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/affine_constraints.h>

#include <map>
#include <memory>
#include <random>
#include <vector>

#include "scene_helpers.h"
#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using fmpm::ShapeFunction::Type;

  enum class MeshKind
  {
    uniform,
    distorted,
    hanging
  };

  const std::vector<Type> all_types{Type::classic,
                                    Type::ugimp,
                                    Type::cpgimp,
                                    Type::cpdi};

  std::string
  name(const Type type)
  {
    return fmpm::ShapeFunction::parameter_name(type);
  }

  std::string
  name(const MeshKind kind)
  {
    return kind == MeshKind::uniform ?
             "uniform" :
             (kind == MeshKind::distorted ? "distorted" : "hanging");
  }

  /** The unit cube with n cells per direction, as the Simulator sets up. */
  template <int dim>
  struct Setup
  {
    Setup(const MeshKind kind, const unsigned int n)
      : triangulation(MPI_COMM_WORLD)
      , fe(1)
      , dof_handler(triangulation)
      , h(1.0 / n)
    {
      GridGenerator::subdivided_hyper_cube(triangulation, n, 0, 1);
      if (kind == MeshKind::distorted)
        GridTools::distort_random(0.25, triangulation, true, 4242);
      if (kind == MeshKind::hanging)
        {
          // Refine the cells left of x = 0.5 and one more inside the right
          // half: coarse-fine faces in both directions.
          for (const auto &cell : triangulation.active_cell_iterators())
            if (cell->center()[0] < 0.5 ||
                (cell->center() - Point<dim>()).norm() > 0.5 * std::sqrt(dim))
              cell->set_refine_flag();
          triangulation.execute_coarsening_and_refinement();
        }
      dof_handler.distribute_dofs(fe);
      const IndexSet owned = dof_handler.locally_owned_dofs();
      IndexSet       relevant;
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      constraints.reinit(relevant);
      DoFTools::make_hanging_node_constraints(dof_handler, constraints);
      constraints.close();
      partitioner =
        std::make_shared<Utilities::MPI::Partitioner>(owned,
                                                      relevant,
                                                      MPI_COMM_WORLD);
      transfer.reinit(dof_handler, constraints, *partitioner);
      DoFTools::map_dofs_to_support_points(MappingQ<dim>(1),
                                           dof_handler,
                                           support_points);
    }

    /** The active cell index of the cell around x. */
    unsigned int
    cell_of(const Point<dim> &x) const
    {
      const auto found =
        GridTools::find_active_cell_around_point(MappingQ<dim>(1),
                                                 triangulation,
                                                 x);
      return found.first->active_cell_index();
    }

    Point<dim>
    position(const fmpm::ShapeFunction::Node<dim> &node) const
    {
      return support_points.at(node.dof);
    }

    parallel::distributed::Triangulation<dim>     triangulation;
    FE_Q<dim>                                     fe;
    DoFHandler<dim>                               dof_handler;
    AffineConstraints<double>                     constraints;
    std::shared_ptr<Utilities::MPI::Partitioner>  partitioner;
    fmpm::GridTransfer<dim>                       transfer;
    std::map<types::global_dof_index, Point<dim>> support_points;
    const double                                  h;
  };

  template <int dim>
  Tensor<2, dim>
  random_deformation_gradient(std::mt19937 &generator, const double amount)
  {
    std::uniform_real_distribution<double> uniform(-amount, amount);
    Tensor<2, dim>                         F;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = 0; j < dim; ++j)
        F[i][j] = (i == j ? 1 : 0) + uniform(generator);
    return F;
  }

  template <typename T>
  class ShapeFunctionTest : public ::testing::Test
  {};

  template <int d>
  using Dim        = std::integral_constant<int, d>;
  using Dimensions = ::testing::Types<Dim<2>, Dim<3>>;
  TYPED_TEST_SUITE(ShapeFunctionTest, Dimensions);



  // Σ S̄ = 1, Σ Ḡ = 0, Σ v_g S̄ = v(x_p) and Σ v_g ⊗ Ḡ = ∇v for a linear
  // field v = A x + b (every shape function reproduces it: the FE_Q(1)
  // basis reproduces linear fields on any mesh, GIMP averages over a box
  // centred at x_p, CPDI over corners symmetric about x_p), at random
  // points and deformation gradients, on three kinds of meshes.
  TYPED_TEST(ShapeFunctionTest, PartitionOfUnityAndLinearFieldsOnAnyMesh)
  {
    constexpr int                          dim = TypeParam::value;
    std::mt19937                           generator(17 + dim);
    std::uniform_real_distribution<double> uniform(0.2, 0.8), unit(-1, 1);
    Tensor<2, dim>                         A;
    Tensor<1, dim>                         b;
    for (unsigned int i = 0; i < dim; ++i)
      {
        b[i] = unit(generator);
        for (unsigned int j = 0; j < dim; ++j)
          A[i][j] = unit(generator);
      }
    for (const MeshKind kind :
         {MeshKind::uniform, MeshKind::distorted, MeshKind::hanging})
      {
        Setup<dim> setup(kind, dim == 2 ? 8 : 4);
        // Half-lengths: a quarter of the finest cell (hanging: h/2).
        const double l = 0.25 * setup.h * (kind == MeshKind::hanging ? 0.5 : 1);
        std::vector<fmpm::ShapeFunction::Node<dim>> support;
        unsigned int                                n_checked = 0;
        for (unsigned int p = 0; p < (dim == 2 ? 40 : 15); ++p)
          {
            Point<dim>     x;
            Tensor<1, dim> l0;
            for (unsigned int d = 0; d < dim; ++d)
              {
                x[d]  = uniform(generator);
                l0[d] = l * (0.6 + 0.4 * (d + 1) / dim);
              }
            const Tensor<2, dim> F =
              random_deformation_gradient<dim>(generator, 0.3);
            const unsigned int cell = setup.cell_of(x);
            for (const Type type : all_types)
              {
                const auto status = fmpm::ShapeFunction::compute_support(
                  type, setup.transfer, cell, x, F, l0, support);
                ASSERT_EQ(status, fmpm::ShapeFunction::Status::ok)
                  << name(type) << " on " << name(kind) << " at " << x;
                double         sum_S = 0, value_error = 0;
                Tensor<1, dim> sum_G, value;
                Tensor<2, dim> gradient;
                for (const auto &node : support)
                  {
                    const Tensor<1, dim> v = A * setup.position(node) + b;
                    sum_S += node.S;
                    sum_G += node.G;
                    value += node.S * v;
                    gradient += outer_product(v, node.G);
                  }
                value_error = (value - (A * x + b)).norm();
                const std::string where =
                  name(type) + " on " + name(kind) + " mesh";
                EXPECT_NEAR(sum_S, 1.0, 1e-12) << where << " at " << x;
                EXPECT_NEAR(sum_G.norm() * setup.h, 0.0, 1e-12)
                  << where << " at " << x;
                EXPECT_NEAR(value_error, 0.0, 1e-12) << where << " at " << x;
                EXPECT_NEAR((gradient - A).norm(), 0.0, 1e-10)
                  << where << " at " << x;
                ++n_checked;
              }
          }
        EXPECT_GT(n_checked, 0u);
      }
  }



  // On uniform axis-aligned cells the closed forms of seed 001 (Eqs.
  // gimp_shape, gimpGrad) equal the quadrature split at the cell faces,
  // node by node, for uGIMP and cpGIMP; the closed-form path is the one
  // taken inside the mesh.
  // UniformGimpPatch (the closed forms the support cache uses) against a
  // brute force over every node of the mesh: a node is in the support when
  // a cell of the mesh that has it as a vertex overlaps the box x ± l, with
  // S̄ = Π_d S̄_d and Ḡ_d = Ḡ_d Π_{e≠d} S̄_e. Cells at the mesh boundary have
  // a patch without the cells outside: it applies to boxes inside the mesh
  // (the others take the quadrature, which reports them).
  TYPED_TEST(ShapeFunctionTest, GimpPatchEqualsBruteForce)
  {
    constexpr int dim = TypeParam::value;
    Setup<dim>    setup(MeshKind::uniform, dim == 2 ? 6 : 4);
    const double  h = setup.h;
    std::mt19937  generator(11 + dim);
    std::uniform_real_distribution<double> anywhere(1e-9, 1 - 1e-9),
      size(0.05, 0.5);
    unsigned int n_tested = 0, n_boundary_tested = 0;
    for (unsigned int p = 0; p < 200; ++p)
      {
        Point<dim>     x;
        Tensor<1, dim> l;
        for (unsigned int d = 0; d < dim; ++d)
          {
            x[d] = anywhere(generator);
            l[d] = size(generator) * h;
          }
        const unsigned int cell = setup.cell_of(x);
        ASSERT_TRUE(setup.transfer.cell_data(cell).uniform_patch);
        fmpm::ShapeFunction::UniformGimpPatch<dim> patch;
        patch.reinit(setup.transfer, cell);
        // The closed forms hold unless the box leaves the mesh.
        bool inside_mesh = true, at_boundary = false;
        for (unsigned int d = 0; d < dim; ++d)
          {
            inside_mesh = inside_mesh && x[d] - l[d] > 0 && x[d] + l[d] < 1;
            at_boundary = at_boundary || x[d] < h || x[d] > 1 - h;
          }
        ASSERT_EQ(patch.applies(x, l), inside_mesh) << x << ", l " << l;
        if (!inside_mesh)
          continue;
        ++n_tested;
        n_boundary_tested += at_boundary;
        std::map<types::global_dof_index, std::pair<double, Tensor<1, dim>>>
          found;
        patch.for_each_node(x,
                            l,
                            [&](const unsigned int,
                                const types::global_dof_index dof,
                                const double                  S,
                                const Tensor<1, dim>         &G) {
                              EXPECT_EQ(found.count(dof), 0u); // once each
                              found[dof] = {S, G};
                            });
        unsigned int n_expected = 0;
        for (const auto &[dof, X] : setup.support_points)
          {
            bool   in_support = true;
            double S          = 1;
            double w[dim], dw[dim];
            for (unsigned int d = 0; d < dim; ++d)
              {
                bool overlapped = false;
                for (const double lower : {X[d] - h, X[d]})
                  if (lower > -1e-12 && lower + h < 1 + 1e-12 &&
                      lower < x[d] + l[d] && lower + h > x[d] - l[d])
                    overlapped = true;
                in_support = in_support && overlapped;
                fmpm::ShapeFunction::gimp_1d(x[d] - X[d], h, l[d], w[d], dw[d]);
                S *= w[d];
              }
            Tensor<1, dim> G;
            for (unsigned int d = 0; d < dim; ++d)
              {
                G[d] = dw[d];
                for (unsigned int e = 0; e < dim; ++e)
                  if (e != d)
                    G[d] *= w[e];
              }
            if (!in_support || (S == 0 && G.norm_square() == 0))
              {
                EXPECT_EQ(found.count(dof), 0u) << "node at " << X;
                continue;
              }
            ++n_expected;
            ASSERT_EQ(found.count(dof), 1u) << "node at " << X << ", x " << x;
            EXPECT_NEAR(found[dof].first, S, 1e-14) << X;
            EXPECT_NEAR((found[dof].second - G).norm() * h, 0, 1e-13) << X;
          }
        EXPECT_EQ(found.size(), n_expected);
      }
    // Every cell has a uniform patch; those at the mesh boundary lack
    // cells, and boxes that stay in the mesh there are tested too.
    EXPECT_GT(n_tested, dim == 2 ? 100u : 50u);
    EXPECT_GT(n_boundary_tested, dim == 2 ? 60u : 40u);
  }

  TYPED_TEST(ShapeFunctionTest, GimpClosedFormsEqualQuadratureOnUniformCells)
  {
    constexpr int dim = TypeParam::value;
    Setup<dim>    setup(MeshKind::uniform, dim == 2 ? 8 : 5);
    std::mt19937  generator(3 + dim);
    std::uniform_real_distribution<double> uniform(0.25, 0.75),
      size(0.05, 0.45);
    std::vector<fmpm::ShapeFunction::Node<dim>> closed, quadrature;
    unsigned int                                n_closed = 0;
    for (unsigned int p = 0; p < 30; ++p)
      {
        Point<dim>     x;
        Tensor<1, dim> l0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            x[d]  = uniform(generator);
            l0[d] = size(generator) * setup.h;
          }
        // cpGIMP: a diagonal F keeps l = F l0 below h/2.
        Tensor<2, dim> F;
        for (unsigned int d = 0; d < dim; ++d)
          F[d][d] = 0.8 + 0.3 * d / dim;
        const unsigned int cell = setup.cell_of(x);
        EXPECT_TRUE(setup.transfer.cell_data(cell).uniform_patch);
        for (const Type type : {Type::ugimp, Type::cpgimp})
          {
            fmpm::ShapeFunction::compute_support(
              type, setup.transfer, cell, x, F, l0, closed, true);
            fmpm::ShapeFunction::compute_support(
              type, setup.transfer, cell, x, F, l0, quadrature, false);
            std::map<unsigned int, std::pair<double, Tensor<1, dim>>> q;
            for (const auto &node : quadrature)
              q[node.local_index] = {node.S, node.G};
            for (const auto &node : closed)
              {
                ASSERT_TRUE(q.count(node.local_index)) << name(type);
                EXPECT_NEAR(node.S, q[node.local_index].first, 1e-13)
                  << name(type) << " at " << x;
                EXPECT_NEAR((node.G - q[node.local_index].second).norm() *
                              setup.h,
                            0.0,
                            1e-13)
                  << name(type) << " at " << x;
                q.erase(node.local_index);
              }
            // Nodes only the quadrature has carry no weight.
            for (const auto &rest : q)
              {
                EXPECT_NEAR(rest.second.first, 0.0, 1e-13) << name(type);
                EXPECT_NEAR(rest.second.second.norm() * setup.h, 0.0, 1e-13);
              }
            ++n_closed;
          }
      }
    EXPECT_EQ(n_closed, 60u);

    // The 1D closed form against a direct integration of the hat function.
    const double h = 0.3, l = 0.1;
    for (double r = -0.45; r <= 0.45; r += 0.0123)
      {
        double    sum = 0;
        const int m   = 20000;
        for (int k = 0; k < m; ++k)
          {
            const double x = r - l + (k + 0.5) * 2 * l / m;
            sum += std::max(0.0, 1 - std::abs(x) / h);
          }
        EXPECT_NEAR(fmpm::ShapeFunction::gimp_1d(r, h, l).first, sum / m, 1e-8)
          << "r = " << r;
        const double dr = 1e-6;
        EXPECT_NEAR(fmpm::ShapeFunction::gimp_1d(r, h, l).second,
                    (fmpm::ShapeFunction::gimp_1d(r + dr, h, l).first -
                     fmpm::ShapeFunction::gimp_1d(r - dr, h, l).first) /
                      (2 * dr),
                    1e-5)
          << "r = " << r;
      }
  }



  // A domain inside one cell of a uniform grid: uGIMP, cpGIMP and CPDI
  // (F diagonal) average a multilinear function over a domain symmetric
  // about x_p, so S̄ and Ḡ equal the classic S and G at x_p.
  TYPED_TEST(ShapeFunctionTest, DomainInsideOneCellGivesClassicWeights)
  {
    constexpr int                               dim = TypeParam::value;
    Setup<dim>                                  setup(MeshKind::uniform, 4);
    std::mt19937                                generator(11 + dim);
    std::uniform_real_distribution<double>      uniform(0.3, 0.7);
    std::vector<fmpm::ShapeFunction::Node<dim>> classic, other;
    for (unsigned int p = 0; p < 10; ++p)
      {
        // x in the middle of a cell, the domain well inside it.
        Point<dim> x;
        for (unsigned int d = 0; d < dim; ++d)
          x[d] = (1 + std::floor(uniform(generator) * 2) + uniform(generator)) *
                 setup.h;
        Tensor<1, dim> l0;
        Tensor<2, dim> F;
        for (unsigned int d = 0; d < dim; ++d)
          {
            l0[d]   = 0.1 * setup.h * (1 + 0.3 * d);
            F[d][d] = 1.1 - 0.2 * d;
          }
        const unsigned int cell = setup.cell_of(x);
        fmpm::ShapeFunction::compute_support(
          Type::classic, setup.transfer, cell, x, F, l0, classic);
        ASSERT_EQ(classic.size(), GeometryInfo<dim>::vertices_per_cell);
        for (const Type type : {Type::ugimp, Type::cpgimp, Type::cpdi})
          for (const bool closed_form : {true, false})
            {
              fmpm::ShapeFunction::compute_support(
                type, setup.transfer, cell, x, F, l0, other, closed_form);
              std::map<unsigned int, const fmpm::ShapeFunction::Node<dim> *>
                by_index;
              for (const auto &node : other)
                by_index[node.local_index] = &node;
              for (const auto &node : classic)
                {
                  ASSERT_TRUE(by_index.count(node.local_index));
                  EXPECT_NEAR(by_index[node.local_index]->S, node.S, 1e-13)
                    << name(type) << " at " << x;
                  EXPECT_NEAR((by_index[node.local_index]->G - node.G).norm() *
                                setup.h,
                              0,
                              1e-12)
                    << name(type) << " at " << x;
                  by_index.erase(node.local_index);
                }
              for (const auto &rest : by_index)
                EXPECT_NEAR(rest.second->S, 0, 1e-13) << name(type);
            }
      }
  }



  // The split quadrature against brute-force sampling of the FE basis over
  // the GIMP box (every sample located in its own cell) on a distorted and
  // a hanging-node mesh: S̄ per node within the sampling error.
  // (2D only: the sampling is slow in 3D.)
  TEST(ShapeFunction2D, GimpQuadratureMatchesSampling)
  {
    constexpr int dim = 2;
    for (const MeshKind kind : {MeshKind::distorted, MeshKind::hanging})
      {
        ::Setup<dim>                                setup(kind, 6);
        std::mt19937                                generator(5);
        std::uniform_real_distribution<double>      uniform(0.2, 0.8);
        std::vector<fmpm::ShapeFunction::Node<dim>> support;
        for (unsigned int p = 0; p < 4; ++p)
          {
            Point<dim>     x;
            Tensor<1, dim> l0;
            for (unsigned int d = 0; d < dim; ++d)
              {
                x[d]  = uniform(generator);
                l0[d] = 0.2 * setup.h;
              }
            const unsigned int cell = setup.cell_of(x);
            fmpm::ShapeFunction::compute_support(Type::ugimp,
                                                 setup.transfer,
                                                 cell,
                                                 x,
                                                 Tensor<2, dim>(),
                                                 l0,
                                                 support);
            // Midpoint sampling with m^dim points.
            const unsigned int                        m = 60;
            std::map<types::global_dof_index, double> sampled;
            std::vector<types::global_dof_index>      dofs(
              GeometryInfo<dim>::vertices_per_cell);
            for (unsigned int k = 0; k < m * m; ++k)
              {
                Point<dim> y;
                y[0] = x[0] - l0[0] + (k % m + 0.5) * 2 * l0[0] / m;
                y[1] = x[1] - l0[1] + (k / m + 0.5) * 2 * l0[1] / m;
                const auto found =
                  GridTools::find_active_cell_around_point(MappingQ<dim>(1),
                                                           setup.triangulation,
                                                           y);
                typename DoFHandler<dim>::active_cell_iterator dof_cell(
                  &setup.triangulation,
                  found.first->level(),
                  found.first->index(),
                  &setup.dof_handler);
                dof_cell->get_dof_indices(dofs);
                for (unsigned int i = 0; i < dofs.size(); ++i)
                  sampled[dofs[i]] +=
                    setup.fe.shape_value(i, found.second) / (m * m);
              }
            // The sampling itself is accurate to ~5e-5 (measured on the
            // hanging-node mesh, where the split quadrature is exact); on
            // the distorted mesh the quadrature is approximate (one
            // bisection per direction, then 3-point Gauss with each point
            // located): 2.1e-4 at most here. A missing or misplaced piece
            // of the box is off by 1e-2 or more.
            const double tolerance = kind == MeshKind::hanging ? 1e-4 : 3e-4;
            for (const auto &node : support)
              {
                EXPECT_NEAR(node.S, sampled[node.dof], tolerance)
                  << name(kind) << " at " << x;
                sampled.erase(node.dof);
              }
            for (const auto &rest : sampled)
              EXPECT_NEAR(rest.second, 0, tolerance) << name(kind);
          }
      }
  }



  // A domain larger than the cells around the point's cell is reported
  // (not cut), and so is one reaching far outside the mesh; slightly
  // outside the mesh the boundary cell's basis is extended (partition of
  // unity kept).
  TYPED_TEST(ShapeFunctionTest, DomainsReachingTooFarAreReported)
  {
    constexpr int dim = TypeParam::value;
    Setup<dim>    setup(MeshKind::uniform, 8);
    Point<dim>    x;
    for (unsigned int d = 0; d < dim; ++d)
      x[d] = 0.45; // in [0.375, 0.5], its patch [0.25, 0.625]
    const unsigned int cell = setup.cell_of(x);
    Tensor<2, dim>     F;
    Tensor<1, dim>     l0;
    for (unsigned int d = 0; d < dim; ++d)
      {
        F[d][d] = 1;
        l0[d]   = 1.6 * setup.h;
      }
    std::vector<fmpm::ShapeFunction::Node<dim>> support;
    for (const Type type : {Type::ugimp, Type::cpgimp, Type::cpdi})
      EXPECT_EQ(fmpm::ShapeFunction::compute_support(
                  type, setup.transfer, cell, x, F, l0, support),
                fmpm::ShapeFunction::Status::beyond_neighbors)
        << name(type);

    // Near the boundary x = 0: a little outside is fine, far is reported.
    for (unsigned int d = 0; d < dim; ++d)
      {
        x[d]  = 0.05 * setup.h + 0.5 * setup.h * (d > 0);
        l0[d] = 0.3 * setup.h;
      }
    const unsigned int boundary_cell = setup.cell_of(x);
    for (const Type type : {Type::ugimp, Type::cpgimp, Type::cpdi})
      {
        ASSERT_EQ(fmpm::ShapeFunction::compute_support(
                    type, setup.transfer, boundary_cell, x, F, l0, support),
                  fmpm::ShapeFunction::Status::ok)
          << name(type);
        double sum = 0;
        for (const auto &node : support)
          sum += node.S;
        EXPECT_NEAR(sum, 1, 1e-12) << name(type);
      }
    x[0]  = -0.7 * setup.h; // outside the mesh: the point itself
    l0[0] = 0.1 * setup.h;
    for (const Type type : {Type::ugimp, Type::cpdi})
      EXPECT_EQ(fmpm::ShapeFunction::compute_support(
                  type, setup.transfer, boundary_cell, x, F, l0, support),
                fmpm::ShapeFunction::Status::outside_mesh)
        << name(type);
  }



  // limit_cpdi_domain(): every half-diagonal s r ends at most r_max long; a
  // domain within the limit is unchanged; in 2D a diagonal within the limit
  // keeps its length and direction (only the long one is shortened).
  TYPED_TEST(ShapeFunctionTest, CriticalRadiusShortensOnlyLongDiagonals)
  {
    constexpr int dim = TypeParam::value;
    std::mt19937  generator(5 + dim);
    auto          diagonals = [](const Tensor<2, dim> &s) {
      std::vector<Tensor<1, dim>> d;
      for (unsigned int k = 0; k < (1u << (dim - 1)); ++k)
        {
          Tensor<1, dim> r;
          for (unsigned int j = 0; j + 1 < dim; ++j)
            r[j] = ((k >> j) & 1) ? -1. : 1.;
          r[dim - 1] = 1.;
          d.push_back(s * r);
        }
      return d;
    };
    unsigned int n_checked = 0;
    for (unsigned int trial = 0; trial < 20; ++trial)
      {
        const Tensor<2, dim> s0 =
          0.25 * random_deformation_gradient<dim>(generator, 1.5);
        if (determinant(s0) <= 0)
          continue;
        ++n_checked;
        double longest = 0;
        for (const auto &d : diagonals(s0))
          longest = std::max(longest, d.norm());
        Tensor<2, dim> s = s0;
        EXPECT_FALSE(fmpm::ShapeFunction::limit_cpdi_domain(s, longest * 1.01));
        EXPECT_EQ(s, s0);
        const double r_max = 0.7 * longest;
        ASSERT_TRUE(fmpm::ShapeFunction::limit_cpdi_domain(s, r_max));
        const auto before = diagonals(s0), after = diagonals(s);
        for (unsigned int k = 0; k < after.size(); ++k)
          {
            EXPECT_LE(after[k].norm(), r_max * (1 + 1e-12)) << trial;
            if (dim == 2 && before[k].norm() <= r_max)
              {
                EXPECT_NEAR((after[k] - before[k]).norm(), 0, 1e-14) << trial;
              }
            if (dim == 2 && before[k].norm() > r_max)
              {
                EXPECT_NEAR(
                  (after[k] - before[k] * (r_max / before[k].norm())).norm(),
                  0,
                  1e-14)
                  << trial;
              }
          }
        EXPECT_GT(determinant(s), 0) << trial;
      }
    EXPECT_GE(n_checked, 5u);
  }



  // A CPDI domain stretched beyond the neighbour cells is reported without
  // a critical radius; with a radius of one cell its support stays in the
  // patch and still reproduces linear fields (Σ S̄ = 1, Σ S̄ x_g = x_p,
  // Σ x_g ⊗ Ḡ = I), and a radius larger than the domain changes nothing.
  TYPED_TEST(ShapeFunctionTest, CriticalRadiusKeepsStretchedCpdiDomainsInPatch)
  {
    constexpr int dim = TypeParam::value;
    Setup<dim>    setup(MeshKind::uniform, 8);
    Point<dim>    x;
    for (unsigned int d = 0; d < dim; ++d)
      x[d] = 0.45;
    const unsigned int cell = setup.cell_of(x);
    Tensor<2, dim>     F;
    Tensor<1, dim>     l0;
    for (unsigned int d = 0; d < dim; ++d)
      {
        F[d][d] = d == 0 ? 8.0 : 1.0 / 8; // stretched along x, thin in y
        l0[d]   = 0.25 * setup.h;
      }
    F[0][1] = 0.5;
    std::vector<fmpm::ShapeFunction::Node<dim>> support, reference;
    EXPECT_EQ(fmpm::ShapeFunction::compute_support(
                Type::cpdi, setup.transfer, cell, x, F, l0, support),
              fmpm::ShapeFunction::Status::beyond_neighbors);
    ASSERT_EQ(fmpm::ShapeFunction::compute_support(
                Type::cpdi, setup.transfer, cell, x, F, l0, support, true, 1.0),
              fmpm::ShapeFunction::Status::ok);
    double         sum_S = 0;
    Tensor<1, dim> centroid;
    Tensor<2, dim> gradient;
    for (const auto &node : support)
      {
        const Point<dim> x_g = setup.position(node);
        sum_S += node.S;
        centroid += node.S * x_g;
        gradient += outer_product(x_g, node.G);
        for (unsigned int d = 0; d < dim; ++d)
          EXPECT_LE(std::abs(x_g[d] - x[d]), 2 * setup.h + 1e-12);
      }
    EXPECT_NEAR(sum_S, 1, 1e-12);
    EXPECT_NEAR((centroid - x).norm(), 0, 1e-12);
    EXPECT_NEAR(
      (gradient - Tensor<2, dim>(unit_symmetric_tensor<dim>())).norm(),
      0,
      1e-10);

    // A domain inside the limit: the same support with and without it.
    F = Tensor<2, dim>(unit_symmetric_tensor<dim>());
    ASSERT_EQ(fmpm::ShapeFunction::compute_support(
                Type::cpdi, setup.transfer, cell, x, F, l0, reference),
              fmpm::ShapeFunction::Status::ok);
    ASSERT_EQ(fmpm::ShapeFunction::compute_support(
                Type::cpdi, setup.transfer, cell, x, F, l0, support, true, 1.0),
              fmpm::ShapeFunction::Status::ok);
    ASSERT_EQ(support.size(), reference.size());
    for (unsigned int i = 0; i < support.size(); ++i)
      {
        EXPECT_EQ(support[i].S, reference[i].S);
        EXPECT_EQ(support[i].G, reference[i].G);
      }
  }



  // UniformCpdiPatch (CPDI's corners located arithmetically, the path the
  // support cache takes on uniform patches) against the general path that
  // locates each corner with GridTransfer::locate(): the same nodes in the
  // same order with the same S̄ and Ḡ, bit for bit. Random points and
  // deformed domains whose corners reach into the neighbour cells, at the
  // mesh boundary (corners beyond it, in the extended basis of a boundary
  // cell), with the critical radius, and undeformed points of a regular
  // lattice (l⁰ = h/4: every corner on a cell face or node). A domain too
  // large for the patch gives no support (the general path reports it).
  TYPED_TEST(ShapeFunctionTest, CpdiPatchEqualsGeneralPath)
  {
    constexpr int          dim = TypeParam::value;
    constexpr unsigned int n   = GeometryInfo<dim>::vertices_per_cell;
    // h = 1/6 and 1/5: the cell sizes differ in their last bits.
    Setup<dim>   setup(MeshKind::uniform, dim == 2 ? 6 : 5);
    const double h = setup.h;
    std::mt19937 generator(23 + dim);
    std::uniform_real_distribution<double> anywhere(1e-9, 1 - 1e-9),
      size(0.1, 0.5);
    std::vector<fmpm::ShapeFunction::Node<dim>> fast, general;
    unsigned int n_compared = 0, n_neighbour_corners = 0, n_beyond_mesh = 0,
                 n_on_faces = 0, n_too_far = 0;
    auto compare = [&](const Point<dim>     &x,
                       const Tensor<2, dim> &F,
                       const Tensor<1, dim> &l0,
                       const double          critical_radius) {
      const unsigned int cell = setup.cell_of(x);
      ASSERT_TRUE(setup.transfer.cell_data(cell).uniform_patch);
      fmpm::ShapeFunction::UniformCpdiPatch<dim> patch;
      patch.reinit(setup.transfer, cell);
      ASSERT_TRUE(patch.applies());
      const auto status = fmpm::ShapeFunction::compute_support(Type::cpdi,
                                                               setup.transfer,
                                                               cell,
                                                               x,
                                                               F,
                                                               l0,
                                                               general,
                                                               false,
                                                               critical_radius);
      // The patch as the support cache calls it.
      constexpr unsigned int size =
        fmpm::ShapeFunction::UniformCpdiPatch<dim>::max_support_size;
      unsigned int       node[size];
      double             S[size];
      Tensor<1, dim>     G[size];
      const unsigned int count =
        patch.support(setup.transfer, x, F, l0, critical_radius, node, S, G);
      if (status != fmpm::ShapeFunction::Status::ok)
        {
          EXPECT_EQ(count, 0u) << x;
          ++n_too_far;
          return;
        }
      ASSERT_EQ(count, general.size()) << x;
      ASSERT_EQ(fmpm::ShapeFunction::compute_support(Type::cpdi,
                                                     setup.transfer,
                                                     cell,
                                                     x,
                                                     F,
                                                     l0,
                                                     fast,
                                                     true,
                                                     critical_radius),
                fmpm::ShapeFunction::Status::ok);
      ASSERT_EQ(fast.size(), general.size());
      for (unsigned int e = 0; e < count; ++e)
        {
          EXPECT_EQ(node[e], general[e].local_index) << x;
          EXPECT_EQ(S[e], general[e].S) << x;
          EXPECT_EQ(G[e], general[e].G) << x;
          EXPECT_EQ(fast[e].local_index, general[e].local_index);
          EXPECT_EQ(fast[e].dof, general[e].dof);
          EXPECT_FALSE(fast[e].constrained);
          EXPECT_EQ(fast[e].S, general[e].S);
          EXPECT_EQ(fast[e].G, general[e].G);
        }
      ++n_compared;
      n_neighbour_corners += (count > n);
      // Corners beyond the mesh (without the limit).
      bool beyond = false;
      for (unsigned int alpha = 0; alpha < n; ++alpha)
        for (unsigned int c = 0; c < dim; ++c)
          {
            double corner = x[c];
            for (unsigned int j = 0; j < dim; ++j)
              corner += F[c][j] * l0[j] * (((alpha >> j) & 1) ? 1 : -1);
            beyond = beyond || corner < 0 || corner > 1;
          }
      n_beyond_mesh += beyond;
    };

    for (unsigned int p = 0; p < 400; ++p)
      {
        Point<dim>     x;
        Tensor<1, dim> l0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            x[d]  = anywhere(generator);
            l0[d] = size(generator) * h;
          }
        const Tensor<2, dim> F =
          random_deformation_gradient<dim>(generator, 0.5);
        compare(x, F, l0, 0);
        compare(x, 3 * F, l0, 1.0);
      }
    // The regular lattice, undeformed and sheared: corners on faces.
    Tensor<2, dim> identity, shear;
    Tensor<1, dim> quarter;
    for (unsigned int d = 0; d < dim; ++d)
      {
        identity[d][d] = shear[d][d] = 1;
        quarter[d]                   = 0.25 * h;
      }
    shear[0][1] = 1; // corners x ± l⁰ on faces in direction 1 only
    const unsigned int n_cells = dim == 2 ? 6 : 5;
    for (unsigned int cell = 0; cell < Utilities::pow(n_cells, dim); cell += 3)
      for (unsigned int q = 0; q < n; ++q)
        {
          Point<dim>   x;
          unsigned int index = cell;
          for (unsigned int d = 0; d < dim; ++d)
            {
              x[d] = (index % n_cells + (((q >> d) & 1) ? 0.75 : 0.25)) * h;
              index /= n_cells;
            }
          compare(x, identity, quarter, 0);
          compare(x, shear, quarter, 0);
          n_on_faces += 2;
        }
    // A domain beyond the patch.
    Point<dim> centre;
    for (unsigned int d = 0; d < dim; ++d)
      centre[d] = 0.5;
    compare(centre, 8 * identity, quarter, 0);

    EXPECT_GT(n_compared, 700u);
    EXPECT_GT(n_neighbour_corners, 300u);
    EXPECT_GT(n_beyond_mesh, 50u);
    EXPECT_GT(n_on_faces, 40u);
    EXPECT_GE(n_too_far, 1u);
  }
} // namespace



namespace
{
  /** A spinning, translating neo-Hookean disk in free flight. */
  std::vector<fmpm::HistoryRow<2>>
  run_free_disk(const std::string &type,
                const std::string &update,
                const std::string &mesh)
  {
    auto sources = fmpm::load_scene_sources(
      {FMPM_SOURCE_DIR "/parameters/vibrating_bar.prm"});
    sources.emplace_back(
      "overrides",
      "subsection Output\n set Directory = output-shape-functions\n"
      " set Write vtu = false\nend\n"
      "subsection Timer\n set Type = none\nend\n"
      "subsection Shape function\n set Type = " +
        type +
        "\nend\n"
        "subsection Particle update\n set Model name = " +
        update +
        "\nend\n"
        "subsection Mass matrix\n set Model name = " +
        (update == "pic" ? std::string("lumped") : std::string("fmpm")) +
        "\n subsection Fmpm\n  set Order = 3\n end\nend\n"
        "subsection Reference solution\n set Enable = false\nend\n" +
        mesh +
        "subsection Boundary conditions\n set Roller boundary ids =\nend\n"
        "subsection Time\n set End time = 0.1\n set Courant number = 0.3\n"
        " set Strain update = usf\n set Strain update mass matrix = "
        "lumped\nend\n"
        "subsection Material 0\n set Model name = neo hookean\n"
        " subsection Neo hookean\n  set Bulk modulus = 100\n"
        "  set Shear modulus = 40\n end\nend\n"
        "subsection Body 0\n set Shape = sphere\n set Center = 0.45, 0.5\n"
        " set Half lengths = 0.25, 0.25\n"
        " set Initial velocity = 0.5 - 2*(y-0.5), 0.2 + 2*(x-0.45)\n"
        "end\n");
    ParameterHandler prm;
    fmpm::Parameters parameters;
    fmpm::read_scene(sources, prm, parameters);
    fmpm::Simulator<2> simulator(parameters, prm, MPI_COMM_WORLD);
    simulator.run();
    return fmpm_tests::inspect(simulator).get_history();
  }

  void
  expect_momentum_conserved(const std::vector<fmpm::HistoryRow<2>> &history,
                            const std::string                      &what)
  {
    ASSERT_GT(history.size(), 2u) << what;
    const auto  &first = history.front();
    const double scale =
      std::abs(first.momentum[0]) + std::abs(first.momentum[1]);
    for (const auto &row : history)
      for (unsigned int d = 0; d < 2; ++d)
        EXPECT_NEAR(row.momentum[d], first.momentum[d], 1e-11 * scale)
          << what << " at t = " << row.time;
    EXPECT_GT(history.back().strain_energy, 0) << what; // it deforms
    // Bounded energy: PIC and FMPM(3) only lose energy.
    EXPECT_LT(history.back().total_energy, 1.001 * first.total_energy) << what;
  }
} // namespace



// A body in free flight (no walls) conserves momentum exactly with every
// shape function: Σ_g S̄_gp = 1 and Σ_g Ḡ_gp = 0 make the grid forces sum
// to zero. With lumped and full mass matrices (PIC, FMPM(3)).
TEST(ShapeFunctionWholeRun, EveryShapeFunctionConservesMomentum)
{
  for (const std::string type : {"classic", "ugimp", "cpgimp", "cpdi"})
    for (const std::string update : {"pic", "fmpm"})
      expect_momentum_conserved(
        run_free_disk(type,
                      update,
                      "subsection Mesh\n set Upper corner = 1, 1\n"
                      " set Subdivisions = 10, 10\nend\n"),
        type + " " + update);
}



// The same on a mesh of non-parallelogram cells (four distorted quads from
// Gmsh, refined three times): GIMP's quadrature split by bisection and
// points located by Newton's method in the Simulator.
TEST(ShapeFunctionWholeRun, ConservesMomentumOnDistortedMesh)
{
  for (const std::string type : {"ugimp", "cpgimp", "cpdi"})
    expect_momentum_conserved(
      run_free_disk(type,
                    "fmpm",
                    "subsection Mesh\n set Type = gmsh\n"
                    " set File name = " FMPM_SOURCE_DIR
                    "/tests/unit/distorted_quads.msh\n"
                    " set Initial global refinement = 3\nend\n"),
      type + " on the distorted mesh");
}
