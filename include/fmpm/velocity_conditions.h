// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_velocity_conditions_h
#define fmpm_velocity_conditions_h

#include <fmpm/grid_vectors.h>
#include <fmpm/parameters.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/partitioner.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace fmpm
{
  /**
   * @brief What the velocity conditions did to the material: the impulse
   * each reaction label gave in the current step, the resulting reaction
   * forces of the last step (over all ranks), and the largest |v⁺ · n̂ −
   * v_b| on the condition nodes since the start (this rank; reduced when
   * written). Units: N s, N (per m in 2D), m/s.
   */
  template <int dim>
  struct ConditionReactions
  {
    std::vector<Tensor<1, dim>> step_impulse;
    std::vector<Tensor<1, dim>> forces;
    double                      max_condition_error = 0;

    /** What a checkpoint keeps (the error reduced over the ranks). */
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &max_condition_error &forces;
    }
  };



  /**
   * @brief Grid velocity conditions (fixed, roller, moving walls on boundary
   * ids or moving boxes) and the methods of seed 000 §2.4 that impose them
   * with lumped or full mass matrices.
   *
   * A condition b on node j_b prescribes v_{j_b} · n̂_b = v_b(t). The
   * conditions of one node have orthonormal n̂. The time step calls
   *  - impose_on_momenta() on p before the strain update (stage P) and on
   *    p' + fΔt after the force extrapolation (stage F, the change divided
   *    by Δt is f^(BC), Eq. 2.42), and
   *  - correct_velocities() / correct_accelerations() on grid fields found
   *    with the mass matrix (the velocity method, Eq. 2.53, and the
   *    re-imposition after the momentum update).
   * Reactions: the total force each boundary exerts on the material, from
   * f^(BC) of stage F (for the velocity method f^(b) = m̃ a^(b), whose sum
   * over nodes is Σ m_j a_j^(b) because the columns of m̃ sum to m).
   *
   * A wall's velocity v_w(x, t) is evaluated as rarely as it can change:
   * once at set-up when it is a constant, once per time when it depends on
   * t only, and per node (at its position) when it depends on x. The nodes
   * of a wall given by a region are found once (and after a mesh change)
   * unless the region depends on t; those of a box wall whenever the box
   * moves.
   */
  template <int dim>
  class VelocityConditions
  {
  public:
    enum class Method
    {
      constrained,
      lumped,
      velocity,
      unlumped_1,
      unlumped_2,
      collection_full,
      collection_partial
    };

    struct NodeCondition
    {
      /** Owned node: local index in the ghosted grid vectors. */
      unsigned int local_index;
      /** Unit direction; orthonormal among one node's conditions. */
      Tensor<1, dim> normal;
      /** Index of the reaction label (boundary id or box wall). */
      unsigned int source;
      /** Moving wall whose v(x, t) this is, or -1 for v = 0. */
      int wall;
    };

    /** The grid operators the methods need, all on GridVectorFields. */
    struct Operators
    {
      /** Lumped masses m (ghosted). */
      const GridScalar *lumped_mass = nullptr;
      double            mass_floor  = 0;
      /** v = m̃ₖ⁻¹ p with the scene's mass matrix. */
      std::function<void(const GridVectorField &, GridVectorField &)> solve;
      /** p = M v with the scene's mass matrix (m, m̃ or the consistent). */
      std::function<void(const GridVectorField &, GridVectorField &)> forward;
      /** p = m̃ v with m̃ = SᵀMS (unlumped 1 only). */
      std::function<void(const GridVectorField &, GridVectorField &)> full_mass;
    };

    /** @brief Read the method, walls and labels. */
    void
    initialize(const Parameters &parameters, MPI_Comm mpi_communicator);

    /**
     * @brief Find the nodes' positions and boundary normals and build the
     * node conditions (at set-up and after a mesh change or a
     * repartition). Throws if a boundary id is unknown.
     */
    void
    setup_nodes(const DoFHandler<dim>             &dof_handler,
                const Utilities::MPI::Partitioner &partitioner);

    /** @brief The time at which the node conditions evaluate the regions. */
    void
    set_time(const double t)
    {
      current_time = t;
    }

    /**
     * @brief Whether the condition nodes change during a run: a box wall
     * that moves, or a region that depends on t.
     */
    bool
    nodes_move() const
    {
      return moving_nodes;
    }

    /**
     * @brief Rebuild the node conditions at time @p t from the positions
     * and normals setup_nodes() found (box walls and regions in t).
     */
    void
    move_nodes(const double t);

    /** @brief Move the box walls over [t, t + Δt] (midpoint velocity). */
    void
    advance_walls(const double t, const double dt);

    /** @brief Whether a wall is given by a box or a region. */
    bool
    has_moving_boxes() const;

    /**
     * @brief Work the moving walls did over [t, t + Δt] with @p reactions
     * (per label): Σ_w (R · n̂_w) v_w(t + Δt/2) Δt, and for a velocity
     * v_w(x, t) Σ_b Δp_b v_b(t + Δt/2) over the wall's node conditions b
     * with their stage-F impulses Δp_b (collective). Clears those
     * impulses.
     */
    double
    wall_work(const std::vector<Tensor<1, dim>> &reactions,
              const double                       t,
              const double                       dt) const;

    /**
     * @brief Add @p amount to the stage-F impulse along n̂ of node
     * condition @p b (the velocity method's reactions; impose_on_momenta()
     * adds its own).
     */
    void
    add_condition_impulse(const unsigned int b, const double amount) const
    {
      if (!condition_impulse.empty())
        condition_impulse[b] += amount;
    }

    /** @brief The largest |v_w(x, t)| of the moving walls (0 without;
     * collective when a velocity depends on x). */
    double
    fastest_wall_speed(const double t) const;

    /** @brief Whether the method needs m̃ = SᵀMS assembled. */
    bool
    needs_full_mass_matrix() const
    {
      return method == Method::unlumped_1;
    }

    Method
    get_method() const
    {
      return method;
    }

    /** @brief Whether the mass-matrix solves hold the condition values. */
    bool
    uses_known_values() const
    {
      return method == Method::constrained;
    }

    /** @brief Whether the grid velocities are corrected after each solve. */
    bool
    corrects_velocities() const
    {
      return method == Method::constrained || method == Method::velocity;
    }

    /**
     * @brief Stage P/F: add the method's Δp (= f^(BC)Δt at stage F) to the
     * momentum-like field @p q whose velocities must satisfy the conditions
     * at time @p t. If @p impulse is given, Σ Δp per reaction label is added
     * to it (what each boundary gave the material).
     */
    void
    impose_on_momenta(GridVectorField             &q,
                      const double                 t,
                      const Operators             &operators,
                      std::vector<Tensor<1, dim>> *impulse) const;

    /**
     * @brief Set v_j · n̂_b = v_b(t) on the condition nodes (Eq. 2.53). If
     * @p corrections is given, it receives Δv of each node condition.
     */
    void
    correct_velocities(GridVectorField     &v,
                       const double         t,
                       std::vector<double> *corrections) const;

    /** @brief a_j · n̂_b = (v_b(t1) − v_b(t0)) / (t1 − t0). */
    void
    correct_accelerations(GridVectorField &a,
                          const double     t0,
                          const double     t1) const;

    /**
     * @brief Per velocity component: 1 where a condition holds the
     * component (axis-aligned conditions), and the value there at @p t.
     * Used by the mass matrices with Method::constrained.
     */
    void
    known_values(const double             t,
                 std::vector<GridScalar> &mask,
                 std::vector<GridScalar> &value) const;

    /** @brief Whether a padding layer mirrors nodes (B-spline boundary =
     * padding with velocity conditions; the same on every rank). */
    bool
    has_padding_mirrors() const
    {
      return padding_layer;
    }

    /**
     * @brief Set the padding nodes of the velocity-like field @p v from
     * their mirrors (collective): v_pad = R v_mirror + 2 (v_w · n̂) n̂ along
     * the held directions n̂, at time @p t, or with @p difference the
     * walls' rate (v_w(t) − v_w(t0)) / (t − t0) (accelerations).
     */
    void
    mirror_padding(GridVectorField &v,
                   const double     t,
                   const double     t0,
                   const bool       difference) const
    {
      if (padding_layer)
        apply_padding_mirrors(v, nullptr, 0., t, t0, difference, nullptr);
    }

    /** @brief The owned padding nodes that mirror a node (local indices). */
    std::vector<unsigned int>
    padding_node_indices() const
    {
      std::vector<unsigned int> result;
      for (const PaddingMirror &r : mirrors)
        result.push_back(r.padding);
      return result;
    }

    /** @brief The reaction labels: boundary ids, or "wall<N>" for boxes. */
    const std::vector<std::string> &
    labels() const
    {
      return source_labels;
    }

    const std::vector<NodeCondition> &
    node_conditions() const
    {
      return conditions;
    }

    /** @brief v_b(t) of a condition, an element of node_conditions(). */
    double
    value(const NodeCondition &condition, const double t) const
    {
      Assert(&condition >= conditions.data() &&
               &condition < conditions.data() + conditions.size(),
             ExcMessage("Not one of node_conditions()."));
      return values_at(t)[&condition - conditions.data()];
    }

    /** @brief v_b(t) of every node condition, in their order (cached for
     * the last few times). */
    const std::vector<double> &
    values_at(const double t) const;

    /** @brief Whether x is inside box wall @p w now. */
    bool
    is_inside_box(const unsigned int w, const Point<dim> &x) const;

    /**
     * @brief Move a point that entered a box wall out along n̂ through the
     * nearer face across n̂; returns whether it moved.
     */
    bool
    push_out_of_walls(Point<dim> &x) const;

    /** @brief Count of collection solves that fell back to 'partial'. */
    unsigned int n_collection_fallbacks = 0;

    /**
     * @brief Read or write the state that evolves during a run (the walls'
     * displacements, the time of the node conditions, the fallback count)
     * for checkpoints; @p archive is a Boost archive.
     */
    template <class Archive>
    void
    serialize_state(Archive &archive)
    {
      archive &wall_displacement &current_time &n_collection_fallbacks;
    }

  private:
    /**
     * @brief B-splines with a padding layer: a node of the layer next to a
     * wall takes the velocity of the interior node it mirrors across the
     * wall (two cells apart): 2 v_w − v_mirror along each direction the wall
     * holds, v_mirror along the others (a roller's or moving wall's
     * tangential directions: symmetry). The wall itself lies on the nodes
     * one cell inside the mesh boundary, which carry the conditions.
     */
    struct PaddingMirror
    {
      /** Owned padding node and its mirror (local indices, the mirror may
       * be a ghost). */
      unsigned int padding, mirror;
      /** Orthonormal directions the wall holds and their walls (-1: v = 0). */
      std::vector<Tensor<1, dim>> directions;
      std::vector<int>            direction_wall;
      /** Reaction label of the boundary id. */
      unsigned int source;
    };

    /**
     * @brief Set the padding nodes of @p field from their mirrors (ghosts
     * updated first). With @p mass, @p field holds momenta (velocities p/m);
     * @p wall_rate scales the walls' values (1 for velocities, the
     * acceleration's 1/(t1 − t0) otherwise, with @p t0 the start).
     * Adds Δp per label to @p impulse if given.
     */
    void
    apply_padding_mirrors(GridVectorField             &field,
                          const GridScalar            *mass,
                          const double                 mass_floor,
                          const double                 t,
                          const double                 t0,
                          const bool                   difference,
                          std::vector<Tensor<1, dim>> *impulse) const;

    /**
     * @brief φ of 'collection full' (Eqs. 2.47-2.50): A φ = r with A_bc =
     * n̂_b · (m̃ₖ⁻¹ n̂_c e_{j_c})_{j_b}, one solve per condition (collective,
     * in global order), φ_b = 0 on empty nodes (not @p active). @p like
     * gives the field layout. Returns false (φ untouched) if A is singular.
     */
    bool
    solve_collection(const GridVectorField     &like,
                     const Operators           &operators,
                     const std::vector<bool>   &active,
                     const std::vector<double> &r,
                     std::vector<double>       &phi) const;

    void
    add_node_condition(std::vector<std::vector<NodeCondition>> &per_node,
                       const NodeCondition                     &candidate);

    /** @brief Build the node conditions from node_position and
     * boundary_normals at current_time. */
    void
    build_conditions();

    /** v_w(x_b, t) of wall @p w at node condition @p c. */
    double
    wall_value(const unsigned int   w,
               const NodeCondition &c,
               const double         t) const;

    MPI_Comm                          mpi_communicator;
    Method                            method = Method::constrained;
    std::vector<types::boundary_id>   fixed, roller;
    std::vector<MovingWallParameters> walls;
    /** v_w(x, t) of each wall. */
    std::vector<std::unique_ptr<FunctionParser<dim>>> wall_velocity;
    /** What v_w depends on, and v_w when it is a constant. */
    std::vector<bool>   velocity_in_x, velocity_in_t;
    std::vector<double> constant_velocity;
    bool                any_velocity_in_x = false;
    /** φ(x, t) of region walls (nullptr for the others). */
    std::vector<std::unique_ptr<FunctionParser<dim>>> wall_region;
    /** The region of 'Fixed region' (nullptr without). */
    std::unique_ptr<FunctionParser<dim>> fixed_region;
    unsigned int                         fixed_region_label = 0;
    /** Axisymmetric: v_r = 0 on the nodes at r <= 0 (the axis; the mesh
     * starts at r = 0 or beyond), reaction label "axis". */
    bool         axis       = false;
    unsigned int axis_label = 0;
    /** Box walls that move or regions in t. */
    bool   moving_nodes = false;
    double current_time = 0;
    /** Displacement s(t) of each wall along its direction. */
    std::vector<double>        wall_displacement;
    std::vector<std::string>   source_labels;
    std::vector<NodeCondition> conditions;
    /** v_b(t) of every condition at a few recent times. */
    mutable std::array<double, 3>              cached_time;
    mutable std::array<std::vector<double>, 3> cached_values;
    mutable unsigned int                       next_cache_slot = 0;
    mutable unsigned int                       last_cache_slot = 0;
    /** Stage-F impulse of each condition in this step (only with a
     * velocity that depends on x). */
    mutable std::vector<double> condition_impulse;
    /** Owned node positions by local index (only with walls given by a
     * region or box, a velocity in x, or a fixed region). */
    std::vector<Point<dim>> node_position;
    /** (boundary id, owned node) and the sum of its outward unit face
     * normals, in that order. */
    std::vector<
      std::pair<std::pair<types::boundary_id, unsigned int>, Tensor<1, dim>>>
      boundary_normals;
    /** B-splines with 'B-spline boundary = padding'. */
    bool padding_layer = false;
    /** Padding layer: (boundary id, owned padding node) → (mirror node,
     * outward normal), found by setup_nodes(). */
    std::vector<std::pair<std::pair<types::boundary_id, unsigned int>,
                          std::pair<unsigned int, Tensor<1, dim>>>>
                                       padding_nodes;
    std::vector<PaddingMirror>         mirrors;
    const DoFHandler<dim>             *dof_handler_pointer = nullptr;
    const Utilities::MPI::Partitioner *partitioner_pointer = nullptr;

    unsigned int
    label_index(const std::string &label);
  };
} // namespace fmpm

#endif
