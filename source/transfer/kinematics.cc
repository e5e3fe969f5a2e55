// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/transfer/kinematics.h>

#include <deal.II/base/symmetric_tensor.h>

#include <algorithm>
#include <cmath>

namespace fmpm
{
  namespace Kinematics
  {
    template <int n>
    void
    increments(const DeformationGradientUpdate update,
               const MethodParameters         &method,
               const BatchEntries             &L,
               const double                    dt,
               const unsigned int              n_points,
               BatchEntries                   &dF)
    {
      if (update == DeformationGradientUpdate::first_order)
        {
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < n; ++b)
              for (unsigned int q = 0; q < n_points; ++q)
                dF[3 * a + b][q] = (a == b ? 1.0 : 0.0) + L[3 * a + b][q] * dt;
          return;
        }
      Assert(update != DeformationGradientUpdate::cayley,
             ExcMessage("Cayley: cayley_update()."));
      const Tensor<2, n> I = unit_symmetric_tensor<n>();
      for (unsigned int q = 0; q < n_points; ++q)
        {
          Tensor<2, n> L_dt;
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < n; ++b)
              L_dt[a][b] = L[3 * a + b][q] * dt;
          Tensor<2, n> increment;
          if (update == DeformationGradientUpdate::taylor)
            {
              Tensor<2, n> term = I;
              increment         = I;
              for (unsigned int k = 1; k <= method.taylor_terms; ++k)
                {
                  term = term * L_dt / static_cast<double>(k);
                  increment += term;
                }
            }
          else
            {
              // Subcycles: first-order substeps with |L Δt_sub| below the
              // bound.
              const unsigned int n_sub =
                std::max(1u,
                         static_cast<unsigned int>(std::ceil(
                           L_dt.norm() / method.subcycle_strain_increment)));
              const Tensor<2, n> step = I + L_dt / static_cast<double>(n_sub);
              increment               = I;
              for (unsigned int k = 0; k < n_sub; ++k)
                increment = step * increment;
            }
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < n; ++b)
              dF[3 * a + b][q] = increment[a][b];
        }
    }



    template void
    increments<2>(const DeformationGradientUpdate,
                  const MethodParameters &,
                  const BatchEntries &,
                  const double,
                  const unsigned int,
                  BatchEntries &);
    template void
    increments<3>(const DeformationGradientUpdate,
                  const MethodParameters &,
                  const BatchEntries &,
                  const double,
                  const unsigned int,
                  BatchEntries &);
  } // namespace Kinematics
} // namespace fmpm
