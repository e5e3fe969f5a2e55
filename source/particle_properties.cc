// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/particle_properties.h>

#include <deal.II/base/exceptions.h>

namespace fmpm
{
  template <int dim>
  ParticleProperties<dim>::ParticleProperties()
  {
    using Index = PropertyIndex<dim>;
    request("mass", 1);
    request("volume", 1);
    request("initial_volume", 1);
    request("velocity", dim);
    request("deformation_gradient", 9);
    request("stress", 6);
    request("strain_energy_density", 1);
    request("material_id", 1);
    request("body_id", 1);
    request("initial_position", dim);
    request("initial_half_length", dim);
    AssertThrow(n_properties() == Index::n_core_properties &&
                  offset("velocity") == Index::velocity &&
                  offset("stress") == Index::stress &&
                  offset("initial_half_length") == Index::initial_half_length,
                ExcInternalError());
  }



  template <int dim>
  unsigned int
  ParticleProperties<dim>::request(const std::string &name,
                                   const unsigned int n_components)
  {
    AssertThrow(n_components > 0, ExcInternalError());
    // A name requested again with the same size is shared (e.g. the
    // internal energy of several materials of one model).
    for (unsigned int f = 0; f < fields.size(); ++f)
      if (fields[f].first == name)
        {
          const unsigned int end =
            f + 1 < fields.size() ? fields[f + 1].second : names.size();
          AssertThrow(end - fields[f].second == n_components,
                      ExcMessage("Particle property <" + name +
                                 "> was requested with two sizes."));
          return fields[f].second;
        }
    const unsigned int first = names.size();
    fields.emplace_back(name, first);
    const bool is_vector = (n_components == dim);
    for (unsigned int c = 0; c < n_components; ++c)
      {
        // Vectors are shown as vectors in ParaView; tensors as components.
        names.push_back(is_vector || n_components == 1 ?
                          name :
                          name + "_" + std::to_string(c));
        interpretations.push_back(
          is_vector ? DataComponentInterpretation::component_is_part_of_vector :
                      DataComponentInterpretation::component_is_scalar);
      }
    return first;
  }



  template <int dim>
  bool
  ParticleProperties<dim>::has(const std::string &name) const
  {
    for (const auto &field : fields)
      if (field.first == name)
        return true;
    return false;
  }



  template <int dim>
  unsigned int
  ParticleProperties<dim>::offset(const std::string &name) const
  {
    for (const auto &field : fields)
      if (field.first == name)
        return field.second;
    AssertThrow(false, ExcMessage("No particle property <" + name + ">."));
    return 0;
  }

  template class ParticleProperties<2>;
  template class ParticleProperties<3>;
} // namespace fmpm
