// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks that the owners of a run's history serialize themselves in a
// checkpoint: History keeps its rows and writes them again after the header
// when a resumed run opens history.csv (the file equals the one of a run
// that did not stop), and RunCounters keeps its counts and the wall time
// elapsed.

#include <fmpm/postprocess/energy_balance.h>
#include <fmpm/postprocess/history.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <boost/archive/binary_iarchive.hpp>
#include <boost/archive/binary_oarchive.hpp>
#include <gtest/gtest.h>

namespace
{
  /** A row whose every column differs from the other rows'. */
  fmpm::HistoryRow<2>
  row(const unsigned int step)
  {
    fmpm::HistoryRow<2> r;
    r.step                  = step;
    r.time                  = 1e-3 * step + 1.0 / 3;
    r.dt                    = 1e-3 / 7;
    r.kinetic_energy        = 2.5 + step;
    r.strain_energy         = 0.125 * step;
    r.potential_energy      = -1.0 / (step + 1);
    r.total_energy          = r.kinetic_energy + r.strain_energy;
    r.momentum[0]           = 0.1 * step;
    r.momentum[1]           = -0.2 * step;
    r.mass                  = 7.75;
    r.error_velocity_l2     = 1e-4 / (step + 1);
    r.error_displacement_l2 = 2e-4 / (step + 1);
    r.dissipated_energy     = 3e-6 * step;
    r.volume_change_rms     = 1e-5 * step;
    r.checkerboard_j        = 0.01 * step;
    r.reactions.resize(1);
    r.reactions[0][0] = 4.0 * step;
    r.reactions[0][1] = -5.0 / (step + 2);
    r.extra           = {1.0 * step, 2.0 / (step + 3)};
    return r;
  }

  std::string
  contents(const std::filesystem::path &file)
  {
    std::ifstream      in(file);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  void
  open(fmpm::History<2> &history, const std::filesystem::path &file)
  {
    history.open(file.string(), true, true, true, {"wall"}, {"a", "b"});
  }
} // namespace



TEST(History, CheckpointKeepsTheRowsAndOpenWritesThemAgain)
{
  const std::filesystem::path directory =
    std::filesystem::temp_directory_path() / "fmpm-history-test";
  std::filesystem::create_directories(directory);

  // A run that does not stop: rows 0..3.
  fmpm::History<2> whole;
  open(whole, directory / "whole.csv");
  for (unsigned int step = 0; step < 3; ++step)
    whole.add(row(step));

  // The same run checkpointed after row 2 and resumed into a new History.
  std::stringstream state;
  {
    boost::archive::binary_oarchive archive(state);
    archive << whole;
  }
  fmpm::History<2> resumed;
  {
    boost::archive::binary_iarchive archive(state);
    archive >> resumed;
  }
  ASSERT_EQ(resumed.rows().size(), 3u);
  open(resumed, directory / "resumed.csv");
  ASSERT_EQ(resumed.rows().size(), 3u);

  whole.add(row(3));
  resumed.add(row(3));
  ASSERT_EQ(resumed.rows().size(), 4u);
  for (unsigned int r = 0; r < 4; ++r)
    {
      EXPECT_EQ(resumed.rows()[r].step, r);
      EXPECT_EQ(resumed.rows()[r].time, whole.rows()[r].time);
      EXPECT_EQ(resumed.rows()[r].momentum, whole.rows()[r].momentum);
      EXPECT_EQ(resumed.rows()[r].reactions, whole.rows()[r].reactions);
      EXPECT_EQ(resumed.rows()[r].extra, whole.rows()[r].extra);
    }
  const std::string expected = contents(directory / "whole.csv");
  // The header and four rows.
  EXPECT_EQ(std::count(expected.begin(), expected.end(), '\n'), 5);
  EXPECT_EQ(contents(directory / "resumed.csv"), expected);

  // A History opened without a checkpoint starts empty.
  fmpm::History<2> fresh;
  open(fresh, directory / "fresh.csv");
  EXPECT_TRUE(fresh.rows().empty());
  const std::string header_only = contents(directory / "fresh.csv");
  EXPECT_EQ(std::count(header_only.begin(), header_only.end(), '\n'), 1);
  std::filesystem::remove_all(directory);
}



TEST(RunCounters, CheckpointKeepsTheCountsAndTheWallTimeElapsed)
{
  fmpm::Postprocess::RunCounters counters;
  counters.particle_steps    = 123456789012ull;
  counters.cell_steps        = 98765;
  counters.max_cells         = 4321;
  counters.total_lost_points = 17;
  counters.mesh_adaptations  = 5;
  counters.wall_start        = MPI_Wtime() - 1000;

  std::stringstream state;
  {
    boost::archive::binary_oarchive archive(state);
    archive << counters;
  }
  fmpm::Postprocess::RunCounters resumed;
  {
    boost::archive::binary_iarchive archive(state);
    archive >> resumed;
  }
  EXPECT_EQ(resumed.particle_steps, counters.particle_steps);
  EXPECT_EQ(resumed.cell_steps, counters.cell_steps);
  EXPECT_EQ(resumed.max_cells, counters.max_cells);
  EXPECT_EQ(resumed.total_lost_points, counters.total_lost_points);
  EXPECT_EQ(resumed.mesh_adaptations, counters.mesh_adaptations);
  // The resumed run's clock starts the 1000 s before the checkpoint earlier
  // (up to the few milliseconds this test takes).
  const double elapsed = MPI_Wtime() - resumed.wall_start;
  EXPECT_GE(elapsed, 1000);
  EXPECT_LT(elapsed, 1010);
}
