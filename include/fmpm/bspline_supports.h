// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_bspline_supports_h
#define fmpm_bspline_supports_h

#include <fmpm/bspline.h>
#include <fmpm/grid_transfer.h>
#include <fmpm/shape_function.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <array>
#include <cmath>
#include <vector>

namespace fmpm
{
  namespace ShapeFunction
  {
    using namespace dealii;

    /**
     * @brief The supports of the B-spline shape functions (b2spline,
     * b3spline, b2gimp, b2cpdi; fmpm::BSpline) on a mesh of equal
     * axis-aligned boxes: the lattice of the mesh, and the local index of
     * each lattice vertex this rank holds. Built once per mesh; support()
     * is called per point (no allocation, no virtual call).
     *
     * A direction with fewer cells than the degree's basis needs (open
     * knots: 2p, padding: 3) carries the linear basis (a tensor product of
     * bases of different degrees keeps Σ S = 1 and Σ S x_i = x).
     */
    template <int dim>
    class BSplineSupports
    {
    public:
      /** The most entries of one support (6 vertices per direction). */
      static constexpr unsigned int max_support_size =
        BSpline::BoxSupport<dim>::max_size;

      /** Whether reinit() has set up a B-spline type. */
      bool
      active() const
      {
        return kind != Kind::none;
      }

      /**
       * @brief The lattice of the mesh GridTransfer caches and the local
       * indices of its vertices. Throws ExcMessage naming Shape
       * function/Type if the mesh is not a lattice of equal axis-aligned
       * boxes.
       */
      void
      reinit(const Type               type,
             const BSpline::Boundary  boundary,
             const GridTransfer<dim> &transfer,
             const unsigned int       n_active_cells,
             const MPI_Comm           communicator);

      /**
       * @brief Makes the lattice vertices at @p positions, beyond the cells
       * GridTransfer caches, known with @p local_indices in the ghosted
       * vectors (BSpline::vertices_beyond_ghost_cells()).
       */
      void
      add_vertices(const std::vector<Point<dim>>   &positions,
                   const std::vector<unsigned int> &local_indices)
      {
        vertices.add(lattice, positions, local_indices);
      }

      const BSpline::Lattice<dim> &
      get_lattice() const
      {
        return lattice;
      }

      /** The local index of the lattice vertex @p index in the ghosted
       * vectors, or numbers::invalid_unsigned_int if this rank has none. */
      unsigned int
      vertex_local_index(const std::array<int, dim> &index) const
      {
        return vertices.local_index(index);
      }

      /**
       * @brief How many cells beyond a point's cell its support may reach
       * per direction: 1 for b2spline and b3spline (the cells sharing a
       * vertex with it), 2 for b2gimp and b2cpdi.
       */
      unsigned int
      reach() const
      {
        return kind == Kind::values ? 1 : 2;
      }

      /**
       * @brief The local indices of the lattice vertices within reach() cells
       * of @p cell that this rank holds (the nodes a point in the cell may
       * couple to, for the sparsity of the full mass matrix).
       */
      void
      vertices_in_reach(const typename GridTransfer<dim>::CellData &cell,
                        std::vector<unsigned int> &local_indices) const;

      /**
       * @brief S_ip, G_ip of the point at @p x with deformation gradient
       * @p F and initial half-lengths @p l0: the B-splines at x (b2spline,
       * b3spline), their averages over the box x ± l⁰ (b2gimp), or over
       * the corners of s = F diag(l⁰) (b2cpdi, s limited to @p
       * cpdi_critical_radius cells as limit_cpdi_domain() when positive).
       * Writes @p count entries (at most max_support_size) to @p node, @p S,
       * @p G.
       */
      Status
      support(const Point<dim>     &x,
              const Tensor<2, dim> &F,
              const Tensor<1, dim> &l0,
              const double          cpdi_critical_radius,
              unsigned int         *node,
              double               *S,
              Tensor<1, dim>       *G,
              unsigned int         &count) const
      {
        count         = 0;
        Status status = Status::ok;
        auto   sink   = [&](const std::array<int, dim> &index,
                        const double                S_ip,
                        const Tensor<1, dim>       &G_ip) {
          const unsigned int local = vertices.local_index(index);
          if (local == numbers::invalid_unsigned_int)
            {
              status = Status::vertex_not_on_rank;
              return;
            }
          node[count] = local;
          S[count]    = S_ip;
          G[count]    = G_ip;
          ++count;
        };
        switch (kind)
          {
            case Kind::values:
              {
                BSpline::ProductSupport<dim> product;
                if (lattice.point_support(x, product) != BSpline::Status::ok)
                  return Status::in_padding_layer;
                write_product(product, node, S, G, count, sink, status);
                break;
              }
            case Kind::gimp:
              {
                for (unsigned int d = 0; d < dim; ++d)
                  if (l0[d] > half_cell[d])
                    return Status::domain_too_wide;
                BSpline::ProductSupport<dim> product;
                if (lattice.gimp_support(x, l0, product) != BSpline::Status::ok)
                  return Status::in_padding_layer;
                write_product(product, node, S, G, count, sink, status);
                break;
              }
            case Kind::cpdi:
              {
                Tensor<2, dim> s;
                for (unsigned int a = 0; a < dim; ++a)
                  for (unsigned int b = 0; b < dim; ++b)
                    s[a][b] = F[a][b] * l0[b];
                if (cpdi_critical_radius > 0)
                  limit_cpdi_domain(s, cpdi_critical_radius * smallest_cell);
                // Corners within a cell of the point in each direction
                // (max_α |(s r_α)_d| = Σ_j |s_dj|), so the support stays
                // within reach().
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    double extent = 0;
                    for (unsigned int j = 0; j < dim; ++j)
                      extent += std::abs(s[d][j]);
                    if (!(extent <= 2 * half_cell[d]))
                      return Status::domain_too_wide;
                  }
                BSpline::BoxSupport<dim> box;
                const BSpline::Status    box_status =
                  lattice.cpdi_support(x, s, box);
                if (box_status == BSpline::Status::outside_lattice)
                  return Status::in_padding_layer;
                if (box_status != BSpline::Status::ok)
                  return Status::domain_too_wide;
                bool all_on_rank = true;
                if (vertices.write_box(box, node, S, G, count, all_on_rank))
                  {
                    if (!all_on_rank)
                      status = Status::vertex_not_on_rank;
                  }
                else
                  box.for_each_node(sink);
                break;
              }
            default:
              break;
          }
        return status;
      }

      /** What a failed support() means, for the run's error message. */
      static const char *
      explain(const Status status);

    private:
      /** The entries of a tensor-product support: along the rows of the
       * vertex map (VertexMap::write_product()), or through @p sink where
       * the support leaves the map's box. */
      template <typename Sink>
      DEAL_II_ALWAYS_INLINE void
      write_product(const BSpline::ProductSupport<dim> &product,
                    unsigned int                       *node,
                    double                             *S,
                    Tensor<1, dim>                     *G,
                    unsigned int                       &count,
                    Sink                               &sink,
                    Status                             &status) const
      {
        bool all_on_rank = true;
        if (vertices.write_product(product, node, S, G, count, all_on_rank))
          {
            if (!all_on_rank)
              status = Status::vertex_not_on_rank;
          }
        else
          product.for_each_node(sink);
      }

      enum class Kind
      {
        none,
        values,
        gimp,
        cpdi
      };
      Kind                    kind = Kind::none;
      BSpline::Lattice<dim>   lattice;
      BSpline::VertexMap<dim> vertices;
      std::array<double, dim> half_cell{};
      double                  smallest_cell = 0;
    };
  } // namespace ShapeFunction
} // namespace fmpm

#endif
