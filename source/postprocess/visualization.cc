// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/contact/manager.h>
#include <fmpm/postprocess/visualization.h>
#include <fmpm/simulation_control.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/reference_cell.h>
#include <deal.II/numerics/data_component_interpretation.h>

#include <fstream>
#include <memory>
#include <sstream>

#include <boost/archive/binary_iarchive.hpp>
#include <boost/archive/binary_oarchive.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

namespace fmpm
{
  namespace Postprocess
  {
    namespace
    {
      /**
       * Patches held for writing: the storage and the three queries of
       * DataOutInterface that PointOutput and GridPatches share.
       */
      template <int patch_dim, int dim>
      class StoredPatches : public DataOutInterface<patch_dim, dim>
      {
      protected:
        using Range =
          std::tuple<unsigned int,
                     unsigned int,
                     std::string,
                     DataComponentInterpretation::DataComponentInterpretation>;

        /** The next @p n_components names form the vector or tensor @p name. */
        void
        add_range(const unsigned int n_components,
                  const std::string &name,
                  const DataComponentInterpretation::DataComponentInterpretation
                    interpretation)
        {
          ranges.emplace_back(names.size(),
                              names.size() + n_components - 1,
                              name,
                              interpretation);
        }

        std::vector<DataOutBase::Patch<patch_dim, dim>> patches;
        std::vector<std::string>                        names;
        std::vector<Range>                              ranges;

      private:
        const std::vector<DataOutBase::Patch<patch_dim, dim>> &
        get_patches() const override
        {
          return patches;
        }

        std::vector<std::string>
        get_dataset_names() const override
        {
          return names;
        }

        std::vector<Range>
        get_nonscalar_data_ranges() const override
        {
          return ranges;
        }
      };

      /**
       * The material points as VTU patches (one vertex each), in the order of
       * the point store, so that a resumed run writes the same bytes as the
       * uninterrupted one. The
       * fields as ParaView reads them: id, the properties by name, vectors
       * as vectors, the Cauchy stress and F as dim x dim tensors (in 2D also
       * their zz components, plane strain).
       */
      template <int dim>
      class PointOutput : public StoredPatches<0, dim>
      {
      public:
        void
        build_patches(
          const MaterialPoints<dim>      &points,
          const std::vector<std::string> &property_names,
          const std::vector<
            DataComponentInterpretation::DataComponentInterpretation>
            &interpretations)
        {
          // How each output field is read from the properties.
          enum class Kind
          {
            copy,
            stress_tensor,
            stress_zz,
            deformation_tensor,
            deformation_zz
          };
          struct Field
          {
            Kind         kind;
            unsigned int first; // property index
          };
          std::vector<Field> fields;
          auto              &names   = this->names;
          auto              &patches = this->patches;
          names                      = {"id"};
          for (unsigned int c = 0; c < property_names.size(); ++c)
            {
              const bool tensor = property_names[c] == "stress_0" ||
                                  property_names[c] == "deformation_gradient_0";
              if (tensor)
                {
                  const bool        stress = property_names[c] == "stress_0";
                  const std::string name =
                    stress ? "stress" : "deformation_gradient";
                  this->add_range(
                    dim * dim,
                    name,
                    DataComponentInterpretation::component_is_part_of_tensor);
                  for (unsigned int i = 0; i < dim * dim; ++i)
                    {
                      fields.push_back({stress ? Kind::stress_tensor :
                                                 Kind::deformation_tensor,
                                        c});
                      names.push_back(name + "_" + std::to_string(i));
                    }
                  if (dim == 2)
                    {
                      fields.push_back(
                        {stress ? Kind::stress_zz : Kind::deformation_zz, c});
                      names.push_back(name + "_zz");
                    }
                  c += (stress ? 6 : 9) - 1;
                }
              else if (interpretations[c] ==
                       DataComponentInterpretation::component_is_part_of_vector)
                {
                  this->add_range(
                    dim,
                    property_names[c],
                    DataComponentInterpretation::component_is_part_of_vector);
                  for (unsigned int d = 0; d < dim; ++d)
                    {
                      fields.push_back({Kind::copy, c + d});
                      names.push_back(property_names[c]);
                    }
                  c += dim - 1;
                }
              else
                {
                  fields.push_back({Kind::copy, c});
                  names.push_back(property_names[c]);
                }
            }

          for (unsigned int k = 0; k < points.n_points(); ++k)
            {
              DataOutBase::Patch<0, dim> patch;
              patch.vertices[0]        = points.position[k];
              patch.patch_index        = patches.size();
              const PointRecord values = points.record(k);
              patch.data.reinit(names.size(), 1);
              patch.data(0, 0)          = points.id[k];
              unsigned int tensor_entry = 0;
              Tensor<2, 3> sigma;
              for (unsigned int f = 0; f < fields.size(); ++f)
                {
                  const Field &field = fields[f];
                  double       value = 0;
                  switch (field.kind)
                    {
                      case Kind::copy:
                        value = values[field.first];
                        break;
                      case Kind::stress_tensor:
                      case Kind::deformation_tensor:
                        {
                          const unsigned int i = tensor_entry / dim,
                                             j = tensor_entry % dim;
                          if (field.kind == Kind::stress_tensor &&
                              tensor_entry == 0)
                            sigma = get_symmetric_tensor3(values, field.first);
                          tensor_entry = (tensor_entry + 1) % (dim * dim);
                          value = field.kind == Kind::deformation_tensor ?
                                    values[field.first + 3 * i + j] :
                                    sigma[i][j];
                          break;
                        }
                      case Kind::stress_zz:
                        value = values[field.first + 2];
                        break;
                      case Kind::deformation_zz:
                        value = values[field.first + 8];
                        break;
                    }
                  patch.data(f + 1, 0) = value;
                }
              patches.push_back(std::move(patch));
            }
        }
      };

      /**
       * The grid as VTU patches, one per locally owned cell with its vertex
       * values (Q1 fields are their vertex values, so no FEValues are
       * needed): scalar fields, and vectors given by their components.
       */
      template <int dim>
      class GridPatches : public StoredPatches<dim, dim>
      {
      public:
        /** A scalar nodal field. */
        void
        add_scalar(const GridScalar &field, const std::string &name)
        {
          fields.push_back(&field);
          this->names.push_back(name);
        }

        /** A vector of nodal components, written as the vector @p name. */
        void
        add_vector(const GridVectorField &field, const std::string &name)
        {
          this->add_range(
            dim,
            name,
            DataComponentInterpretation::component_is_part_of_vector);
          for (unsigned int d = 0; d < dim; ++d)
            {
              fields.push_back(&field.block(d));
              this->names.push_back(name);
            }
        }

        /** One patch per locally owned cell; the last field is the rank. */
        void
        build_patches(const DoFHandler<dim> &dof_handler, const double rank)
        {
          auto &names   = this->names;
          auto &patches = this->patches;
          names.push_back("subdomain");
          const unsigned int n_vertices = GeometryInfo<dim>::vertices_per_cell;
          for (const auto &cell : dof_handler.active_cell_iterators())
            if (cell->is_locally_owned())
              {
                DataOutBase::Patch<dim, dim> patch;
                patch.patch_index    = patches.size();
                patch.n_subdivisions = 1;
                patch.reference_cell = ReferenceCells::get_hypercube<dim>();
                patch.data.reinit(names.size(), n_vertices);
                for (unsigned int v = 0; v < n_vertices; ++v)
                  {
                    patch.vertices[v] = cell->vertex(v);
                    const types::global_dof_index node =
                      cell->vertex_dof_index(v, 0);
                    for (unsigned int f = 0; f < fields.size(); ++f)
                      patch.data(f, v) = (*fields[f])(node);
                    patch.data(fields.size(), v) = rank;
                  }
                patches.push_back(std::move(patch));
              }
        }

      private:
        std::vector<const GridScalar *> fields;
      };

      /** The VTU flags of 'Output/Compression'. */
      DataOutBase::VtkFlags
      vtk_flags(const OutputParameters::Compression compression)
      {
        using Compression = OutputParameters::Compression;
        DataOutBase::VtkFlags flags;
        flags.print_date_and_time = false;
        flags.compression_level =
          compression == Compression::best_compression ?
            DataOutBase::VtkFlags::best_compression :
          compression == Compression::default_compression ?
            DataOutBase::VtkFlags::default_compression :
          compression == Compression::none ?
            DataOutBase::VtkFlags::no_compression :
            DataOutBase::VtkFlags::best_speed;
        return flags;
      }
    } // namespace



    template <int dim>
    Visualization<dim>::~Visualization()
    {
      if (writer.valid())
        writer.wait();
    }



    template <int dim>
    void
    Visualization<dim>::finish()
    {
      if (!writer.valid())
        return;
      TimerOutput::Scope timer(this->get_computing_timer(), "vtu writer");
      writer.get();
    }



    template <int dim>
    void
    Visualization<dim>::execute(const GlobalStatistics<dim> &)
    {
      finish();
      const OutputParameters  &output    = this->get_parameters().output;
      const SimulationControl &control   = this->get_simulation_control();
      TimerOutput             &timer     = this->get_computing_timer();
      const MPI_Comm           comm      = this->get_mpi_communicator();
      const std::string        directory = output.directory + "/";
      const unsigned int       rank    = Utilities::MPI::this_mpi_process(comm);
      const unsigned int       n_ranks = Utilities::MPI::n_mpi_processes(comm);
      // particles_NNNNN.R.vtu and grid_NNNNN.R.vtu (one piece per rank), the
      // .pvtu records naming them.
      const auto pieces = [&](const std::string &name) {
        std::vector<std::string> result;
        for (unsigned int r = 0; r < n_ranks; ++r)
          result.push_back(
            name + "_" + Utilities::int_to_string(control.output_number(), 5) +
            "." + std::to_string(r) + ".vtu");
        return result;
      };
      const auto record = [&](const std::string &name) {
        return name + "_" +
               Utilities::int_to_string(control.output_number(), 5) + ".pvtu";
      };

      auto points = std::make_shared<PointOutput<dim>>();
      {
        TimerOutput::Scope             points_timer(timer, "vtu points");
        const ParticleProperties<dim> &properties =
          this->get_particle_properties();
        points->set_flags(vtk_flags(output.compression));
        points->build_patches(this->get_material_points(),
                              properties.component_names(),
                              properties.component_interpretations());
      }
      auto grid = std::make_shared<GridPatches<dim>>();
      {
        TimerOutput::Scope grid_timer(timer, "vtu grid");
        grid->set_flags(vtk_flags(output.compression));
        grid->add_scalar(this->get_lumped_mass(), "nodal_mass");
        grid->add_vector(this->get_grid_field(ParticleUpdate::updated_velocity),
                         "velocity");
        if (output.write_grid_acceleration &&
            this->grid_field_computed(ParticleUpdate::acceleration))
          grid->add_vector(this->get_grid_field(ParticleUpdate::acceleration),
                           "acceleration");
        if (const Contact::Manager<dim> *contact = this->get_contact())
          {
            grid->add_vector(contact->normal_field(), "contact_normal");
            grid->add_scalar(contact->separation_field(), "contact_separation");
          }
        grid->build_patches(
          this->get_dof_handler(),
          this->get_triangulation().locally_owned_subdomain());
      }
      TimerOutput::Scope records_timer(timer, "vtu records");
      particle_pvd_records.emplace_back(control.time(), record("particles"));
      grid_pvd_records.emplace_back(control.time(), record("grid"));
      if (rank == 0)
        {
          std::ofstream particles_pvtu(directory + record("particles"));
          points->write_pvtu_record(particles_pvtu, pieces("particles"));
          std::ofstream grid_pvtu(directory + record("grid"));
          grid->write_pvtu_record(grid_pvtu, pieces("grid"));
          write_pvd_records();
        }
      // Compression and writing of this rank's pieces go on while the run
      // continues.
      const std::string point_file = directory + pieces("particles")[rank];
      const std::string grid_file  = directory + pieces("grid")[rank];
      writer =
        std::async(std::launch::async, [points, grid, point_file, grid_file]() {
          std::ofstream point_out(point_file);
          points->write_vtu(point_out);
          std::ofstream grid_out(grid_file);
          grid->write_vtu(grid_out);
          AssertThrow(point_out && grid_out,
                      ExcMessage("Cannot write the VTU files <" + point_file +
                                 "> and <" + grid_file + ">."));
        });
    }



    template <int dim>
    void
    Visualization<dim>::write_pvd_records() const
    {
      const std::string directory = this->get_parameters().output.directory;
      std::ofstream     particles_pvd(directory + "/particles.pvd");
      DataOutBase::write_pvd_record(particles_pvd, particle_pvd_records);
      std::ofstream grid_pvd(directory + "/grid.pvd");
      DataOutBase::write_pvd_record(grid_pvd, grid_pvd_records);
    }



    template <int dim>
    void
    Visualization<dim>::save(
      std::map<std::string, std::string> &status_strings) const
    {
      std::ostringstream out;
      {
        boost::archive::binary_oarchive archive(out);
        archive << particle_pvd_records << grid_pvd_records;
      }
      status_strings["Visualization"] = out.str();
    }



    template <int dim>
    void
    Visualization<dim>::load(
      const std::map<std::string, std::string> &status_strings)
    {
      const auto saved = status_strings.find("Visualization");
      if (saved == status_strings.end())
        return;
      std::istringstream in(saved->second);
      {
        boost::archive::binary_iarchive archive(in);
        archive >> particle_pvd_records >> grid_pvd_records;
      }
      if (Utilities::MPI::this_mpi_process(this->get_mpi_communicator()) == 0)
        write_pvd_records();
    }



    template class Visualization<2>;
    template class Visualization<3>;
  } // namespace Postprocess
} // namespace fmpm
