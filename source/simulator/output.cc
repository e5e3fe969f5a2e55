// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// An output of the run: the postprocessors (history.csv, VTU, point csv,
// test output) with the statistics of the instant.

#include <fmpm/simulator.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/utilities.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/particles/data_out.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace fmpm
{
  template <int dim>
  void
  Simulator<dim>::output_results(const GlobalStatistics<dim> &statistics)
  {
    TimerOutput::Scope timer(computing_timer, "output");

    // Accumulate the time-averaged reference errors over outputs.
    energy_balance.record_output(statistics);

    control.output_written();
    // The postprocessors time themselves (no section inside another).
    timer.stop();
    postprocessors.execute(statistics);
    control.count_output();
  }



  template class Simulator<2>;
  template class Simulator<3>;
} // namespace fmpm
