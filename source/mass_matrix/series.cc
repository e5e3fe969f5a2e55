// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/interface.h>
#include <fmpm/mass_matrix/series.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

namespace fmpm
{
  namespace MassMatrix
  {
    namespace
    {
      /**
       * z += m⁻¹(q − m̃z) on nodes [begin, end), except where @p held
       * (nonzero; or nullptr): two nodes per DoublePair, the same
       * operations per node as one at a time.
       */
      void
      add_series_increments(const unsigned int  begin,
                            const unsigned int  end,
                            double *const       z,
                            const double *const q,
                            const double *const m_tilde_z,
                            const double *const m,
                            const double *const held)
      {
        unsigned int i = begin;
        for (; i + 2 <= end; i += 2)
          {
            const DoublePair z_old = load_pair(z + i);
            DoublePair       z_new =
              z_old +
              (load_pair(q + i) - load_pair(m_tilde_z + i)) / load_pair(m + i);
            if (held)
              where(load_pair(held + i) != 0., z_new) = z_old;
            store_pair(z + i, z_new);
          }
        for (; i < end; ++i)
          if (!(held && held[i] != 0))
            z[i] += (q[i] - m_tilde_z[i]) / m[i];
      }
    } // namespace



    unsigned int
    fmpm_series(const FullMassProduct                &product,
                const std::vector<SeriesField>       &fields,
                const std::vector<GridVectorField *> &products,
                const unsigned int                    k,
                const double                          mass_floor,
                const double                          tolerance,
                const SeriesHooks                    &hooks)
    {
      std::vector<GridVectorField *> z;
      for (const SeriesField &field : fields)
        z.push_back(field.velocity);
      // The runs [begin, end) of owned nodes with m > the floor, the only
      // ones a sweep changes: on a grid mostly without points each sweep
      // then reads a fraction of the vectors.
      std::vector<std::vector<std::pair<unsigned int, unsigned int>>> runs(
        fields.size());
      for (unsigned int f = 0; f < fields.size(); ++f)
        {
          const GridScalar   &m       = *fields[f].mass;
          const unsigned int  n_owned = m.locally_owned_size();
          const double *const m_i     = m.begin();
          for (unsigned int i = 0; i < n_owned;)
            {
              while (i < n_owned && !(m_i[i] > mass_floor))
                ++i;
              const unsigned int begin = i;
              while (i < n_owned && m_i[i] > mass_floor)
                ++i;
              if (i > begin)
                runs[f].emplace_back(begin, i);
            }
        }
      // ‖z₁‖² for the adaptive order's test.
      double z1_squared = 0;
      if (tolerance > 0)
        for (const GridVectorField *z_f : z)
          z1_squared += z_f->norm_sqr();
      for (unsigned int j = 1; j < k; ++j)
        {
          product(z, products);
          if (hooks.before_update)
            hooks.before_update(j);
          // z_{j+1} = z_j + m⁻¹ (q − m̃ z_j)
          double increment_squared = 0;
          for (unsigned int f = 0; f < fields.size(); ++f)
            {
              const SeriesField &field = fields[f];
              for (unsigned int b = 0; b < z[f]->n_blocks(); ++b)
                {
                  double *const       zb = z[f]->block(b).begin();
                  const double *const qb = field.rhs->block(b).begin();
                  const double *const mz = products[f]->block(b).begin();
                  const double *const held =
                    field.held ? (*field.held)[b].begin() : nullptr;
                  const double *const m_i = field.mass->begin();
                  const double *const untested =
                    field.untested ? field.untested->begin() : nullptr;
                  if (tolerance == 0)
                    {
                      for (const auto &[begin, end] : runs[f])
                        add_series_increments(
                          begin, end, zb, qb, mz, m_i, held);
                      continue;
                    }
                  for (const auto &[begin, end] : runs[f])
                    for (unsigned int i = begin; i < end; ++i)
                      if (!(held && held[i] != 0))
                        {
                          const double dz = (qb[i] - mz[i]) / m_i[i];
                          zb[i] += dz;
                          if (!(untested && untested[i] != 0))
                            increment_squared += dz * dz;
                        }
                }
            }
          if (hooks.after_update)
            hooks.after_update(j);
          if (tolerance > 0 &&
              Utilities::MPI::sum(increment_squared,
                                  fields[0].mass->get_mpi_communicator()) <=
                tolerance * tolerance * z1_squared)
            return j + 1;
        }
      return k;
    }
  } // namespace MassMatrix
} // namespace fmpm
