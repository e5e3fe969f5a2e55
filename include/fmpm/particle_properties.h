// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_properties_h
#define fmpm_particle_properties_h

#include <deal.II/base/array_view.h>
#include <deal.II/base/data_out_base.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <string>
#include <utility>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief Slots of the per-point state: the columns of the point store
   * (MaterialPoints) and the record the ParticleHandler carries at events
   * (as Lethe's dem_properties.h).
   *
   * The deformation gradient F and the Cauchy stress are always stored as
   * 3x3 tensors: in 2D the scene is in plane strain (F_33 = 1), so that the
   * constitutive models are written once. Plugins that need more per-point
   * state request named slots from ParticleProperties, appended after
   * n_core_properties.
   *
   * @tparam dim space dimension
   */
  template <int dim>
  struct PropertyIndex
  {
    /** Mass M_p. Units: kg (per metre of thickness in 2D). */
    static constexpr unsigned int mass = 0;
    /** Current volume V_p = J V_p0. Units: m^dim. */
    static constexpr unsigned int volume = 1;
    /** Initial volume V_p0. */
    static constexpr unsigned int initial_volume = 2;
    /** Velocity V_p, dim components. Units: m/s. */
    static constexpr unsigned int velocity = 3;
    /** Deformation gradient F, 9 components, row major. */
    static constexpr unsigned int deformation_gradient = velocity + dim;
    /** Cauchy stress, 6 components (xx, yy, zz, xy, xz, yz). Units: Pa. */
    static constexpr unsigned int stress = deformation_gradient + 9;
    /** Strain energy per unit initial volume. Units: J/m^3. */
    static constexpr unsigned int strain_energy_density = stress + 6;
    /** Index of the material (a double holding an integer). */
    static constexpr unsigned int material_id = strain_energy_density + 1;
    /** Index of the body the point was created in. */
    static constexpr unsigned int body_id = material_id + 1;
    /** Initial position X_p(0), for displacements and reference solutions. */
    static constexpr unsigned int initial_position = body_id + 1;
    /** Initial half-lengths of the point's domain (for GIMP/CPDI). */
    static constexpr unsigned int initial_half_length = initial_position + dim;
    /** Number of slots every scene has. */
    static constexpr unsigned int n_core_properties = initial_half_length + dim;
  };

  /**
   * @brief Named layout of all per-point properties: the core slots of
   * PropertyIndex plus slots plugins request during setup.
   *
   * The names and interpretations feed Particles::DataOut, so every slot is
   * visible in ParaView under its name.
   */
  template <int dim>
  class ParticleProperties
  {
  public:
    ParticleProperties();

    /**
     * @brief Request @p n_components slots called @p name.
     * @return the offset of the first slot. A name requested before with
     * the same number of components returns the same slots.
     * Must be called before the ParticleHandler is created.
     */
    unsigned int
    request(const std::string &name, const unsigned int n_components);

    /** @brief Whether slots called @p name were requested. */
    bool
    has(const std::string &name) const;

    /** @brief Offset of the slots called @p name; throws if unknown. */
    unsigned int
    offset(const std::string &name) const;

    /** @brief Total number of doubles per point. */
    unsigned int
    n_properties() const
    {
      return names.size();
    }

    /** @brief One name per double, for Particles::DataOut. */
    const std::vector<std::string> &
    component_names() const
    {
      return names;
    }

    /** @brief One interpretation per double, for Particles::DataOut. */
    const std::vector<DataComponentInterpretation::DataComponentInterpretation>
      &
      component_interpretations() const
    {
      return interpretations;
    }

  private:
    /** (name, offset) of each requested field. */
    std::vector<std::pair<std::string, unsigned int>> fields;
    std::vector<std::string>                          names;
    std::vector<DataComponentInterpretation::DataComponentInterpretation>
      interpretations;
  };

  /**
   * @brief The properties of one point, addressed by slot: column @p slot
   * of the point store at the point's place (MaterialPoints::record()), or
   * one record of consecutive slots (RecordColumns).
   */
  struct PointRecord
  {
    double *const *columns = nullptr;
    unsigned int   index   = 0;

    double &
    operator[](const unsigned int slot) const
    {
      return columns[slot][index];
    }
  };

  /** @brief Column pointers into one record of consecutive slots (set-up,
   * tests): record() addresses it like a point of the store. */
  struct RecordColumns
  {
    explicit RecordColumns(const ArrayView<double> &values)
    {
      for (unsigned int s = 0; s < values.size(); ++s)
        pointers.push_back(&values[s]);
    }

    PointRecord
    record() const
    {
      return PointRecord{pointers.data(), 0};
    }

    std::vector<double *> pointers;
  };

  /** @name Accessors that read typed values out of a point's property slots
   * (an ArrayView record or a PointRecord). */
  /** @{ */
  template <int dim, typename Record>
  inline Tensor<1, dim>
  get_vector(const Record &properties, const unsigned int offset)
  {
    Tensor<1, dim> v;
    for (unsigned int d = 0; d < dim; ++d)
      v[d] = properties[offset + d];
    return v;
  }

  template <int dim, typename Record>
  inline void
  set_vector(const Record         &properties,
             const unsigned int    offset,
             const Tensor<1, dim> &v)
  {
    for (unsigned int d = 0; d < dim; ++d)
      properties[offset + d] = v[d];
  }

  template <typename Record>
  inline Tensor<2, 3>
  get_tensor3(const Record &properties, const unsigned int offset)
  {
    Tensor<2, 3> t;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        t[i][j] = properties[offset + 3 * i + j];
    return t;
  }

  template <typename Record>
  inline void
  set_tensor3(const Record       &properties,
              const unsigned int  offset,
              const Tensor<2, 3> &t)
  {
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        properties[offset + 3 * i + j] = t[i][j];
  }

  /** Voigt-like order of the 6 stored stress components. */
  constexpr unsigned int stress_component_i[6] = {0, 1, 2, 0, 0, 1};
  constexpr unsigned int stress_component_j[6] = {0, 1, 2, 1, 2, 2};

  template <typename Record>
  inline SymmetricTensor<2, 3>
  get_symmetric_tensor3(const Record &properties, const unsigned int offset)
  {
    SymmetricTensor<2, 3> t;
    for (unsigned int c = 0; c < 6; ++c)
      t[stress_component_i[c]][stress_component_j[c]] = properties[offset + c];
    return t;
  }

  template <typename Record>
  inline void
  set_symmetric_tensor3(const Record                &properties,
                        const unsigned int           offset,
                        const SymmetricTensor<2, 3> &t)
  {
    for (unsigned int c = 0; c < 6; ++c)
      properties[offset + c] = t[stress_component_i[c]][stress_component_j[c]];
  }
  /** @} */
} // namespace fmpm

#endif
