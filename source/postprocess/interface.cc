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

    template class Interface<2>;
    template class Interface<3>;
  } // namespace Postprocess
} // namespace fmpm
