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
      const unsigned int             order = series_this_step ? k : 1;
      const GridScalar              &m     = this->get_lumped_mass();
      const double                   floor = this->get_mass_floor();
      const std::vector<GridScalar> &known = this->get_known_velocity_mask();
      const std::vector<GridScalar> &known_values =
        this->get_known_velocity_values();
      // v₁ = m⁻¹p; known components hold their values in every sweep.
      apply_lumped_inverse(m, p, v, floor);
      for (unsigned int b = 0; b < p.n_blocks(); ++b)
        for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
          if (known[b].local_element(i) != 0)
            v.block(b).local_element(i) = known_values[b].local_element(i);
      // B-splines with a padding layer: the mirror v_pad = R v_mirror +
      // 2 (v_w · n̂) n̂ is a constraint on v like the known values, so it
      // is imposed on every iterate as they are held in every sweep: the
      // series then converges to m̃ v = p on the interior rows with the
      // padding nodes slaved to their mirrors (seed 000 Eqs. 1.22-1.23,
      // 2.51-2.53), and with k = 1 it is the lumped padding layer.
      const auto &mirror = this->get_padding_mirror();
      if (mirror)
        mirror(v);
      if (order == 1)
        {
          count(1);
          return;
        }
      const CellwiseMatrix *cellwise = this->get_cellwise_full_mass_matrix();
      GridVectorField       m_tilde_v(v);
      // The adaptive order tests the increments of the nodes the sweep
      // sets: a padding node's is overwritten by its mirror.
      GridScalar padding;
      if (tolerance > 0 && mirror)
        {
          padding.reinit(m);
          for (const unsigned int i :
               this->get_velocity_conditions().padding_node_indices())
            padding.local_element(i) = 1;
        }
      count(fmpm_series(
        [&](const std::vector<GridVectorField *> &in,
            const std::vector<GridVectorField *> &out) {
          if (cellwise)
            apply_full_mass(*cellwise, *out[0], *in[0]);
          else
            apply_full_mass(this->get_full_mass_matrix(), *out[0], *in[0]);
        },
        {SeriesField{
          &m, &p, &v, &known, tolerance > 0 && mirror ? &padding : nullptr}},
        {&m_tilde_v},
        order,
        floor,
        tolerance,
        mirror ? SeriesHooks{nullptr, [&](const unsigned int) { mirror(v); }} :
                 SeriesHooks{}));
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
            this->get_cellwise_full_mass_matrix())
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
      // USL- and USAVG- with the series' velocities: lower with some shape
      // functions.
      const double   shape_limit = method.lumped_strain_velocities ?
                                     std::numeric_limits<double>::infinity() :
                                     shape_order_limit(std::min(k, 10u),
                                                     method.shape_function,
                                                     method.bspline_padding,
                                                     method.strain_update);
      StabilityLimit limit;
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
      if (shape_limit < limit.max_courant)
        {
          limit.max_courant = shape_limit;
          limit.basis =
            name + ", " + strain_text + ", shape function '" +
            ShapeFunction::parameter_name(method.shape_function) + "'" +
            (method.bspline_padding ? " with a padding layer" : "") +
            ": the vibrating bar's measured critical Courant number";
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
