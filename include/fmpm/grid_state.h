// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_grid_state_h
#define fmpm_grid_state_h

#include <fmpm/grid_vectors.h>
#include <fmpm/nodal_field.h>
#include <fmpm/particle_update/interface.h>

#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <array>
#include <functional>
#include <vector>

namespace fmpm
{
  namespace MassMatrix
  {
    template <int dim>
    class Interface;
  }

  /**
   * @brief The centre-of-mass grid state of a step (seed 000 §2.2): the
   * nodal field m, p, f, p⁺ and its solved fields, the full mass matrix m̃
   * the extrapolation assembles, the known velocities of the mass-matrix
   * solves, the time of the momenta, and the solve of its fields
   * (compute()).
   *
   * @tparam dim spatial dimension
   */
  template <int dim>
  struct GridState : public NodalField<dim>
  {
    /** Nodes with m at or below this are empty (1e-12 of the lightest
     * point's mass). Units: kg. */
    double mass_floor = 0;
    /** Time at which the momenta p are (t^n, or t^{n+1} after the
     * re-extrapolation of USL+/USAVG+). Units: s. */
    double momentum_time = 0;
    /** The fields a step reads: field_needed for the configured particle
     * update, lumped_step_fields for the FLIP of the lumped steps of a
     * periodic FMPM(k). */
    std::array<bool, ParticleUpdate::n_grid_fields> field_needed{};
    std::array<bool, ParticleUpdate::n_grid_fields> lumped_step_fields{};
    /** m̃ = SᵀMS (seed 000 Eq. 1.9) assembled, when a solve needs it. */
    TrilinosWrappers::SparseMatrix full_mass_matrix;
    /** m̃ as one local matrix per cell (FMPM(k) without hanging nodes),
     * used instead of full_mass_matrix when use_cellwise_full_mass. */
    CellwiseMatrix cellwise_full_mass;
    bool           use_cellwise_full_mass = false;
    /** Per component: 1 on owned nodes whose component is known in the
     * mass-matrix solves (constrained method), and the known values. */
    std::vector<GridScalar> known_velocity_mask;
    std::vector<GridScalar> known_velocity_value;
    /** B-splines with a padding layer and velocity conditions: sets the
     * padding nodes of a solved field from their mirrors at the field's
     * time (collective), during compute()'s solve only; empty otherwise. */
    std::function<void(GridVectorField &)> padding_mirror;
    /** Corrections Δv (of v) and Δv⁺ (of v⁺) per node condition of the
     * last solves (the velocity method's reactions). */
    std::array<std::vector<double>, 2> velocity_corrections;

    /**
     * @brief Solve fields[@p field] once per step (a field already computed
     * is kept): a full-mass field v = m̃ₖ⁻¹p, v⁺ = m̃ₖ⁻¹p⁺, a = m̃ₖ⁻¹f with
     * @p mass_matrix (seed 000 Eqs. 3.13-3.22), a lumped one with m (Eq.
     * 1.7), then @p solver's tail: the velocity conditions (Eq. 2.53, on
     * full-mass fields only where the method corrects velocities), the
     * hanging nodes and the ghosts. The known values are set first when
     * the conditions have them and the mass matrix reads them.
     * @p time_step is Δt of the step (known accelerations, the residual
     * scale of accelerations).
     */
    void
    compute(const ParticleUpdate::GridField   field,
            const FieldSolver<dim>           &solver,
            const MassMatrix::Interface<dim> &mass_matrix,
            const double                      time_step);

    /** What a checkpoint keeps of it: the mass floor (the fields are
     * transferred with the mesh). */
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &mass_floor;
    }
  };
} // namespace fmpm

#endif
