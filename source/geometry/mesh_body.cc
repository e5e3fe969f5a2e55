// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Bodies from volume meshes: read by GridIn, points at the Gauss points of
// each cell (FEValues of each cell's reference cell: triangles,
// quadrilaterals, tetrahedra, hexahedra).

#include <fmpm/geometry/mesh_body.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/fe/fe_nothing.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/reference_cell.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace fmpm
{
  namespace Geometry
  {
    namespace
    {
      /** Call @p f for every multi-index in [first, last] (inclusive). */
      template <int dim, typename F>
      void
      for_each_index(const std::array<unsigned int, dim> &first,
                     const std::array<unsigned int, dim> &last,
                     const F                             &f)
      {
        std::array<unsigned int, dim> i = first;
        while (true)
          {
            f(i);
            unsigned int d = 0;
            while (d < dim && i[d] == last[d])
              {
                i[d] = first[d];
                ++d;
              }
            if (d == dim)
              return;
            ++i[d];
          }
      }

      /** Whether @p x lies in the simplex @p cell (barycentric
       * coordinates >= 0 up to round-off). */
      template <int dim>
      bool
      in_simplex(const typename Triangulation<dim>::active_cell_iterator &cell,
                 const Point<dim>                                        &x)
      {
        Tensor<2, dim> A;
        for (unsigned int v = 0; v < dim; ++v)
          for (unsigned int d = 0; d < dim; ++d)
            A[d][v] = cell->vertex(v + 1)[d] - cell->vertex(0)[d];
        const Tensor<1, dim> lambda = invert(A) * (x - cell->vertex(0));
        double               sum    = 0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            if (lambda[d] < -1e-12)
              return false;
            sum += lambda[d];
          }
        return sum <= 1 + 1e-12;
      }
    } // namespace



    template <int dim>
    MeshRegion<dim>::MeshRegion(
      const std::string               &file_name,
      const unsigned int               n_points_1d,
      const std::string               &where,
      const std::vector<unsigned int> &physical_groups)
    {
      AssertThrow(std::filesystem::is_regular_file(file_name),
                  ExcMessage(where + " = <" + file_name +
                             "> cannot be read: the volume mesh file is "
                             "missing."));
      GridIn<dim> grid_in;
      grid_in.attach_triangulation(mesh);
      try
        {
          grid_in.read(file_name);
        }
      catch (const ExceptionBase &e)
        {
          std::ostringstream message;
          e.print_info(message);
          AssertThrow(false,
                      ExcMessage(where + " = <" + file_name +
                                 "> is not a volume mesh deal.II's GridIn "
                                 "reads (Gmsh .msh, VTK .vtk, UCD .ucd, "
                                 "Abaqus .inp) in " +
                                 std::to_string(dim) + "D: " + message.str()));
        }
      AssertThrow(mesh.n_active_cells() > 0,
                  ExcMessage(where + " = <" + file_name + "> holds no cell."));

      // The cells of the chosen physical groups (GridIn reads a Gmsh
      // physical tag as the cell's material id).
      std::set<unsigned int> groups_in_file;
      for (const auto &cell : mesh.active_cell_iterators())
        groups_in_file.insert(cell->material_id());
      const auto chosen = [&](const auto &cell) {
        return physical_groups.empty() ||
               std::find(physical_groups.begin(),
                         physical_groups.end(),
                         cell->material_id()) != physical_groups.end();
      };
      for (const unsigned int group : physical_groups)
        if (groups_in_file.count(group) == 0)
          {
            std::string present;
            for (const unsigned int g : groups_in_file)
              present += (present.empty() ? "" : ", ") + std::to_string(g);
            AssertThrow(false,
                        ExcMessage(where + " = <" + file_name +
                                   "> has no cell of physical group " +
                                   std::to_string(group) +
                                   " (Physical groups); its cells' groups "
                                   "are: " +
                                   present + "."));
          }

      // One FEValues per kind of cell.
      std::map<ReferenceCell, std::unique_ptr<FE_Nothing<dim>>> elements;
      std::map<ReferenceCell, std::unique_ptr<FEValues<dim>>>   fe_values;
      for (const auto &cell : mesh.active_cell_iterators())
        {
          const ReferenceCell kind = cell->reference_cell();
          if (fe_values.find(kind) != fe_values.end())
            continue;
          elements[kind]  = std::make_unique<FE_Nothing<dim>>(kind);
          fe_values[kind] = std::make_unique<FEValues<dim>>(
            kind.template get_default_linear_mapping<dim>(),
            *elements[kind],
            kind.template get_gauss_type_quadrature<dim>(n_points_1d),
            update_quadrature_points | update_JxW_values);
        }
      std::vector<Point<dim>> chosen_vertices;
      for (const auto &cell : mesh.active_cell_iterators())
        {
          if (!chosen(cell))
            continue;
          for (const unsigned int v : cell->vertex_indices())
            chosen_vertices.push_back(cell->vertex(v));
          FEValues<dim> &values = *fe_values[cell->reference_cell()];
          values.reinit(cell);
          for (unsigned int q = 0; q < values.n_quadrature_points; ++q)
            {
              AssertThrow(values.JxW(q) > 0,
                          ExcMessage(where + " = <" + file_name + ">: cell " +
                                     std::to_string(cell->index()) +
                                     " is inverted (negative volume)."));
              positions.push_back(values.quadrature_point(q));
              volumes.push_back(values.JxW(q));
            }
        }

      // Buckets: about one cell per bucket.
      box       = BoundingBox<dim>(chosen_vertices);
      n_buckets = std::max<unsigned int>(
        1,
        std::min<unsigned int>(256, std::pow(mesh.n_active_cells(), 1. / dim)));
      bucket_points.assign(std::pow(n_buckets, dim), {});
      bucket_cells.assign(bucket_points.size(), {});
      for (unsigned int i = 0; i < positions.size(); ++i)
        bucket_points[bucket_index(bucket_of(positions[i]))].push_back(i);
      for (const auto &cell : mesh.active_cell_iterators())
        {
          if (!chosen(cell))
            continue;
          const BoundingBox<dim> cell_box = cell->bounding_box();
          for_each_index<dim>(bucket_of(cell_box.get_boundary_points().first),
                              bucket_of(cell_box.get_boundary_points().second),
                              [&](const std::array<unsigned int, dim> &i) {
                                bucket_cells[bucket_index(i)].push_back(cell);
                              });
        }
    }



    template <int dim>
    std::array<unsigned int, dim>
    MeshRegion<dim>::bucket_of(const Point<dim> &x) const
    {
      std::array<unsigned int, dim> i;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const double width = box.side_length(d);
          const double s =
            width > 0 ? (x[d] - box.lower_bound(d)) / width * n_buckets : 0;
          i[d] = std::min<double>(n_buckets - 1, std::max(0., s));
        }
      return i;
    }



    template <int dim>
    unsigned int
    MeshRegion<dim>::bucket_index(const std::array<unsigned int, dim> &i) const
    {
      unsigned int index = 0;
      for (unsigned int d = dim; d-- > 0;)
        index = index * n_buckets + i[d];
      return index;
    }



    template <int dim>
    bool
    MeshRegion<dim>::inside(const Point<dim> &x) const
    {
      if (!box.point_inside(x))
        return false;
      for (const auto &cell : bucket_cells[bucket_index(bucket_of(x))])
        if (cell->bounding_box().point_inside(x) &&
            (cell->reference_cell().is_simplex() ? in_simplex<dim>(cell, x) :
                                                   cell->point_inside(x)))
          return true;
      return false;
    }



    template <int dim>
    BoundingBox<dim>
    MeshRegion<dim>::bounding_box() const
    {
      return box;
    }



    template <int dim>
    void
    MeshRegion<dim>::points_in_cell(
      const typename Triangulation<dim>::active_cell_iterator &cell,
      const Mapping<dim>                                      &mapping,
      std::vector<std::pair<unsigned int, Point<dim>>>        &found) const
    {
      const BoundingBox<dim> cell_box = cell->bounding_box();
      if (cell_box.get_neighbor_type(box) == NeighborType::not_neighbors)
        return;
      for_each_index<dim>(
        bucket_of(cell_box.get_boundary_points().first),
        bucket_of(cell_box.get_boundary_points().second),
        [&](const std::array<unsigned int, dim> &i) {
          for (const unsigned int p : bucket_points[bucket_index(i)])
            {
              if (!cell_box.point_inside(positions[p], 1e-12))
                continue;
              const Point<dim> reference =
                mapping.transform_real_to_unit_cell(cell, positions[p]);
              bool in = true;
              for (unsigned int d = 0; d < dim; ++d)
                in = in && reference[d] >= 0 && reference[d] < 1;
              if (in)
                found.emplace_back(p, reference);
            }
        });
      // In the order of the mesh body's points, whatever the buckets.
      std::sort(found.begin(), found.end(), [](const auto &a, const auto &b) {
        return a.first < b.first;
      });
    }



    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_mesh_region(const std::string               &file_name,
                     const unsigned int               n_points_1d,
                     const std::string               &where,
                     const std::vector<unsigned int> &physical_groups)
    {
      return std::make_unique<MeshRegion<dim>>(file_name,
                                               n_points_1d,
                                               where,
                                               physical_groups);
    }



    template class MeshRegion<2>;
    template class MeshRegion<3>;
    template std::unique_ptr<Shape<2>>
    make_mesh_region<2>(const std::string &,
                        const unsigned int,
                        const std::string &,
                        const std::vector<unsigned int> &);
    template std::unique_ptr<Shape<3>>
    make_mesh_region<3>(const std::string &,
                        const unsigned int,
                        const std::string &,
                        const std::vector<unsigned int> &);
  } // namespace Geometry
} // namespace fmpm
