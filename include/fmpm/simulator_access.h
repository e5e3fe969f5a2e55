// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_simulator_access_h
#define fmpm_simulator_access_h

#include <fmpm/grid_vectors.h>
#include <fmpm/material_points.h>
#include <fmpm/nodal_field.h>
#include <fmpm/parameters.h>
#include <fmpm/particle_properties.h>
#include <fmpm/shape_function.h>
#include <fmpm/timer_output.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/particles/particle_handler.h>

#include <functional>

namespace fmpm
{
  template <int dim>
  class Simulator;
  template <int dim>
  class SupportCache;
  template <int dim>
  class VelocityConditions;
  namespace MassMatrix
  {
    template <int dim>
    class Interface;
  }
  template <int dim>
  struct HistoryRow;
  template <int dim>
  struct GlobalStatistics;

  /**
   * @brief Read-only view of the Simulator's state for plugins.
   *
   * The Simulator calls initialize_simulator() on each plugin that derives
   * from this class before the plugin's initialize().
   */
  template <int dim>
  class SimulatorAccess
  {
  public:
    virtual ~SimulatorAccess() = default;

    /** @brief Connect to the Simulator; called by the Simulator. */
    void
    initialize_simulator(const Simulator<dim> &simulator_object)
    {
      simulator = &simulator_object;
    }

  protected:
    const Simulator<dim> &
    get_simulator() const
    {
      Assert(simulator != nullptr, ExcNotInitialized());
      return *simulator;
    }

    MPI_Comm
    get_mpi_communicator() const;
    const ConditionalOStream &
    get_pcout() const;
    const Parameters &
    get_parameters() const;
    const parallel::distributed::Triangulation<dim> &
    get_triangulation() const;
    const DoFHandler<dim> &
    get_dof_handler() const;
    const AffineConstraints<double> &
    get_constraints() const;
    /** The material points (the point store). */
    const MaterialPoints<dim> &
    get_material_points() const;
    const ParticleProperties<dim> &
    get_particle_properties() const;
    /** Lumped nodal masses m = SᵀM (Eq. 1.6), ghosted. */
    const GridScalar &
    get_lumped_mass() const;
    /** Full mass matrix m̃ = SᵀMS (Eq. 1.9); assembled only on request. */
    const TrilinosWrappers::SparseMatrix &
    get_full_mass_matrix() const;
    /**
     * Per velocity component, 1 on locally owned nodes whose component is a
     * known value in mass-matrix solves (Boundary conditions/Method =
     * constrained: axis-aligned conditions), else 0.
     */
    const std::vector<GridScalar> &
    get_known_velocity_mask() const;
    /** The known values where the mask is 1 (set before each solve). */
    const std::vector<GridScalar> &
    get_known_velocity_values() const;
    /** Sets the padding nodes of a solved velocity-like field from their
     * mirrors (B-splines with a padding layer and velocity conditions;
     * collective), or empty: set for each solve of a grid field. */
    const std::function<void(GridVectorField &)> &
    get_padding_mirror() const;
    double
    get_time() const;
    double
    get_timestep() const;
    unsigned int
    get_timestep_number() const;
    /** Time of the current momenta p (t^n, or t^{n+1} after the
     * re-extrapolation of USL+/USAVG+). */
    double
    get_momentum_time() const;

    /** The solver of the nodal fields (lumped solve, conditions,
     * constraints, ghosts) at the current step's times. */
    FieldSolver<dim>
    get_field_solver() const;
    /** Nodes with mass below this are empty. */
    double
    get_mass_floor() const;
    /** Whether any rank has hanging nodes (constraints to distribute). */
    bool
    has_hanging_nodes() const;
    /** The shape functions' type. */
    ShapeFunction::Type
    get_shape_function_type() const;
    /** S and G of every point of the store this step. */
    const SupportCache<dim> &
    get_support_cache() const;
    /** The cells' nodes, geometry and shape functions (computed supports
     * read it). */
    const GridTransfer<dim> &
    get_grid_transfer() const;
    const VelocityConditions<dim> &
    get_velocity_conditions() const;
    const MassMatrix::Interface<dim> &
    get_mass_matrix() const;
    /** The run's timer (sections of a subsystem). */
    TimerOutput &
    get_computing_timer() const;
    /** m̃ as cell-wise matrices this step, or nullptr when m̃ is the
     * assembled sparse matrix (or not needed). */
    const CellwiseMatrix *
    get_cellwise_full_mass_matrix() const;
    /** A grid field of the centre of mass, as the last step left it. */
    const GridVectorField &
    get_grid_field(const ParticleUpdate::GridField field) const;
    /** The rows of history.csv written so far. */
    const std::vector<HistoryRow<dim>> &
    get_history() const;
    /** The reaction forces of the last step, per label. */
    const std::vector<Tensor<1, dim>> &
    get_reaction_forces() const;
    /** How often the mesh was adapted (after the initial one). */
    unsigned int
    n_mesh_adaptations() const;
    /** Statistics of the material points now (collective). */
    GlobalStatistics<dim>
    compute_statistics() const;

  private:
    const Simulator<dim> *simulator = nullptr;
  };
} // namespace fmpm

#endif
