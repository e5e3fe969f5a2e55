// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/bspline.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <cmath>
#include <sstream>

namespace fmpm
{
  namespace BSpline
  {
    Boundary
    parse_boundary(const std::string &name)
    {
      if (name == "padding")
        return Boundary::padding;
      if (name == "open knots")
        return Boundary::open_knots;
      AssertThrow(false,
                  ExcMessage("B-spline boundary <" + name + "> is not one of " +
                             boundary_pattern() + "."));
      return Boundary::padding;
    }



    Basis1D::Basis1D(const unsigned int degree,
                     const double       lower,
                     const double       h,
                     const unsigned int n_cells,
                     const Boundary     boundary)
      : p(degree)
      , lower(lower)
      , h(h)
      , inverse_h(1. / h)
      , n(n_cells)
      , boundary_treatment(boundary)
      , shift(0.5 * (degree + 1))
      , first_span(boundary == Boundary::open_knots ?
                     static_cast<int>(std::floor(shift)) :
                     static_cast<int>(degree))
      , last_span(boundary == Boundary::open_knots ?
                    static_cast<int>(std::ceil(n_cells + shift)) - 1 :
                    static_cast<int>(n_cells))
    {
      AssertThrow(degree >= 1 && degree <= max_degree,
                  ExcMessage("B-spline degree " + std::to_string(degree) +
                             " is not 1, 2 or 3."));
      AssertThrow(h > 0, ExcMessage("B-spline lattice: cell size <= 0."));
      // Open knots: the two ends' modified functions must not overlap;
      // padding: a cell between the two padding layers.
      const unsigned int fewest = fewest_cells(degree, boundary);
      AssertThrow(n_cells >= fewest,
                  ExcMessage("B-splines of degree " + std::to_string(degree) +
                             " need at least " + std::to_string(fewest) +
                             " cells per direction, not " +
                             std::to_string(n_cells) + "."));
      // Open knots: each span's functions as polynomials in u = t − u_j,
      // from their values at p + 1 points of the span (exact: they are of
      // degree p there), for averages_by_polynomials().
      if (boundary == Boundary::open_knots)
        {
          span_polynomials.resize(last_span - first_span + 1);
          for (int j = first_span; j <= last_span; ++j)
            {
              SpanPolynomials &span  = span_polynomials[j - first_span];
              const double     width = knot(j + 1) - knot(j);
              if (!(width > 0))
                continue;
              double       values[max_degree + 1][max_nodes];
              double       u[max_degree + 1];
              double       dS[max_nodes];
              int          first = 0;
              unsigned int count = 0;
              for (unsigned int m = 0; m <= p; ++m)
                {
                  u[m] = width * m / p;
                  int          first_m;
                  unsigned int count_m;
                  span_values_with_knots(j,
                                         knot(j) + u[m],
                                         OwnKnots{this},
                                         first_m,
                                         count_m,
                                         values[m],
                                         dS);
                  AssertThrow(m == 0 || (first_m == first && count_m == count),
                              ExcInternalError());
                  first = first_m;
                  count = count_m;
                }
              span.first = first;
              span.count = count;
              // Newton's divided differences on u_0 ... u_p, then the
              // Newton form expanded into powers of u.
              for (unsigned int k = 0; k < count; ++k)
                {
                  double d[max_degree + 1];
                  for (unsigned int m = 0; m <= p; ++m)
                    d[m] = values[m][k];
                  for (unsigned int level = 1; level <= p; ++level)
                    for (unsigned int m = p; m >= level; --m)
                      d[m] = (d[m] - d[m - 1]) / (u[m] - u[m - level]);
                  // c(u) = d_p; c ← c (u − u_m) + d_m for m = p − 1 ... 0.
                  double c[max_degree + 1] = {};
                  c[0]                     = d[p];
                  for (int m = static_cast<int>(p) - 1; m >= 0; --m)
                    {
                      for (int q = static_cast<int>(p); q >= 1; --q)
                        c[q] = c[q - 1] - u[m] * c[q];
                      c[0] = d[m] - u[m] * c[0];
                    }
                  for (unsigned int q = 0; q <= p; ++q)
                    span.coefficient[k][q] = c[q];
                }
            }
        }
    }



    template <int dim>
    Lattice<dim>::Lattice(const Point<dim>                    &lower,
                          const Point<dim>                    &upper,
                          const std::array<unsigned int, dim> &n_cells,
                          const unsigned int                   degree,
                          const Boundary                       boundary)
    {
      // (Too few cells in a direction for the degree: the linear basis.)
      for (unsigned int d = 0; d < dim; ++d)
        bases[d] =
          Basis1D(n_cells[d] >= Basis1D::fewest_cells(degree, boundary) ?
                    degree :
                    1,
                  lower[d],
                  (upper[d] - lower[d]) / n_cells[d],
                  n_cells[d],
                  boundary);
    }



    template <int dim>
    Lattice<dim>
    Lattice<dim>::of_mesh(const GridTransfer<dim> &transfer,
                          const unsigned int       n_active_cells,
                          const unsigned int       degree,
                          const Boundary           boundary,
                          const MPI_Comm           communicator,
                          std::string             &error)
    {
      error.clear();
      // The size and box of the cached cells, combined over the ranks.
      std::vector<double> lowest(dim, std::numeric_limits<double>::max()),
        highest_negated(dim, std::numeric_limits<double>::max()), size(dim, 0);
      std::ostringstream message;
      bool               is_box_lattice = true;
      for (unsigned int c = 0; c < n_active_cells; ++c)
        if (transfer.has_cell_data(c))
          {
            const auto &cell = transfer.cell_data(c);
            if (!cell.is_axis_aligned || cell.has_constraints)
              {
                if (is_box_lattice)
                  message << "a cell at " << cell.lower() << " is "
                          << (cell.has_constraints ? "next to a hanging node" :
                                                     "not an axis-aligned box");
                is_box_lattice = false;
                continue;
              }
            for (unsigned int d = 0; d < dim; ++d)
              {
                lowest[d] = std::min(lowest[d], cell.lower()[d]);
                highest_negated[d] =
                  std::min(highest_negated[d], -cell.upper()[d]);
                size[d] = std::max(size[d], cell.upper()[d] - cell.lower()[d]);
              }
          }
      std::vector<double> combined(3 * dim);
      for (unsigned int d = 0; d < dim; ++d)
        {
          combined[d]           = lowest[d];
          combined[dim + d]     = highest_negated[d];
          combined[2 * dim + d] = -size[d];
        }
      Utilities::MPI::min(combined, communicator, combined);
      Point<dim>                    lower, upper;
      std::array<unsigned int, dim> n_cells;
      for (unsigned int d = 0; d < dim; ++d)
        {
          lower[d]   = combined[d];
          upper[d]   = -combined[dim + d];
          size[d]    = -combined[2 * dim + d];
          n_cells[d] = static_cast<unsigned int>(
            std::round((upper[d] - lower[d]) / size[d]));
        }
      // Every cell of the lattice's size and on it.
      for (unsigned int c = 0; c < n_active_cells && is_box_lattice; ++c)
        if (transfer.has_cell_data(c))
          {
            const auto &cell = transfer.cell_data(c);
            for (unsigned int d = 0; d < dim && is_box_lattice; ++d)
              {
                const double h      = (upper[d] - lower[d]) / n_cells[d];
                const double extent = cell.upper()[d] - cell.lower()[d];
                const double t      = (cell.lower()[d] - lower[d]) / h;
                if (std::abs(extent - h) > 1e-10 * h ||
                    std::abs(t - std::round(t)) > 1e-10 * (1 + std::abs(t)))
                  {
                    message << "the cell at " << cell.lower()
                            << " is not a cell of the lattice of " << n_cells[d]
                            << " cells of size " << h << " in direction " << d;
                    is_box_lattice = false;
                  }
              }
          }
      const bool all_box_lattice =
        Utilities::MPI::min(is_box_lattice ? 1u : 0u, communicator) == 1u;
      if (!all_box_lattice)
        {
          error = "B-spline shape functions need a mesh of equal axis-aligned "
                  "boxes without hanging nodes (a subdivided box, no "
                  "adaptive, graded or distorted mesh)";
          if (!is_box_lattice)
            error += ": " + message.str();
          return Lattice();
        }
      return Lattice(lower, upper, n_cells, degree, boundary);
    }



    template <int dim>
    void
    VertexMap<dim>::reinit(const Lattice<dim>      &lattice,
                           const GridTransfer<dim> &transfer,
                           const unsigned int       n_active_cells)
    {
      // The lattice index of a coordinate (a vertex: exact to round-off).
      auto index_of = [&](const double x, const unsigned int d) {
        const Basis1D &basis = lattice.basis(d);
        return static_cast<int>(
          std::round((x - basis.vertex(0)) / basis.cell_size()));
      };
      int last[dim];
      for (unsigned int d = 0; d < dim; ++d)
        {
          first[d] = std::numeric_limits<int>::max();
          last[d]  = std::numeric_limits<int>::min();
        }
      for (unsigned int c = 0; c < n_active_cells; ++c)
        if (transfer.has_cell_data(c))
          {
            const auto &cell = transfer.cell_data(c);
            for (unsigned int d = 0; d < dim; ++d)
              {
                first[d] = std::min(first[d], index_of(cell.lower()[d], d));
                last[d]  = std::max(last[d], index_of(cell.upper()[d], d));
              }
          }
      std::size_t size = 1;
      for (unsigned int d = 0; d < dim; ++d)
        {
          if (last[d] < first[d])
            {
              first[d] = 0;
              last[d]  = -1;
            }
          count[d] = last[d] - first[d] + 1;
          size *= count[d];
        }
      local.assign(size, numbers::invalid_unsigned_int);
      for (unsigned int c = 0; c < n_active_cells; ++c)
        if (transfer.has_cell_data(c))
          {
            const auto &cell = transfer.cell_data(c);
            // Vertex i of a box: lower or upper in direction d by bit d.
            for (unsigned int i = 0; i < GridTransfer<dim>::n_nodes; ++i)
              {
                std::size_t e = 0, stride = 1;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    const double x =
                      ((i >> d) & 1) ? cell.upper()[d] : cell.lower()[d];
                    e += stride * (index_of(x, d) - first[d]);
                    stride *= count[d];
                  }
                local[e] = cell.local_index[i];
              }
          }
    }



    template class Lattice<2>;
    template class Lattice<3>;
    template class VertexMap<2>;
    template class VertexMap<3>;
  } // namespace BSpline
} // namespace fmpm
