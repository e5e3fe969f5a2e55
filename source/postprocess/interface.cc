// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/postprocess/interface.h>
#include <fmpm/simulator.h>

namespace fmpm
{
  namespace Postprocess
  {
    template <int dim>
    const SimulationControl &
    Interface<dim>::get_simulation_control() const
    {
      return this->get_simulator().control;
    }

    template <int dim>
    const GridVectorField &
    Interface<dim>::get_grid_field(const ParticleUpdate::GridField field) const
    {
      return this->get_simulator().centre_of_mass.fields[field];
    }

    template <int dim>
    bool
    Interface<dim>::grid_field_computed(
      const ParticleUpdate::GridField field) const
    {
      return this->get_simulator().centre_of_mass.computed[field];
    }

    template <int dim>
    const Contact::Manager<dim> *
    Interface<dim>::get_contact() const
    {
      return this->get_simulator().contact.get();
    }



    template <int dim>
    const std::string &
    Interface<dim>::checkpoint_resumed_from() const
    {
      return this->get_simulator().checkpoint_state.resumed_from;
    }



    template <int dim>
    const ConditionReactions<dim> &
    Interface<dim>::get_reactions() const
    {
      return this->get_simulator().reactions;
    }



    template <int dim>
    const EnergyBalance<dim> &
    Interface<dim>::get_energy_balance() const
    {
      return this->get_simulator().energy_balance;
    }



    template <int dim>
    std::vector<double>
    Interface<dim>::mass_matrix_history_values() const
    {
      return this->get_simulator().mass_matrix->history_values();
    }



    template <int dim>
    std::pair<double, double>
    Interface<dim>::contact_history_values() const
    {
      return this->get_simulator().contact->history_values();
    }



    template <int dim>
    GlobalStatistics<dim>
    Interface<dim>::current_statistics() const
    {
      return this->get_simulator().compute_statistics();
    }



    template <int dim>
    const RunCounters &
    Interface<dim>::get_run_counters() const
    {
      return this->get_simulator().counters;
    }



    template <int dim>
    const std::string &
    Interface<dim>::latest_checkpoint() const
    {
      return this->get_simulator().checkpoint_state.latest;
    }



    template <int dim>
    const ExternalLoads<dim> &
    Interface<dim>::get_external_loads() const
    {
      return this->get_simulator().external_loads;
    }



    template <int dim>
    const Manager<dim> &
    Interface<dim>::get_postprocess_manager() const
    {
      return this->get_simulator().postprocessors;
    }

    template class Interface<2>;
    template class Interface<3>;
  } // namespace Postprocess
} // namespace fmpm
