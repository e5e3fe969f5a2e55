// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_point_csv_h
#define fmpm_postprocess_point_csv_h

#include <fmpm/postprocess/interface.h>

namespace fmpm
{
  namespace Postprocess
  {
    /**
     * @brief particles_NNNNN.csv of every output (Output/Write particle
     * csv): id, body, material, x, v, the Cauchy stress, pressure, J,
     * internal energy and plastic strain of every point, sorted by id, on
     * rank 0.
     */
    template <int dim>
    class PointCsv : public Interface<dim>
    {
    public:
      void
      execute(const GlobalStatistics<dim> &statistics) override;
    };
  } // namespace Postprocess
} // namespace fmpm

#endif
