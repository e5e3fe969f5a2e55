// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/shape_function.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fmpm
{
  namespace ShapeFunction
  {
    template <int dim>
    Tensor<1, dim>
    gimp_half_lengths(const Type            type,
                      const Tensor<2, dim> &F,
                      const Tensor<1, dim> &l0)
    {
      if (type != Type::cpgimp)
        return l0;
      // The box circumscribing the deformed particle F·diag(l⁰) (seed 001
      // §UGIMP and cpGIMP, after Ma et al. 2006).
      Tensor<1, dim> l;
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int j = 0; j < dim; ++j)
          l[d] += std::abs(F[d][j]) * l0[j];
      return l;
    }



    namespace
    {
      /** Add S and G of node i of a cell, summing repeated nodes. */
      template <int dim>
      inline void
      add_node(std::vector<Node<dim>>                     &support,
               const GridTransfer<dim>                    &transfer,
               const typename GridTransfer<dim>::CellData &cell,
               const unsigned int                          i,
               const double                                S,
               const Tensor<1, dim>                       &G)
      {
        for (auto &node : support)
          if (node.local_index == cell.local_index[i])
            {
              node.S += S;
              node.G += G;
              return;
            }
        support.push_back(Node<dim>{cell.local_index[i],
                                    transfer.dof_index(cell, i),
                                    ((cell.constrained_nodes >> i) & 1) != 0,
                                    S,
                                    G});
      }

      /** Gauss-Legendre points and weights on [0, 1]. */
      struct Gauss1D
      {
        unsigned int n;
        double       x[3];
        double       w[3];
      };
      constexpr Gauss1D gauss2{2,
                               {0.5 - 0.28867513459481287, // 1/(2√3)
                                0.5 + 0.28867513459481287,
                                0},
                               {0.5, 0.5, 0}};
      constexpr Gauss1D gauss3{3,
                               {0.5 - 0.3872983346207417, // √(3/5)/2
                                0.5,
                                0.5 + 0.3872983346207417},
                               {5. / 18, 8. / 18, 5. / 18}};

      /**
       * S̄ = 1/V ∫_Ω S_g and Ḡ = 1/V ∫_Ω ∇S_g over an axis-aligned box Ω
       * (seed 001 Eqs. effectiveS, G_gimp) by a quadrature split at the
       * faces of the cells the box crosses.
       */
      template <int dim>
      class GimpQuadrature
      {
      public:
        GimpQuadrature(const GridTransfer<dim> &transfer,
                       const unsigned int       home,
                       const double             inverse_volume,
                       std::vector<Node<dim>>  &support)
          : transfer(transfer)
          , home(home)
          , hint(home)
          , inverse_volume(inverse_volume)
          , support(support)
        {}

        void
        integrate(const Point<dim>  &lo,
                  const Point<dim>  &hi,
                  const unsigned int depth,
                  const unsigned int bisections)
        {
          if (status != Status::ok)
            return;
          using Transfer = GridTransfer<dim>;
          typename Transfer::Location center;
          if (!locate(0.5 * (lo + hi), center))
            return;
          const auto &cell = transfer.cell_data(center.cell);
          hint             = center.cell;

          // Does the cell hold the whole box (corners suffice: cells are
          // convex)?
          bool inside = true;
          for (unsigned int c = 0; c < Transfer::n_nodes && inside; ++c)
            {
              Point<dim> corner;
              for (unsigned int d = 0; d < dim; ++d)
                corner[d] = ((c >> d) & 1) ? hi[d] : lo[d];
              inside = Transfer::contains(cell,
                                          Transfer::reference_point(cell,
                                                                    corner,
                                                                    center.xi),
                                          1e-10,
                                          0.5);
            }
          if (inside)
            {
              integrate_in_cell(lo,
                                hi,
                                center.cell,
                                center.xi,
                                cell.is_affine ? gauss2 : gauss3);
              return;
            }

          if (depth < 24)
            {
              // Split at a face of an axis-aligned cell that crosses the
              // box (exact), else bisect the longest side.
              unsigned int split_direction = dim;
              double       split           = 0;
              if (cell.is_axis_aligned)
                for (unsigned int d = 0; d < dim && split_direction == dim; ++d)
                  {
                    const double margin = 1e-10 * (hi[d] - lo[d]);
                    for (const double plane :
                         {cell.lower()[d], cell.upper()[d]})
                      if (plane > lo[d] + margin && plane < hi[d] - margin)
                        {
                          split_direction = d;
                          split           = plane;
                          break;
                        }
                  }
              // Across non-axis-aligned cells: one bisection per direction
              // (a 2^dim-th of the box), then pointwise Gauss (accuracy
              // ~1e-4 of S̄ on distorted meshes; partition of unity and
              // linear fields stay exact).
              if (split_direction == dim && bisections < dim)
                {
                  split_direction = 0;
                  for (unsigned int d = 1; d < dim; ++d)
                    if (hi[d] - lo[d] >
                        hi[split_direction] - lo[split_direction])
                      split_direction = d;
                  split = 0.5 * (lo[split_direction] + hi[split_direction]);
                }
              if (split_direction < dim)
                {
                  const bool bisected =
                    !cell.is_axis_aligned ||
                    split == 0.5 * (lo[split_direction] + hi[split_direction]);
                  Point<dim> upper_of_first = hi, lower_of_second = lo;
                  upper_of_first[split_direction]  = split;
                  lower_of_second[split_direction] = split;
                  integrate(lo,
                            upper_of_first,
                            depth + 1,
                            bisections + (bisected ? 1 : 0));
                  integrate(lower_of_second,
                            hi,
                            depth + 1,
                            bisections + (bisected ? 1 : 0));
                  return;
                }
            }
          // Small pieces that still cross faces of non-axis-aligned cells:
          // Gauss points located one by one.
          integrate_pointwise(lo, hi);
        }

        Status status = Status::ok;

      private:
        bool
        locate(const Point<dim>                     &x,
               typename GridTransfer<dim>::Location &location)
        {
          const auto result = transfer.locate(home, x, hint, location);
          if (result == GridTransfer<dim>::LocateStatus::found)
            return true;
          status = (result == GridTransfer<dim>::LocateStatus::outside_mesh) ?
                     Status::outside_mesh :
                     Status::beyond_neighbors;
          return false;
        }

        void
        integrate_in_cell(const Point<dim>  &lo,
                          const Point<dim>  &hi,
                          const unsigned int cell_index,
                          const Point<dim>  &xi_guess,
                          const Gauss1D     &gauss)
        {
          using Transfer   = GridTransfer<dim>;
          const auto &cell = transfer.cell_data(cell_index);
          double      box  = inverse_volume;
          for (unsigned int d = 0; d < dim; ++d)
            box *= hi[d] - lo[d];
          std::array<double, Transfer::n_nodes>         S, S_sum{};
          std::array<Tensor<1, dim>, Transfer::n_nodes> G, G_sum;
          unsigned int                                  n_points = 1;
          for (unsigned int d = 0; d < dim; ++d)
            n_points *= gauss.n;
          for (unsigned int q = 0; q < n_points; ++q)
            {
              Point<dim>   x;
              double       w = box;
              unsigned int k = q;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const unsigned int j = k % gauss.n;
                  k /= gauss.n;
                  x[d] = lo[d] + gauss.x[j] * (hi[d] - lo[d]);
                  w *= gauss.w[j];
                }
              const Point<dim> xi =
                Transfer::reference_point(cell, x, xi_guess);
              Transfer::values_and_gradients(cell, xi, S, G);
              for (unsigned int i = 0; i < Transfer::n_nodes; ++i)
                {
                  S_sum[i] += w * S[i];
                  G_sum[i] += w * G[i];
                }
            }
          for (unsigned int i = 0; i < Transfer::n_nodes; ++i)
            add_node<dim>(support, transfer, cell, i, S_sum[i], G_sum[i]);
        }

        void
        integrate_pointwise(const Point<dim> &lo, const Point<dim> &hi)
        {
          using Transfer       = GridTransfer<dim>;
          const Gauss1D &gauss = gauss3;
          double         box   = inverse_volume;
          for (unsigned int d = 0; d < dim; ++d)
            box *= hi[d] - lo[d];
          std::array<double, Transfer::n_nodes>         S;
          std::array<Tensor<1, dim>, Transfer::n_nodes> G;
          unsigned int                                  n_points = 1;
          for (unsigned int d = 0; d < dim; ++d)
            n_points *= gauss.n;
          for (unsigned int q = 0; q < n_points; ++q)
            {
              Point<dim>   x;
              double       w = box;
              unsigned int k = q;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const unsigned int j = k % gauss.n;
                  k /= gauss.n;
                  x[d] = lo[d] + gauss.x[j] * (hi[d] - lo[d]);
                  w *= gauss.w[j];
                }
              typename Transfer::Location location;
              if (!locate(x, location))
                return;
              hint             = location.cell;
              const auto &cell = transfer.cell_data(location.cell);
              Transfer::values_and_gradients(cell, location.xi, S, G);
              for (unsigned int i = 0; i < Transfer::n_nodes; ++i)
                add_node<dim>(support, transfer, cell, i, w * S[i], w * G[i]);
            }
        }

        const GridTransfer<dim> &transfer;
        const unsigned int       home;
        unsigned int             hint;
        const double             inverse_volume;
        std::vector<Node<dim>>  &support;
      };
    } // namespace



    template <int dim>
    bool
    limit_cpdi_domain(Tensor<2, dim> &s, const double r_max)
    {
      constexpr unsigned int                  n_diagonals = 1u << (dim - 1);
      std::array<Tensor<1, dim>, n_diagonals> r, d;
      bool                                    limited = false;
      for (unsigned int k = 0; k < n_diagonals; ++k)
        {
          for (unsigned int j = 0; j + 1 < dim; ++j)
            r[k][j] = ((k >> j) & 1) ? -1. : 1.;
          r[k][dim - 1]       = 1.;
          d[k]                = s * r[k];
          const double length = d[k].norm();
          if (length > r_max)
            {
              d[k] *= r_max / length;
              limited = true;
            }
        }
      if (!limited)
        return false;
      for (unsigned int j = 0; j < dim; ++j)
        {
          Tensor<1, dim> column;
          for (unsigned int k = 0; k < n_diagonals; ++k)
            column += r[k][j] * d[k];
          column /= n_diagonals;
          for (unsigned int c = 0; c < dim; ++c)
            s[c][j] = column[c];
        }
      // In 3D the fit can leave a diagonal a little long: scale s as a whole.
      double longest = 0;
      for (unsigned int k = 0; k < n_diagonals; ++k)
        longest = std::max(longest, (s * r[k]).norm());
      if (longest > r_max)
        s *= r_max / longest;
      return true;
    }



    namespace
    {
      /** The CPDI support of compute_support(): on a uniform patch of exact
       * boxes the closed form (UniformCpdiPatch), else the corners located
       * one by one (seed 001 Eq. cpdi). */
      template <int dim>
      Status
      cpdi_support(const GridTransfer<dim> &transfer,
                   const unsigned int       cell_index,
                   const Point<dim>        &x,
                   const Tensor<2, dim>    &F,
                   const Tensor<1, dim>    &l0,
                   std::vector<Node<dim>>  &support,
                   const bool               allow_closed_form,
                   const double             cpdi_critical_radius)
      {
        using Transfer                  = GridTransfer<dim>;
        constexpr unsigned int      n   = Transfer::n_nodes;
        const auto                 &own = transfer.cell_data(cell_index);
        std::array<double, n>       S;
        typename Transfer::Location location;
        // On a uniform patch of exact boxes: the corners' cells
        // arithmetically (the same bits).
        if (allow_closed_form && own.uniform_patch)
          {
            UniformCpdiPatch<dim> patch;
            patch.reinit(transfer, cell_index);
            constexpr unsigned int size =
              UniformCpdiPatch<dim>::max_support_size;
            std::array<unsigned int, size>   node;
            std::array<double, size>         S_p;
            std::array<Tensor<1, dim>, size> G_p;
            const unsigned int               count = patch.applies() ?
                                                       patch.support(transfer,
                                                       x,
                                                       F,
                                                       l0,
                                                       cpdi_critical_radius,
                                                       node.data(),
                                                       S_p.data(),
                                                       G_p.data()) :
                                                       0;
            for (unsigned int e = 0; e < count; ++e)
              for (const unsigned int other : transfer.patch(cell_index))
                {
                  const auto &cell = transfer.cell_data(other);
                  const auto  i    = std::find(cell.local_index.begin(),
                                           cell.local_index.end(),
                                           node[e]);
                  if (i != cell.local_index.end())
                    {
                      support.push_back(Node<dim>{
                        node[e],
                        transfer.dof_index(cell, i - cell.local_index.begin()),
                        false,
                        S_p[e],
                        G_p[e]});
                      break;
                    }
                }
            if (count > 0)
              return Status::ok;
          }
        // Corners x_α = x_p + s r_α, s = F diag(l⁰) (seed 001 Eq. cpdi):
        // S̄ = mean_α S_g(x_α), Ḡ = 2^-dim s⁻ᵀ Σ_α r_α S_g(x_α).
        Tensor<2, dim> s;
        for (unsigned int c = 0; c < dim; ++c)
          for (unsigned int j = 0; j < dim; ++j)
            s[c][j] = F[c][j] * l0[j];
        if (cpdi_critical_radius > 0)
          {
            double h = std::numeric_limits<double>::max();
            for (unsigned int d = 0; d < dim; ++d)
              h = std::min(h, own.upper()[d] - own.lower()[d]);
            limit_cpdi_domain(s, cpdi_critical_radius * h);
          }
        const Tensor<2, dim> s_inverse_transpose = transpose(invert(s));
        const double         weight              = 1.0 / n; // 2^-dim
        unsigned int         hint                = cell_index;
        for (unsigned int alpha = 0; alpha < n; ++alpha)
          {
            Tensor<1, dim> r;
            for (unsigned int j = 0; j < dim; ++j)
              r[j] = ((alpha >> j) & 1) ? 1. : -1.;
            const Point<dim> corner = x + s * r;
            const auto       found =
              transfer.locate(cell_index, corner, hint, location);
            if (found != Transfer::LocateStatus::found)
              return found == Transfer::LocateStatus::outside_mesh ?
                       Status::outside_mesh :
                       Status::beyond_neighbors;
            hint             = location.cell;
            const auto &cell = transfer.cell_data(location.cell);
            Transfer::values(location.xi, S);
            const Tensor<1, dim> w = weight * (s_inverse_transpose * r);
            for (unsigned int i = 0; i < n; ++i)
              add_node<dim>(
                support, transfer, cell, i, weight * S[i], S[i] * w);
          }
        return Status::ok;
      }
    } // namespace



    template <int dim>
    Status
    compute_support(const Type               type,
                    const GridTransfer<dim> &transfer,
                    const unsigned int       cell_index,
                    const Point<dim>        &x,
                    const Tensor<2, dim>    &F,
                    const Tensor<1, dim>    &l0,
                    std::vector<Node<dim>>  &support,
                    const bool               allow_closed_form,
                    const double             cpdi_critical_radius)
    {
      using Transfer             = GridTransfer<dim>;
      constexpr unsigned int n   = Transfer::n_nodes;
      const auto            &own = transfer.cell_data(cell_index);
      support.clear();
      std::array<double, n>         S;
      std::array<Tensor<1, dim>, n> G;
      typename Transfer::Location   location;

      auto status_of = [](const typename Transfer::LocateStatus s) {
        return s == Transfer::LocateStatus::outside_mesh ?
                 Status::outside_mesh :
                 Status::beyond_neighbors;
      };

      switch (type)
        {
          case Type::classic:
            {
              const auto s =
                transfer.locate(cell_index, x, cell_index, location);
              if (s != Transfer::LocateStatus::found)
                return status_of(s);
              const auto &cell = transfer.cell_data(location.cell);
              Transfer::values_and_gradients(cell, location.xi, S, G);
              for (unsigned int i = 0; i < n; ++i)
                add_node<dim>(support, transfer, cell, i, S[i], G[i]);
              return Status::ok;
            }

          case Type::cpdi:
            return cpdi_support(transfer,
                                cell_index,
                                x,
                                F,
                                l0,
                                support,
                                allow_closed_form,
                                cpdi_critical_radius);

          case Type::ugimp:
          case Type::cpgimp:
            {
              const Tensor<1, dim> l  = gimp_half_lengths<dim>(type, F, l0);
              Point<dim>           lo = x, hi = x;
              double               volume = 1;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  lo[d] -= l[d];
                  hi[d] += l[d];
                  volume *= 2 * l[d];
                }
              const bool closed_form = allow_closed_form && own.uniform_patch;
              UniformGimpPatch<dim> patch;
              if (closed_form)
                patch.reinit(transfer, cell_index);
              if (closed_form && patch.applies(x, l))
                {
                  patch.for_each_node(x,
                                      l,
                                      [&](const unsigned int local_index,
                                          const types::global_dof_index dof,
                                          const double                  S,
                                          const Tensor<1, dim>         &G) {
                                        support.push_back(Node<dim>{
                                          local_index, dof, false, S, G});
                                      });
                  return Status::ok;
                }
              GimpQuadrature<dim> quadrature(transfer,
                                             cell_index,
                                             1.0 / volume,
                                             support);
              quadrature.integrate(lo, hi, 0, 0);
              return quadrature.status;
            }

          case Type::b2spline:
          case Type::b3spline:
          case Type::b2gimp:
          case Type::b2cpdi:
            Assert(false,
                   ExcMessage("B-spline supports are built on their lattice "
                              "(ShapeFunction::BSplineSupports)."));
            break;
        }
      return Status::ok;
    }



    template <int dim>
    void
    UniformPatchPlanes<dim>::reinit(const GridTransfer<dim> &transfer,
                                    const unsigned int       cell_index)
    {
      const auto &own = transfer.cell_data(cell_index);
      for (unsigned int d = 0; d < dim; ++d)
        {
          h[d]        = own.upper()[d] - own.lower()[d];
          plane[d][0] = own.lower()[d] - h[d];
          plane[d][1] = own.lower()[d];
          plane[d][2] = own.upper()[d];
          plane[d][3] = own.upper()[d] + h[d];
        }
      local_index.fill(numbers::invalid_unsigned_int);
      has_cell.fill(false);
      Assert(own.uniform_patch,
             ExcMessage("UniformPatchPlanes needs a uniform patch."));
      for (const unsigned int other : transfer.patch(cell_index))
        {
          const auto  &cell   = transfer.cell_data(other);
          unsigned int column = 0, stride = 1;
          for (unsigned int d = 0; d < dim; ++d, stride *= 3)
            {
              const double centre = 0.5 * (cell.lower()[d] + cell.upper()[d]);
              column += stride * (centre < own.lower()[d] ? 0 :
                                  centre < own.upper()[d] ? 1 :
                                                            2);
            }
          has_cell[column] = true;
          // Each vertex's planes from its coordinates (any vertex order).
          for (unsigned int i = 0; i < GridTransfer<dim>::n_nodes; ++i)
            {
              unsigned int slot = 0;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const double       v = cell.vertex[i][d];
                  const unsigned int p = v < own.lower()[d] - 0.5 * h[d] ? 0 :
                                         v < own.lower()[d] + 0.5 * h[d] ? 1 :
                                         v < own.upper()[d] + 0.5 * h[d] ? 2 :
                                                                           3;
                  plane[d][p]          = v;
                  slot |= p << (2 * d);
                }
              local_index[slot] = cell.local_index[i];
              dof[slot]         = transfer.dof_index(cell, i);
            }
        }
    }



    template <int dim>
    bool
    UniformGimpPatch<dim>::applies(const Point<dim>     &x,
                                   const Tensor<1, dim> &l) const
    {
      unsigned int first[dim], last[dim];
      return columns_if_applies(x, l, first, last);
    }



    template <int dim>
    void
    UniformCpdiPatch<dim>::reinit(const GridTransfer<dim> &transfer,
                                  const unsigned int       cell_index)
    {
      const auto &own = transfer.cell_data(cell_index);
      Assert(own.uniform_patch,
             ExcMessage("UniformCpdiPatch needs a uniform patch."));
      // compute_support()'s h of the critical radius.
      smallest_extent = std::numeric_limits<double>::max();
      for (unsigned int d = 0; d < dim; ++d)
        smallest_extent =
          std::min(smallest_extent, own.upper()[d] - own.lower()[d]);
      double h[dim];
      for (unsigned int d = 0; d < dim; ++d)
        {
          h[d]               = own.upper()[d] - own.lower()[d];
          inverse_spacing[d] = 1. / h[d];
          plane[d][0]        = own.lower()[d] - h[d];
          plane[d][1]        = own.lower()[d];
          plane[d][2]        = own.upper()[d];
          plane[d][3]        = own.upper()[d] + h[d];
        }
      // The plane of each vertex coordinate (any vertex order).
      auto plane_of = [&](const double v, const unsigned int d) {
        return v < own.lower()[d] - 0.5 * h[d] ? 0u :
               v < own.lower()[d] + 0.5 * h[d] ? 1u :
               v < own.upper()[d] + 0.5 * h[d] ? 2u :
                                                 3u;
      };
      const auto &patch = transfer.patch(cell_index);
      for (const unsigned int other : patch)
        for (unsigned int i = 0; i < n_nodes; ++i)
          for (unsigned int d = 0; d < dim; ++d)
            {
              const double v           = transfer.cell_data(other).vertex[i][d];
              plane[d][plane_of(v, d)] = v;
            }

      has_cell.fill(false);
      this->cell_index.fill(numbers::invalid_unsigned_int);
      exact = true;
      for (const unsigned int other : patch)
        {
          const auto  &data   = transfer.cell_data(other);
          unsigned int column = 0, stride = 1;
          for (unsigned int d = 0; d < dim; ++d, stride *= 3)
            {
              const double centre = 0.5 * (data.lower()[d] + data.upper()[d]);
              column += stride * (centre < own.lower()[d] ? 0 :
                                  centre < own.upper()[d] ? 1 :
                                                            2);
            }
          has_cell[column]         = true;
          this->cell_index[column] = other;
          ColumnCell &column_cell  = cell[column];
          // ξ = diag(1/h) (x − x_lower) with the bits of
          // GridTransfer::reference_point(): the inverse Jacobian has no
          // off-diagonal entry and vertex 0 lies on the lower planes.
          unsigned int c = column;
          for (unsigned int d = 0; d < dim; ++d, c /= 3)
            {
              column_cell.inverse_extent[d] =
                data.inverse_jacobian_transpose[d][d];
              exact = exact && data.inverse_jacobian_transpose[d][d] > 0 &&
                      data.vertex[0][d] == plane[d][c % 3];
              for (unsigned int e = 0; e < dim; ++e)
                if (e != d)
                  exact = exact && data.inverse_jacobian_transpose[d][e] == 0;
            }
          for (unsigned int i = 0; i < n_nodes; ++i)
            {
              unsigned int slot = 0;
              for (unsigned int d = 0; d < dim; ++d)
                slot |= plane_of(data.vertex[i][d], d) << (2 * d);
              column_cell.local_index[i] = data.local_index[i];
              column_cell.slot[i]        = slot;
            }
        }
      exact = exact && own.uniform_patch;
    }



    template <int dim>
    bool
    UniformCpdiPatch<dim>::locate_in_general(const GridTransfer<dim> &transfer,
                                             const Point<dim>        &corner,
                                             const unsigned int       hint,
                                             unsigned int            &column,
                                             Point<dim>              &xi) const
    {
      typename GridTransfer<dim>::Location location;
      if (transfer.locate(cell_index[own_column],
                          corner,
                          cell_index[hint],
                          location) != GridTransfer<dim>::LocateStatus::found)
        return false;
      for (unsigned int c = 0; c < n_columns; ++c)
        if (has_cell[c] && cell_index[c] == location.cell)
          {
            column = c;
            xi     = location.xi;
            return true;
          }
      return false;
    }



    template class UniformCpdiPatch<2>;
    template class UniformCpdiPatch<3>;
    template struct UniformPatchPlanes<2>;
    template struct UniformPatchPlanes<3>;
    template class UniformGimpPatch<2>;
    template class UniformGimpPatch<3>;

    template Tensor<1, 2>
    gimp_half_lengths<2>(const Type,
                         const Tensor<2, 2> &,
                         const Tensor<1, 2> &);
    template Tensor<1, 3>
    gimp_half_lengths<3>(const Type,
                         const Tensor<2, 3> &,
                         const Tensor<1, 3> &);
    template Status
    compute_support<2>(const Type,
                       const GridTransfer<2> &,
                       const unsigned int,
                       const Point<2> &,
                       const Tensor<2, 2> &,
                       const Tensor<1, 2> &,
                       std::vector<Node<2>> &,
                       const bool,
                       const double);
    template bool
    limit_cpdi_domain<2>(Tensor<2, 2> &, const double);
    template Status
    compute_support<3>(const Type,
                       const GridTransfer<3> &,
                       const unsigned int,
                       const Point<3> &,
                       const Tensor<2, 3> &,
                       const Tensor<1, 3> &,
                       std::vector<Node<3>> &,
                       const bool,
                       const double);
    template bool
    limit_cpdi_domain<3>(Tensor<2, 3> &, const double);
  } // namespace ShapeFunction
} // namespace fmpm
