// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The checkerboard indicator of J (postprocess/checkerboard.h): 0 for a
// field linear in each cell, 1 for J = 1 ± ε alternating between
// neighbouring points, whatever the cell's placement.

#include <fmpm/postprocess/checkerboard.h>

#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using namespace fmpm;

  /** The sums of an n x n block of cells of size h with 2 x 2 points each,
   * J given at each point's position and its index (i, j) in the block. */
  template <typename Field>
  Checkerboard::Sums
  block_sums(const unsigned int n,
             const double       h,
             const Field       &field,
             const bool         uneven_masses = true)
  {
    Checkerboard::Sums sums;
    for (unsigned int cx = 0; cx < n; ++cx)
      for (unsigned int cy = 0; cy < n; ++cy)
        {
          std::vector<Point<2>> x;
          std::vector<double>   mass, J;
          for (unsigned int a = 0; a < 2; ++a)
            for (unsigned int b = 0; b < 2; ++b)
              {
                const unsigned int i = 2 * cx + a, j = 2 * cy + b;
                x.emplace_back((i + 0.5) * h / 2 + 0.3, (j + 0.5) * h / 2 - 1);
                mass.push_back(uneven_masses ? 1 + 0.1 * ((i * 7 + j * 3) % 5) :
                                               1.5);
                J.push_back(field(x.back(), i, j));
              }
          sums += Checkerboard::cell_sums<2>(make_array_view(x),
                                             make_array_view(mass),
                                             make_array_view(J));
        }
    return sums;
  }

  /** The indicator of sums taken at one instant. */
  double
  indicator_now(const Checkerboard::Sums &sums)
  {
    return Checkerboard::indicator(sums.residual_rms(),
                                   sums.volume_change_rms());
  }
} // namespace



TEST(Checkerboard, LinearFieldIsZero)
{
  const auto linear = [](const Point<2> &x, unsigned int, unsigned int) {
    return 0.9 + 0.05 * x[0] - 0.08 * x[1];
  };
  EXPECT_LT(indicator_now(block_sums(6, 0.125, linear)), 1e-12);
}



TEST(Checkerboard, SmoothFieldIsSmall)
{
  // A bending-like field J = 1 + 0.1 sin(x) y on h = 1/8: the in-cell
  // curvature is O(h²) of the deformation.
  const auto smooth = [](const Point<2> &x, unsigned int, unsigned int) {
    return 1 + 0.1 * std::sin(x[0]) * x[1];
  };
  EXPECT_LT(indicator_now(block_sums(8, 0.125, smooth)), 0.01);
}



TEST(Checkerboard, AlternatingFieldIsOne)
{
  const double epsilon = 0.2;
  const auto   alternating =
    [&](const Point<2> &, unsigned int i, unsigned int j) {
      return (i + j) % 2 == 0 ? 1 + epsilon : 1 - epsilon;
    };
  EXPECT_NEAR(indicator_now(
                block_sums(6, 0.125, alternating, /*uneven_masses=*/false)),
              1.,
              1e-12);
  // Uneven masses let the linear fit take a little of the pattern.
  EXPECT_NEAR(indicator_now(block_sums(6, 0.125, alternating)), 1., 0.1);
  // On top of a linear deformation of the same size it is still O(1), and
  // above the warning threshold.
  const auto both = [&](const Point<2> &x, unsigned int i, unsigned int j) {
    return alternating(x, i, j) + epsilon * (x[0] - 0.6);
  };
  const double both_indicator = indicator_now(block_sums(6, 0.125, both));
  EXPECT_GT(both_indicator, Checkerboard::warning_threshold<2>);
  EXPECT_LT(both_indicator, 1.);
  // Measured against the largest deformation so far, a body that swings
  // back through its undeformed shape does not raise it: the same residual
  // against twice the volume change gives half the indicator.
  const Checkerboard::Sums sums =
    block_sums(6, 0.125, alternating, /*uneven_masses=*/false);
  EXPECT_NEAR(Checkerboard::indicator(sums.residual_rms(),
                                      2 * sums.volume_change_rms()),
              0.5,
              1e-12);
}



TEST(Checkerboard, TinyDeformationsAreMeasuredAgainstTheFloor)
{
  // A body that hardly deforms, like the rigid rotation: J − 1 of 0.002
  // (smooth) with point noise of half that. Against its own volume change
  // the noise reads about 0.5; against the floor, 0.001 / 0.15.
  const auto tiny = [](const Point<2> &x, unsigned int i, unsigned int j) {
    return 1 + 0.002 * std::sin(3 * x[0] + 2 * x[1]) +
           0.001 * (((i * 7 + j * 3) % 5) / 2. - 1);
  };
  const Checkerboard::Sums sums = block_sums(8, 0.125, tiny);
  ASSERT_LT(sums.volume_change_rms(), 0.003);
  EXPECT_GT(sums.residual_rms(), 3e-4);
  EXPECT_GT(sums.residual_rms() / sums.volume_change_rms(),
            Checkerboard::warning_threshold<2>);
  EXPECT_NEAR(indicator_now(sums),
              sums.residual_rms() / Checkerboard::j_floor,
              1e-15);
  EXPECT_LT(indicator_now(sums), 0.01);
  // The cantilever's (doc/studies/cantilever.md): a volume change of 0.1
  // RMS with an alternating pattern of 0.027 RMS (the run that leaves the
  // reference) warns, with 0.0046 (the run that follows it) not.
  for (const double amplitude : {0.027, 0.0046})
    {
      const auto bending =
        [&](const Point<2> &x, unsigned int i, unsigned int j) {
          return 1 + 0.17 * x[1] + ((i + j) % 2 == 0 ? amplitude : -amplitude);
        };
      const Checkerboard::Sums bent =
        block_sums(8, 0.125, bending, /*uneven_masses=*/false);
      EXPECT_NEAR(bent.residual_rms(), amplitude, 1e-12);
      EXPECT_EQ(indicator_now(bent) > Checkerboard::warning_threshold<2>,
                amplitude > 0.01)
        << amplitude;
    }
}



TEST(Checkerboard, DegenerateCellsAddNoResidual)
{
  // Three points, or four on a line, cannot be fitted: no residual, but
  // their deformation counts.
  const std::vector<Point<2>> line = {Point<2>(0, 0),
                                      Point<2>(1, 1),
                                      Point<2>(2, 2),
                                      Point<2>(3, 3)};
  const std::vector<double>   mass = {1, 1, 1, 1}, J = {1.2, 0.8, 1.2, 0.8};
  const Checkerboard::Sums    sums =
    Checkerboard::cell_sums<2>(make_array_view(line),
                               make_array_view(mass),
                               make_array_view(J));
  EXPECT_EQ(sums.residual, 0.);
  EXPECT_NEAR(sums.volume_change, 4 * 0.04, 1e-12);
  EXPECT_EQ(sums.mass, 4.);
  const Checkerboard::Sums three =
    Checkerboard::cell_sums<2>(ArrayView<const Point<2>>(line.data(), 3),
                               ArrayView<const double>(mass.data(), 3),
                               ArrayView<const double>(J.data(), 3));
  EXPECT_EQ(three.residual, 0.);
}



TEST(Checkerboard, ThreeDimensions)
{
  // 2 x 2 x 2 points: a linear field gives 0, J = 1 ± ε by parity 1.
  std::vector<Point<3>> x;
  std::vector<double>   mass(8, 2.), linear, alternating;
  for (unsigned int i = 0; i < 2; ++i)
    for (unsigned int j = 0; j < 2; ++j)
      for (unsigned int k = 0; k < 2; ++k)
        {
          x.emplace_back(0.25 + 0.5 * i, 0.25 + 0.5 * j, 0.25 + 0.5 * k);
          linear.push_back(1 + 0.1 * x.back()[0] - 0.2 * x.back()[2]);
          alternating.push_back((i + j + k) % 2 == 0 ? 1.2 : 0.8);
        }
  EXPECT_LT(indicator_now(Checkerboard::cell_sums<3>(make_array_view(x),
                                                     make_array_view(mass),
                                                     make_array_view(linear))),
            1e-12);
  EXPECT_NEAR(indicator_now(
                Checkerboard::cell_sums<3>(make_array_view(x),
                                           make_array_view(mass),
                                           make_array_view(alternating))),
              1.,
              1e-12);
}
