// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_contact_manager_h
#define fmpm_contact_manager_h

#include <fmpm/contact/geometry_sink.h>
#include <fmpm/contact/laws.h>
#include <fmpm/contact/normals.h>
#include <fmpm/contact/parameters.h>
#include <fmpm/grid_vectors.h>
#include <fmpm/mass_matrix/full_solve.h>
#include <fmpm/nodal_field.h>
#include <fmpm/particle_update/interface.h>
#include <fmpm/simulator_access.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fmpm
{
  namespace Contact
  {
    /** The momenta a contact correction changes. */
    enum class Stage
    {
      /** after the extrapolation: p^α = p^α0 + Δp^α (Eq. 26), Δv^α kept */
      extrapolated,
      /** after the momentum update: p^α+ = p^α0+ + Δp^α+ (Eq. 31) */
      updated,
      /** after the re-extrapolation of USL+/USAVG+ */
      re_extrapolated,
      /** on the increments m^α δz^α of the FMPM(k)/XPIC(k) series (net
       * incremental contact) */
      increment
    };

    /** One velocity field per material (seed 004 Eqs. 5-6): m^α, p^α, f^α0,
     * p^α+ and the fields of NodalField, and what contact adds. */
    template <int dim>
    struct MaterialField : public NodalField<dim>
    {
      GridVectorField volume_gradient;     // g^α = Σ G V (Eq. 11)
      GridVectorField position_moment;     // Σ S M X: x^α = S^{+α}X (Eq. 11)
      GridVectorField displacement_moment; // Σ S M u (interface laws)
      GridScalar      volume;              // Σ S V (interface laws)
      GridVectorField delta_velocity;      // Δv^α of the first correction
      GridVectorField series_product;      // m̃^α z (multimaterial XPIC(k))
      GridVectorField series_rhs;       // q^α = p^α − m^α Δv^α (series)
      GridVectorField series_increment; // m^α δz^α (net incremental contact)
      // The exact solve: m̃^α_ii, the weak nodes and the CG's fields.
      GridScalar                    full_mass_diagonal, weak;
      MassMatrix::FullMassWorkspace solve_workspace;
    };

    /**
     * @brief Multimaterial contact (seed 004 §2-3): owns the per-material
     * fields, the contact laws of the pairs, the normal method, the
     * geometry of the contact nodes and the contact state; applies the
     * corrections and computes the material fields the stress and particle
     * updates read.
     *
     * The Simulator creates it only for 'Contact/Model name =
     * multimaterial' with 2+ materials; it reads the rest of the run
     * through SimulatorAccess.
     */
    template <int dim>
    class Manager : public SimulatorAccess<dim>
    {
    public:
      /** Create the laws and the normal method of the scene (once, after
       * initialize_simulator()). */
      void
      initialize();

      /** Allocate the per-material fields on the current mesh (at set-up
       * and after every mesh change). */
      void
      reinit();

      /** The per-material fields (the extrapolation fills m^α, p^α, f^α
       * and what normal_needs() asks for; the updates read fields). */
      std::vector<MaterialField<dim>> &
      material_fields()
      {
        return fields;
      }
      const std::vector<MaterialField<dim>> &
      material_fields() const
      {
        return fields;
      }

      /** What the normal method reads (the extrapolation adds g^α and Σ S M
       * X only when asked). */
      const NormalNeeds &
      normal_needs() const
      {
        return needs;
      }

      /** Whether the series or the exact solve apply m̃^α (the
       * extrapolation then assembles material_full_mass()). */
      bool
      needs_material_full_mass() const
      {
        return material_full_mass_needed;
      }

      /** m̃^α = Σ_{p∈α} S M Sᵀ as local matrices of the cells with points
       * of α (seed 004 Eq. 37), one per material. */
      std::vector<CellwiseMatrix> &
      material_full_mass()
      {
        return full_mass;
      }

      /** Whether a law needs u^α and V^α (interface laws). */
      bool
      needs_interface_state() const
      {
        return needs_interface;
      }

      /** The extrapolation of a step over @p points of materials
       * @p point_material: m^α, p^α, with @p with_forces f^α0, m̃^α where
       * needed and the geometry fields zeroed; returns the sink that adds
       * each point's share of g^α, Σ S M X, u^α and V^α (what normal_needs()
       * and needs_interface_state() ask for) to the point loop. */
      GeometrySink<dim> &
      begin_extrapolation(const MaterialPoints<dim> &points,
                          const unsigned char *const point_material,
                          const bool                 with_forces);

      /** After the point loop of begin_extrapolation(): m = Σ_α m^α, p =
       * Σ_α p^α and with @p with_forces f = Σ_α f^α0 into @p total (seed
       * 004 Eq. 6; ghosts included, @p total's compress() is the
       * caller's), then the ghosts of every material field added. */
      void
      finish_extrapolation(NodalField<dim> &total, const bool with_forces);

      /** The forces of the stress update (USF/USAVG): f^α0 zeroed; returns
       * the material fields for the force sinks. */
      std::vector<MaterialField<dim>> &
      begin_forces()
      {
        for (auto &field : fields)
          field.force = 0;
        return fields;
      }

      /** After the stress update's forces: f = Σ_α f^α0 into @p total (as
       * finish_extrapolation()), then the ghosts of f^α0 added. */
      void
      finish_forces(NodalField<dim> &total)
      {
        total.set_to_sum(fields, false, false, true);
        for (auto &field : fields)
          field.force.compress(VectorOperation::add);
      }

      /** The re-extrapolation p^α = SᵀMV^{n+1} of the particle update
       * (USL+/USAVG+): p^α and the geometry fields zeroed; returns the
       * geometry sink (as begin_extrapolation()). */
      GeometrySink<dim> &
      begin_re_extrapolation(const MaterialPoints<dim> &points,
                             const unsigned char *const point_material);

      /** After the re-extrapolation: p = Σ_α p^α into @p total (as
       * finish_extrapolation()), the ghosts of p^α and the geometry
       * added. */
      void
      finish_re_extrapolation(NodalField<dim> &total);

      /** Velocity conditions on every material's extrapolated momenta p^α
       * at time @p t (with that material's lumped masses), then the
       * correction of @p stage: the first (extrapolated, Eq. 26; only with
       * two corrections per step) or the one before the USL+/USAVG+
       * stresses (re_extrapolated). */
      void
      correct_extrapolated_momenta(const double t, const Stage stage);

      /** p^α+ = p^α + f^α0 Δt (Eq. 30) and the velocity conditions at
       * @p t_end. */
      void
      update_momenta(const double dt, const double t_end);

      /** The contact corrections at every owned node with 2+ materials. */
      void
      apply(const Stage stage);

      /** Material fields v^α, v^α+, a^α (lumped: seed 004 Eqs. 26, 31-34;
       * with the FMPM(k) mass matrix, v^α of multimaterial XPIC(k), Eq. 37;
       * with the full one, its exact limit). */
      void
      compute_field(const ParticleUpdate::GridField field);

      /** ½ A_c Σ D [u]² of the interfaces at this rank's nodes, from the
       * last correction of the updated momenta. */
      double
      local_interface_energy() const
      {
        return interface_energy;
      }

      /** history.csv: friction work since the start and the contact nodes
       * of the last correction of the updated momenta (collective). */
      std::pair<double, double>
      history_values();

      /** n̂ and the separation (cells) at the contact nodes (grid output). */
      const GridVectorField &
      normal_field() const
      {
        return contact_normal;
      }
      const GridScalar &
      separation_field() const
      {
        return contact_separation;
      }

      /** summary.json figures as (key, value): the normal method's and the
       * exact solve's (collective). */
      std::vector<std::pair<std::string, double>>
      summary_entries() const;

      /** What checkpoints keep: the friction work and the exact solve's
       * figures. */
      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &friction_work &material_solves &material_solve_iterations
          &material_solve_failures;
      }

    private:
      /** One pair the corrections may handle at an owned node. */
      struct Slot
      {
        unsigned int node;
        /** Index into geometry and state. */
        unsigned int slot;
        /** Material x of the node against the sum of the others (Eq. 50),
         * partner the heaviest of them; else α and β are one material
         * each. */
        bool lumped;
        /** The node has 3+ materials and 'Three or more materials =
         * explicit': its slots are its pairs, then its lumped slots, and
         * apply() chooses among them. */
        bool                             explicit_node;
        unsigned int                     x;
        const std::vector<unsigned int> &alpha;
        const std::vector<unsigned int> &beta;
        unsigned int                     partner;
      };
      /** One correction over the owned nodes (apply()). */
      class CorrectionSweep;
      /** The owned nodes with 2+ materials and their materials, and the
       * nodes of each material, from the masses m^α of the last
       * extrapolation. */
      void
      find_multimaterial_nodes();
      /** Calls visit(Slot) for every pair the corrections may handle at
       * owned node i, in the order of the geometry slots (pairs in turn;
       * with 3+ materials lumped, material x of the node against the
       * others; explicit: both), then node_done(i, materials present). */
      template <class Visit, class NodeDone>
      void
      for_each_pair(Visit &&visit, NodeDone &&node_done);
      /** n̂, touching and separation of every pair apply() corrects, in its
       * order: once per extrapolation. */
      void
      compute_geometry();
      /** contact_groups from the contact state of the last correction. */
      void
      find_contact_groups();
      /** The point cloud of every owned node with 2+ materials. */
      void
      gather_point_clouds();
      /** Velocity conditions on material α's momenta @p q at time @p t. */
      void
      impose_material_conditions(const unsigned int alpha,
                                 GridVectorField   &q,
                                 const double       t) const;
      /** out^α = m̃^α in^α for every material, from the cell matrices of
       * material_full_mass(). */
      void
      apply_material_full_mass(const std::vector<GridVectorField *> &in,
                               const std::vector<GridVectorField *> &out);
      /** Multimaterial XPIC(k) and FMPM(k) (seed 004 Eq. 37): the series of
       * every material from the lumped start in fields[@p field]. */
      void
      material_series(const ParticleUpdate::GridField field);
      /** The exact full-mass solve with per-material fields: the k → ∞
       * limit of multimaterial FMPM(k) with net incremental contact
       * (doc/contact.md). On entry @p field holds the contact-corrected
       * lumped velocities z₁^α. */
      void
      solve_material_full_mass(const ParticleUpdate::GridField field);

      std::vector<MaterialField<dim>> fields;
      /** The owned nodes with 2+ materials (the only ones the corrections
       * and normals visit); node multimaterial_nodes[n] has the materials
       * multimaterial_materials[multimaterial_begin[n], [n + 1]). */
      std::vector<unsigned int> multimaterial_nodes, multimaterial_begin,
        multimaterial_materials;
      /** The owned nodes with m^α > floor, of each material. */
      std::vector<std::vector<unsigned int>> material_nodes;
      bool                                   multimaterial_nodes_valid = false;
      /** The nodes where Δv^α, and the output's normal and separation, may
       * be nonzero (zeroed there, not over the grid, before new values). */
      std::vector<unsigned int>   delta_velocity_nodes, recorded_nodes;
      bool                        material_full_mass_needed = false;
      std::vector<CellwiseMatrix> full_mass;
      NormalNeeds                 needs;
      bool                        needs_interface = false;
      /** The points moved or were extrapolated again: the geometry is found
       * anew at the next correction; with @p masses_changed also the nodes
       * with 2+ materials. */
      void
      invalidate_geometry(const bool masses_changed)
      {
        geometry_valid = false;
        if (masses_changed)
          multimaterial_nodes_valid = false;
      }
      /** The geometry sink emptied for a new point loop over @p points. */
      GeometrySink<dim> &
      reset_geometry_sink(const MaterialPoints<dim> &points,
                          const unsigned char *const point_material);
      /** What the points add to the geometry fields (begin_extrapolation()).
       */
      GeometrySink<dim>                           geometry_sink;
      std::unique_ptr<NormalMethodInterface<dim>> normal_method;
      /** The law of materials a < b at [a * n_materials + b]. */
      std::vector<std::unique_ptr<LawInterface<dim>>> laws;
      /** Net incremental contact: the law of the increments at pairs in
       * contact (perfect: the same increment in both materials). */
      std::unique_ptr<LawInterface<dim>> increment_law;
      /** The geometry of every pair apply() corrects, in its order. */
      std::vector<NodeGeometry<dim>> geometry;
      bool                           geometry_valid = false;
      /** Whether each pair was in contact at the last correction (the
       * pairs net incremental contact corrects). */
      std::vector<char> state;
      /** The position of each node (normal methods that read it). */
      GridVectorField node_position;
      /** The local cell size at each node (separations in cells). */
      GridScalar node_cell_size;
      /** The cloud of owned node i is cloud[cloud_begin[i],
       * cloud_begin[i + 1]). */
      std::vector<unsigned int>    cloud_begin;
      std::vector<CloudPoint<dim>> cloud;
      /** The exact solve with contact (Mass matrix = full): its settings,
       * taken from the mass matrix, and its CG figures since the start. */
      std::optional<MassMatrix::ExactSolveSettings> material_exact_solve;
      /** The owned nodes with materials in contact and those materials
       * (bit a: material a). */
      std::vector<std::pair<unsigned int, unsigned int>> contact_groups;
      std::vector<GridScalar> known_velocity_mask, known_velocity_value;
      unsigned long long material_solves = 0, material_solve_iterations = 0,
                         material_solve_failures = 0;
      /** n̂ and the separation (cells) at contact nodes (grid output). */
      GridVectorField contact_normal;
      GridScalar      contact_separation;
      /** Friction work since the start, and of this rank since the last
       * history row. */
      double friction_work       = 0;
      double local_friction_work = 0;
      /** ½ A_c Σ D [u]² at the owned nodes (last correction of the updated
       * momenta); per slot while it is found. */
      double              interface_energy = 0;
      std::vector<double> slot_interface_energy;
      unsigned long long  local_contact_nodes = 0;
    };
  } // namespace Contact
} // namespace fmpm

#endif
