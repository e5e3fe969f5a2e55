// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_global_statistics_h
#define fmpm_postprocess_global_statistics_h

#include <deal.II/base/tensor.h>

#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief Global quantities of the material points at one instant.
   */
  template <int dim>
  struct GlobalStatistics
  {
    double         mass             = 0;
    double         kinetic_energy   = 0;
    double         strain_energy    = 0;
    double         potential_energy = 0;
    Tensor<1, dim> momentum;
    /** Σ M |V − v_ref|² and Σ M |v_ref|² against the reference solution. */
    double velocity_error_squared         = 0;
    double velocity_reference_squared     = 0;
    double displacement_error_squared     = 0;
    double displacement_reference_squared = 0;
    /** With 2+ materials, per material: mass, momentum (dim), volume, σV
     * (xx, yy, xy in 2D; xx, yy, zz, xy, xz, yz in 3D), kinetic and strain
     * energy (material_stride() values each). */
    std::vector<double>           per_material;
    static constexpr unsigned int n_stress = dim == 2 ? 3 : 6;
    static constexpr unsigned int
    material_stride()
    {
      return 1 + dim + 1 + n_stress + 2;
    }

    double
    total_energy() const
    {
      return kinetic_energy + strain_energy + potential_energy;
    }
  };
} // namespace fmpm

#endif
