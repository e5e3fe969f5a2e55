// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks fmpm::PointSort<2> on any number of ranks (ctest runs it on one
// and on two): two points per cell of an 8 x 8 mesh, one moved across one
// or two faces (some onto the other rank), one kept in its cell; after
// sort() every point lies in a locally owned cell at the reference
// position of its new location, with its record (the id in the mass slot,
// its initial position), the store is in cell order and by id in a cell,
// and every id is on exactly one rank; on two ranks points changed rank.
// A point moved outside the mesh on one rank makes sort() return false on
// every rank, and with a periodic direction a point that crossed the face
// enters through the opposite one, its initial position shifted by the
// period.

#include <fmpm/grid_transfer.h>
#include <fmpm/material_points.h>
#include <fmpm/particle_properties.h>
#include <fmpm/points/point_sort.h>

#include <deal.II/base/mpi.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/affine_constraints.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using Index                  = fmpm::PropertyIndex<2>;
  constexpr unsigned int n     = 8;
  constexpr double       h     = 1. / n;
  constexpr unsigned int owner = Index::volume;

  /** The unit square in n x n cells on all ranks, its transfer data, a
   * store with two points per owned cell, and the sort. */
  struct SortSetup
  {
    parallel::distributed::Triangulation<2>      triangulation;
    FE_Q<2>                                      fe;
    DoFHandler<2>                                dof_handler;
    AffineConstraints<double>                    constraints;
    std::shared_ptr<Utilities::MPI::Partitioner> partitioner;
    fmpm::GridTransfer<2>                        transfer;
    fmpm::PointSort<2>                           sort;
    fmpm::MaterialPoints<2>                      points;
    const unsigned int                           rank;

    explicit SortSetup(const bool periodic_x)
      : triangulation(MPI_COMM_WORLD)
      , fe(1)
      , dof_handler(triangulation)
      , rank(Utilities::MPI::this_mpi_process(MPI_COMM_WORLD))
    {
      GridGenerator::hyper_cube(triangulation, 0, 1, true);
      if (periodic_x)
        {
          std::vector<GridTools::PeriodicFacePair<
            typename Triangulation<2>::cell_iterator>>
            pairs;
          GridTools::collect_periodic_faces(triangulation, 0, 1, 0, pairs);
          triangulation.add_periodicity(pairs);
        }
      triangulation.refine_global(3);
      dof_handler.distribute_dofs(fe);
      IndexSet relevant;
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      constraints.reinit(relevant);
      constraints.close();
      partitioner = std::make_shared<Utilities::MPI::Partitioner>(
        dof_handler.locally_owned_dofs(), relevant, MPI_COMM_WORLD);
      sort.reinit(triangulation,
                  transfer,
                  Point<2>(0, 0),
                  Point<2>(1, 1),
                  {{periodic_x, false}});
      transfer.reinit(
        dof_handler, constraints, *partitioner, false, &sort.vertex_cells());

      std::vector<Triangulation<2>::active_cell_iterator> cells;
      for (const auto &cell : triangulation.active_cell_iterators())
        if (cell->is_locally_owned())
          cells.push_back(cell);
      std::sort(cells.begin(), cells.end(), [](const auto &a, const auto &b) {
        return a->id() < b->id();
      });
      points.initialize(Index::n_core_properties);
      points.set_cell_order(cells, triangulation.n_active_cells());
      // Point 2c at the centre of cell c = i + n j, point 2c + 1 beside it.
      for (const auto &cell : cells)
        {
          const Point<2>     center = cell->center();
          const unsigned int c      = static_cast<unsigned int>(center[0] / h) +
                                 n * static_cast<unsigned int>(center[1] / h);
          for (const unsigned int id : {2 * c, 2 * c + 1})
            {
              const Point<2> x =
                id % 2 == 0 ? center : center + Tensor<1, 2>({0.2 * h, 0.});
              std::vector<double> record(Index::n_core_properties, 0.);
              record[Index::mass]                 = id;
              record[owner]                       = rank;
              record[Index::initial_position]     = x[0];
              record[Index::initial_position + 1] = x[1];
              const Point<2> xi = fmpm::GridTransfer<2>::reference_point(
                transfer.cell_data(cell->active_cell_index()),
                x,
                Point<2>(0.5, 0.5));
              points.add(id, x, xi, cell, record.data());
            }
        }
      points.rebin();
    }

    /** The particle update's part: move point k by @p shift(id); a point
     * still in its cell gets its new ξ, the others are listed. */
    template <class Shift>
    void
    move_points(const Shift &shift)
    {
      sort.clear();
      for (unsigned int c = 0; c < points.n_cells(); ++c)
        for (unsigned int k = points.cell_point_begin[c];
             k < points.cell_point_begin[c + 1];
             ++k)
          {
            points.position[k] += shift(points.id[k], points.position[k]);
            const Point<2> xi = fmpm::GridTransfer<2>::reference_point(
              transfer.cell_data(points.cell_iterator(c)->active_cell_index()),
              points.position[k],
              points.reference_position[k]);
            if (fmpm::GridTransfer<2>::is_inside(xi))
              points.reference_position[k] = xi;
            else
              sort.left_cell(k);
          }
    }

    /** Every point in an owned cell at its ξ, in cell order and by id in
     * a cell; returns the ids of this rank. */
    std::vector<unsigned int>
    check_store() const
    {
      std::vector<unsigned int> ids;
      for (unsigned int c = 0; c < points.n_cells(); ++c)
        {
          const auto cell = points.cell_iterator(c);
          EXPECT_TRUE(cell->is_locally_owned());
          for (unsigned int k = points.cell_point_begin[c];
               k < points.cell_point_begin[c + 1];
               ++k)
            {
              EXPECT_EQ(points.cell[k], cell->active_cell_index());
              const Point<2> xi = fmpm::GridTransfer<2>::reference_point(
                transfer.cell_data(cell->active_cell_index()),
                points.position[k],
                Point<2>(0.5, 0.5));
              EXPECT_TRUE(fmpm::GridTransfer<2>::is_inside(xi))
                << "point " << points.id[k];
              EXPECT_LT(xi.distance(points.reference_position[k]), 1e-12);
              EXPECT_EQ(points.column(Index::mass)[k], points.id[k]);
              if (k > points.cell_point_begin[c])
                {
                  EXPECT_LT(points.id[k - 1], points.id[k]);
                }
              ids.push_back(points.id[k]);
            }
        }
      return ids;
    }
  };
} // namespace



TEST(PointSort, PointsFindTheirCellsOnTheirOwners)
{
  SortSetup setup(false);
  // Even ids: across one or two faces, towards the middle (no point leaves
  // the mesh); odd ids: within their cells.
  const auto shift = [](const unsigned int id, const Point<2> &x) {
    if (id % 2 == 1)
      return Tensor<1, 2>({-0.1 * h, 0.1 * h});
    Tensor<1, 2> s;
    s[0] = (x[0] < 0.5 ? 0.7 : -0.7) * h;
    s[1] = (id / 2) % 3 == 0 ? (x[1] < 0.5 ? 0.6 : -0.6) * h : 0.;
    return s;
  };
  setup.move_points(shift);
  ASSERT_TRUE(setup.sort.sort(setup.points));

  const std::vector<unsigned int> ids            = setup.check_store();
  unsigned int                    n_changed_rank = 0;
  for (unsigned int k = 0; k < setup.points.n_points(); ++k)
    {
      const unsigned int id = setup.points.id[k];
      // The record followed: the initial position is the creation's.
      const unsigned int c = id / 2;
      Point<2>           X((c % n + 0.5) * h, (c / n + 0.5) * h);
      if (id % 2 == 1)
        X[0] += 0.2 * h;
      EXPECT_LT(setup.points.position[k].distance(X + shift(id, X)), 1e-14);
      EXPECT_NEAR(setup.points.column(Index::initial_position)[k], X[0], 1e-15);
      EXPECT_NEAR(setup.points.column(Index::initial_position + 1)[k],
                  X[1],
                  1e-15);
      n_changed_rank += setup.points.column(owner)[k] != setup.rank;
    }
  // Every id on exactly one rank.
  const auto all_ids = Utilities::MPI::all_gather(MPI_COMM_WORLD, ids);
  std::vector<unsigned int> sorted;
  for (const auto &rank_ids : all_ids)
    sorted.insert(sorted.end(), rank_ids.begin(), rank_ids.end());
  std::sort(sorted.begin(), sorted.end());
  ASSERT_EQ(sorted.size(), 2 * n * n);
  for (unsigned int id = 0; id < sorted.size(); ++id)
    EXPECT_EQ(sorted[id], id);
  const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
  const unsigned int total_changed =
    Utilities::MPI::sum(n_changed_rank, MPI_COMM_WORLD);
  if (n_ranks > 1)
    EXPECT_GT(total_changed, 0u);
  else
    EXPECT_EQ(total_changed, 0u);
}



TEST(PointSort, APointOutsideTheMeshAsksEveryRankForTheFullSort)
{
  SortSetup          setup(false);
  const unsigned int n_points = setup.points.n_points();
  // Rank 0's first point leaves the mesh; the others move one cell up or
  // down.
  const bool         has_lost = setup.rank == 0 && n_points > 0;
  const unsigned int lost_id  = has_lost ? setup.points.id[0] : 0;
  setup.move_points([&](const unsigned int id, const Point<2> &x) {
    if (has_lost && id == lost_id)
      return Tensor<1, 2>({-2., 0.});
    return Tensor<1, 2>({0., (x[1] < 0.5 ? 1. : -1.) * h});
  });
  EXPECT_FALSE(setup.sort.sort(setup.points));
  // No point moved in the store.
  EXPECT_EQ(setup.points.n_points(), n_points);
}



TEST(PointSort, PeriodicFacesShiftThePoint)
{
  SortSetup setup(true);
  // The points of the first column leave through x = 0 and enter through
  // x = 1; the others move right within their cells.
  setup.move_points([](const unsigned int, const Point<2> &x) {
    return Tensor<1, 2>({x[0] < h ? -0.75 * h : 0.05 * h, 0.});
  });
  ASSERT_TRUE(setup.sort.sort(setup.points));
  setup.check_store();
  for (unsigned int k = 0; k < setup.points.n_points(); ++k)
    {
      const double x = setup.points.position[k][0];
      const double X = setup.points.column(Index::initial_position)[k];
      EXPECT_GE(x, 0.);
      EXPECT_LT(x, 1.);
      // u = x − X kept: −0.75 h for the wrapped points, 0.05 h else.
      const bool wrapped = x > 1 - h && X > 1;
      EXPECT_NEAR(x - X, wrapped ? -0.75 * h : 0.05 * h, 1e-14)
        << "point " << setup.points.id[k];
    }
  const unsigned int n_wrapped = Utilities::MPI::sum(
    [&]() {
      unsigned int count = 0;
      for (unsigned int k = 0; k < setup.points.n_points(); ++k)
        count += setup.points.column(Index::initial_position)[k] > 1;
      return count;
    }(),
    MPI_COMM_WORLD);
  EXPECT_EQ(n_wrapped, 2 * n);
}
