// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_contact_h
#define fmpm_contact_h

// Multimaterial contact (seed 004 §2-3, seed 000 Ch. 3): the settings, the
// contact laws and normal methods (plugin systems) and the manager of the
// per-material fields.
#include <fmpm/contact/laws.h>
#include <fmpm/contact/manager.h>
#include <fmpm/contact/normals.h>
#include <fmpm/contact/parameters.h>

#endif
