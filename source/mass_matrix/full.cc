// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/mass_matrix/full.h>
#include <fmpm/parameter_entries.h>
#include <fmpm/simulator.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <cmath>
#include <cstring>

namespace fmpm
{
  namespace MassMatrix
  {
    template <int dim>
    void
    Full<dim>::declare_parameters(ParameterHandler &prm)
    {
      const Full<dim> defaults;
      prm.declare_entry("Tolerance",
                        format_number(defaults.tolerance),
                        Patterns::Double(0, 1),
                        "Relative residual |p - m~ v| / |p| at which CG stops "
                        "(all components together; for accelerations "
                        "|f - m~ a| dt / (|p| + |f| dt), so that a dt is as "
                        "accurate as the velocities). Units: none.");
      prm.declare_entry("Maximum iterations",
                        std::to_string(defaults.max_iterations),
                        Patterns::Integer(1),
                        "CG iterations after which the solve counts as "
                        "failed and the step falls back to the lumped mass "
                        "matrix. Units: none.");
      prm.declare_entry("Weak node threshold",
                        format_number(defaults.weak_node_threshold),
                        Patterns::Double(0, 1),
                        "Remedy for a nearly singular full mass matrix: nodes "
                        "whose diagonal m~_ii is below this fraction of the "
                        "lumped mass m_i (a node barely touched by points) "
                        "take the lumped velocity p_i/m_i; the other nodes "
                        "solve the full system with these velocities known. "
                        "0 solves the exact full system everywhere. "
                        "Units: none.");
      prm.declare_entry("Lumped fraction",
                        format_number(defaults.lumped_fraction),
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



    template <int dim>
    const CellwiseMatrix *
    Full<dim>::cellwise_matrix() const
    {
      return this->get_cellwise_full_mass_matrix();
    }



    template <int dim>
    void
    Full<dim>::solve(const GridVectorField &p, GridVectorField &v) const
    {
      solve_system(p, v, false, 0);
    }



    template <int dim>
    void
    Full<dim>::solve_from_guess(const GridVectorField &p,
                                GridVectorField       &v,
                                const double           residual_scale) const
    {
      solve_system(p, v, true, residual_scale);
    }



    template <int dim>
    void
    Full<dim>::solve_system(const GridVectorField &p,
                            GridVectorField       &v,
                            const bool             start_from_v,
                            const double           residual_scale) const
    {
      const auto        &mask   = this->get_known_velocity_mask();
      const auto        &values = this->get_known_velocity_values();
      const unsigned int n      = this->get_lumped_mass().locally_owned_size();
      // Known nodes: components held by a grid condition.
      for (unsigned int b = 0; b < p.n_blocks(); ++b)
        for (unsigned int i = 0; i < n; ++i)
          if (mask[b].local_element(i) != 0)
            v.block(b).local_element(i) = values[b].local_element(i);
      FullMassSolveSettings settings;
      settings.tolerance         = tolerance;
      settings.residual_scale    = residual_scale;
      settings.max_iterations    = max_iterations;
      settings.lumped_fraction   = lumped_fraction;
      settings.mass_floor        = this->get_mass_floor();
      settings.conserve_momentum = columns_sum_to_lumped_mass();
      const GridScalar &m        = this->get_lumped_mass();
      const auto        solve    = [&](const std::vector<GridScalar> &held,
                             const bool                     from_v) {
        const FullMassSolve result =
          cellwise_matrix() ? solve_full_mass_system(*cellwise_matrix(),
                                                     diagonal,
                                                     m,
                                                     &held,
                                                     weak,
                                                     p,
                                                     v,
                                                     from_v,
                                                     settings,
                                                     &workspace) :
                                        solve_full_mass_system(matrix(),
                                                     diagonal,
                                                     m,
                                                     &held,
                                                     weak,
                                                     p,
                                                     v,
                                                     from_v,
                                                     settings,
                                                     &workspace);
        ++n_solves;
        total_iterations += result.iterations;
        max_iterations_used = std::max(max_iterations_used, result.iterations);
        n_lumped_fallbacks += result.converged ? 0 : 1;
      };
      const auto &mirror = this->get_padding_mirror();
      if (!mirror)
        {
          solve(mask, start_from_v);
          return;
        }
      // B-splines with a padding layer: the padding nodes are slaved to
      // their mirrors, v_pad = R v_mirror + 2 (v_w · n̂) n̂ (a constraint on
      // v as the known values are). The solve is m̃ v = p on the interior
      // rows with v_pad so constrained, the limit of the FMPM(k) series
      // that imposes the mirror on every iterate (seed 000 Eqs. 1.22-1.23,
      // 2.51-2.53). It is found by holding the padding nodes as known
      // values at their mirrors' last values and solving again from the
      // previous solution until the padding values stop changing (block
      // Gauss-Seidel: the padding nodes carry only the B-splines' tails of
      // the points next to the layer, a weak coupling).
      const std::vector<unsigned int> padding =
        this->get_velocity_conditions().padding_node_indices();
      std::vector<GridScalar> held(mask);
      for (const unsigned int i : padding)
        for (unsigned int b = 0; b < p.n_blocks(); ++b)
          held[b].local_element(i) = 1;
      std::vector<double> previous(padding.size() * p.n_blocks());
      const MPI_Comm      comm = m.get_mpi_communicator();
      if (!start_from_v)
        apply_lumped_inverse(m, p, v, settings.mass_floor);
      for (unsigned int b = 0; b < p.n_blocks(); ++b)
        for (unsigned int i = 0; i < n; ++i)
          if (mask[b].local_element(i) != 0)
            v.block(b).local_element(i) = values[b].local_element(i);
      for (unsigned int sweep = 0; sweep < max_mirror_sweeps; ++sweep)
        {
          mirror(v);
          for (unsigned int k = 0; k < padding.size(); ++k)
            for (unsigned int b = 0; b < p.n_blocks(); ++b)
              previous[k * p.n_blocks() + b] =
                v.block(b).local_element(padding[k]);
          solve(held, true);
          mirror(v);
          double change = 0, size = 0;
          for (unsigned int k = 0; k < padding.size(); ++k)
            for (unsigned int b = 0; b < p.n_blocks(); ++b)
              {
                const double value = v.block(b).local_element(padding[k]);
                change =
                  std::max(change,
                           std::abs(value - previous[k * p.n_blocks() + b]));
              }
          for (unsigned int b = 0; b < p.n_blocks(); ++b)
            size = std::max(size, v.block(b).linfty_norm());
          ++n_mirror_sweeps;
          if (Utilities::MPI::max(change, comm) <=
              tolerance * Utilities::MPI::max(size, comm))
            break;
        }
    }



    template <int dim>
    void
    Full<dim>::setup()
    {
      const GridScalar &m = this->get_lumped_mass();
      for (GridScalar *vector : {&weak, &diagonal})
        if (vector->size() != m.size() ||
            !vector->get_partitioner()->is_compatible(*m.get_partitioner()))
          vector->reinit(m.get_partitioner());
      if (const CellwiseMatrix *cellwise = cellwise_matrix())
        cellwise->diagonal(diagonal);
      else
        {
          const auto &range = m.get_partitioner()->locally_owned_range();
          for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
            diagonal.local_element(i) =
              matrix().diag_element(range.nth_index_in_set(i));
        }
      weak = 0;
      if (weak_node_threshold <= 0)
        return;
      const double       floor  = this->get_mass_floor();
      unsigned long long n_weak = 0;
      for (unsigned int i = 0; i < m.locally_owned_size(); ++i)
        {
          // A node barely touched by points: m̃ᵢᵢ/mᵢ = Σ M S² / Σ M S < τ.
          const double m_i     = m.local_element(i);
          const bool   is_weak = m_i > floor && diagonal.local_element(i) <
                                                weak_node_threshold * m_i;
          weak.local_element(i) = is_weak ? 1. : 0.;
          n_weak += is_weak;
        }
      // B-splines with a padding layer: the padding nodes are held at
      // their mirrors' values in every solve (solve_system()), as known
      // values are, and never weak: a weak node's couplings move onto its
      // neighbours' diagonals, as if it moved with them, where the mirror
      // moves it against them across a held wall (measured: the padded
      // bar's energy changed by 28 % with the padding nodes weak).
      const VelocityConditions<dim> &conditions =
        this->get_velocity_conditions();
      if (conditions.has_padding_mirrors())
        for (const unsigned int i : conditions.padding_node_indices())
          if (weak.local_element(i) != 0)
            {
              weak.local_element(i) = 0;
              --n_weak;
            }
      n_weak_node_steps += n_weak;
      ++n_setups;
    }



    template <int dim>
    void
    Full<dim>::save(std::map<std::string, std::string> &status) const
    {
      // The counters are the same on every rank (CG is global) except the
      // weak nodes, which each rank counts on its own nodes: their sum is
      // kept, so that a run resumed on another number of ranks reports the
      // same figures.
      const MPI_Comm comm                = this->get_mpi_communicator();
      status["full.n_solves"]            = std::to_string(n_solves);
      status["full.total_iterations"]    = std::to_string(total_iterations);
      status["full.max_iterations_used"] = std::to_string(max_iterations_used);
      status["full.n_lumped_fallbacks"] =
        std::to_string(Utilities::MPI::max(n_lumped_fallbacks, comm));
      status["full.n_weak_node_steps"] =
        std::to_string(Utilities::MPI::sum(n_weak_node_steps, comm));
      status["full.n_setups"]        = std::to_string(n_setups);
      status["full.n_mirror_sweeps"] = std::to_string(n_mirror_sweeps);
    }



    template <int dim>
    void
    Full<dim>::load(const std::map<std::string, std::string> &status)
    {
      const auto value = [&status](const std::string &key) {
        const auto entry = status.find(key);
        return entry == status.end() ? 0ULL : std::stoull(entry->second);
      };
      const bool is_root =
        Utilities::MPI::this_mpi_process(this->get_mpi_communicator()) == 0;
      n_solves            = value("full.n_solves");
      total_iterations    = value("full.total_iterations");
      max_iterations_used = value("full.max_iterations_used");
      n_lumped_fallbacks  = value("full.n_lumped_fallbacks");
      n_weak_node_steps   = is_root ? value("full.n_weak_node_steps") : 0;
      n_setups            = value("full.n_setups");
      n_mirror_sweeps     = value("full.n_mirror_sweeps");
    }



    template <int dim>
    std::map<std::string, double>
    Full<dim>::statistics() const
    {
      const MPI_Comm                comm   = this->get_mpi_communicator();
      std::map<std::string, double> result = {
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
      if (n_mirror_sweeps > 0)
        result["padding_mirror_solves"] = static_cast<double>(n_mirror_sweeps);
      return result;
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
      // Σ M_p of each cell, by active cell index.
      const MaterialPoints<dim> &points = this->get_material_points();
      const double *const        mass = points.column(PropertyIndex<dim>::mass);
      std::vector<double>        mass_of_cell(
        this->get_triangulation().n_active_cells(), 0.);
      for (unsigned int c = 0; c < points.n_cells(); ++c)
        for (unsigned int k = points.cell_point_begin[c];
             k < points.cell_point_begin[c + 1];
             ++k)
          mass_of_cell[points.cell_index[c]] += mass[k];
      consistent_mass = 0;
      std::vector<types::global_dof_index> dofs(
        this->get_dof_handler().get_fe().dofs_per_cell);
      FullMatrix<double> local;
      for (const auto &cell : this->get_dof_handler().active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const double cell_mass = mass_of_cell[cell->active_cell_index()];
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

    template <int dim>
    StabilityLimit
    Full<dim>::stability_limit(const StabilityMethod &method) const
    {
      const std::string name = "full mass matrix";
      StabilityLimit    limit;
      limit.max_courant = Stability::full_limit;
      limit.basis       = name + ", " + Stability::strain_update_text(method) +
                    ": the rigid rotation is stable at C = 0.12, "
                    "unstable at 0.15";
      Stability::limit_full_mass_method(limit, method, name, order(), true);
      return limit;
    }



    template <int dim>
    StabilityLimit
    Consistent<dim>::stability_limit(const StabilityMethod &method) const
    {
      StabilityLimit limit;
      limit.max_courant = Stability::consistent_limit;
      limit.basis       = "consistent mass matrix, " +
                    Stability::strain_update_text(method) +
                    ": FLIP on the vibrating bar stable up to C = 0.4";
      limit.warning =
        "the consistent finite element mass matrix amplifies a mode at "
        "free surfaces once material points move relative to the cells, "
        "at any time step (with " +
        Stability::update_text(method) + " and strain update '" +
        method.strain_update.name() +
        "' the vibrating bar of doc/studies/stability.md is unstable at " +
        (method.flip_type && method.strain_update.average ?
           "Courant numbers above 0.45 and " :
           "every Courant number and ") +
        "at large displacements); use it for small-displacement studies "
        "only, or choose 'Mass matrix/Model name = full' with the fmpm "
        "update or 'fmpm' (FMPM(k)).";
      return limit;
    }

    FMPM_REGISTER_MASS_MATRIX(
      Full,
      "full",
      "The exact particle full mass matrix m~ = S^T M S of [Nairn2023-FMPM] Eq. 1.9, "
      "solved with CG (Jacobi preconditioner) to 'Tolerance'; CG "
      "iteration counts go to summary.json.")
    FMPM_REGISTER_MASS_MATRIX(
      Consistent,
      "consistent",
      "The consistent finite element mass matrix int rho N_i N_j dx with the "
      "cell densities carried from the material points, solved like 'full'.")
  } // namespace MassMatrix
} // namespace fmpm
