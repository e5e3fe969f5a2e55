// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/parameters.h>
#include <fmpm/postprocess/energy_balance.h>
#include <fmpm/postprocess/progress.h>
#include <fmpm/simulation_control.h>
#include <fmpm/timer_output.h>

#include <deal.II/base/mpi.h>

#include <iomanip>
#include <iostream>

namespace fmpm
{
  namespace Postprocess
  {
    template <int dim>
    bool
    Progress<dim>::progress_due() const
    {
      return MPI_Wtime() - last_line_wall >
             this->get_parameters().output.progress_seconds;
    }



    template <int dim>
    void
    Progress<dim>::progress(const GlobalStatistics<dim> &statistics)
    {
      TimerOutput::Scope       timer(this->get_computing_timer(), "progress");
      const SimulationControl &control = this->get_simulation_control();
      const double wall = MPI_Wtime() - this->get_run_counters().wall_start;
      last_line_wall    = MPI_Wtime();
      const double fraction =
        control.time() / this->get_parameters().time.end_time;
      const double eta = fraction > 0 ? wall * (1 - fraction) / fraction : 0.0;
      this->get_pcout() << std::defaultfloat << std::setprecision(5)
                        << "*** Step " << std::setw(6) << control.step_number()
                        << "  t = " << std::setw(11) << control.time()
                        << "  dt = " << std::setw(11) << control.time_step()
                        << "  E = " << std::setw(11)
                        << statistics.total_energy() << " (kinetic "
                        << statistics.kinetic_energy << ", strain "
                        << statistics.strain_energy << ")  "
                        << std::setprecision(3) << 100 * fraction << "%  wall "
                        << wall << " s, about " << eta << " s left"
                        << std::endl;
    }

    template class Progress<2>;
    template class Progress<3>;
  } // namespace Postprocess
} // namespace fmpm
