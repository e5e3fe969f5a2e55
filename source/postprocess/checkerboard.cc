// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/postprocess/checkerboard.h>

#include <deal.II/base/symmetric_tensor.h>

namespace fmpm
{
  namespace Checkerboard
  {
    template <int dim>
    Sums
    cell_sums(const ArrayView<const Point<dim>> &x,
              const ArrayView<const double>     &mass,
              const ArrayView<const double>     &J)
    {
      Sums               sums;
      const unsigned int n      = x.size();
      double             mean_J = 0;
      Point<dim>         mean_x;
      for (unsigned int p = 0; p < n; ++p)
        {
          sums.mass += mass[p];
          mean_J += mass[p] * J[p];
          mean_x += mass[p] * x[p];
          sums.volume_change += mass[p] * (J[p] - 1) * (J[p] - 1);
        }
      if (n < dim + 2 || !(sums.mass > 0))
        return sums;
      mean_J /= sums.mass;
      mean_x /= sums.mass;
      // The mass-weighted least-squares slope: C b = Σ M (x − x̄)(J − J̄).
      SymmetricTensor<2, dim> C;
      Tensor<1, dim>          moment;
      for (unsigned int p = 0; p < n; ++p)
        {
          const Tensor<1, dim> dx = x[p] - mean_x;
          C += mass[p] * symmetrize(outer_product(dx, dx));
          moment += mass[p] * (J[p] - mean_J) * dx;
        }
      // Points on a line (plane) leave C singular: no fit, no residual.
      const double spread = trace(C) / dim;
      if (!(determinant(C) > 1e-8 * std::pow(spread, dim)))
        return sums;
      const Tensor<1, dim> b = invert(C) * moment;
      for (unsigned int p = 0; p < n; ++p)
        {
          const double r = J[p] - mean_J - b * (x[p] - mean_x);
          sums.residual += mass[p] * r * r;
        }
      return sums;
    }

    template Sums
    cell_sums<2>(const ArrayView<const Point<2>> &,
                 const ArrayView<const double> &,
                 const ArrayView<const double> &);
    template Sums
    cell_sums<3>(const ArrayView<const Point<3>> &,
                 const ArrayView<const double> &,
                 const ArrayView<const double> &);
  } // namespace Checkerboard
} // namespace fmpm
