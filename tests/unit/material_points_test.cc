// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks fmpm::MaterialPoints<2>, the point store: after rebin() the points
// are in the cell order given to set_cell_order() and by id in a cell, with
// every column following its point; a column no pass writes whose values
// are all equal reads its value from an array shared with the other such
// columns of that value (0: the zeros of the plane-strain slots), and the
// first point with another value gives it its own array without changing
// the values of the points already there; removed points go.

#include <fmpm/material_points.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;

  // Slots of this test's records: 0 written by the passes, 1 and 2
  // invariant, 3 always zero.
  constexpr unsigned int written = 0, invariant_a = 1, invariant_b = 2,
                         zero = 3, n_slots = 4;

  struct Store
  {
    Triangulation<2>                                    triangulation;
    std::vector<Triangulation<2>::active_cell_iterator> cells;
    fmpm::MaterialPoints<2>                             points;

    Store()
    {
      GridGenerator::subdivided_hyper_cube(triangulation, 2);
      // Pass order: the cells in reverse storage order.
      for (const auto &cell : triangulation.active_cell_iterators())
        cells.insert(cells.begin(), cell);
      points.initialize(n_slots, {zero}, {invariant_a, invariant_b});
      points.set_cell_order(cells, triangulation.n_active_cells());
    }

    void
    add(const unsigned int id,
        const unsigned int cell,
        const double       value,
        const double       a,
        const double       b)
    {
      const double record[n_slots] = {value, a, b, 0.};
      points.add(
        id, cells[cell]->center(), Point<2>(0.5, 0.5), cells[cell], record);
    }
  };
} // namespace



TEST(MaterialPoints, RebinOrdersByCellThenIdAndColumnsFollow)
{
  Store store;
  // (id, cell in pass order); the written slot holds 10 id.
  const std::vector<std::pair<unsigned int, unsigned int>> created = {
    {7, 2}, {3, 0}, {5, 2}, {1, 3}, {4, 0}, {2, 1}};
  for (const auto &[id, cell] : created)
    store.add(id, cell, 10. * id, 2.5, 0.);
  store.points.rebin();

  auto &points = store.points;
  ASSERT_EQ(points.n_points(), 6u);
  const std::vector<unsigned int> expected_ids = {3, 4, 2, 5, 7, 1};
  for (unsigned int k = 0; k < points.n_points(); ++k)
    {
      EXPECT_EQ(points.id[k], expected_ids[k]);
      EXPECT_EQ(points.column(written)[k], 10. * expected_ids[k]);
    }
  ASSERT_EQ(points.n_cells(), 4u);
  const std::vector<unsigned int> expected_begin = {0, 2, 3, 5, 6};
  for (unsigned int c = 0; c <= points.n_cells(); ++c)
    EXPECT_EQ(points.cell_point_begin[c], expected_begin[c]);
  for (unsigned int c = 0; c < points.n_cells(); ++c)
    EXPECT_EQ(points.cell_iterator(c), store.cells[c]);

  // Point 4 moves to the last cell, point 5 leaves the rank.
  points.move(1, store.cells[3], Point<2>(0.25, 0.25));
  points.remove(3);
  points.rebin();
  const std::vector<unsigned int> ids_after = {3, 2, 7, 1, 4};
  ASSERT_EQ(points.n_points(), ids_after.size());
  for (unsigned int k = 0; k < points.n_points(); ++k)
    {
      EXPECT_EQ(points.id[k], ids_after[k]);
      EXPECT_EQ(points.column(written)[k], 10. * ids_after[k]);
    }
  EXPECT_EQ(points.reference_position[4], Point<2>(0.25, 0.25));
}



TEST(MaterialPoints, UniformColumnsShareAnArrayUntilAnotherValueArrives)
{
  Store store;
  for (unsigned int id = 0; id < 5; ++id)
    store.add(id, id % 4, 1. + id, 2.5, 0.);
  auto &points = store.points;
  points.rebin();

  // Slot b holds 0 everywhere: it reads the plane-strain zeros; slot a
  // reads its value.
  EXPECT_EQ(points.column(invariant_b), points.column(zero));
  for (unsigned int k = 0; k < points.n_points(); ++k)
    {
      EXPECT_EQ(points.column(invariant_a)[k], 2.5);
      EXPECT_EQ(points.column(invariant_b)[k], 0.);
    }

  // A point with another value of slot a: the column gets its own array,
  // the points already there keep 2.5.
  store.add(9, 1, 100., -1., 0.);
  points.rebin();
  ASSERT_EQ(points.n_points(), 6u);
  unsigned int n_other = 0;
  for (unsigned int k = 0; k < points.n_points(); ++k)
    {
      const double expected = points.id[k] == 9 ? -1. : 2.5;
      EXPECT_EQ(points.column(invariant_a)[k], expected);
      n_other += points.column(invariant_a)[k] == -1.;
      double record[n_slots];
      points.copy_record(k, record);
      EXPECT_EQ(record[invariant_a], expected);
      EXPECT_EQ(record[invariant_b], 0.);
      EXPECT_EQ(record[written], points.id[k] == 9 ? 100. : 1. + points.id[k]);
    }
  EXPECT_EQ(n_other, 1u);
  EXPECT_EQ(points.column(invariant_b), points.column(zero));

  // -0 is not 0: a column of -0 does not read the zeros.
  fmpm::MaterialPoints<2> negative_zero;
  negative_zero.initialize(n_slots, {zero}, {invariant_a, invariant_b});
  negative_zero.set_cell_order(store.cells,
                               store.triangulation.n_active_cells());
  const double record[n_slots] = {1., -0., 0., 0.};
  negative_zero.add(
    0, store.cells[0]->center(), Point<2>(0.5, 0.5), store.cells[0], record);
  negative_zero.rebin();
  EXPECT_NE(negative_zero.column(invariant_a), negative_zero.column(zero));
  EXPECT_TRUE(std::signbit(negative_zero.column(invariant_a)[0]));
}
