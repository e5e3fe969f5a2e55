// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_interface_h
#define fmpm_particle_update_interface_h

#include <fmpm/plugins.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <array>
#include <string>
#include <vector>

namespace fmpm
{
  /**
   * @defgroup ParticleUpdates Particle updates
   * The columns of seed 000 Table 2.1: how material points get their new
   * velocity and position from the grid.
   */
  namespace ParticleUpdate
  {
    using namespace dealii;

    /**
     * @brief Nodal fields a particle update may ask the Simulator to compute
     * and extrapolate to the points with S. Notation of seed 000 (m̃ₖ⁻¹ is
     * the scene's mass matrix, m⁻¹ the lumped one).
     */
    enum GridField : unsigned int
    {
      /** v⁺ = m̃ₖ⁻¹ p⁺, extrapolated: v_p of Table 2.1. Always computed. */
      updated_velocity = 0,
      /** m̃ₖ⁻¹ f, extrapolated: the acceleration a of Table 2.1. */
      acceleration,
      /** v = m̃ₖ⁻¹ p, before the momentum update. */
      velocity,
      /** m⁻¹ p with the lumped mass: v_m of Table 2.1 (XPIC). */
      lumped_velocity,
      /** m⁻¹ p⁺ with the lumped mass. */
      lumped_updated_velocity,
      /** m⁻¹ f with the lumped mass. */
      lumped_acceleration,
      n_grid_fields
    };

    /**
     * @brief The points of one cell: grid fields extrapolated to them, and
     * their velocity and position, which the update overwrites.
     */
    template <int dim>
    struct Batch
    {
      /** grid[field][q]: field extrapolated to point q (S times the field). */
      std::array<std::vector<Tensor<1, dim>>, n_grid_fields> grid;
      /** Particle velocities V^(n), replaced by V^(n+1). */
      std::vector<Tensor<1, dim>> velocity;
      /** Particle positions X^(n), replaced by X^(n+1). */
      std::vector<Point<dim>> position;
      /** The time step Δt. Units: s. */
      double time_step = 0;

      void
      resize(const unsigned int n)
      {
        for (auto &field : grid)
          field.resize(n);
        velocity.resize(n);
        position.resize(n);
      }

      unsigned int
      size() const
      {
        return velocity.size();
      }
    };

    /**
     * @brief Interface of particle updates (seed 000 §2.3, Table 2.1).
     *
     * The Simulator asks required_fields() once, computes those nodal fields
     * after the momentum update, and calls update() for the points of each
     * locally owned cell.
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class Interface : public Plugins::InterfaceBase
    {
    public:
      static void
      declare_parameters(ParameterHandler &)
      {}

      /** @brief The grid fields update() reads (updated_velocity always). */
      virtual std::vector<GridField>
      required_fields() const = 0;

      /** @brief psi of seed 000 Eq. 2.28 in the position update, where the
       * update has one that the stability factor depends on (FMPM, XPIC);
       * 0 otherwise. */
      virtual double
      position_update_psi() const
      {
        return 0;
      }

      /** @brief Told the name of 'Time/Strain update' before the run: an
       * update whose position update follows the velocity the strain update
       * uses (FLIP's 'Position update psi = auto') takes it from here. */
      virtual void
      set_strain_update(const std::string &)
      {}

      /** @brief Overwrite velocity and position of every point of @p batch. */
      virtual void
      update(Batch<dim> &batch) const = 0;
    };

    template <int dim>
    using Registry = Plugins::Registry<Interface<dim>>;
  } // namespace ParticleUpdate
} // namespace fmpm

#define FMPM_REGISTER_PARTICLE_UPDATE(CLASSNAME, NAME, DESCRIPTION) \
  FMPM_REGISTER_PLUGIN(::fmpm::ParticleUpdate::Interface,           \
                       CLASSNAME,                                   \
                       NAME,                                        \
                       DESCRIPTION)

#endif
