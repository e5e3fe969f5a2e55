// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks Transfer::for_each_point() with the sinks of m, p (Eq. 1.6) and f
// (Eq. 2.11): on supports built in the loop (SupportBuilder), read back from
// the cache (StoredSupports) and, for classic shape functions on affine
// cells, computed from ξ (ComputedSupports), the grid vectors have the same
// bits; and they are the right sums: Σ_i m_i = Σ_p M_p (partition of
// unity), Σ_i p_i = Σ_p M_p V_p and Σ_i f_i = Σ_p M_p g (Σ_i G_i = 0), in
// 2D and 3D, classic and uGIMP.

#include <fmpm/external_loads.h>
#include <fmpm/grid_transfer.h>
#include <fmpm/material_points.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_properties.h>
#include <fmpm/points/point_sort.h>
#include <fmpm/transfer/point_loop.h>
#include <fmpm/transfer/sinks.h>
#include <fmpm/transfer/support_builder.h>

#include <deal.II/base/mpi.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/affine_constraints.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;

  /** The unit cube in 4^dim cells, two points per owned cell (off its
   * centre, half a cell wide), with mass, velocity, volume and stress that
   * differ from point to point, and gravity. */
  template <int dim>
  struct Scene
  {
    using Index = fmpm::PropertyIndex<dim>;
    static constexpr double                                 h           = 0.25;
    static constexpr double                                 hoop_stress = -3.5;
    parallel::distributed::Triangulation<dim>               triangulation;
    FE_Q<dim>                                               fe;
    DoFHandler<dim>                                         dof_handler;
    AffineConstraints<double>                               constraints;
    std::shared_ptr<Utilities::MPI::Partitioner>            partitioner;
    fmpm::GridTransfer<dim>                                 transfer;
    fmpm::PointSort<dim>                                    sort;
    fmpm::ParticleProperties<dim>                           properties;
    fmpm::ExternalLoads<dim>                                loads;
    fmpm::MaterialPoints<dim>                               points;
    fmpm::SupportCache<dim>                                 cache;
    std::vector<fmpm::ShapeFunction::UniformGimpPatch<dim>> gimp;
    std::vector<fmpm::ShapeFunction::UniformCpdiPatch<dim>> cpdi;
    std::vector<unsigned int> gimp_of_cell, cpdi_of_cell;

    /** @p hoop_scene (2D): one point per cell at its centre filling it
     * (half-length h/2), volume per radian h² r_p, no mass, the uniform
     * stress σ_rr = σ_θθ = hoop_stress, σ_zz = σ_rz = 0. */
    explicit Scene(const bool hoop_scene = false)
      : triangulation(MPI_COMM_WORLD)
      , fe(1)
      , dof_handler(triangulation)
    {
      GridGenerator::hyper_cube(triangulation, 0, 1, true);
      triangulation.refine_global(2);
      dof_handler.distribute_dofs(fe);
      IndexSet relevant;
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      constraints.reinit(relevant);
      constraints.close();
      partitioner = std::make_shared<Utilities::MPI::Partitioner>(
        dof_handler.locally_owned_dofs(), relevant, MPI_COMM_WORLD);
      std::array<bool, dim> periodic{};
      sort.reinit(triangulation,
                  transfer,
                  Point<dim>(),
                  Point<dim>() + 1. * unit(),
                  periodic);
      transfer.reinit(
        dof_handler, constraints, *partitioner, true, &sort.vertex_cells());

      fmpm::Parameters parameters;
      parameters.gravity = {0.5, -9.81, 2.};
      loads.initialize(parameters, properties);
      points.initialize(properties.n_properties());
      std::vector<typename Triangulation<dim>::active_cell_iterator> cells;
      for (const auto &cell : triangulation.active_cell_iterators())
        if (cell->is_locally_owned())
          cells.push_back(cell);
      std::sort(cells.begin(), cells.end(), [](const auto &a, const auto &b) {
        return a->id() < b->id();
      });
      points.set_cell_order(cells, triangulation.n_active_cells());
      unsigned int id = 0;
      if (hoop_scene)
        for (const auto &cell : cells)
          {
            const Point<dim>    x = cell->center();
            std::vector<double> record(properties.n_properties(), 0.);
            record[Index::volume] = h * h * x[0];
            for (unsigned int d = 0; d < dim; ++d)
              {
                record[Index::initial_position + d]         = x[d];
                record[Index::initial_half_length + d]      = h / 2;
                record[Index::deformation_gradient + 4 * d] = 1.;
              }
            record[Index::deformation_gradient + 8] = 1.;
            record[Index::stress + 0]               = hoop_stress;
            record[Index::stress + 2]               = hoop_stress;
            const Point<dim> xi = fmpm::GridTransfer<dim>::reference_point(
              transfer.cell_data(cell->active_cell_index()),
              x,
              Point<dim>() + 0.5 * unit());
            points.add(id++, x, xi, cell, record.data());
          }
      else
        for (const auto &cell : cells)
          for (const double shift : {-0.35, 0.3})
            {
              // (uGIMP: the point's domain, ±h/4, reaches the neighbours.)
              Point<dim> x = cell->center();
              for (unsigned int d = 0; d < dim; ++d)
                x[d] += shift * h * (1. - 0.2 * d);
              std::vector<double> record(properties.n_properties(), 0.);
              record[Index::mass]   = 1. + 0.1 * id;
              record[Index::volume] = 0.5 + 0.01 * id;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  record[Index::velocity + d] = std::sin(3. * x[d] + id);
                  record[Index::initial_position + d]         = x[d];
                  record[Index::initial_half_length + d]      = h / 4;
                  record[Index::deformation_gradient + 4 * d] = 1.;
                }
              for (unsigned int c = 0; c < 6; ++c)
                record[Index::stress + c] = std::cos(1. + c + 0.3 * id);
              const Point<dim> xi = fmpm::GridTransfer<dim>::reference_point(
                transfer.cell_data(cell->active_cell_index()),
                x,
                Point<dim>() + 0.5 * unit());
              points.add(id, x, xi, cell, record.data());
              ++id;
            }
      points.rebin();
    }

    static Tensor<1, dim>
    unit()
    {
      Tensor<1, dim> one;
      for (unsigned int d = 0; d < dim; ++d)
        one[d] = 1;
      return one;
    }

    fmpm::Transfer::SupportBuilder<dim>
    builder(const fmpm::ShapeFunction::Type type,
            const bool                      axisymmetric = false)
    {
      cache.clear();
      return fmpm::Transfer::SupportBuilder<dim>(
        cache,
        points,
        transfer,
        constraints,
        *partitioner,
        type,
        0.,
        triangulation.n_active_cells(),
        {gimp, gimp_of_cell, cpdi, cpdi_of_cell},
        nullptr,
        axisymmetric);
    }
  };

  /** m, p and f on the ghosted local nodes. */
  template <int dim>
  struct GridSums
  {
    std::vector<double>                  m;
    std::array<std::vector<double>, dim> p, f;
  };

  /** One loop of the m, p and f sinks over @p supports (@p hoop: f with
   * the hoop force, axisymmetric). */
  template <int dim, typename Supports, bool hoop = false>
  GridSums<dim>
  extrapolate(Scene<dim> &scene, Supports &supports)
  {
    const unsigned int n = scene.partitioner->locally_owned_size() +
                           scene.partitioner->n_ghost_indices();
    GridSums<dim> sums;
    sums.m.assign(n, 0.);
    double *p[dim], *f[dim];
    for (unsigned int d = 0; d < dim; ++d)
      {
        sums.p[d].assign(n, 0.);
        sums.f[d].assign(n, 0.);
        p[d] = sums.p[d].data();
        f[d] = sums.f[d].data();
      }
    const fmpm::Transfer::MassMomentumSink<dim> mass_momentum(scene.points,
                                                              sums.m.data(),
                                                              p);
    fmpm::Transfer::ForceSink<dim, hoop> force(scene.points, scene.loads, f);
    force.read_hoop_function(scene.cache);
    fmpm::Transfer::for_each_point(scene.points,
                                   supports,
                                   mass_momentum,
                                   force);
    return sums;
  }

  template <int dim>
  void
  expect_same_bits(const GridSums<dim> &a, const GridSums<dim> &b)
  {
    auto same = [](const std::vector<double> &x, const std::vector<double> &y) {
      return x.size() == y.size() &&
             std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
    };
    EXPECT_TRUE(same(a.m, b.m));
    for (unsigned int d = 0; d < dim; ++d)
      {
        EXPECT_TRUE(same(a.p[d], b.p[d])) << "p component " << d;
        EXPECT_TRUE(same(a.f[d], b.f[d])) << "f component " << d;
      }
  }

  /** Σ_i m_i = Σ M, Σ_i p_i = Σ M V, Σ_i f_i = Σ M g (one rank: no
   * ghosts to add). */
  template <int dim>
  void
  expect_right_sums(const Scene<dim> &scene, const GridSums<dim> &sums)
  {
    using Index                    = fmpm::PropertyIndex<dim>;
    const double *const M          = scene.points.column(Index::mass);
    double              total_mass = 0;
    Tensor<1, dim>      momentum;
    for (unsigned int k = 0; k < scene.points.n_points(); ++k)
      {
        total_mass += M[k];
        for (unsigned int d = 0; d < dim; ++d)
          momentum[d] += M[k] * scene.points.column(Index::velocity + d)[k];
      }
    auto sum = [](const std::vector<double> &x) {
      double s = 0;
      for (const double v : x)
        s += v;
      return s;
    };
    EXPECT_NEAR(sum(sums.m), total_mass, 1e-12 * total_mass);
    for (unsigned int d = 0; d < dim; ++d)
      {
        EXPECT_NEAR(sum(sums.p[d]), momentum[d], 1e-12 * total_mass);
        EXPECT_NEAR(sum(sums.f[d]),
                    total_mass * scene.loads.gravity()[d],
                    1e-10 * total_mass);
      }
  }

  template <int dim>
  void
  check(const fmpm::ShapeFunction::Type type)
  {
    if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
      GTEST_SKIP() << "one rank: the sums need no ghost exchange";
    Scene<dim> scene;
    ASSERT_GT(scene.points.n_points(), 0u);
    auto                built   = scene.builder(type);
    const GridSums<dim> in_loop = extrapolate(scene, built);
    EXPECT_EQ(built.failed_point, numbers::invalid_unsigned_int);
    // uGIMP supports reach beyond the cell's 2^dim nodes.
    const std::size_t n_cell_entries =
      scene.points.n_points() * fmpm::GridTransfer<dim>::n_nodes;
    if (type == fmpm::ShapeFunction::Type::ugimp)
      EXPECT_GT(scene.cache.n_stored, n_cell_entries);
    else
      EXPECT_EQ(scene.cache.n_stored, n_cell_entries);
    expect_right_sums(scene, in_loop);
    fmpm::Transfer::StoredSupports<dim> stored(scene.cache);
    const GridSums<dim>                 from_cache = extrapolate(scene, stored);
    expect_same_bits(in_loop, from_cache);
    if (type == fmpm::ShapeFunction::Type::classic)
      {
        scene.cache.implicit_classic   = true;
        scene.cache.n_implicit_points  = scene.points.n_points();
        scene.cache.reference_position = scene.points.reference_position.data();
        fmpm::Transfer::ComputedSupports<dim> computed(scene.cache,
                                                       scene.transfer,
                                                       scene.points,
                                                       true);
        expect_same_bits(extrapolate(scene, computed), from_cache);
      }
  }
} // namespace

TEST(PointLoop, ClassicSupportsBuiltStoredAndComputedGiveTheSameBits2D)
{
  check<2>(fmpm::ShapeFunction::Type::classic);
}

TEST(PointLoop, ClassicSupportsBuiltStoredAndComputedGiveTheSameBits3D)
{
  check<3>(fmpm::ShapeFunction::Type::classic);
}

TEST(PointLoop, UgimpSupportsBuiltAndStoredGiveTheSameBits2D)
{
  check<2>(fmpm::ShapeFunction::Type::ugimp);
}

TEST(PointLoop, UgimpSupportsBuiltAndStoredGiveTheSameBits3D)
{
  check<3>(fmpm::ShapeFunction::Type::ugimp);
}

namespace
{
  /**
   * Axisymmetric wiring: the builder stores T with S and G, the hoop force
   * sink reads it. A uniform stress σ_rr = σ_θθ = s (σ_zz = σ_rz = 0) on
   * points that tile [0, 1]² (V = ∫ r dA per radian) is in discrete
   * equilibrium: Σ_p V_p (G_ip,r + T_ip) s = s ∫ ∂(r N_i)/∂r dA (exact for
   * these supports), so f_r = −s ∫ N_i(1, z) dz at r = 1 (−s h, −s h/2 at
   * the corners) and f = 0 at every other node, the axis included; without
   * the hoop term the interior nodes are not in equilibrium.
   */
  void
  check_hoop_equilibrium(const fmpm::ShapeFunction::Type type)
  {
    if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
      GTEST_SKIP() << "one rank: the sums need no ghost exchange";
    constexpr double h = Scene<2>::h, s = Scene<2>::hoop_stress;
    Scene<2>         scene(true);
    ASSERT_EQ(scene.points.n_points(), 16u);
    auto              built = scene.builder(type, true);
    const GridSums<2> sums =
      extrapolate<2, decltype(built), true>(scene, built);
    EXPECT_EQ(built.failed_point, numbers::invalid_unsigned_int);
    ASSERT_EQ(scene.cache.T.size() >= scene.cache.n_stored, true);
    // Without the hoop force (the same stored supports).
    fmpm::Transfer::StoredSupports<2> stored(scene.cache);
    const GridSums<2>                 plane =
      extrapolate<2, decltype(stored), false>(scene, stored);
    double largest_plane_interior = 0;
    for (const auto &cell : scene.dof_handler.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        {
          const Point<2>     x = cell->vertex(v);
          const unsigned int i =
            scene.partitioner->global_to_local(cell->vertex_dof_index(v, 0));
          const bool   outer      = std::abs(x[0] - 1) < 1e-12;
          const bool   corner     = outer && (x[1] < 1e-12 || x[1] > 1 - 1e-12);
          const double expected_r = outer ? -s * (corner ? h / 2 : h) : 0.;
          EXPECT_NEAR(sums.f[0][i], expected_r, 1e-13)
            << "node at " << x << ", "
            << fmpm::ShapeFunction::parameter_name(type);
          EXPECT_NEAR(sums.f[1][i], 0., 1e-13) << "node at " << x;
          if (!outer)
            largest_plane_interior =
              std::max(largest_plane_interior, std::abs(plane.f[0][i]));
        }
    EXPECT_GT(largest_plane_interior, 0.1 * std::abs(s) * h);
    // Classic on affine cells: the computed supports (T = S/r_p in the
    // sink) give the bits of the stored ones.
    if (type == fmpm::ShapeFunction::Type::classic)
      {
        scene.cache.implicit_classic   = true;
        scene.cache.n_implicit_points  = scene.points.n_points();
        scene.cache.reference_position = scene.points.reference_position.data();
        fmpm::Transfer::ComputedSupports<2> computed(scene.cache,
                                                     scene.transfer,
                                                     scene.points,
                                                     true);
        expect_same_bits(extrapolate<2, decltype(computed), true>(scene,
                                                                  computed),
                         sums);
      }
  }
} // namespace

TEST(PointLoop, AxisymmetricClassicHoopForceBalancesUniformStress)
{
  check_hoop_equilibrium(fmpm::ShapeFunction::Type::classic);
}

TEST(PointLoop, AxisymmetricUgimpHoopForceBalancesUniformStress)
{
  check_hoop_equilibrium(fmpm::ShapeFunction::Type::ugimp);
}

TEST(PointLoop, AxisymmetricCpdiHoopForceBalancesUniformStress)
{
  check_hoop_equilibrium(fmpm::ShapeFunction::Type::cpdi);
}
