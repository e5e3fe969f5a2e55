// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_transfer_support_builder_h
#define fmpm_transfer_support_builder_h

#include <fmpm/axisymmetric_shape_function.h>
#include <fmpm/bspline_supports.h>
#include <fmpm/grid_transfer.h>
#include <fmpm/material_points.h>
#include <fmpm/support_cache.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/lac/affine_constraints.h>

#include <array>
#include <vector>

namespace fmpm
{
  namespace Transfer
  {
    using namespace dealii;

    /**
     * @brief Support reader of for_each_point() that computes each point's
     * support (S, G of its nodes; S̄, Ḡ for GIMP/CPDI) and stores it in the
     * SupportCache as it goes, then hands the stored entries to the sinks:
     * the supports are built in the loop of the first pass that reads
     * them.
     *
     * Hanging nodes pass their weights to their masters (SupportCache).
     * A support that reaches beyond the cells around the point's cell is
     * replaced by the classic one and its point kept in failed_point (the
     * first one only), for the caller to report.
     */
    template <int dim>
    class SupportBuilder
    {
    public:
      /** The per-cell closed forms of GIMP and CPDI on uniform patches,
       * built when a cell first needs them and kept across steps. */
      struct Patches
      {
        std::vector<ShapeFunction::UniformGimpPatch<dim>> &gimp;
        std::vector<unsigned int>                         &gimp_of_cell;
        std::vector<ShapeFunction::UniformCpdiPatch<dim>> &cpdi;
        std::vector<unsigned int>                         &cpdi_of_cell;
      };

      /** Clears @p cache's entries (after SupportCache::clear() and the
       * materials: see Simulator::prepare_supports()) and makes room. */
      SupportBuilder(SupportCache<dim>                 &cache,
                     const MaterialPoints<dim>         &points,
                     const GridTransfer<dim>           &transfer,
                     const AffineConstraints<double>   &constraints,
                     const Utilities::MPI::Partitioner &partitioner,
                     const ShapeFunction::Type          shape_function,
                     const double                       cpdi_critical_radius,
                     const unsigned int                 n_active_cells,
                     const Patches                     &patches,
                     const ShapeFunction::BSplineSupports<dim> *bsplines,
                     const bool axisymmetric = false);

      /** The cell's data and patches (cell @p cell_number of the store). */
      void
      begin_cell(const unsigned int cell_number);

      /** Compute and store point @p k's support (the next point of the
       * store). */
      void
      build(const unsigned int k);

      /** build() point @p k, then body(node, S, G, n) with its stored
       * entries. */
      template <typename Body>
      DEAL_II_ALWAYS_INLINE void
      visit(const unsigned int k, const Body &body)
      {
        const std::size_t first = cache.n_stored;
        build(k);
        body(cache.node.data() + first,
             cache.S.data() + first,
             cache.G.data() + first,
             static_cast<unsigned int>(cache.n_stored - first));
      }

      /** The first point whose support failed (invalid: none), and how
       * (axisymmetric runs: axisymmetric_failure). */
      unsigned int          failed_point = numbers::invalid_unsigned_int;
      ShapeFunction::Status failure      = ShapeFunction::Status::ok;
      ShapeFunction::Axisymmetric::Status axisymmetric_failure =
        ShapeFunction::Axisymmetric::Status::ok;

    private:
      static constexpr unsigned int n = GridTransfer<dim>::n_nodes;

      /** Point @p k: classic supports (the cell's nodes). */
      void
      build_classic(const unsigned int first, const unsigned int k);
      /** Point @p k: GIMP and CPDI (closed forms on a uniform patch, else
       * the general support). */
      void
      build_general(const unsigned int first, const unsigned int k);
      /** Point @p k, axisymmetric (2D): S, G and the hoop function T
       * (ShapeFunction::Axisymmetric; classic from ξ as build_classic()
       * with T = S/r_p). */
      void
      build_axisymmetric(const unsigned int first, const unsigned int k);
      /** build_axisymmetric() for the B-spline shape functions
       * (ShapeFunction::Axisymmetric::bspline_support()). */
      void
      build_axisymmetric_bspline(const unsigned int first,
                                 const unsigned int k);
      /** Append an axisymmetric entry (T into cache.T), a hanging node's
       * weights to its masters. */
      void
      add_axisymmetric_node(const unsigned int            first,
                            const unsigned int            local_index,
                            const types::global_dof_index dof,
                            const bool                    constrained,
                            const double                  S,
                            const Tensor<1, dim>         &G,
                            const double                  T);
      /** Point @p k: B-splines on the mesh's lattice (no hanging nodes). */
      void
      build_bspline(const unsigned int k);
      /** Append a node of a support: itself, or for a hanging node its
       * masters with the constraint weights (S_jp += c_ij S_ip). */
      void
      add_node(const unsigned int            first,
               const unsigned int            local_index,
               const types::global_dof_index dof,
               const bool                    constrained,
               const double                  S,
               const Tensor<1, dim>         &G);

      SupportCache<dim>                 &cache;
      const MaterialPoints<dim>         &points;
      const GridTransfer<dim>           &transfer;
      const AffineConstraints<double>   &constraints;
      const Utilities::MPI::Partitioner &partitioner;
      const ShapeFunction::Type          shape_function;
      const double                       cpdi_critical_radius;
      const Patches                      patches;
      /** The B-spline supports (null for the other shape functions). */
      const ShapeFunction::BSplineSupports<dim> *const bsplines;
      const bool                                       classic, gimp, cpdi;
      const bool                                       axisymmetric;

      const double *F_column[dim][dim];
      const double *l0_column[dim];
      /** support_begin[k + 1]. */
      unsigned int *support_end;

      unsigned int                                   c          = 0;
      const typename GridTransfer<dim>::CellData    *data       = nullptr;
      const ShapeFunction::UniformGimpPatch<dim>    *gimp_patch = nullptr;
      const ShapeFunction::UniformCpdiPatch<dim>    *cpdi_patch = nullptr;
      std::array<double, n>                          S;
      std::array<Tensor<1, dim>, n>                  G;
      std::vector<ShapeFunction::Node<dim>>          support;
      std::vector<ShapeFunction::Axisymmetric::Node> axisymmetric_support;
      /** Axisymmetric GIMP: the closed forms around the current cell (2D,
       * uniform patches; rebuilt per cell of each pass). */
      ShapeFunction::Axisymmetric::UniformGimpPatch axisymmetric_gimp_patch;
      bool axisymmetric_gimp_patch_ready = false;
    };
  } // namespace Transfer
} // namespace fmpm

#endif
