// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_parameters_h
#define fmpm_parameters_h

#include <fmpm/contact/parameters.h>
#include <fmpm/parameter_entries.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>

#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The parts of a scene that must be known before the full set of
   * parameters can be declared: the dimension and how many bodies and
   * materials the scene has (each gets its own subsection).
   */
  struct SceneSize
  {
    unsigned int dimension      = 2;
    unsigned int n_bodies       = 1;
    unsigned int n_materials    = 1;
    unsigned int n_moving_walls = 0;
    unsigned int n_tractions    = 0;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /** @brief Background mesh. */
  struct MeshParameters
  {
    /** 'Mesh/Type'. */
    enum class Type
    {
      box,
      gmsh,
      ball
    };
    static constexpr SelectionNames<Type, 3> type_names{
      {"box", "gmsh", "ball"}};

    /** box (GridGenerator::subdivided_hyper_rectangle), gmsh or ball. */
    Type                      type = Type::box;
    std::vector<double>       lower_corner{0, 0, 0};
    std::vector<double>       upper_corner{1, 1, 1};
    std::vector<unsigned int> subdivisions{8, 8, 8};
    std::string               file_name;
    unsigned int              global_refinement = 0;
    /** Random vertex displacement (GridTools::distort_random) as a fraction
     * of the shortest adjacent edge; 0 keeps the mesh. */
    double distortion = 0;
    /** 'Mesh/Periodic directions': periodic[d] if the box's two faces
     * across axis d are one (boundary ids 2d and 2d + 1). */
    std::array<bool, 3> periodic{{false, false, false}};

    /** Whether any direction is periodic. */
    bool
    any_periodic() const
    {
      return periodic[0] || periodic[1] || periodic[2];
    }

    static void
    declare_parameters(ParameterHandler &prm, const unsigned int dim);
    void
    parse_parameters(ParameterHandler &prm, const unsigned int dim);
  };

  /** @brief Adaptive refinement of the background mesh during the run. */
  struct MeshRefinementParameters
  {
    /** 'Mesh refinement/Strategy'. */
    enum class Strategy
    {
      none,
      material_points,
      material_boundary,
      kelly
    };
    static constexpr SelectionNames<Strategy, 4> strategy_names{
      {"none", "material points", "material boundary", "kelly"}};

    Strategy strategy = Strategy::none;
    /** Whether the mesh adapts during the run (a strategy other than
     * none). */
    bool
    adaptive() const
    {
      return strategy != Strategy::none;
    }
    /** Remesh every this many steps (0: only before the first step). */
    unsigned int interval = 10;
    /** Cell levels (0 = the coarse mesh, before global refinement). */
    unsigned int minimum_level = 0;
    unsigned int maximum_level = 3;
    /** Layers of vertex neighbours added around the marked cells. */
    unsigned int buffer_layers = 1;
    /** Kelly: fractions of cells (by count) to refine and to coarsen. */
    double refine_fraction  = 0.3;
    double coarsen_fraction = 0.3;
    /** Adapt the mesh to the bodies before the first step. */
    bool initial_refinement = true;
    /** Load-balancing weight of a material point against a cell's 1. */
    unsigned int point_weight = 10;

    static void
    declare_parameters(ParameterHandler &prm);
    /** Reads the values and checks them against the @p mesh they refine. */
    void
    parse_parameters(ParameterHandler &prm, const MeshParameters &mesh);
  };

  /**
   * @brief A prescribed grid velocity v(t) along a direction n̂ on boundary
   * ids or on the nodes inside a box (which moves with the wall): rigid
   * moving walls and pistons.
   */
  struct MovingWallParameters
  {
    std::vector<types::boundary_id> boundary_ids;
    /** Box region (empty when the wall is given by boundary ids). */
    std::vector<double> box_lower, box_upper;
    /** Or a region φ(x, t) > 0 (FunctionParser in x, y, z, t). */
    std::string region;
    /** Unit direction n̂ of the prescribed velocity component. */
    std::vector<double> direction{1, 0, 0};
    /** v(x, t) (FunctionParser in x, y(, z), t). Units: m/s. */
    std::string velocity = "0";
    std::string constants;

    /** Declare the entries of one 'Moving wall N' (the caller enters it). */
    static void
    declare_parameters(ParameterHandler &prm, const unsigned int dim);
    /** Read and check them; @p where names the subsection in messages. */
    void
    parse_parameters(ParameterHandler  &prm,
                     const unsigned int dim,
                     const std::string &where);
  };

  /** @brief A traction t(t) on the material points inside a box. */
  struct TractionParameters
  {
    std::vector<double> box_lower{0, 0, 0}, box_upper{0, 0, 0};
    /** dim expressions of t separated by ';' (or numbers; the default's
     * first dim). Units: Pa. */
    std::string traction = "0, 0, 0";
    /** Axis of the loaded face's normal: the point's face area is the
     * product of its initial side lengths in the other directions. */
    unsigned int normal_axis = 0;
    std::string  constants;
    /** 'Distribution': false 'point' (F = t A_p through the point's S_ip),
     * true 'face' (∫ t N_i dA over the point's loaded face). */
    bool on_face = false;

    /** Declare the entries of one 'Traction N' (the caller enters it). */
    static void
    declare_parameters(ParameterHandler &prm, const unsigned int dim);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /** @brief Grid velocity conditions, how they are imposed, tractions. */
  struct BoundaryConditionParameters
  {
    std::vector<types::boundary_id> fixed;
    std::vector<types::boundary_id> roller;
    /** Nodes where this φ(x, t) is positive hold v = 0 (empty: none). */
    std::string fixed_region;
    /** constrained, lumped, velocity, unlumped 1, unlumped 2, collection
     * full, collection partial (seed 000 §2.4). */
    std::string                       method = "constrained";
    std::vector<MovingWallParameters> moving_walls;
    std::vector<TractionParameters>   tractions;

    static void
    declare_parameters(ParameterHandler &prm, const SceneSize &size);
    void
    parse_parameters(ParameterHandler &prm, const SceneSize &size);
  };

  /** @brief Body force in a rotating frame (seed 001, body force). */
  struct RotatingFrameParameters
  {
    bool enable = false;
    /** ω(t): 3 expressions of t separated by ';' (or numbers). Units: 1/s. */
    std::string         angular_velocity = "0; 0; 0";
    std::vector<double> center{0, 0, 0};
    std::string         constants;

    /** 'Body force/Rotating frame' (the caller enters 'Body force'). */
    static void
    declare_parameters(ParameterHandler &prm, const unsigned int dim);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /** @brief Time stepping. */
  struct TimeParameters
  {
    double       end_time        = 1.0;
    double       time_step       = 0.0;
    double       courant_number  = 0.5;
    unsigned int max_steps       = 1000000000;
    bool         check_stability = true;
    /** The largest Courant number of the automatic time step; 0: the
     * method's measured limit (stability_limit(), 'auto'); infinity:
     * none. */
    double courant_limit = 0;

    /** Declares 'Time' but for the strain update (MethodParameters). */
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /** @brief How F^(n+1) follows from F^n and L (Deformation gradient/Update).
   */
  enum class DeformationGradientUpdate
  {
    first_order,
    taylor,
    subcycle,
    cayley
  };

  /**
   * @brief Which stress updates a time step makes (seed 000 §2.2), resolved
   * from 'Time/Strain update' when the scene is read.
   */
  struct StrainUpdateScheme
  {
    /** Stresses from the extrapolated velocities, before the momentum
     * update (USF, USAVG±). */
    bool update_first = false;
    /** Stresses after the momentum update (USL±, USAVG±). */
    bool update_last = true;
    /** From momenta re-extrapolated from the updated points (USL+,
     * USAVG+). */
    bool re_extrapolate = true;
    /** Half a step in each of the two updates (USAVG±). */
    bool average = true;

    /** The scheme of 'usf', 'usl' (= usl-), 'usl+', 'usavg' (= usavg-) or
     * 'usavg+' (the names of 'Time/Strain update'). */
    static StrainUpdateScheme
    of(const std::string &name)
    {
      StrainUpdateScheme scheme;
      scheme.update_first =
        name == "usf" || name == "usavg" || name == "usavg+";
      scheme.update_last    = name != "usf";
      scheme.re_extrapolate = name == "usl+" || name == "usavg+";
      scheme.average        = name == "usavg" || name == "usavg+";
      return scheme;
    }

    /** The name of() reads back as this scheme. */
    std::string
    name() const
    {
      if (!update_last)
        return "usf";
      if (average)
        return re_extrapolate ? "usavg+" : "usavg";
      return re_extrapolate ? "usl+" : "usl";
    }
  };

  /** @brief Choice of the MPM algorithm. */
  struct MethodParameters
  {
    std::string particle_update = "flip";
    std::string mass_matrix     = "lumped";
    /** usf, usl (= usl-), usl+, usavg (= usavg-), usavg+ */
    std::string strain_update = "usavg+";
    /** strain_update, resolved when the scene is read. */
    StrainUpdateScheme strain_update_scheme =
      StrainUpdateScheme::of(strain_update);
    /** 'Time/Strain update mass matrix': 'same' (false) or 'lumped' (true):
     * the strain update's grid velocities from the lumped mass matrix. */
    bool                                     lumped_strain_velocities = false;
    static constexpr SelectionNames<bool, 2> strain_update_mass_matrix_names{
      {"same", "lumped"}};
    /** ShapeFunction::pattern() (ShapeFunction::Type) */
    std::string shape_function = "classic";
    /** CPDI: half-diagonal limit in cells (0: none; limit_cpdi_domain()). */
    double cpdi_critical_radius = 0;
    /** 'Shape function/B-spline boundary': padding or open knots. */
    std::string bspline_boundary = "open knots";
    /** 'Deformation gradient/Update'. */
    DeformationGradientUpdate deformation_gradient_update =
      DeformationGradientUpdate::cayley;
    static constexpr SelectionNames<DeformationGradientUpdate, 4>
      deformation_gradient_update_names{
        {"first order", "taylor", "subcycle", "cayley"}};
    unsigned int taylor_terms              = 3;
    double       subcycle_strain_increment = 0.01;
    /** α_g and α_p of seed 003 Eq. 1.17. Units: 1/s. */
    double grid_damping     = 0;
    double particle_damping = 0;

    /** 'Time/Strain update...', 'Shape function', 'Deformation gradient'.
     */
    static void
    declare_parameters(ParameterHandler &prm);
    /** 'Particle update' and 'Mass matrix' with their plugins. */
    static void
    declare_plugin_parameters(ParameterHandler &prm, const unsigned int dim);
    /** Reads what both declare. */
    void
    parse_parameters(ParameterHandler &prm);
  };

  /** @brief One material: a density and a constitutive model. */
  struct MaterialParameters
  {
    std::string model_name = "linear elastic";
    double      density    = 1000.0;

    /** Declare the entries of one 'Material N' with the constitutive models'
     * (the caller enters it). */
    static void
    declare_parameters(ParameterHandler &prm, const unsigned int dim);
    void
    parse_parameters(ParameterHandler &prm, const std::string &where);
  };

  /** @brief One body: a shape filled with material points. */
  struct BodyParameters
  {
    /** 'Body N/Shape' (rectangle, disk, ellipse in 2D). */
    enum class Shape
    {
      box,
      sphere,
      ellipsoid
    };
    static constexpr SelectionNames<Shape, 3> shape_names{
      {"box", "sphere", "ellipsoid"}};

    Shape shape = Shape::box;
    /** 'Body N/Shape' when it is a shape formula (Geometry::parse_shape())
     * rather than one of shape_names; empty otherwise. */
    std::string shape_formula;
    /** 'Body N/File name': the polygon, surface or volume mesh file. */
    std::string file_name;
    /** Whether the body is the volume mesh of 'File name' (Shape = mesh). */
    bool from_mesh = false;
    /** 'Body N/Physical groups': the mesh cells' groups (all if empty). */
    std::vector<unsigned int> physical_groups;
    std::vector<double>       center{0.5, 0.5, 0.5};
    std::vector<double>       half_lengths{0.25, 0.25, 0.25};
    unsigned int              material        = 0;
    unsigned int              points_per_cell = 2;
    /** Initial velocity: numbers separated by ',' or expressions by ';'
     * (the default's first dim). */
    std::string velocity_expression = "0, 0, 0";
    /** "name=value, ..." for the expressions. */
    std::string function_constants;
    /** Start with the stress in equilibrium with gravity (lithostatic). */
    bool initial_stress_from_gravity = false;
    /** Initial Cauchy stress: expressions in x, y(, z) separated by ';'
     * (xx; yy; xy in 2D, xx; yy; zz; xy; xz; yz in 3D); empty: none. */
    std::string initial_stress_expression;

    /** Declare the entries of one 'Body N' (the caller enters it). */
    static void
    declare_parameters(ParameterHandler &prm, const unsigned int dim);
    /** Read and check them against the scene's @p size. */
    void
    parse_parameters(ParameterHandler  &prm,
                     const SceneSize   &size,
                     const std::string &where);
  };

  /**
   * @brief Parse "a=1, b=2" into a map for FunctionParser; @p where names
   * the parameter in error messages.
   */
  std::map<std::string, double>
  parse_function_constants(const std::string &text, const std::string &where);

  /**
   * @brief FunctionParser expressions from a parameter value: "1, 2"
   * (numbers separated by ',') or "x; 2*y" (expressions separated by ';').
   */
  std::string
  to_function_expressions(const std::string &value);

  /** @brief What a run writes and how often. */
  struct OutputParameters
  {
    std::string  directory     = "output";
    double       interval      = 0.0;
    unsigned int step_interval = 0;
    /** Shorten the step that would pass a multiple of 'interval' so that
     * the output lands on it. */
    bool exact_output_times = false;
    bool write_vtu          = true;
    /** Output/Tracked points as written: positions (dim numbers) or point
     * ids, separated by ';' (resolved by the Simulator). */
    std::string tracked_points;
    /** zlib level of the VTU data. */
    enum class Compression
    {
      best_speed,
      best_compression,
      default_compression,
      none
    };
    static constexpr SelectionNames<Compression, 4> compression_names{
      {"best speed", "best compression", "default", "none"}};
    Compression compression = Compression::best_speed;
    /** particles_NNNNN.csv at each output (rank 0, rows by point id). */
    bool write_particle_csv = false;
    /** Grid acceleration m̃ₖ⁻¹f + Δv⁺/Δt (seed 000 Eq. 4.1) in the grid VTU. */
    bool   write_grid_acceleration = false;
    double progress_seconds        = 5.0;
    bool   track_dissipation       = false;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /** @brief When a run writes checkpoints (Output directory/checkpoint/). */
  struct CheckpointParameters
  {
    /** Steps between checkpoints; 0: none by step count. */
    unsigned int step_interval = 0;
    /** Wall-clock minutes between checkpoints; 0: none by wall time. */
    double wall_time_interval = 0;
    /** How many complete checkpoints to keep (the newest ones). */
    unsigned int keep = 2;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /** @brief How a run detects and treats failures. */
  struct FailureParameters
  {
    double energy_growth_limit = 2.0;
    /** The run fails when the kinetic energy exceeds this; 0: no limit.
     * For quasi-static scenes, whose instabilities show as kinetic energy
     * while the total stays below the external work. Units: J. */
    double kinetic_energy_limit = 0;
    /** What happens to material points that leave the mesh. */
    enum class LostPoints
    {
      stop,
      remove
    };
    static constexpr SelectionNames<LostPoints, 2> lost_points_names{
      {"stop", "delete"}};
    LostPoints lost_points = LostPoints::stop;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /** @brief An analytical solution the run measures its error against. */
  struct ReferenceSolutionParameters
  {
    bool enable = false;
    /** Expressions of each component separated by ';' (the defaults' first
     * dim components). */
    std::string velocity     = "0, 0, 0";
    std::string displacement = "0, 0, 0";
    std::string constants;

    static void
    declare_parameters(ParameterHandler &prm, const unsigned int dim);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /**
   * @brief All parameters of a scene, read in two passes (SceneSize first).
   */
  struct Parameters
  {
    SceneSize                       size;
    MeshParameters                  mesh;
    MeshRefinementParameters        refinement;
    BoundaryConditionParameters     boundary_conditions;
    TimeParameters                  time;
    MethodParameters                method;
    std::vector<MaterialParameters> materials;
    std::vector<BodyParameters>     bodies;
    std::vector<double>             gravity{0, 0, 0};
    /** Extra body acceleration b(x, t) (FunctionParser), empty for none. */
    std::string body_acceleration;
    std::string body_acceleration_constants;
    /** Evaluate b at the point's initial position X instead of x. */
    bool                        body_acceleration_at_initial_position = false;
    RotatingFrameParameters     rotating_frame;
    OutputParameters            output;
    CheckpointParameters        checkpoint;
    Contact::Parameters         contact;
    FailureParameters           failure;
    ReferenceSolutionParameters reference;
    bool                        test_mode = false;
    /** 'Geometry': plane strain (false) or axisymmetric (true: 2D scenes in
     * the r–z plane, x = r, y = z; masses, volumes, forces and energies per
     * radian). */
    bool                                     axisymmetric = false;
    static constexpr SelectionNames<bool, 2> geometry_names{
      {"plane strain", "axisymmetric"}};
    /** Move only the points that left their cell (else deal.II's sort). */
    bool fast_point_sorting = true;
    /** 'Timer/Type = summary' (true) or 'none'. */
    bool                                     print_timer_summary = true;
    static constexpr SelectionNames<bool, 2> timer_type_names{
      {"none", "summary"}};

    /**
     * @brief Declare everything for a scene of size @p size, including the
     * parameters of every plugin.
     */
    static void
    declare_parameters(ParameterHandler &prm, const SceneSize &size);

    /** @brief Read the values and check them across parameters. */
    void
    parse_parameters(ParameterHandler &prm);

    /** @brief 'Body force' with its 'Rotating frame'. */
    static void
    declare_body_force_parameters(ParameterHandler  &prm,
                                  const unsigned int dim);
    /** @brief Reads what declare_body_force_parameters() declares. */
    void
    parse_body_force_parameters(ParameterHandler &prm);
  };

  /**
   * @brief The text of each scene source, in order: each file, standard
   * input for "-", or the built-in default scene if @p files is empty.
   * Returns (name, text) pairs.
   */
  std::vector<std::pair<std::string, std::string>>
  load_scene_sources(const std::vector<std::string> &files);

  /**
   * @brief Parse scene sources in order (later `set` lines override earlier
   * ones) into @p prm and @p parameters. Throws an ExcMessage naming the
   * file, line and parameter on any error.
   */
  void
  read_scene(const std::vector<std::pair<std::string, std::string>> &sources,
             ParameterHandler                                       &prm,
             Parameters &parameters);

  /** @brief Declared error messages without deal.II's source location. */
  std::string
  error_message(const std::exception &e);

  /** @brief The built-in default scene: two elastic disks colliding. */
  std::string
  default_scene();

  /** @brief "fmpm VERSION (git SHORTREV, BRANCH, DATE), deal.II VERSION". */
  std::string
  version_text();

  /**
   * @brief The scene's size (dimension and the counts of the numbered
   * subsections Body N, Material N, Moving wall N, Traction N): the first
   * pass of read_scene(), which ignores every other parameter.
   */
  SceneSize
  read_scene_size(
    const std::vector<std::pair<std::string, std::string>> &sources);
} // namespace fmpm

#endif
