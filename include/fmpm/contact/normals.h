// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_contact_normals_h
#define fmpm_contact_normals_h

#include <fmpm/contact/parameters.h>
#include <fmpm/plugins.h>
#include <fmpm/shape_function.h>

#include <deal.II/base/array_view.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>
#include <deal.II/particles/property_pool.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace fmpm
{
  namespace Contact
  {
    /**
     * @brief The geometry of a node shared by α and β: n̂ (from α to β),
     * whether the materials touch there (the normal method's separation
     * test) and the separation in cells. It depends on the points'
     * positions only, so it is found once per extrapolation and used by
     * every correction until the points move.
     */
    template <int dim>
    struct NodeGeometry
    {
      Tensor<1, dim> normal;
      bool           touching   = true;
      double         separation = 0;
    };

    /**
     * @brief d(x) of seed 004 Fig. 1 for the DF method: the signed distance
     * from the edge of a semi-infinite material to a node, as a function of
     * the extrapolated position x = (x^α − x_i)·n̂, both in cells.
     *
     * Tabulated at set-up for the shape function in use and the points'
     * half-length (undeformed points on a line, linear grid functions),
     * then inverted: for each edge position e the row of points at
     * e − (k + 1/2) 2 l_p gives x^α(e) = Σ S_ip x_p / Σ S_ip; d(x) is the
     * inverse on the branch where x^α rises with e, extended with slope 1.
     */
    class EdgeDistance
    {
    public:
      EdgeDistance() = default;
      EdgeDistance(const ShapeFunction::Type type,
                   const double              half_length_in_cells);

      /** d for a material on the −n̂ side of the node (material α). */
      double
      alpha(const double x) const;

      /** d for a material on the +n̂ side: d_β(x) = −d_α(−x). */
      double
      beta(const double x) const
      {
        return -alpha(-x);
      }

    private:
      std::vector<double> x_table, d_table;
    };

    /** @brief The result of a logistic regression fit at a node. */
    template <int dim>
    struct RegressionResult
    {
      /** n̂ = (φ_1, ..., φ_dim)/|...|, from class −1 (α) to class +1 (β). */
      Tensor<1, dim> normal;
      /** NLLS iterations after the first (linear regression) one. */
      unsigned int iterations = 0;
      bool         converged  = false;
      /** False when the normal equations were singular from the start. */
      bool valid = false;
    };

    /**
     * @brief The most probable plane between two point classes (seed 004
     * Eqs. 19-21, appendix Eqs. 53-57): minimise Σ (f(x_p·φ) − c_p)² +
     * Σ λ_j φ_j² with f(s) = 2/(1 + e^{−s}) − 1 = tanh(s/2), by NLLS from
     * φ⁽⁰⁾ = 0 (the first iterate is the linear regression). w_p = 1,
     * λ = 10⁻⁷ Δx² (1, ..., 1, 0), converged when 1 − n̂⁽ᵏ⁺¹⁾·n̂⁽ᵏ⁾ <
     * @p tolerance (Eq. 57), at most @p max_iterations NLLS steps. If an
     * NLLS step is singular or not finite the last good normal is kept.
     *
     * At most 8 steps, not the paper's 15: a cloud that has not converged
     * by then is separable, |φ| grows at each step and the normal creeps
     * while its sensitivity to the positions grows (steps 9-15 turned
     * round-off of the grid sums into a 4e-5 kinetic-energy difference
     * between 1 and 2 ranks on an oblique 3D collision; with 8, none at
     * 12 digits).
     *
     * @p x are the positions (any origin; the cloud's mean is the best
     * conditioned), @p c the classes (−1 or 1), @p cell_size Δx.
     */
    template <int dim>
    RegressionResult<dim>
    logistic_regression_normal(const Tensor<1, dim> *x,
                               const double         *c,
                               const unsigned int    n,
                               const double          cell_size,
                               const double          tolerance      = 1e-5,
                               const unsigned int    max_iterations = 8);

    /**
     * @brief R_p of Eq. 25: the distance along n̂ from a point's centre to
     * its deformed ellipsoid, 1/R_p = |n₀/R₀| with n₀ = F⁻¹n̂.
     */
    template <int dim>
    inline double
    deformed_radius(const Tensor<2, dim> &F_inverse,
                    const Tensor<1, dim> &initial_radii,
                    const Tensor<1, dim> &normal)
    {
      const Tensor<1, dim> n0  = F_inverse * normal;
      double               sum = 0;
      for (unsigned int d = 0; d < dim; ++d)
        sum += n0[d] * n0[d] / (initial_radii[d] * initial_radii[d]);
      return 1. / std::sqrt(sum);
    }

    /** LR: a point of the cloud of a node (plain data: sent between
     * ranks). */
    template <int dim>
    struct CloudPoint
    {
      types::global_dof_index node;
      /** The point's id: a node's cloud is in id order on any number of
       * ranks (the fit's sums then run in one order). */
      types::particle_index id;
      unsigned int          material;
      double                position[dim];
      double                F_inverse[dim * dim];
      double                initial_radii[dim];

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &node &id &material &position &F_inverse &initial_radii;
      }
    };

    /** What a normal method reads; the manager extrapolates and gathers
     * only that. */
    struct NormalNeeds
    {
      /** g^α = Σ G V (Eq. 11). */
      bool volume_gradients = false;
      /** x^α = Σ S M X / m^α (Eq. 11). */
      bool positions = false;
      /** The local cell size h at the node (separations in cells). */
      bool cell_size = false;
      /** The position of the node. */
      bool node_positions = false;
      /** The point cloud of the node, the points of other ranks included
       * (seed 004 §3.1). */
      bool point_clouds = false;
      /** Whether the method measures the gap d between the materials (then
       * 'Touching tolerance' and 'Gap closing' apply). */
      bool measures_gap = false;
    };

    /** The node pair a normal method sees: α against β (β may be the sum
     * of several materials, Eq. 50), the sums over each side of what
     * needs() asked for. */
    template <int dim>
    struct NormalInputs
    {
      /** The first material of each side. */
      unsigned int   first_alpha = 0, first_beta = 0;
      double         mass_alpha = 0, mass_beta = 0;
      Tensor<1, dim> volume_gradient_alpha, volume_gradient_beta;
      /** Σ S M X of each side (x^α times m^α). */
      Tensor<1, dim> position_moment_alpha, position_moment_beta;
      Tensor<1, dim> node_position;
      double         cell_size = 0;
      /** The node's cloud (every material), and whether a cloud point's
       * material is on side α (−1), side β (+1) or neither (0). */
      ArrayView<const CloudPoint<dim>> cloud;
      ArrayView<const int>             side_of_material;
    };

    /** Set-up data of a normal method. */
    struct NormalSetup
    {
      ShapeFunction::Type type = ShapeFunction::Type::classic;
      /** Points per cell and direction of each material's first body. */
      std::vector<unsigned int> points_per_cell;
    };

    /**
     * @brief A contact normal method (plugin system): n̂ at a node shared by
     * α and β and whether they touch there (seed 004 §2.3, §3.1).
     *
     * Called once per pair at each contact node and extrapolation (not per
     * point). Registered: 'velocity only', 'average gradient', 'contact
     * position', 'd fit', 'logistic regression' and 'specified'. A new
     * method derives from this class and registers with
     * FMPM_REGISTER_CONTACT_NORMALS.
     */
    template <int dim>
    class NormalMethodInterface : public Plugins::InterfaceBase
    {
    public:
      virtual NormalNeeds
      needs() const = 0;
      /** Read the settings of subsection Contact. */
      virtual void
      set_up(const Parameters &, const NormalSetup &)
      {}
      virtual NodeGeometry<dim>
      geometry(const NormalInputs<dim> &node) = 0;
      /** Figures for summary.json as (key, value) over all ranks since
       * the start (collective). */
      virtual std::vector<std::pair<std::string, double>>
      statistics(const MPI_Comm) const
      {
        return {};
      }
    };

    /** @brief The registered normal methods, '|'-separated. */
    std::string
    normal_method_names();

    /** @brief The registered normal methods with their descriptions. */
    std::string
    normal_method_documentation();

    /** @brief Create the normal method @p name. */
    template <int dim>
    std::unique_ptr<NormalMethodInterface<dim>>
    create_normal_method(const std::string &name);

    /** Registers a normal method class template for dim = 2 and 3. */
    template <template <int> class MethodType>
    struct RegisterNormalMethod
    {
      RegisterNormalMethod(const std::string &name,
                           const std::string &description)
      {
        Plugins::Registry<NormalMethodInterface<2>>::instance().register_plugin(
          name, description, nullptr, []() {
            return std::make_unique<MethodType<2>>();
          });
        Plugins::Registry<NormalMethodInterface<3>>::instance().register_plugin(
          name, description, nullptr, []() {
            return std::make_unique<MethodType<3>>();
          });
      }
    };
  } // namespace Contact
} // namespace fmpm

/** Registers the normal method class template CLASSNAME as NAME. */
#define FMPM_REGISTER_CONTACT_NORMALS(CLASSNAME, NAME, DESCRIPTION)     \
  namespace                                                             \
  {                                                                     \
    const ::fmpm::Contact::RegisterNormalMethod<CLASSNAME>              \
      fmpm_contact_normals_registration_##CLASSNAME(NAME, DESCRIPTION); \
  }

#endif
