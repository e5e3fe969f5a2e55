// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks the axisymmetric shape functions of
// fmpm::ShapeFunction::Axisymmetric (Nairn and Guilkey 2015; NairnMPM's
// GIMP_Theory Eqs. 5.5, 5.8, 5.9): the radial closed forms against Gauss
// quadrature of their defining integrals and their classic limit; for every
// type at random points, near-axis and cut domains included, the identities
// Σ S = 1, Σ S x_i = the r-weighted centroid, Σ G = 0, Σ G ⊗ x_i = I,
// Σ T r_i = 1 and Σ T = ∫dA/∫r dA; the 2D supports against quadrature of
// the defining integrals over the mesh's own shape functions; no node at
// r < 0; and a uniform radial expansion v_r = a r whose hoop rate
// Σ v_r,i T_ip equals L_rr, whose Cayley and first-order updates give
// F_33 = F_11, and the linear-elastic stress σ_θθ = σ_rr for it.

#include <fmpm/axisymmetric_shape_function.h>
#include <fmpm/constitutive_model/linear_elastic.h>
#include <fmpm/constitutive_model/neo_hookean.h>
#include <fmpm/grid_transfer.h>
#include <fmpm/transfer/kinematics.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/affine_constraints.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using fmpm::ShapeFunction::Type;
  namespace Axisymmetric = fmpm::ShapeFunction::Axisymmetric;

  /** A uniform n_r x n_z mesh of cells of size h from (r_0, 0). */
  struct RzMesh
  {
    RzMesh(const double       r_0,
           const unsigned int n_r,
           const unsigned int n_z,
           const double       h_,
           const bool         refine_near_axis = false)
      : triangulation(MPI_COMM_WORLD)
      , fe(1)
      , dof_handler(triangulation)
      , h(h_)
    {
      GridGenerator::subdivided_hyper_rectangle(triangulation,
                                                {n_r, n_z},
                                                Point<2>(r_0, 0),
                                                Point<2>(r_0 + n_r * h,
                                                         n_z * h));
      // Refined cells in the inner half in r: hanging nodes between.
      if (refine_near_axis)
        {
          for (const auto &cell : triangulation.active_cell_iterators())
            if (cell->center()[0] < r_0 + 0.5 * n_r * h)
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
      DoFTools::map_dofs_to_support_points(MappingQ<2>(1),
                                           dof_handler,
                                           support_points);
    }

    unsigned int
    cell_of(const Point<2> &x) const
    {
      return GridTools::find_active_cell_around_point(MappingQ<2>(1),
                                                      triangulation,
                                                      x)
        .first->active_cell_index();
    }

    parallel::distributed::Triangulation<2>      triangulation;
    FE_Q<2>                                      fe;
    DoFHandler<2>                                dof_handler;
    AffineConstraints<double>                    constraints;
    std::shared_ptr<Utilities::MPI::Partitioner> partitioner;
    fmpm::GridTransfer<2>                        transfer;
    std::map<types::global_dof_index, Point<2>>  support_points;
    const double                                 h;
  };

  /** ∫_lo^hi f by a 12-point Gauss rule on the pieces between @p breaks. */
  template <typename Function>
  double
  integrate_1d(const double        lo,
               const double        hi,
               std::vector<double> breaks,
               const Function     &f)
  {
    const QGauss<1> gauss(12);
    breaks.push_back(lo);
    breaks.push_back(hi);
    std::sort(breaks.begin(), breaks.end());
    double sum = 0;
    for (unsigned int k = 0; k + 1 < breaks.size(); ++k)
      {
        const double a = std::max(breaks[k], lo),
                     b = std::min(breaks[k + 1], hi);
        if (!(b > a))
          continue;
        for (unsigned int q = 0; q < gauss.size(); ++q)
          sum += gauss.weight(q) * (b - a) * f(a + gauss.point(q)[0] * (b - a));
      }
    return sum;
  }



  // The radial factors against Gauss quadrature of their defining integrals
  // S = ∫N r/∫r, G = ∫N' r/∫r, T = ∫N/∫r over [max(r_p − l, 0), r_p + l],
  // near the axis (cut and touching domains) and far from it.
  TEST(AxisymmetricShapeFunction, RadialClosedFormsEqualQuadrature)
  {
    std::mt19937                           generator(5);
    std::uniform_real_distribution<double> unit(0, 1);
    const double                           h         = 0.5;
    unsigned int                           n_checked = 0;
    for (const double r_0 : {0.0, 3.0, 1000.0})
      for (unsigned int k = 0; k < 200; ++k)
        {
          const double l   = h * (0.02 + 0.48 * unit(generator));
          const double r_p = r_0 + (k % 4 == 0 ? l : 2.5 * h * unit(generator));
          const double a = std::max(r_p - l, 0.0), b = r_p + l;
          const double r_area =
            integrate_1d(a, b, {}, [](const double r) { return r; });
          for (int i = -1; i <= 7; ++i)
            {
              const double r_i = r_0 + i * h;
              auto         N   = [&](const double r) {
                return std::max(0.0, 1 - std::abs(r - r_i) / h);
              };
              auto dN = [&](const double r) {
                return std::abs(r - r_i) >= h ? 0.0 :
                                                (r < r_i ? 1 / h : -1 / h);
              };
              const std::vector<double> breaks{r_i - h, r_i, r_i + h};
              const auto   w = Axisymmetric::gimp_radial(r_p, r_i, h, l);
              const double S =
                integrate_1d(a,
                             b,
                             breaks,
                             [&](const double r) { return N(r) * r; }) /
                r_area;
              const double G =
                integrate_1d(a,
                             b,
                             breaks,
                             [&](const double r) { return dN(r) * r; }) /
                r_area;
              const double T = integrate_1d(a, b, breaks, N) / r_area;
              EXPECT_NEAR(w.S, S, 1e-12) << r_p << " " << l << " " << r_i;
              EXPECT_NEAR(w.G * h, G * h, 1e-12)
                << r_p << " " << l << " " << r_i;
              EXPECT_NEAR(w.T * r_p, T * r_p, 1e-12)
                << r_p << " " << l << " " << r_i;
              ++n_checked;
            }
        }
    EXPECT_EQ(n_checked, 3u * 200 * 9);
  }



  // As the domain shrinks the GIMP factors tend to the classic ones N(r_p),
  // N'(r_p), N(r_p)/r_p, at second order in l (away from the nodes' kinks).
  TEST(AxisymmetricShapeFunction, ClassicLimitAsTheDomainShrinks)
  {
    const double h = 1;
    for (const double r_p : {0.3, 1.37, 2.81, 40.6})
      for (int i = -1; i <= 42; ++i)
        {
          const double r_i     = i * h;
          const auto   classic = Axisymmetric::classic_radial(r_p, r_i, h);
          double       previous_error = 0;
          for (const double l : {1e-2, 5e-3})
            {
              const auto   w     = Axisymmetric::gimp_radial(r_p, r_i, h, l);
              const double error = std::abs(w.S - classic.S) +
                                   std::abs(w.G - classic.G) * h +
                                   std::abs(w.T - classic.T) * r_p;
              EXPECT_LT(error, 2 * l * l / (h * std::min(r_p, h)))
                << r_p << " " << r_i << " " << l;
              if (previous_error > 1e-14)
                {
                  EXPECT_NEAR(previous_error / error, 4, 0.1)
                    << r_p << " " << r_i;
                }
              previous_error = error;
            }
        }
  }



  /** The r-weighted centroid ∫x r dA/∫r dA and ∫dA/∫r dA of a point's
   * domain, from the geometry alone. */
  void
  domain_moments(const Type          type,
                 const Point<2>     &x,
                 const Tensor<2, 2> &F,
                 const Tensor<1, 2> &l0,
                 Point<2>           &centroid,
                 double             &area_over_r_area)
  {
    centroid = x;
    if (type == Type::classic)
      area_over_r_area = 1 / x[0];
    else if (type == Type::cpdi)
      {
        Tensor<2, 2> s;
        for (unsigned int c = 0; c < 2; ++c)
          for (unsigned int j = 0; j < 2; ++j)
            s[c][j] = F[c][j] * l0[j];
        Axisymmetric::keep_cpdi_domain_off_axis(x[0], s);
        // x = x_p + s ξ, r = r_p + s_0j ξ_j over ξ ∈ [−1, 1]²:
        // ∫ξ_j r dξ = 4 s_0j / 3, ∫r dξ = 4 r_p.
        Tensor<1, 2> first_row;
        first_row[0] = s[0][0];
        first_row[1] = s[0][1];
        centroid += s * first_row / (3 * x[0]);
        area_over_r_area = 1 / x[0];
      }
    else
      {
        const Tensor<1, 2> l =
          fmpm::ShapeFunction::gimp_half_lengths<2>(type, F, l0);
        const double a = std::max(x[0] - l[0], 0.0), b = x[0] + l[0];
        centroid[0]      = 2. / 3 * (b * b * b - a * a * a) / (b * b - a * a);
        area_over_r_area = 2 / (a + b);
      }
  }



  // Σ S = 1, Σ S x_i = centroid, Σ G = 0, Σ G ⊗ x_i = I, Σ T r_i = 1,
  // Σ T = ∫dA/∫r dA for every type at random points of a mesh from the axis
  // (a quarter of them in the first column of cells, where GIMP domains are
  // cut) and of one far from it; no support node at r < 0.
  TEST(AxisymmetricShapeFunction, IdentitiesForEveryType)
  {
    std::mt19937                           generator(11);
    std::uniform_real_distribution<double> unit(0, 1), amount(-0.25, 0.25);
    unsigned int                           n_checked = 0;
    for (const double r_0 : {0.0, 50.0})
      {
        const double                    h = 0.125;
        RzMesh                          setup(r_0, 8, 8, h);
        std::vector<Axisymmetric::Node> support;
        for (unsigned int p = 0; p < 60; ++p)
          {
            Point<2>           x(r_0 + (r_0 == 0 && p % 4 == 0 ?
                                          h * (0.05 + 0.95 * unit(generator)) :
                                          h * (1 + 6 * unit(generator))),
                       h * (1 + 6 * unit(generator)));
            const Tensor<1, 2> l0({0.25 * h, 0.2 * h});
            Tensor<2, 2>       F;
            for (unsigned int i = 0; i < 2; ++i)
              for (unsigned int j = 0; j < 2; ++j)
                F[i][j] = (i == j ? 1 : 0) + amount(generator);
            const unsigned int cell = setup.cell_of(x);
            for (const Type type :
                 {Type::classic, Type::ugimp, Type::cpgimp, Type::cpdi})
              {
                const auto status = Axisymmetric::compute_support(
                  type, setup.transfer, cell, x, F, l0, support);
                ASSERT_EQ(status, Axisymmetric::Status::ok)
                  << fmpm::ShapeFunction::parameter_name(type) << " at " << x;
                Point<2> centroid;
                double   area_over_r_area;
                domain_moments(type, x, F, l0, centroid, area_over_r_area);
                double       sum_S = 0, sum_T = 0, sum_T_r = 0;
                Tensor<1, 2> sum_G, sum_S_x;
                Tensor<2, 2> sum_G_x;
                for (const auto &node : support)
                  {
                    const Point<2> &x_i = setup.support_points.at(node.dof);
                    EXPECT_GE(x_i[0], 0.0);
                    sum_S += node.S;
                    sum_S_x += node.S * x_i;
                    sum_G += node.G;
                    sum_G_x += outer_product(node.G, x_i);
                    sum_T += node.T;
                    sum_T_r += node.T * x_i[0];
                  }
                const std::string where =
                  fmpm::ShapeFunction::parameter_name(type) + " at " +
                  std::to_string(x[0]) + ", " + std::to_string(x[1]);
                const double scale = r_0 + 1;
                EXPECT_NEAR(sum_S, 1, 1e-13 * scale) << where;
                EXPECT_NEAR((sum_S_x - centroid).norm(), 0, 1e-13 * scale)
                  << where;
                EXPECT_NEAR(sum_G.norm() * h, 0, 1e-13 * scale) << where;
                EXPECT_NEAR((sum_G_x - unit_symmetric_tensor<2>()).norm(),
                            0,
                            1e-12 * scale)
                  << where;
                EXPECT_NEAR(sum_T_r, 1, 1e-13 * scale) << where;
                EXPECT_NEAR(sum_T / area_over_r_area, 1, 1e-13 * scale)
                  << where;
                ++n_checked;
              }
          }
      }
    EXPECT_EQ(n_checked, 2u * 60 * 4);
  }



  // The supports against the defining integrals S = ∫N_i r/∫r,
  // G = ∫∇N_i r/∫r, T = ∫N_i/∫r evaluated with the mesh's own shape
  // functions at Gauss points: GIMP over the cut box split at the grid
  // lines; CPDI over the parallelogram with N_i interpolated from the
  // corners by the parallelogram's bilinear functions.
  TEST(AxisymmetricShapeFunction, SupportsEqualQuadratureOfDefiningIntegrals)
  {
    const double                           h = 0.25;
    RzMesh                                 setup(0, 8, 8, h);
    std::mt19937                           generator(3);
    std::uniform_real_distribution<double> unit(0, 1), amount(-0.2, 0.2);
    const QGauss<2>                        gauss(6);
    unsigned int                           n_checked = 0;
    for (unsigned int p = 0; p < 30; ++p)
      {
        const Point<2>     x(h * (p % 3 == 0 ? 0.1 + 0.9 * unit(generator) :
                                               1 + 6 * unit(generator)),
                         h * (1 + 6 * unit(generator)));
        const Tensor<1, 2> l0({0.25 * h, 0.25 * h});
        Tensor<2, 2>       F;
        for (unsigned int i = 0; i < 2; ++i)
          for (unsigned int j = 0; j < 2; ++j)
            F[i][j] = (i == j ? 1 : 0) + amount(generator);
        const unsigned int home = setup.cell_of(x);
        for (const Type type : {Type::ugimp, Type::cpgimp, Type::cpdi})
          {
            std::vector<Axisymmetric::Node> support;
            ASSERT_EQ(Axisymmetric::compute_support(
                        type, setup.transfer, home, x, F, l0, support),
                      Axisymmetric::Status::ok);
            struct Sums
            {
              double       S = 0, T = 0;
              Tensor<1, 2> G;
            };
            std::map<types::global_dof_index, Sums> expected;
            double                                  r_area = 0;
            fmpm::GridTransfer<2>::Location         location;
            std::array<double, 4>                   N;
            std::array<Tensor<1, 2>, 4>             dN;
            if (type == Type::cpdi)
              {
                Tensor<2, 2> s;
                for (unsigned int c = 0; c < 2; ++c)
                  for (unsigned int j = 0; j < 2; ++j)
                    s[c][j] = F[c][j] * l0[j];
                Axisymmetric::keep_cpdi_domain_off_axis(x[0], s);
                // N_i at the corners, then its bilinear interpolant.
                std::map<types::global_dof_index, std::array<double, 4>> corner;
                for (unsigned int alpha = 0; alpha < 4; ++alpha)
                  {
                    const Tensor<1, 2> r(
                      {(alpha & 1) ? 1. : -1., (alpha & 2) ? 1. : -1.});
                    ASSERT_EQ(
                      setup.transfer.locate(home, x + s * r, home, location),
                      fmpm::GridTransfer<2>::LocateStatus::found);
                    const auto &cell = setup.transfer.cell_data(location.cell);
                    fmpm::GridTransfer<2>::values(location.xi, N);
                    for (unsigned int i = 0; i < 4; ++i)
                      corner[setup.transfer.dof_index(cell, i)][alpha] += N[i];
                  }
                const double       det                 = determinant(s);
                const Tensor<2, 2> s_inverse_transpose = transpose(invert(s));
                for (unsigned int q = 0; q < gauss.size(); ++q)
                  {
                    const Point<2>     xi_ref = gauss.point(q);
                    const Tensor<1, 2> xi(
                      {2 * xi_ref[0] - 1, 2 * xi_ref[1] - 1});
                    const double r = (x + s * xi)[0];
                    const double w = gauss.weight(q) * 4 * det;
                    r_area += w * r;
                    for (const auto &[dof, values] : corner)
                      for (unsigned int alpha = 0; alpha < 4; ++alpha)
                        {
                          const double r0 = (alpha & 1) ? 1. : -1.;
                          const double r1 = (alpha & 2) ? 1. : -1.;
                          const double M =
                            0.25 * (1 + r0 * xi[0]) * (1 + r1 * xi[1]);
                          const Tensor<1, 2> dM_dxi(
                            {0.25 * r0 * (1 + r1 * xi[1]),
                             0.25 * r1 * (1 + r0 * xi[0])});
                          expected[dof].S += w * values[alpha] * M * r;
                          expected[dof].T += w * values[alpha] * M;
                          expected[dof].G += w * values[alpha] * r *
                                             (s_inverse_transpose * dM_dxi);
                        }
                  }
              }
            else
              {
                const Tensor<1, 2> l =
                  fmpm::ShapeFunction::gimp_half_lengths<2>(type, F, l0);
                const double lo[2] = {std::max(x[0] - l[0], 0.0), x[1] - l[1]};
                const double hi[2] = {x[0] + l[0], x[1] + l[1]};
                // The pieces between grid lines per direction.
                std::vector<double> cuts[2];
                for (unsigned int d = 0; d < 2; ++d)
                  {
                    cuts[d].push_back(lo[d]);
                    for (int k = -2; k <= 40; ++k)
                      if (k * h > lo[d] && k * h < hi[d])
                        cuts[d].push_back(k * h);
                    cuts[d].push_back(hi[d]);
                  }
                for (unsigned int i0 = 0; i0 + 1 < cuts[0].size(); ++i0)
                  for (unsigned int i1 = 0; i1 + 1 < cuts[1].size(); ++i1)
                    for (unsigned int q = 0; q < gauss.size(); ++q)
                      {
                        const double   dr = cuts[0][i0 + 1] - cuts[0][i0];
                        const double   dz = cuts[1][i1 + 1] - cuts[1][i1];
                        const Point<2> y(cuts[0][i0] + gauss.point(q)[0] * dr,
                                         cuts[1][i1] + gauss.point(q)[1] * dz);
                        const double   w = gauss.weight(q) * dr * dz;
                        ASSERT_EQ(
                          setup.transfer.locate(home, y, home, location),
                          fmpm::GridTransfer<2>::LocateStatus::found);
                        const auto &cell =
                          setup.transfer.cell_data(location.cell);
                        fmpm::GridTransfer<2>::values_and_gradients(cell,
                                                                    location.xi,
                                                                    N,
                                                                    dN);
                        r_area += w * y[0];
                        for (unsigned int i = 0; i < 4; ++i)
                          {
                            auto &e =
                              expected[setup.transfer.dof_index(cell, i)];
                            e.S += w * N[i] * y[0];
                            e.T += w * N[i];
                            e.G += w * y[0] * dN[i];
                          }
                      }
              }
            for (const auto &node : support)
              {
                const auto found = expected.find(node.dof);
                ASSERT_NE(found, expected.end());
                const Sums &e = found->second;
                EXPECT_NEAR(node.S, e.S / r_area, 1e-12);
                EXPECT_NEAR(node.G[0] * h, e.G[0] / r_area * h, 1e-12);
                EXPECT_NEAR(node.G[1] * h, e.G[1] / r_area * h, 1e-12);
                EXPECT_NEAR(node.T * x[0], e.T / r_area * x[0], 1e-12);
                expected.erase(found);
                ++n_checked;
              }
            // Nodes the support leaves out carry nothing.
            for (const auto &[dof, e] : expected)
              EXPECT_NEAR(std::abs(e.S) + std::abs(e.T) * x[0] + e.G.norm() * h,
                          0,
                          1e-13);
          }
      }
    EXPECT_GT(n_checked, 30u * 3 * 4);
  }



  // A mesh that reaches beyond the axis (r from −2h): no node at r < 0 in
  // any support, and the identities still hold for points near the axis.
  TEST(AxisymmetricShapeFunction, NodesBeyondTheAxisAreDropped)
  {
    const double h = 0.5;
    RzMesh       setup(-2 * h, 8, 6, h);
    for (const Type type :
         {Type::classic, Type::ugimp, Type::cpgimp, Type::cpdi})
      for (const double r_p : {0.02, 0.125, 0.2, 0.3, 0.6})
        {
          const Point<2>                  x(r_p, 1.3);
          const Tensor<1, 2>              l0({0.25 * h, 0.25 * h});
          Tensor<2, 2>                    F({{1.1, 0.1}, {-0.05, 0.95}});
          std::vector<Axisymmetric::Node> support;
          ASSERT_EQ(
            Axisymmetric::compute_support(
              type, setup.transfer, setup.cell_of(x), x, F, l0, support),
            Axisymmetric::Status::ok);
          double sum_S = 0, sum_T_r = 0;
          for (const auto &node : support)
            {
              EXPECT_GE(setup.support_points.at(node.dof)[0], 0.0);
              sum_S += node.S;
              sum_T_r += node.T * setup.support_points.at(node.dof)[0];
            }
          EXPECT_NEAR(sum_S, 1, 1e-13);
          EXPECT_NEAR(sum_T_r, 1, 1e-13);
        }
    // A point on the axis has no hoop term (classic) and a GIMP domain
    // wholly at r < 0 none either.
    std::vector<Axisymmetric::Node> support;
    const Point<2>                  on_axis(0, 1.3);
    EXPECT_EQ(Axisymmetric::compute_support(Type::classic,
                                            setup.transfer,
                                            setup.cell_of(Point<2>(0.01, 1.3)),
                                            on_axis,
                                            unit_symmetric_tensor<2>(),
                                            Tensor<1, 2>({0.1, 0.1}),
                                            support),
              Axisymmetric::Status::on_axis);
    EXPECT_EQ(Axisymmetric::compute_support(Type::ugimp,
                                            setup.transfer,
                                            setup.cell_of(Point<2>(-0.3, 1.3)),
                                            Point<2>(-0.3, 1.3),
                                            unit_symmetric_tensor<2>(),
                                            Tensor<1, 2>({0.1, 0.1}),
                                            support),
              Axisymmetric::Status::on_axis);
  }


  // A uniform radial expansion v_r = a r with v_z = b z, nodal values on a
  // mesh from the axis: every type's support gives L = diag(a, b, a)
  // (L_33 = Σ v_r,i T_ip, Kinematics::hoop_rate()) at random points, near
  // the axis included. One batch of them through the axisymmetric Cayley
  // update for n steps: F = diag(c_a^n, c_b^n, c_a^n) with
  // c = (1 + xΔt/2)/(1 − xΔt/2) (F_33 = F_11), J = F_11 F_22 F_33; the
  // first-order increments give ΔF_33 = ΔF_11 = 1 + aΔt. The linear-elastic
  // stress of the step then has σ_θθ = σ_rr = Δt(λ(2a + b) + 2μa) and
  // σ_zz = Δt(λ(2a + b) + 2μb) (incremental), and σ_θθ = σ_rr from the
  // total strain of F.
  TEST(AxisymmetricKinematics, UniformRadialExpansion)
  {
    const double       h = 0.125, a = 0.8, b = -0.3, dt = 0.01;
    RzMesh             mesh(0, 8, 8, h);
    const unsigned int n_local = mesh.partitioner->locally_owned_size() +
                                 mesh.partitioner->n_ghost_indices();
    std::vector<double> v_r(n_local), v_z(n_local);
    for (unsigned int i = 0; i < n_local; ++i)
      {
        const Point<2> &x_i =
          mesh.support_points.at(mesh.partitioner->local_to_global(i));
        v_r[i] = a * x_i[0];
        v_z[i] = b * x_i[1];
      }
    const double *const v[2] = {v_r.data(), v_z.data()};

    std::mt19937                           generator(23);
    std::uniform_real_distribution<double> unit(0, 1), amount(-0.2, 0.2);
    fmpm::Kinematics::BatchEntries         L        = {};
    unsigned int                           n_points = 0;
    for (unsigned int p = 0; p < 12; ++p)
      {
        const Point<2> x(h * (p % 3 == 0 ? 0.05 + 0.95 * unit(generator) :
                                           1 + 6 * unit(generator)),
                         h * (1 + 6 * unit(generator)));
        Tensor<2, 2>   F;
        for (unsigned int i = 0; i < 2; ++i)
          for (unsigned int j = 0; j < 2; ++j)
            F[i][j] = (i == j ? 1 : 0) + amount(generator);
        for (const Type type :
             {Type::classic, Type::ugimp, Type::cpgimp, Type::cpdi})
          {
            std::vector<Axisymmetric::Node> support;
            ASSERT_EQ(Axisymmetric::compute_support(type,
                                                    mesh.transfer,
                                                    mesh.cell_of(x),
                                                    x,
                                                    F,
                                                    Tensor<1, 2>(
                                                      {0.25 * h, 0.25 * h}),
                                                    support),
                      Axisymmetric::Status::ok);
            std::vector<unsigned int> node;
            std::vector<double>       T;
            std::vector<Tensor<1, 2>> G;
            for (const auto &entry : support)
              {
                node.push_back(entry.local_index);
                T.push_back(entry.T);
                G.push_back(entry.G);
              }
            const unsigned int q = n_points++;
            fmpm::Kinematics::velocity_gradient<2>(
              node.data(), G.data(), 0, node.size(), v, L, q);
            fmpm::Kinematics::hoop_rate(
              node.data(), T.data(), 0, node.size(), v_r.data(), L, q);
            const std::string where =
              fmpm::ShapeFunction::parameter_name(type) + " at " +
              std::to_string(x[0]) + ", " + std::to_string(x[1]);
            EXPECT_NEAR(L[0][q], a, 1e-13) << where;
            EXPECT_NEAR(L[1][q], 0, 1e-13) << where;
            EXPECT_NEAR(L[3][q], 0, 1e-13) << where;
            EXPECT_NEAR(L[4][q], b, 1e-13) << where;
            EXPECT_NEAR(L[8][q], a, 1e-13) << where;
          }
      }

    // n Cayley steps from F = I with the gathered rates.
    constexpr unsigned int capacity =
      fmpm::ConstitutiveModel::StressUpdateInputs::capacity;
    ASSERT_LE(n_points, capacity);
    fmpm::Kinematics::BatchEntries F_old = {}, F_new = {};
    double                         J[capacity];
    for (unsigned int q = 0; q < n_points; ++q)
      F_old[0][q] = F_old[4][q] = F_old[8][q] = 1;
    const unsigned int n_steps = 50;
    for (unsigned int step = 0; step < n_steps; ++step)
      {
        std::array<const double *, 9> columns;
        for (unsigned int c = 0; c < 9; ++c)
          columns[c] = F_old[c];
        fmpm::Kinematics::axisymmetric_cayley_update(
          n_points, dt, L, columns, F_new, J);
        std::copy(&F_new[0][0], &F_new[0][0] + 9 * capacity, &F_old[0][0]);
      }
    const double c_a =
      std::pow((1 + 0.5 * a * dt) / (1 - 0.5 * a * dt), n_steps);
    const double c_b =
      std::pow((1 + 0.5 * b * dt) / (1 - 0.5 * b * dt), n_steps);
    for (unsigned int q = 0; q < n_points; ++q)
      {
        EXPECT_NEAR(F_old[0][q], c_a, 1e-11);
        EXPECT_NEAR(F_old[4][q], c_b, 1e-11);
        EXPECT_NEAR(F_old[8][q], c_a, 1e-11);
        EXPECT_NEAR(F_old[8][q], F_old[0][q], 1e-12);
        EXPECT_NEAR(std::abs(F_old[1][q]) + std::abs(F_old[3][q]), 0, 1e-12);
        EXPECT_NEAR(J[q], c_a * c_b * c_a, 1e-11);
      }
    // Second order: c_a^n is exp(a n Δt) up to O(Δt²).
    EXPECT_NEAR(c_a, std::exp(a * n_steps * dt), 1e-4);

    // First-order increments.
    {
      fmpm::Kinematics::BatchEntries dF = {};
      fmpm::Kinematics::axisymmetric_increments(
        fmpm::DeformationGradientUpdate::first_order,
        fmpm::MethodParameters(),
        L,
        dt,
        n_points,
        dF);
      for (unsigned int q = 0; q < n_points; ++q)
        {
          EXPECT_NEAR(dF[8][q], 1 + a * dt, 1e-14);
          EXPECT_NEAR(dF[8][q], dF[0][q], 1e-14);
          EXPECT_NEAR(dF[4][q], 1 + b * dt, 1e-14);
          EXPECT_EQ(dF[2][q], 0.);
          EXPECT_EQ(dF[6][q], 0.);
        }
    }

    // The linear-elastic stress of one step from zero stress.
    fmpm::ConstitutiveModel::LinearElastic<2> model;
    model.youngs_modulus = 200;
    model.poissons_ratio = 0.3;
    const double mu      = 200 / (2 * 1.3);
    const double lambda  = 200 * 0.3 / (1.3 * 0.4);
    for (const auto measure :
         {fmpm::ConstitutiveModel::LinearElastic<2>::StrainMeasure::incremental,
          fmpm::ConstitutiveModel::LinearElastic<2>::StrainMeasure::total})
      {
        model.strain_measure = measure;
        fmpm::ConstitutiveModel::StressUpdateInputs  inputs;
        fmpm::ConstitutiveModel::StressUpdateOutputs outputs;
        inputs.resize(n_points);
        inputs.time_step = dt;
        for (unsigned int q = 0; q < n_points; ++q)
          {
            for (unsigned int c = 0; c < 9; ++c)
              {
                inputs.velocity_gradient[c][q]    = L[c][q];
                inputs.deformation_gradient[c][q] = F_old[c][q];
              }
            inputs.volume_ratio[q] = J[q];
          }
        model.update_stress(inputs, outputs);
        for (unsigned int q = 0; q < n_points; ++q)
          {
            const SymmetricTensor<2, 3> sigma = outputs.stress_tensor(q);
            EXPECT_NEAR(sigma[2][2],
                        sigma[0][0],
                        1e-12 * std::abs(sigma[0][0]));
            EXPECT_NEAR(sigma[0][1], 0, 1e-12 * std::abs(sigma[0][0]));
            if (measure == fmpm::ConstitutiveModel::LinearElastic<
                             2>::StrainMeasure::incremental)
              {
                EXPECT_NEAR(sigma[0][0],
                            dt * (lambda * (2 * a + b) + 2 * mu * a),
                            1e-11);
                EXPECT_NEAR(sigma[1][1],
                            dt * (lambda * (2 * a + b) + 2 * mu * b),
                            1e-11);
              }
            else
              EXPECT_NEAR(sigma[0][0],
                          lambda * (2 * (c_a - 1) + c_b - 1) +
                            2 * mu * (c_a - 1),
                          1e-9);
          }
      }
  }


  // Points filling the cylinder r < R, 0 < z < H (2x2 per cell, volume per
  // radian V_p = A_p⟨r_p⟩ = 4 l_r l_z r_p) under the uniform stress
  // σ_rr = σ_θθ = p, σ_zz = q (the Lamé disk under radial pressure, in
  // equilibrium): the internal forces f_i = −Σ_p V_p (σ G_ip + σ_θθ T_ip e_r)
  // (Eq. 5.13) vanish at every node inside the body and on the axis, and
  // balance the traction per radian σ_rr R h at the nodes of r = R
  // (f_r = −σ_rr R h); without
  // the hoop term they would not vanish. Σ_ip ρ V_p S_ip = ρ R² H / 2, the
  // mass per radian.
  TEST(AxisymmetricShapeFunction, UniformHoopStressIsInEquilibrium)
  {
    const double       h = 0.25, p = -2.5, q = 1.5, rho = 3;
    const unsigned int n_r = 6, n_z = 5;
    const double       R = n_r * h, H = n_z * h;
    RzMesh             mesh(0, n_r + 2, n_z + 2, h);
    for (const Type type : {Type::ugimp, Type::cpgimp, Type::cpdi})
      {
        std::map<types::global_dof_index, Tensor<1, 2>> force,
          force_without_hoop;
        double             mass = 0;
        const Tensor<1, 2> l({0.25 * h, 0.25 * h});
        for (unsigned int i = 0; i < 2 * n_r; ++i)
          for (unsigned int j = 0; j < 2 * n_z; ++j)
            {
              const Point<2> x((i + 0.5) * 0.5 * h, (j + 0.5) * 0.5 * h);
              const double   V = 4 * l[0] * l[1] * x[0];
              std::vector<Axisymmetric::Node> support;
              ASSERT_EQ(
                Axisymmetric::compute_support(type,
                                              mesh.transfer,
                                              mesh.cell_of(x),
                                              x,
                                              unit_symmetric_tensor<2>(),
                                              l,
                                              support),
                Axisymmetric::Status::ok);
              for (const auto &node : support)
                {
                  Tensor<1, 2> stress_term;
                  stress_term[0] = p * node.G[0];
                  stress_term[1] = q * node.G[1];
                  force_without_hoop[node.dof] -= V * stress_term;
                  stress_term[0] += p * node.T;
                  force[node.dof] -= V * stress_term;
                  mass += rho * V * node.S;
                }
            }
        const std::string where = fmpm::ShapeFunction::parameter_name(type);
        EXPECT_NEAR(mass / (rho * R * R * H / 2), 1, 1e-14) << where;
        double largest_without_hoop = 0;
        for (const auto &[dof, f] : force)
          {
            const Point<2> &x_i = mesh.support_points.at(dof);
            const bool      on_z_faces =
              std::abs(x_i[1]) < 1e-12 || std::abs(x_i[1] - H) < 1e-12;
            Tensor<1, 2> expected;
            if (std::abs(x_i[0] - R) < 1e-12 && !on_z_faces)
              expected[0] = -p * R * h;
            if (!on_z_faces)
              {
                EXPECT_NEAR((f - expected).norm(), 0, 1e-14)
                  << where << " at node " << x_i;
              }
            if (!on_z_faces && x_i[0] < R - 1e-12)
              largest_without_hoop =
                std::max(largest_without_hoop,
                         force_without_hoop.at(dof).norm());
          }
        EXPECT_GT(largest_without_hoop, 0.1 * std::abs(p) * h * h) << where;
      }
  }


  // The mesh rule: a mesh from the axis or beyond passes; one that reaches
  // r < 0 stops with an error naming the parameter and the r found.
  TEST(AxisymmetricShapeFunction, MeshMustNotReachBelowTheAxis)
  {
    RzMesh from_axis(0, 2, 2, 0.5), beyond(3, 2, 2, 0.5), across(-1, 4, 2, 0.5);
    EXPECT_NO_THROW(
      Axisymmetric::check_mesh(from_axis.triangulation, "Geometry/Geometry"));
    EXPECT_NO_THROW(
      Axisymmetric::check_mesh(beyond.triangulation, "Geometry/Geometry"));
    try
      {
        Axisymmetric::check_mesh(across.triangulation, "Geometry/Geometry");
        ADD_FAILURE() << "a mesh reaching r = -1 passed";
      }
    catch (const std::exception &error)
      {
        const std::string what = error.what();
        EXPECT_NE(what.find("Geometry/Geometry = axisymmetric"),
                  std::string::npos)
          << what;
        EXPECT_NE(what.find("r = -1 < 0"), std::string::npos) << what;
      }
  }


  // The 2D neo-Hookean kernels read the hoop stretch F_33: for block
  // diagonal F = diag-block(F_rz, F_33) (a radial expansion with shear in
  // the r–z plane) both energy forms give the stress and energy of the 3D
  // kernels (an independent path: the full 3x3 F, J = det F), σ_θθ = σ_rr
  // when F = diag(c, d, c), and σ_θθ ≠ σ_zz of plane strain.
  TEST(AxisymmetricKinematics, NeoHookeanReadsTheHoopStretch)
  {
    using Model = fmpm::ConstitutiveModel::NeoHookean<2>;
    for (const auto form :
         {Model::EnergyForm::j_squared, Model::EnergyForm::log_j})
      {
        fmpm::ConstitutiveModel::NeoHookean<2> model_2d;
        fmpm::ConstitutiveModel::NeoHookean<3> model_3d;
        model_2d.bulk_modulus = model_3d.bulk_modulus = 5e6;
        model_2d.shear_modulus = model_3d.shear_modulus = 1.5e6;
        model_2d.energy_form                            = form;
        model_3d.energy_form =
          static_cast<fmpm::ConstitutiveModel::NeoHookean<3>::EnergyForm>(form);
        fmpm::ConstitutiveModel::StressUpdateInputs  inputs;
        fmpm::ConstitutiveModel::StressUpdateOutputs out_2d, out_3d;
        const std::vector<Tensor<2, 3>>              F{
          Tensor<2, 3>({{1.2, 0, 0}, {0, 0.9, 0}, {0, 0, 1.2}}),
          Tensor<2, 3>({{1.05, 0.1, 0}, {-0.05, 0.97, 0}, {0, 0, 1.3}}),
          Tensor<2, 3>({{0.8, 0, 0}, {0, 1.1, 0}, {0, 0, 0.8}})};
        inputs.resize(F.size());
        for (unsigned int q = 0; q < F.size(); ++q)
          {
            inputs.set_deformation_gradient(q, F[q]);
            inputs.volume_ratio[q] = determinant(F[q]);
          }
        model_2d.update_stress(inputs, out_2d);
        model_3d.update_stress(inputs, out_3d);
        for (unsigned int q = 0; q < F.size(); ++q)
          {
            const SymmetricTensor<2, 3> s2 = out_2d.stress_tensor(q),
                                        s3 = out_3d.stress_tensor(q);
            EXPECT_LT((s2 - s3).norm(), 1e-12 * s3.norm()) << q;
            EXPECT_NEAR(out_2d.strain_energy_density[q],
                        out_3d.strain_energy_density[q],
                        1e-12 * std::abs(out_3d.strain_energy_density[q]));
            if (F[q][0][1] == 0)
              {
                EXPECT_NEAR(s2[2][2], s2[0][0], 1e-12 * s3.norm()) << q;
                EXPECT_GT(std::abs(s2[2][2] - s2[1][1]), 1e-3 * s3.norm());
              }
          }
      }
  }


  // GIMP by the quadrature on axis-aligned cells: on a uniform mesh it
  // equals the closed forms node by node (near the axis too); on a mesh
  // refined near the axis (hanging nodes), where the closed forms do not
  // apply, Σ S = 1, Σ S x_i = centroid, Σ G = 0, Σ G ⊗ x_i = I, Σ T r_i = 1
  // hold.
  TEST(AxisymmetricShapeFunction, GimpQuadratureOnAxisAlignedCells)
  {
    std::mt19937                           generator(29);
    std::uniform_real_distribution<double> unit(0, 1), amount(-0.2, 0.2);
    const double                           h = 0.25;
    RzMesh       uniform(0, 8, 8, h), refined(0, 8, 8, h, true);
    unsigned int n_checked = 0;
    for (unsigned int p = 0; p < 40; ++p)
      {
        const Point<2> x(h * (p % 4 == 0 ? 0.05 + 0.95 * unit(generator) :
                                           1 + 6 * unit(generator)),
                         h * (1 + 6 * unit(generator)));
        Tensor<2, 2>   F;
        for (unsigned int i = 0; i < 2; ++i)
          for (unsigned int j = 0; j < 2; ++j)
            F[i][j] = (i == j ? 1 : 0) + amount(generator);
        // Half-lengths for the finest cells of the refined mesh.
        const Tensor<1, 2> l0({0.1 * h, 0.12 * h});
        for (const Type type : {Type::ugimp, Type::cpgimp})
          {
            std::vector<Axisymmetric::Node> closed, quadrature;
            const unsigned int              cell = uniform.cell_of(x);
            ASSERT_EQ(Axisymmetric::compute_support(
                        type, uniform.transfer, cell, x, F, l0, closed),
                      Axisymmetric::Status::ok);
            ASSERT_EQ(
              Axisymmetric::compute_support(
                type, uniform.transfer, cell, x, F, l0, quadrature, false),
              Axisymmetric::Status::ok);
            std::map<types::global_dof_index, const Axisymmetric::Node *>
              by_dof;
            for (const auto &node : quadrature)
              by_dof[node.dof] = &node;
            for (const auto &node : closed)
              {
                ASSERT_EQ(by_dof.count(node.dof), 1u);
                const auto &other = *by_dof[node.dof];
                EXPECT_NEAR(node.S, other.S, 1e-13);
                EXPECT_NEAR((node.G - other.G).norm() * h, 0, 1e-13);
                EXPECT_NEAR((node.T - other.T) * x[0], 0, 1e-13);
                by_dof.erase(node.dof);
              }
            for (const auto &[dof, node] : by_dof)
              EXPECT_NEAR(std::abs(node->S) + node->G.norm() * h +
                            std::abs(node->T) * x[0],
                          0,
                          1e-13);

            std::vector<Axisymmetric::Node> support;
            ASSERT_EQ(
              Axisymmetric::compute_support(
                type, refined.transfer, refined.cell_of(x), x, F, l0, support),
              Axisymmetric::Status::ok)
              << x;
            Point<2> centroid;
            double   area_over_r_area;
            domain_moments(type, x, F, l0, centroid, area_over_r_area);
            double       sum_S = 0, sum_T_r = 0;
            Tensor<1, 2> sum_G, sum_S_x;
            Tensor<2, 2> sum_G_x;
            for (const auto &node : support)
              {
                const Point<2> &x_i = refined.support_points.at(node.dof);
                sum_S += node.S;
                sum_S_x += node.S * x_i;
                sum_G += node.G;
                sum_G_x += outer_product(node.G, x_i);
                sum_T_r += node.T * x_i[0];
              }
            EXPECT_NEAR(sum_S, 1, 1e-13) << x;
            EXPECT_NEAR((sum_S_x - centroid).norm(), 0, 1e-13) << x;
            EXPECT_NEAR(sum_G.norm() * h, 0, 1e-12) << x;
            EXPECT_NEAR((sum_G_x - unit_symmetric_tensor<2>()).norm(), 0, 1e-12)
              << x;
            EXPECT_NEAR(sum_T_r, 1, 1e-13) << x;
            ++n_checked;
          }
      }
    EXPECT_EQ(n_checked, 80u);
  }
} // namespace
