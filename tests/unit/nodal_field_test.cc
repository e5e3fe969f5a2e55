// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The one nodal field and its solver (seed 000 Eq. 1.7, seed 004 Eqs. 6,
// 26, 31-34) on random grid data with empty nodes: the lumped solve over
// every owned node (the centre of mass) and the solve on a material's nodes
// only (Contact::MaterialField) give the same bits for v, v⁺ and a; the
// fields satisfy m v = p, m v⁺ = p⁺, m a Δt = p⁺ − p and vanish on empty
// nodes; the centre of mass is the sum of the materials (Eq. 6).

#include <fmpm/contact/manager.h>
#include <fmpm/nodal_field.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>

#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using namespace fmpm::ParticleUpdate;

  constexpr unsigned int n_per_rank = 203; // odd: a remainder after blocks

  std::shared_ptr<const Utilities::MPI::Partitioner>
  make_partitioner()
  {
    const unsigned int rank = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    IndexSet owned(n_per_rank * n_ranks);
    owned.add_range(rank * n_per_rank, (rank + 1) * n_per_rank);
    return std::make_shared<Utilities::MPI::Partitioner>(owned,
                                                         owned,
                                                         MPI_COMM_WORLD);
  }

  /** m (a quarter of the nodes empty), p and p⁺, from @p seed. */
  template <int dim>
  void
  fill(fmpm::NodalField<dim> &field, const unsigned int seed)
  {
    std::mt19937                           rng(seed);
    std::uniform_real_distribution<double> unit(-1, 1);
    for (unsigned int i = 0; i < n_per_rank; ++i)
      {
        field.mass.local_element(i) = i % 4 == 1 ? 0. : 1.5 + unit(rng);
        for (unsigned int d = 0; d < dim; ++d)
          {
            field.momentum.block(d).local_element(i)         = unit(rng);
            field.updated_momentum.block(d).local_element(i) = unit(rng);
          }
      }
  }

  template <int dim>
  void
  copy_data(const fmpm::NodalField<dim> &from, fmpm::NodalField<dim> &to)
  {
    to.mass             = from.mass;
    to.momentum         = from.momentum;
    to.updated_momentum = from.updated_momentum;
  }

  template <int dim>
  void
  lumped_solves_agree()
  {
    const auto             partitioner = make_partitioner();
    const double           floor = 1e-12, dt = 0.37;
    fmpm::FieldSolver<dim> solver;
    solver.mass_floor = floor;
    solver.t_begin    = 1.0;
    solver.t_end      = 1.0 + dt;

    fmpm::NodalField<dim> centre_of_mass;
    centre_of_mass.reinit(partitioner, false);
    fill(centre_of_mass, 7);
    fmpm::Contact::MaterialField<dim> material;
    material.reinit(partitioner, true);
    copy_data(centre_of_mass, material);
    std::vector<unsigned int> nodes;
    for (unsigned int i = 0; i < n_per_rank; ++i)
      if (material.mass.local_element(i) > floor)
        nodes.push_back(i);

    for (const GridField field :
         {lumped_velocity, lumped_updated_velocity, lumped_acceleration})
      {
        centre_of_mass.allocate(field);
        EXPECT_EQ(centre_of_mass.fields[field].n_blocks(), dim);
        // Centre of mass: every owned node; an acceleration from f =
        // (p⁺ − p)/Δt.
        const GridField       is_updated = lumped_updated_velocity;
        fmpm::GridVectorField q(centre_of_mass.momentum);
        if (field == lumped_acceleration)
          fmpm::set_scaled_sum(q,
                               centre_of_mass.updated_momentum,
                               -1.,
                               centre_of_mass.momentum,
                               1. / dt);
        else if (field == is_updated)
          q = centre_of_mass.updated_momentum;
        solver.lumped(centre_of_mass, field, q);
        solver.finish(centre_of_mass, field, true);
        EXPECT_TRUE(centre_of_mass.computed[field]);

        // Material: its nodes only, after a solve that wrote elsewhere.
        fmpm::GridVectorField &v = material.fields[field];
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int i = 0; i < n_per_rank; ++i)
            v.block(d).local_element(i) = 1e30;
        material.written_nodes[field].resize(n_per_rank);
        for (unsigned int i = 0; i < n_per_rank; ++i)
          material.written_nodes[field][i] = i;
        solver.lumped_on_nodes(material, field, nodes, dt);
        solver.finish(material, field, true);
        EXPECT_TRUE(material.computed[field]);
        EXPECT_EQ(material.written_nodes[field], nodes);

        const fmpm::GridVectorField &u = centre_of_mass.fields[field];
        for (unsigned int d = 0; d < dim; ++d)
          {
            // The same bits.
            EXPECT_EQ(std::memcmp(u.block(d).begin(),
                                  v.block(d).begin(),
                                  n_per_rank * sizeof(double)),
                      0)
              << "field " << field << ", component " << d;
            // m v = q on nodes with mass, zero on the empty ones.
            for (unsigned int i = 0; i < n_per_rank; ++i)
              {
                const double m   = material.mass.local_element(i);
                const double v_i = v.block(d).local_element(i);
                const double p0  = material.momentum.block(d).local_element(i);
                const double p1 =
                  material.updated_momentum.block(d).local_element(i);
                const double expected = field == lumped_velocity ? p0 :
                                        field == is_updated      ? p1 :
                                                                   (p1 - p0) / dt;
                if (m > floor)
                  EXPECT_NEAR(m * v_i,
                              expected,
                              1e-14 * (1 + std::abs(expected)));
                else
                  EXPECT_EQ(v_i, 0.);
              }
          }
      }
    // A new mesh: nothing computed.
    centre_of_mass.reinit(partitioner, true);
    for (unsigned int f = 0; f < n_grid_fields; ++f)
      EXPECT_FALSE(centre_of_mass.computed[f]);
  }

  template <int dim>
  void
  centre_of_mass_is_the_sum()
  {
    const auto partitioner = make_partitioner();
    for (const unsigned int n_materials : {2u, 3u})
      {
        std::vector<fmpm::Contact::MaterialField<dim>> materials(n_materials);
        for (unsigned int a = 0; a < n_materials; ++a)
          {
            materials[a].reinit(partitioner, false);
            fill(materials[a], 11 + a);
            materials[a].force = materials[a].updated_momentum;
          }
        fmpm::NodalField<dim> total;
        total.reinit(partitioner, false);
        total.mass = 5.; // overwritten, not added to
        total.set_to_sum(materials, true, true, true);
        for (unsigned int i = 0; i < n_per_rank; ++i)
          {
            double m = 0;
            for (unsigned int a = 0; a < n_materials; ++a)
              m += materials[a].mass.local_element(i);
            EXPECT_EQ(total.mass.local_element(i), m);
            for (unsigned int d = 0; d < dim; ++d)
              {
                double p = 0, f = 0;
                for (unsigned int a = 0; a < n_materials; ++a)
                  {
                    p += materials[a].momentum.block(d).local_element(i);
                    f += materials[a].force.block(d).local_element(i);
                  }
                EXPECT_EQ(total.momentum.block(d).local_element(i), p);
                EXPECT_EQ(total.force.block(d).local_element(i), f);
              }
          }
        // Only what is asked for: p and f kept.
        const fmpm::GridVectorField momentum = total.momentum;
        total.mass                           = 0;
        total.set_to_sum(materials, true, false, false);
        EXPECT_EQ(total.momentum.block(0).local_element(3),
                  momentum.block(0).local_element(3));
        EXPECT_GT(total.mass.l1_norm(), 0);
      }
  }
} // namespace

TEST(NodalField, LumpedSolveOfCentreOfMassAndMaterialGiveSameBits2d)
{
  lumped_solves_agree<2>();
}

TEST(NodalField, LumpedSolveOfCentreOfMassAndMaterialGiveSameBits3d)
{
  lumped_solves_agree<3>();
}

TEST(NodalField, CentreOfMassIsTheSumOfTheMaterials2d)
{
  centre_of_mass_is_the_sum<2>();
}

TEST(NodalField, CentreOfMassIsTheSumOfTheMaterials3d)
{
  centre_of_mass_is_the_sum<3>();
}
