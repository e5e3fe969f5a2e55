// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/particle_update/pic_midpoint.h>

namespace fmpm
{
  namespace ParticleUpdate
  {
    FMPM_REGISTER_PARTICLE_UPDATE(
      PicMidpoint,
      "pic midpoint",
      "PIC with the midpoint position update of [Nairn2018-extrap] Eq. 1.67 (second "
      "form): V = v_p, X += (V(n) + V(n+1)) dt/2; the same update as 'fmpm'. "
      "(Modified PIC #1 of [Nairn2018-extrap], Eqs. 1.73-1.74, is 'pic'.)")
  } // namespace ParticleUpdate
} // namespace fmpm
