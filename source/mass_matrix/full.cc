// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/full.h>
#include <fmpm/simulator.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

namespace fmpm
{
  namespace MassMatrix
  {
    namespace
    {
      /**
       * The SPD operator of the solve, on free nodes F:
       * (1 − δ) (K_FF + diag(c)) + δ m, where c = K 1_W lumps the couplings
       * to weak nodes W onto the diagonal (so the column sums stay m and
       * momentum is conserved); on weak and known nodes it is m.
       */
      struct BlendedMass
      {
        const TrilinosWrappers::SparseMatrix &K;
        const GridScalar                     &m;
        const GridScalar                     &known;
        const GridScalar                     &weak;
        const GridScalar                     &weak_coupling;
        double                                delta;
        bool                                  has_fixed;
        mutable GridScalar                    masked;

        bool
        is_fixed(const unsigned int i) const
        {
          return known.local_element(i) != 0 || weak.local_element(i) != 0;
        }

        void
        vmult(GridScalar &dst, const GridScalar &src) const
        {
          const unsigned int n = m.locally_owned_size();
          if (!has_fixed)
            K.vmult(dst, src);
          else
            {
              masked.reinit(src, true);
              for (unsigned int i = 0; i < n; ++i)
                masked.local_element(i) =
                  is_fixed(i) ? 0. : src.local_element(i);
              K.vmult(dst, masked);
            }
          for (unsigned int i = 0; i < n; ++i)
            {
              const double lumped = m.local_element(i) * src.local_element(i);
              if (has_fixed && is_fixed(i))
                dst.local_element(i) = lumped;
              else
                dst.local_element(i) =
                  (1 - delta) *
                    (dst.local_element(i) +
                     weak_coupling.local_element(i) * src.local_element(i)) +
                  delta * lumped;
            }
        }
      };

      /** The lumped inverse m⁻¹ (zero on empty nodes) as preconditioner. */
      struct LumpedInverse
      {
        const GridScalar &m;
        double            mass_floor;

        void
        vmult(GridScalar &dst, const GridScalar &src) const
        {
          const unsigned int n = m.locally_owned_size();
          for (unsigned int i = 0; i < n; ++i)
            {
              const double m_i = m.local_element(i);
              dst.local_element(i) =
                m_i > mass_floor ? src.local_element(i) / m_i : 0.0;
            }
        }
      };
    } // namespace



    template <int dim>
    void
    Full<dim>::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Tolerance",
                        "1e-10",
                        Patterns::Double(0, 1),
                        "Relative residual |p - m~ v| / |p| at which CG stops. "
                        "Units: none.");
      prm.declare_entry("Maximum iterations",
                        "1000",
                        Patterns::Integer(1),
                        "CG iterations after which the solve counts as "
                        "failed and the step falls back to the lumped mass "
                        "matrix. Units: none.");
      prm.declare_entry("Weak node threshold",
                        "0.1",
                        Patterns::Double(0, 1),
                        "Remedy for a nearly singular full mass matrix: nodes "
                        "whose diagonal m~_ii is below this fraction of the "
                        "lumped mass m_i (a node barely touched by points) "
                        "take the lumped velocity p_i/m_i; the other nodes "
                        "solve the full system with these velocities known. "
                        "0 solves the exact full system everywhere. "
                        "Units: none.");
      prm.declare_entry("Lumped fraction",
                        "0",
                        Patterns::Double(0, 1),
                        "Remedy for a nearly singular full mass matrix (few "
                        "points per cell, body edges): solve ((1 - delta) m~ "
                        "+ delta m) v = p with this delta. 0 is the exact full "
                        "mass matrix, 1 the lumped one. Units: none.");
    }



    template <int dim>
    void
    Full<dim>::parse_parameters(ParameterHandler &prm)
    {
      tolerance           = prm.get_double("Tolerance");
      max_iterations      = prm.get_integer("Maximum iterations");
      lumped_fraction     = prm.get_double("Lumped fraction");
      weak_node_threshold = prm.get_double("Weak node threshold");
    }



    FullMassSolve
    solve_full_mass_system(const TrilinosWrappers::SparseMatrix &K,
                           const GridScalar                     &m,
                           const GridScalar                     &known,
                           const GridScalar                     &weak,
                           const GridScalar                     &p,
                           GridScalar                           &v,
                           const double                          tolerance,
                           const unsigned int                    max_iterations,
                           const double                          delta,
                           const double                          mass_floor)
    {
      const unsigned int  n = m.locally_owned_size();
      const LumpedInverse preconditioner{m, mass_floor};
      const bool          has_fixed =
        Utilities::MPI::max(std::max(known.linfty_norm(), weak.linfty_norm()),
                            m.get_partitioner()->get_mpi_communicator()) > 0;
      // c = K 1_W: the couplings of each node to weak nodes.
      GridScalar weak_coupling(m);
      weak_coupling = 0;
      if (weak.linfty_norm() > 0 ||
          Utilities::MPI::max(weak.linfty_norm(),
                              m.get_partitioner()->get_mpi_communicator()) > 0)
        K.vmult(weak_coupling, weak);
      const BlendedMass A{
        K, m, known, weak, weak_coupling, delta, has_fixed, GridScalar()};
      FullMassSolve result;

      // Known values stay; every other node starts from the lumped solution.
      GridScalar rhs(p), v_known(p);
      for (unsigned int i = 0; i < n; ++i)
        {
          const bool   is_known    = known.local_element(i) != 0;
          const double m_i         = m.local_element(i);
          v_known.local_element(i) = is_known ? v.local_element(i) : 0.;
          if (!is_known)
            v.local_element(i) =
              m_i > mass_floor ? p.local_element(i) / m_i : 0.;
        }
      if (has_fixed)
        {
          // Free rows: move (1 − δ) K_FK v_K to the right; known rows read
          // m_K v_K = m_K v_K; weak rows m_W v_W = p_W.
          GridScalar coupling(p);
          K.vmult(coupling, v_known);
          for (unsigned int i = 0; i < n; ++i)
            if (known.local_element(i) != 0)
              rhs.local_element(i) =
                m.local_element(i) * v_known.local_element(i);
            else if (weak.local_element(i) == 0)
              rhs.local_element(i) -= (1 - delta) * coupling.local_element(i);
        }
      const double norm = rhs.l2_norm();
      if (norm == 0)
        return result;
      SolverControl control(max_iterations, tolerance * norm, false, false);
      SolverCG<GridScalar> cg(control);
      try
        {
          cg.solve(A, v, rhs, preconditioner);
        }
      catch (const std::exception &)
        {
          result.converged = false;
          // Breakdown or stagnation: lumped velocities for this field.
          preconditioner.vmult(v, p);
          for (unsigned int i = 0; i < n; ++i)
            if (known.local_element(i) != 0)
              v.local_element(i) = v_known.local_element(i);
        }
      result.iterations = control.last_step();
      return result;
    }



    template <int dim>
    void
    Full<dim>::solve(const GridVectorField &p, GridVectorField &v) const
    {
      const GridScalar  &m         = this->get_lumped_mass();
      const double       floor     = this->get_simulator().mass_floor();
      const auto        &zero_mask = this->get_known_velocity_mask();
      const auto        &values    = this->get_known_velocity_values();
      const unsigned int n         = m.locally_owned_size();
      for (unsigned int b = 0; b < p.n_blocks(); ++b)
        {
          // Known nodes: components held at zero by a grid condition.
          known.reinit(m.get_partitioner());
          for (unsigned int i = 0; i < n; ++i)
            if (zero_mask[b].local_element(i) != 0)
              {
                known.local_element(i)      = 1;
                v.block(b).local_element(i) = values[b].local_element(i);
              }
          const FullMassSolve result = solve_full_mass_system(matrix(),
                                                              m,
                                                              known,
                                                              weak,
                                                              p.block(b),
                                                              v.block(b),
                                                              tolerance,
                                                              max_iterations,
                                                              lumped_fraction,
                                                              floor);
          ++n_solves;
          total_iterations += result.iterations;
          max_iterations_used =
            std::max(max_iterations_used, result.iterations);
          n_lumped_fallbacks += result.converged ? 0 : 1;
        }
    }



    template <int dim>
    void
    Full<dim>::setup()
    {
      const GridScalar &m = this->get_lumped_mass();
      if (weak.size() != m.size() ||
          !weak.get_partitioner()->is_compatible(*m.get_partitioner()))
        weak.reinit(m.get_partitioner());
      weak = 0;
      if (weak_node_threshold <= 0)
        return;
      const double       floor  = this->get_simulator().mass_floor();
      const auto        &range  = m.get_partitioner()->locally_owned_range();
      unsigned long long n_weak = 0;
      for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
        {
          // A node barely touched by points: m̃ᵢᵢ/mᵢ = Σ M S² / Σ M S < τ.
          const double m_i = m.local_element(i);
          const bool   is_weak =
            m_i > floor && matrix().diag_element(range.nth_index_in_set(i)) <
                             weak_node_threshold * m_i;
          weak.local_element(i) = is_weak ? 1. : 0.;
          n_weak += is_weak;
        }
      n_weak_node_steps += n_weak;
      ++n_setups;
    }



    template <int dim>
    std::map<std::string, double>
    Full<dim>::statistics() const
    {
      const MPI_Comm comm = this->get_mpi_communicator();
      return {
        {"weak_nodes_per_step",
         n_setups ?
           Utilities::MPI::sum(static_cast<double>(n_weak_node_steps), comm) /
             n_setups :
           0.},
        {"cg_solves", static_cast<double>(n_solves)},
        {"cg_iterations_mean",
         n_solves ? static_cast<double>(total_iterations) / n_solves : 0.},
        {"cg_iterations_max", static_cast<double>(max_iterations_used)},
        {"lumped_fallbacks",
         Utilities::MPI::max(static_cast<double>(n_lumped_fallbacks), comm)}};
    }



    template <int dim>
    void
    Consistent<dim>::initialize()
    {
      const DoFHandler<dim> &dof_handler = this->get_dof_handler();
      const MPI_Comm         comm        = this->get_mpi_communicator();
      IndexSet               relevant;
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      TrilinosWrappers::SparsityPattern sparsity(
        dof_handler.locally_owned_dofs(),
        dof_handler.locally_owned_dofs(),
        relevant,
        comm);
      DoFTools::make_sparsity_pattern(dof_handler,
                                      sparsity,
                                      this->get_constraints(),
                                      false,
                                      Utilities::MPI::this_mpi_process(comm));
      sparsity.compress();
      consistent_mass.reinit(sparsity);

      // ∫ NᵢNⱼ dx per cell, exact for the (bi/tri)linear map with Gauss(3).
      const FiniteElement<dim> &fe = dof_handler.get_fe();
      FEValues<dim>             fe_values(fe,
                              QGauss<dim>(3),
                              update_values | update_JxW_values);
      cell_mass_integrals.assign(
        dof_handler.get_triangulation().n_active_cells(), FullMatrix<double>());
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            FullMatrix<double> &local =
              cell_mass_integrals[cell->active_cell_index()];
            local.reinit(fe.dofs_per_cell, fe.dofs_per_cell);
            for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q)
              for (unsigned int i = 0; i < fe.dofs_per_cell; ++i)
                for (unsigned int j = 0; j < fe.dofs_per_cell; ++j)
                  local(i, j) += fe_values.shape_value(i, q) *
                                 fe_values.shape_value(j, q) * fe_values.JxW(q);
          }
    }



    template <int dim>
    void
    Consistent<dim>::setup()
    {
      const auto &particle_handler = this->get_particle_handler();
      consistent_mass              = 0;
      std::vector<types::global_dof_index> dofs(
        this->get_dof_handler().get_fe().dofs_per_cell);
      FullMatrix<double> local;
      for (const auto &cell : this->get_dof_handler().active_cell_iterators())
        if (cell->is_locally_owned())
          {
            double cell_mass = 0;
            for (const auto &particle :
                 particle_handler.particles_in_cell(cell))
              cell_mass += particle.get_properties()[PropertyIndex<dim>::mass];
            if (cell_mass == 0)
              continue;
            // ρ_c = Σ M_p / |c|
            local = cell_mass_integrals[cell->active_cell_index()];
            local *= cell_mass / cell->measure();
            cell->get_dof_indices(dofs);
            this->get_constraints().distribute_local_to_global(local,
                                                               dofs,
                                                               consistent_mass);
          }
      consistent_mass.compress(VectorOperation::add);
      Full<dim>::setup();
    }

    FMPM_REGISTER_MASS_MATRIX(
      Full,
      "full",
      "The exact particle full mass matrix m~ = S^T M S of seed 000 Eq. 1.9, "
      "solved with CG (lumped-inverse preconditioner) to 'Tolerance'; CG "
      "iteration counts go to summary.json.")
    FMPM_REGISTER_MASS_MATRIX(
      Consistent,
      "consistent",
      "The consistent finite element mass matrix int rho N_i N_j dx with the "
      "cell densities carried from the material points, solved like 'full'.")
  } // namespace MassMatrix
} // namespace fmpm
