// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The velocity conditions on the grid: imposed on the momenta, the
// corrections of the solved velocities and accelerations, and the known values
// the solves read (set-up, walls and nodes: velocity_conditions.cc).

#include <fmpm/function_parser.h>
#include <fmpm/velocity_conditions.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace fmpm
{
  namespace
  {
    /** A zero field with the layout of @p like. */
    GridVectorField
    zero_like(const GridVectorField &like)
    {
      GridVectorField result(like);
      result = 0;
      return result;
    }

    /** n̂ · (the field at the node of @p c). */
    template <int dim, class NodeCondition>
    double
    component(const GridVectorField &field, const NodeCondition &c)
    {
      double s = 0;
      for (unsigned int d = 0; d < dim; ++d)
        s += field.block(d).local_element(c.local_index) * c.normal[d];
      return s;
    }

    /** The field at the node of @p c += @p amount n̂. */
    template <int dim, class NodeCondition>
    void
    add_along(GridVectorField     &field,
              const NodeCondition &c,
              const double         amount)
    {
      for (unsigned int d = 0; d < dim; ++d)
        field.block(d).local_element(c.local_index) += amount * c.normal[d];
    }
  } // namespace



  template <int dim>
  bool
  VelocityConditions<dim>::solve_collection(const GridVectorField   &like,
                                            const Operators         &operators,
                                            const std::vector<bool> &active,
                                            const std::vector<double> &r,
                                            std::vector<double> &phi) const
  {
    const unsigned int n_local = conditions.size();
    unsigned int       offset  = 0;
    MPI_Exscan(&n_local, &offset, 1, MPI_UNSIGNED, MPI_SUM, mpi_communicator);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      offset = 0;
    const unsigned int n_total = Utilities::MPI::sum(n_local, mpi_communicator);
    std::vector<double> A(n_total * n_total, 0.), rhs(n_total, 0.);
    GridVectorField     unit = zero_like(like), column = zero_like(like);
    for (unsigned int c_global = 0; c_global < n_total; ++c_global)
      {
        unit            = 0;
        const bool mine = c_global >= offset && c_global < offset + n_local;
        if (mine)
          add_along<dim>(unit, conditions[c_global - offset], 1.);
        operators.solve(unit, column);
        for (unsigned int b = 0; b < n_local; ++b)
          A[(offset + b) * n_total + c_global] =
            active[b] ? component<dim>(column, conditions[b]) : 0.;
      }
    for (unsigned int b = 0; b < n_local; ++b)
      {
        rhs[offset + b] = r[b];
        if (!active[b]) // empty node: φ_b = 0
          A[(offset + b) * n_total + offset + b] = 1;
      }
    Utilities::MPI::sum(A, mpi_communicator, A);
    Utilities::MPI::sum(rhs, mpi_communicator, rhs);
    if (n_total > 0)
      {
        LAPACKFullMatrix<double> matrix(n_total, n_total);
        for (unsigned int i = 0; i < n_total; ++i)
          for (unsigned int j = 0; j < n_total; ++j)
            matrix(i, j) = A[i * n_total + j];
        Vector<double> solution(rhs.begin(), rhs.end());
        try
          {
            matrix.compute_lu_factorization();
            matrix.solve(solution);
            for (unsigned int b = 0; b < n_local; ++b)
              phi[b] = solution[offset + b];
            return true;
          }
        catch (const std::exception &)
          {
            ++const_cast<VelocityConditions *>(this)->n_collection_fallbacks;
          }
      }
    return false;
  }



  template <int dim>
  void
  VelocityConditions<dim>::impose_on_momenta(
    GridVectorField             &q,
    const double                 t,
    const Operators             &operators,
    std::vector<Tensor<1, dim>> *impulse) const
  {
    const GridScalar &m     = *operators.lumped_mass;
    const double      floor = operators.mass_floor;
    auto add_impulse        = [&](const NodeCondition &c, const double amount) {
      if (impulse)
        {
          (*impulse)[c.source] += amount * c.normal;
          add_condition_impulse(&c - conditions.data(), amount);
        }
    };
    const std::vector<double> &v_b       = values_at(t);
    const auto                 component = [](const GridVectorField &field,
                              const NodeCondition   &c) {
      return ::fmpm::component<dim>(field, c);
    };
    const auto add_along =
      [](GridVectorField &field, const NodeCondition &c, const double amount) {
        ::fmpm::add_along<dim>(field, c, amount);
      };

    switch (method)
      {
        case Method::velocity:
          return; // the velocities are corrected instead

        case Method::constrained:
        case Method::lumped:
          // Δp_j = (m_j v_b − p_j · n̂) n̂ (Eqs. 2.51-2.52).
          for (unsigned int b = 0; b < conditions.size(); ++b)
            {
              const auto  &c   = conditions[b];
              const double m_j = m.local_element(c.local_index);
              const double dp =
                (m_j > floor ? m_j * v_b[b] : 0.) - component(q, c);
              add_along(q, c, dp);
              add_impulse(c, dp);
            }
          break;

        case Method::unlumped_1:
        case Method::unlumped_2:
          {
            // Δv on the condition nodes: from the lumped velocities p/m
            // (#1, Eq. 2.55) or the full-mass velocities m̃ₖ⁻¹p (#2,
            // Eq. 2.56); then Δp = m̃ Δv (#1) or M Δv (#2).
            GridVectorField delta_v = zero_like(q);
            GridVectorField v;
            if (method == Method::unlumped_2)
              {
                v = zero_like(q);
                operators.solve(q, v);
              }
            for (unsigned int b = 0; b < conditions.size(); ++b)
              {
                const auto  &c   = conditions[b];
                const double m_j = m.local_element(c.local_index);
                if (!(m_j > floor))
                  continue;
                const double v_j = method == Method::unlumped_1 ?
                                     component(q, c) / m_j :
                                     component(v, c);
                const double dv  = v_b[b] - v_j;
                add_along(delta_v, c, dv);
                // Σ_i (m̃ Δv^(b))_i = m_j Δv (columns of m̃ sum to m).
                add_impulse(c, m_j * dv);
              }
            GridVectorField dp = zero_like(q);
            if (method == Method::unlumped_1)
              operators.full_mass(delta_v, dp);
            else
              operators.forward(delta_v, dp);
            q += dp;
            break;
          }

        case Method::collection_partial:
        case Method::collection_full:
          {
            // The velocity error of each condition with the full-mass
            // velocities, r_b = v_b − n̂_b · (m̃ₖ⁻¹q)_{j_b} (Eq. 2.47).
            GridVectorField v = zero_like(q);
            operators.solve(q, v);
            std::vector<double> r(conditions.size());
            std::vector<bool>   active(conditions.size());
            for (unsigned int b = 0; b < conditions.size(); ++b)
              {
                const auto &c = conditions[b];
                active[b]     = m.local_element(c.local_index) > floor;
                r[b]          = active[b] ? v_b[b] - component(v, c) : 0.;
              }
            std::vector<double> phi(conditions.size());
            bool                solved = false;
            if (method == Method::collection_full)
              solved = solve_collection(q, operators, active, r, phi);
            if (!solved) // partial: (m̃ₖ⁻¹)_ij → δ_ij / m_i
              for (unsigned int b = 0; b < conditions.size(); ++b)
                phi[b] = m.local_element(conditions[b].local_index) * r[b];
            for (unsigned int b = 0; b < conditions.size(); ++b)
              {
                add_along(q, conditions[b], phi[b]);
                add_impulse(conditions[b], phi[b]);
              }
            break;
          }
      }
    if (padding_layer)
      apply_padding_mirrors(
        q, operators.lumped_mass, operators.mass_floor, t, t, false, impulse);
  }



  template <int dim>
  void
  VelocityConditions<dim>::correct_velocities(
    GridVectorField     &v,
    const double         t,
    std::vector<double> *corrections) const
  {
    if (corrections)
      corrections->resize(conditions.size());
    const std::vector<double> &v_b = values_at(t);
    for (unsigned int b = 0; b < conditions.size(); ++b)
      {
        const auto &c   = conditions[b];
        double      v_n = 0;
        for (unsigned int d = 0; d < dim; ++d)
          v_n += v.block(d).local_element(c.local_index) * c.normal[d];
        const double dv = v_b[b] - v_n;
        for (unsigned int d = 0; d < dim; ++d)
          v.block(d).local_element(c.local_index) += dv * c.normal[d];
        if (corrections)
          (*corrections)[b] = dv;
      }
    if (padding_layer)
      apply_padding_mirrors(v, nullptr, 0., t, t, false, nullptr);
  }



  template <int dim>
  void
  VelocityConditions<dim>::correct_accelerations(GridVectorField &a,
                                                 const double     t0,
                                                 const double     t1) const
  {
    const std::vector<double> &v_0 = values_at(t0);
    const std::vector<double> &v_1 = values_at(t1);
    for (unsigned int b = 0; b < conditions.size(); ++b)
      {
        const auto &c   = conditions[b];
        double      a_n = 0;
        for (unsigned int d = 0; d < dim; ++d)
          a_n += a.block(d).local_element(c.local_index) * c.normal[d];
        const double target = (v_1[b] - v_0[b]) / (t1 - t0);
        for (unsigned int d = 0; d < dim; ++d)
          a.block(d).local_element(c.local_index) +=
            (target - a_n) * c.normal[d];
      }
    if (padding_layer)
      apply_padding_mirrors(a, nullptr, 0., t1, t0, true, nullptr);
  }



  template <int dim>
  void
  VelocityConditions<dim>::apply_padding_mirrors(
    GridVectorField             &field,
    const GridScalar            *mass,
    const double                 mass_floor,
    const double                 t,
    const double                 t0,
    const bool                   difference,
    std::vector<Tensor<1, dim>> *impulse) const
  {
    // The mirror may be a ghost: its current summed value from its owner
    // (the owned values may have just changed; collective, every rank calls
    // it with a padding layer).
    const bool ghosted = field.has_ghost_elements();
    field.update_ghost_values();
    // The walls' velocities (or, with @p difference, their rate of change
    // over [t0, t]); they depend on t only with a padding layer.
    std::vector<double> wall_speed(walls.size());
    for (unsigned int w = 0; w < walls.size(); ++w)
      wall_speed[w] = difference ? (wall_value(w, NodeCondition{}, t) -
                                    wall_value(w, NodeCondition{}, t0)) /
                                     (t - t0) :
                                   wall_value(w, NodeCondition{}, t);
    // The mirrored values first (a mirror may itself be a padding node of
    // another wall), then written.
    std::vector<Tensor<1, dim>> mirrored(mirrors.size());
    for (unsigned int k = 0; k < mirrors.size(); ++k)
      {
        const PaddingMirror &r  = mirrors[k];
        const double   m_mirror = mass ? mass->local_element(r.mirror) : 1.;
        Tensor<1, dim> v_mirror;
        if (m_mirror > mass_floor)
          for (unsigned int d = 0; d < dim; ++d)
            v_mirror[d] = field.block(d).local_element(r.mirror) / m_mirror;
        // v_pad · n̂ = 2 v_w − v_mirror · n̂ on the directions the wall
        // holds, v_pad = v_mirror on the others.
        Tensor<1, dim> v = v_mirror;
        for (unsigned int j = 0; j < r.directions.size(); ++j)
          {
            const int    w   = r.direction_wall[j];
            const double v_w = w < 0 ? 0. : wall_speed[w];
            v += 2. * (v_w - v_mirror * r.directions[j]) * r.directions[j];
          }
        mirrored[k] = v;
      }
    for (unsigned int k = 0; k < mirrors.size(); ++k)
      {
        const PaddingMirror &r   = mirrors[k];
        const double   m_padding = mass ? mass->local_element(r.padding) : 1.;
        const double   scale     = m_padding > mass_floor ? m_padding : 0.;
        Tensor<1, dim> change;
        for (unsigned int d = 0; d < dim; ++d)
          {
            double &value = field.block(d).local_element(r.padding);
            change[d]     = scale * mirrored[k][d] - value;
            value += change[d];
          }
        if (impulse)
          (*impulse)[r.source] += change;
      }
    if (ghosted)
      field.update_ghost_values();
    else
      field.zero_out_ghost_values();
  }



  template <int dim>
  void
  VelocityConditions<dim>::known_values(
    const double             t,
    std::vector<GridScalar> &mask,
    std::vector<GridScalar> &value_out) const
  {
    for (unsigned int d = 0; d < dim; ++d)
      {
        mask[d]      = 0;
        value_out[d] = 0;
      }
    const std::vector<double> &v_b = values_at(t);
    for (unsigned int b = 0; b < conditions.size(); ++b)
      for (unsigned int d = 0; d < dim; ++d)
        if (std::abs(conditions[b].normal[d]) > 1 - 1e-12)
          {
            mask[d].local_element(conditions[b].local_index) = 1;
            value_out[d].local_element(conditions[b].local_index) =
              v_b[b] * conditions[b].normal[d];
          }
  }

  template class VelocityConditions<2>;
  template class VelocityConditions<3>;
} // namespace fmpm
