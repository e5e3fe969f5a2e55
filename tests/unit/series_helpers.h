// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// v = m̃ₖ⁻¹p of one field for the unit tests: the start v₁ = m⁻¹p and
// MassMatrix::fmpm_series(), as the FMPM(k) mass matrix composes them.

#ifndef fmpm_tests_series_helpers_h
#define fmpm_tests_series_helpers_h

#include <fmpm/grid_vectors.h>
#include <fmpm/mass_matrix/interface.h>
#include <fmpm/mass_matrix/series.h>

#include <vector>

namespace fmpm_tests
{
  /**
   * v = m̃ₖ⁻¹ p (seed 000 Eqs. 1.22-1.23) from v₁ = m⁻¹p; the components
   * where @p held is nonzero keep @p known_values (zero if nullptr).
   * @return the order used
   */
  template <typename MatrixType>
  unsigned int
  fmpm_inverse(const MatrixType                    &m_tilde,
               const fmpm::GridScalar              &m,
               const fmpm::GridVectorField         &p,
               fmpm::GridVectorField               &v,
               const unsigned int                   k,
               const double                         mass_floor,
               const std::vector<fmpm::GridScalar> *held         = nullptr,
               const std::vector<fmpm::GridScalar> *known_values = nullptr,
               const double                         tolerance    = 0)
  {
    using namespace fmpm::MassMatrix;
    apply_lumped_inverse(m, p, v, mass_floor);
    if (held)
      for (unsigned int b = 0; b < p.n_blocks(); ++b)
        for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
          if ((*held)[b].local_element(i) != 0)
            v.block(b).local_element(i) =
              known_values ? (*known_values)[b].local_element(i) : 0.;
    if (k == 1)
      return 1;
    fmpm::GridVectorField m_tilde_v(v);
    return fmpm_series(
      [&m_tilde](const std::vector<fmpm::GridVectorField *> &in,
                 const std::vector<fmpm::GridVectorField *> &out) {
        apply_full_mass(m_tilde, *out[0], *in[0]);
      },
      {SeriesField{&m, &p, &v, held}},
      {&m_tilde_v},
      k,
      mass_floor,
      tolerance);
  }
} // namespace fmpm_tests

#endif
