// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_particle_update_pic_midpoint_h
#define fmpm_particle_update_pic_midpoint_h

#include <fmpm/particle_update/fmpm.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    /**
     * @brief PIC velocity update with the Lagrangian midpoint position update
     * of seed 003 Eq. 1.67 (second form): V = v_p, X += (V^(n) + V^(n+1))
     * Δt/2. This is the FMPM(k) update of seed 000 Eq. 2.26 written from the
     * PIC side, so the class is the same; the name exists so that studies can
     * follow seed 003's naming.
     *
     * @ingroup ParticleUpdates
     */
    template <int dim>
    class PicMidpoint : public Fmpm<dim>
    {};
  } // namespace ParticleUpdate
} // namespace fmpm

#endif
