// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/postprocess/test_output.h>
#include <fmpm/simulation_control.h>
#include <fmpm/simulator.h>

#include <deal.II/base/mpi.h>

#include <iomanip>
#include <iostream>
#include <map>
#include <utility>
#include <vector>

namespace fmpm
{
  namespace Postprocess
  {
    template <int dim>
    ConditionalOStream &
    TestOutput<dim>::out()
    {
      if (!stream)
        stream = std::make_unique<ConditionalOStream>(
          std::cout,
          Utilities::MPI::this_mpi_process(this->get_mpi_communicator()) == 0);
      return *stream;
    }



    template <int dim>
    void
    TestOutput<dim>::start()
    {
      // Tests check where a run resumed.
      const std::string &resumed_from = this->checkpoint_resumed_from();
      if (!resumed_from.empty())
        out() << "resumed from " << resumed_from << " at step "
              << this->get_simulation_control().step_number() << std::endl;
    }



    template <int dim>
    void
    TestOutput<dim>::execute(const GlobalStatistics<dim> &statistics)
    {
      const SimulationControl &control = this->get_simulation_control();
      out() << std::scientific << std::setprecision(8) << "step "
            << control.step_number() << " t " << control.time() << " mass "
            << statistics.mass << " momentum " << statistics.momentum
            << " kinetic " << statistics.kinetic_energy << " strain "
            << statistics.strain_energy << std::endl;
    }



    template <int dim>
    void
    TestOutput<dim>::end_of_run(const std::string &,
                                const SimulationFailure *failure)
    {
      if (failure)
        {
          out() << "FAILED at step " << failure->step << ": " << failure->what()
                << std::endl;
          return;
        }
      using Index                       = PropertyIndex<dim>;
      const MaterialPoints<dim> &points = this->get_material_points();
      const MPI_Comm mpi_communicator   = this->get_mpi_communicator();
      // Gather (id, x, V) to rank 0 and print sorted by id.
      std::vector<std::pair<types::particle_index, std::vector<double>>> local;
      for (unsigned int k = 0; k < points.n_points(); ++k)
        {
          std::vector<double> values;
          for (unsigned int d = 0; d < dim; ++d)
            values.push_back(points.position[k][d]);
          for (unsigned int d = 0; d < dim; ++d)
            values.push_back(points.column(Index::velocity + d)[k]);
          local.emplace_back(points.id[k], values);
        }
      const auto all = Utilities::MPI::gather(mpi_communicator, local, 0);
      if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
        return;
      std::map<types::particle_index, std::vector<double>> sorted;
      for (const auto &rank : all)
        for (const auto &entry : rank)
          sorted[entry.first] = entry.second;
      out() << "points (id, position, velocity):" << std::endl;
      for (const auto &entry : sorted)
        {
          out() << entry.first;
          for (const double value : entry.second)
            out() << ' ' << std::scientific << std::setprecision(8) << value;
          out() << std::endl;
        }
    }

    template class TestOutput<2>;
    template class TestOutput<3>;
  } // namespace Postprocess
} // namespace fmpm
