// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_geometry_mesh_body_h
#define fmpm_geometry_mesh_body_h

#include <fmpm/geometry/shape.h>

#include <deal.II/fe/mapping.h>
#include <deal.II/grid/tria.h>

#include <memory>
#include <string>
#include <vector>

namespace fmpm
{
  namespace Geometry
  {
    /**
     * @brief A body given as a volume mesh (any format deal.II's GridIn
     * reads, any cell type): its material points are the Gauss points of
     * its cells, each point's volume the cell's JxW share, so that the
     * points' volumes sum to the mesh's volume exactly.
     *
     * @tparam dim space dimension
     */
    template <int dim>
    class MeshRegion : public Shape<dim>
    {
    public:
      /** Read @p file_name (its extension picks the format) and place
       * @p n_points_1d Gauss points per direction in each cell whose
       * material id (Gmsh: physical tag) is one of @p physical_groups (all
       * cells if empty); @p where names the parameter in errors. */
      MeshRegion(const std::string               &file_name,
                 const unsigned int               n_points_1d,
                 const std::string               &where,
                 const std::vector<unsigned int> &physical_groups = {});

      /** Whether @p x lies in one of the mesh's cells. */
      bool
      inside(const Point<dim> &x) const override;

      BoundingBox<dim>
      bounding_box() const override;

      /** The points of the mesh body that @p cell (of the background mesh)
       * holds: those whose reference coordinates lie in [0, 1)^dim, so that
       * a point on a face between cells belongs to one of them, on any
       * number of ranks. Appends (index, reference point) to @p found. */
      void
      points_in_cell(
        const typename Triangulation<dim>::active_cell_iterator &cell,
        const Mapping<dim>                                      &mapping,
        std::vector<std::pair<unsigned int, Point<dim>>>        &found) const;

      /** Positions of all the body's points. */
      std::vector<Point<dim>> positions;
      /** Their volumes. Units: m^dim. */
      std::vector<double> volumes;

    private:
      Triangulation<dim> mesh;
      BoundingBox<dim>   box;
      /** A grid of buckets over the box: the points in each bucket, and the
       * mesh cells whose bounding box meets it. */
      unsigned int                           n_buckets;
      std::vector<std::vector<unsigned int>> bucket_points;
      std::vector<
        std::vector<typename Triangulation<dim>::active_cell_iterator>>
        bucket_cells;

      std::array<unsigned int, dim>
      bucket_of(const Point<dim> &x) const;
      unsigned int
      bucket_index(const std::array<unsigned int, dim> &i) const;
    };

    /** A MeshRegion as a Shape. */
    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_mesh_region(const std::string               &file_name,
                     const unsigned int               n_points_1d,
                     const std::string               &where,
                     const std::vector<unsigned int> &physical_groups = {});
  } // namespace Geometry
} // namespace fmpm

#endif
