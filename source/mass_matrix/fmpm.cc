// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/fmpm.h>
#include <fmpm/parameter_entries.h>
#include <fmpm/simulator.h>

#include <algorithm>
#include <cmath>


namespace fmpm
{
  namespace MassMatrix
  {
    namespace
    {
      /**
       * z += m⁻¹(q − m̃z) on nodes [begin, end), except where @p held
       * (nonzero; or nullptr): two nodes per two-lane vector (GCC/Clang
       * vector extension), the same operations per node as one at a time.
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
        typedef double    pair __attribute__((vector_size(16)));
        typedef long long mask __attribute__((vector_size(16)));
        const auto        load = [](const double *source) {
          pair value;
          __builtin_memcpy(&value, source, sizeof(pair));
          return value;
        };
        unsigned int i = begin;
        for (; i + 2 <= end; i += 2)
          {
            const pair z_old = load(z + i);
            pair       z_new =
              z_old + (load(q + i) - load(m_tilde_z + i)) / load(m + i);
            if (held)
              {
                const mask keep = load(held + i) == pair{0., 0.};
                z_new = (pair)(((mask)z_new & keep) | ((mask)z_old & ~keep));
              }
            __builtin_memcpy(z + i, &z_new, sizeof(pair));
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
                          if (tolerance > 0)
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



    template <typename MatrixType>
    unsigned int
    apply_fmpm_inverse(const MatrixType              &m_tilde,
                       const GridScalar              &m,
                       const GridVectorField         &p,
                       GridVectorField               &v,
                       const unsigned int             k,
                       const double                   mass_floor,
                       const std::vector<GridScalar> *zero_mask,
                       const std::vector<GridScalar> *known_values,
                       const double                   tolerance)
    {
      // v_1 = m⁻¹ p; known components hold their values in every sweep.
      apply_lumped_inverse(m, p, v, mass_floor);
      if (zero_mask)
        for (unsigned int b = 0; b < p.n_blocks(); ++b)
          for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
            if ((*zero_mask)[b].local_element(i) != 0)
              v.block(b).local_element(i) =
                known_values ? (*known_values)[b].local_element(i) : 0.;
      if (k == 1)
        return 1;
      GridVectorField m_tilde_v(v);
      return fmpm_series(
        [&m_tilde](const std::vector<GridVectorField *> &in,
                   const std::vector<GridVectorField *> &out) {
          apply_full_mass(m_tilde, *out[0], *in[0]);
        },
        {SeriesField{&m, &p, &v, zero_mask}},
        {&m_tilde_v},
        k,
        mass_floor,
        tolerance);
    }

    template unsigned int
    apply_fmpm_inverse(const TrilinosWrappers::SparseMatrix &,
                       const GridScalar &,
                       const GridVectorField &,
                       GridVectorField &,
                       const unsigned int,
                       const double,
                       const std::vector<GridScalar> *,
                       const std::vector<GridScalar> *,
                       const double);
    template unsigned int
    apply_fmpm_inverse(const CellwiseMatrix &,
                       const GridScalar &,
                       const GridVectorField &,
                       GridVectorField &,
                       const unsigned int,
                       const double,
                       const std::vector<GridScalar> *,
                       const std::vector<GridScalar> *,
                       const double);



    template <int dim>
    void
    Fmpm<dim>::declare_parameters(ParameterHandler &prm)
    {
      const Fmpm<dim> defaults;
      prm.declare_entry(
        "Order",
        std::to_string(defaults.k),
        Patterns::Integer(1, 1000),
        "The order k of the series m~_k^-1 ([Nairn2023-FMPM] Eq. "
        "1.23): 1 is the lumped mass matrix, larger k "
        "approaches the full mass matrix m~ = S^T M S. "
        "Units: none.");
      prm.declare_entry(
        "Increment tolerance",
        format_number(defaults.tolerance),
        Patterns::Double(0, 1),
        "Adaptive order: the series ends after the sweep whose increment "
        "Delta v(l) = v(l+1) - v(l) has an l2 norm over all nodes and "
        "components of at most this fraction of that of v(1) = m^-1 p, "
        "and at the latest after 'Order' terms. 0: always 'Order' terms "
        "(FMPM(k)). history.csv then reports the order used "
        "(fmpm_order_mean, fmpm_order_max over the solves since the "
        "previous output). Not with multimaterial contact (its series "
        "keeps the full order). Units: none.");
      prm.declare_entry(
        "Period",
        std::to_string(defaults.period),
        Patterns::Integer(1),
        "Periodic FMPM(k) (NairnMPM's periodic XPIC, Nairn 2026): the "
        "series and the configured particle update every 'Period' steps "
        "(the steps whose number is a multiple of it), FLIP with the "
        "lumped mass matrix in the steps between. 1: every step (FMPM(k)). "
        "Not with multimaterial contact. Units: steps.");
      prm.declare_entry(
        "Period time",
        format_number(defaults.period_time),
        Patterns::Double(0),
        "As 'Period', in simulated time: the series in the step that "
        "crosses each multiple of this time (and the first step); 0: use "
        "'Period'. Units: s.");
    }



    template <int dim>
    void
    Fmpm<dim>::parse_parameters(ParameterHandler &prm)
    {
      k           = prm.get_integer("Order");
      tolerance   = prm.get_double("Increment tolerance");
      period      = prm.get_integer("Period");
      period_time = prm.get_double("Period time");
    }



    template <int dim>
    bool
    Fmpm<dim>::begin_step(const unsigned int step,
                          const double       time,
                          const double       time_step)
    {
      if (period_time > 0)
        series_this_step =
          step == 0 || std::floor((time + time_step) / period_time) >
                         std::floor(time / period_time);
      else
        series_this_step = (step + 1) % period == 0;
      if (series_this_step)
        ++series_steps;
      return series_this_step;
    }



    template <int dim>
    void
    Fmpm<dim>::count(const unsigned int order_used) const
    {
      ++solves_since_output;
      ++solves;
      orders_since_output += order_used;
      orders += order_used;
      max_order_since_output = std::max(max_order_since_output, order_used);
      max_order              = std::max(max_order, order_used);
    }



    template <int dim>
    std::vector<std::string>
    Fmpm<dim>::history_columns() const
    {
      if (tolerance == 0)
        return {};
      return {"fmpm_order_mean", "fmpm_order_max"};
    }



    template <int dim>
    std::vector<double>
    Fmpm<dim>::history_values()
    {
      if (tolerance == 0)
        return {};
      const std::vector<double> values = {
        solves_since_output > 0 ?
          static_cast<double>(orders_since_output) / solves_since_output :
          0.,
        static_cast<double>(max_order_since_output)};
      solves_since_output = orders_since_output = 0;
      max_order_since_output                    = 0;
      return values;
    }



    template <int dim>
    std::map<std::string, double>
    Fmpm<dim>::statistics() const
    {
      std::map<std::string, double> result;
      if (tolerance > 0)
        {
          result["fmpm_order_mean"] =
            solves > 0 ? static_cast<double>(orders) / solves : 0.;
          result["fmpm_order_max"] = static_cast<double>(max_order);
        }
      if (periodic())
        result["fmpm_series_steps"] = static_cast<double>(series_steps);
      return result;
    }



    template <int dim>
    void
    Fmpm<dim>::solve(const GridVectorField &p, GridVectorField &v) const
    {
      const unsigned int order = series_this_step ? k : 1;
      const auto         apply = [&](const auto &m_tilde) {
        count(apply_fmpm_inverse(m_tilde,
                                 this->get_lumped_mass(),
                                 p,
                                 v,
                                 order,
                                 this->get_simulator().mass_floor(),
                                 &this->get_known_velocity_mask(),
                                 &this->get_known_velocity_values(),
                                 tolerance));
      };
      if (const CellwiseMatrix *cellwise =
            this->get_simulator().get_cellwise_full_mass_matrix())
        apply(*cellwise);
      else
        apply(this->get_full_mass_matrix());
    }



    template <int dim>
    void
    Fmpm<dim>::vmult(const GridVectorField &v, GridVectorField &p) const
    {
      // m̃ (the assembled full mass matrix) stands in for m̃_k, as seed 000
      // suggests for the unlumped boundary-condition methods.
      if (k == 1 || !series_this_step)
        {
          Interface<dim>::vmult(v, p);
          return;
        }
      if (const CellwiseMatrix *cellwise =
            this->get_simulator().get_cellwise_full_mass_matrix())
        apply_full_mass(*cellwise, p, v);
      else
        apply_full_mass(this->get_full_mass_matrix(), p, v);
    }

    template <int dim>
    StabilityLimit
    Fmpm<dim>::stability_limit(const StabilityMethod &method) const
    {
      using namespace Stability;
      if (k <= 1)
        return lumped_mass_matrix_limit();
      const bool        averaged    = method.strain_update.average;
      const std::string name        = "FMPM(" + std::to_string(k) + ")";
      const std::string strain_text = strain_update_text(method);
      const double      k_limit     = fmpm_order_limit(k, averaged);
      StabilityLimit    limit;
      if (k_limit > 0)
        {
          limit.max_courant = k_limit;
          limit.basis       = name + ", " + strain_text +
                        ": the vibrating bar's measured critical Courant "
                        "number";
        }
      else if (!method.lumped_strain_velocities &&
               smooth_for_high_orders(method))
        {
          limit.max_courant =
            std::min(fmpm_order_limit(10, averaged),
                     smooth_high_order_constant / std::sqrt(k));
          limit.basis = name + ", " + strain_text + ", shape function '" +
                        ShapeFunction::parameter_name(method.shape_function) +
                        "': the rigid rotation is stable at C = "
                        "1.18/sqrt(k) (k = 12 to 64), unstable at 0.3 "
                        "(k = 32)";
        }
      else
        {
          limit.max_courant = full_limit;
          limit.basis       = name + ", " + strain_text +
                        ": the rigid rotation is stable at C = 0.12, "
                        "unstable at 0.15";
          if (!method.lumped_strain_velocities &&
              high_order_constant / k < limit.max_courant)
            {
              limit.max_courant = high_order_constant / k;
              limit.basis =
                name + ", " + strain_text +
                ": the series amplifies near-null modes by up to k; "
                "the rigid rotation is stable at C = 2.56/k (k = 32), "
                "unstable at 3.2/k";
            }
        }
      if (periodic() && periodic_limit < limit.max_courant)
        {
          limit.max_courant = periodic_limit;
          limit.basis =
            "periodic " + name +
            ": the vibrating bar with period 5 is stable at C = 0.35, "
            "unstable at 0.4 (periods 3 and 10: at 0.5)";
        }
      limit_full_mass_method(limit, method, name, k, false);
      return limit;
    }

    FMPM_REGISTER_MASS_MATRIX(
      Fmpm,
      "fmpm",
      "FMPM(k): the approximate full mass matrix inverse m~_k^-1 of [Nairn2023-FMPM] "
      "Eq. 1.23 (= XPIC(k)), computed as k Jacobi-Richardson sweeps on the "
      "assembled m~ = S^T M S.")
  } // namespace MassMatrix
} // namespace fmpm
