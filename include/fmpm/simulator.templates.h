// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_simulator_templates_h
#define fmpm_simulator_templates_h

// The member templates of Simulator<dim> that several of its source files
// instantiate.

#include <fmpm/simulator.h>

#include <sstream>

namespace fmpm
{
  template <int dim>
  template <typename... Text>
  void
  Simulator<dim>::report_point_failure(const unsigned int       k,
                                       const FailedPoint::Cause cause,
                                       const Text &...text)
  {
    if (!local_failure.empty())
      return;
    std::ostringstream message;
    switch (cause)
      {
        case FailedPoint::Cause::support_outside_patch:
          message << "the domain of ";
          break;
        case FailedPoint::Cause::velocity_not_finite:
          message << "velocity of ";
          break;
        case FailedPoint::Cause::stress_not_finite:
          message << "stress of ";
          break;
        default:
          break;
      }
    message << "material point " << points.id[k] << " at ("
            << points.position[k] << ") ";
    (message << ... << text);
    local_failure            = message.str();
    local_failed_point.cause = cause;
    local_failed_point.id    = points.id[k];
    for (unsigned int d = 0; d < dim; ++d)
      local_failed_point.position[d] = points.position[k][d];
  }
} // namespace fmpm

#endif
