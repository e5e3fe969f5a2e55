// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_geometry_shape_h
#define fmpm_geometry_shape_h

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/point.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief Regions of space that bodies fill with material points: primitive
   * shapes, their unions, differences and intersections, rotated and
   * translated, and closed triangulated surfaces.
   */
  namespace Geometry
  {
    /** A bound that stands for "no bound" in a bounding box (half-spaces,
     * level sets). */
    constexpr double unbounded = 1e300;

    /**
     * @brief A region of space: which points lie inside, and a box that
     * contains it.
     *
     * The Simulator asks inside() once for each candidate material point at
     * set-up (never while time stepping).
     *
     * @tparam dim space dimension
     */
    template <int dim>
    class Shape
    {
    public:
      virtual ~Shape() = default;

      /** Whether @p x lies inside the region (its boundary included). */
      virtual bool
      inside(const Point<dim> &x) const = 0;

      /** A box that contains the region; coordinates of magnitude
       * Geometry::unbounded where it has no bound. */
      virtual BoundingBox<dim>
      bounding_box() const = 0;
    };

    /** Whether @p box has a finite bound in direction @p d. */
    template <int dim>
    bool
    is_bounded(const BoundingBox<dim> &box, const unsigned int d);

    /**
     * @brief What a shape formula may refer to besides its own text.
     */
    struct ShapeContext
    {
      /** The parameter the formula comes from, for error messages
       * ("Body 0/Shape"). */
      std::string where;
      /** Constants of the 'expression' level sets. */
      std::map<std::string, double> constants;
      /** The file that 'polygon(file)' and 'surface(file)' read
       * (the body's 'File name'). */
      std::string file_name;
      /** The parameter that names the file ("Body 0/File name"). */
      std::string file_parameter;
    };

    /**
     * @brief The shape that a formula describes.
     *
     * Primitives (angles in degrees, points and lengths in m):
     * box(center; half lengths), sphere(center; radius) (alias disk),
     * ellipsoid(center; semi-axes) (alias ellipse), cylinder(end point;
     * end point; radius) (a rectangle in 2D), polygon(x0, y0; x1, y1; ...)
     * or polygon(file) (2D), halfspace(point; outward normal),
     * expression("f(x, y, z)") (where f <= 0), surface(file) (3D, a closed
     * STL surface). Transformations: rotate(angle; [axis (3D);] [about
     * point;] shape) (about the centre of the shape's bounding box unless
     * a point is given) and translate(displacement; shape). Operators:
     * A + B (union), A - B (difference), A * B (intersection), with * before
     * + and -, and parentheses.
     *
     * Throws ExcMessage naming @p context.where and what is wrong for any
     * syntax error, wrong number of values, unreadable file, self-
     * intersecting polygon or open surface.
     */
    template <int dim>
    std::unique_ptr<Shape<dim>>
    parse_shape(const std::string &formula, const ShapeContext &context);

    /** @name Primitives and combinations (parse_shape() builds them) */
    /** @{ */
    /** The box |x_d - center_d| <= half_lengths_d. */
    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_box(const Point<dim> &center, const Tensor<1, dim> &half_lengths);

    /** The ellipsoid sum_d ((x_d - center_d)/semi_axes_d)^2 <= 1. */
    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_ellipsoid(const Point<dim> &center, const Tensor<1, dim> &semi_axes);

    /** The points within @p radius of the segment from @p p0 to @p p1 whose
     * projection lies on it (a rectangle in 2D). */
    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_cylinder(const Point<dim> &p0, const Point<dim> &p1, double radius);

    /** The half-space (x - point)·normal <= 0. */
    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_half_space(const Point<dim> &point, const Tensor<1, dim> &normal);

    /** The polygon with these vertices (2D; even-odd rule); refuses fewer
     * than three vertices and edges that cross, naming @p where. */
    std::unique_ptr<Shape<2>>
    make_polygon(const std::vector<Point<2>> &vertices,
                 const std::string           &where);

    /** Vertices "x y" (or "x, y"), one a line, '#' comments, from
     * @p file_name (2D polygons). */
    std::vector<Point<2>>
    read_polygon_file(const std::string &file_name, const std::string &where);

    /** The region where the FunctionParser expression is <= 0. */
    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_level_set(const std::string                   &expression,
                   const std::map<std::string, double> &constants,
                   const std::string                   &where);

    /** Union (any of), intersection (all of), difference (first minus the
     * others). */
    enum class Combination
    {
      union_of,
      intersection_of,
      difference_of
    };
    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_combination(Combination                                combination,
                     std::vector<std::unique_ptr<Shape<dim>>> &&parts);

    /** @p shape rotated by @p angle (radians) about @p axis (3D; ignored in
     * 2D) through @p about, then translated by @p translation. */
    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_transformed(std::unique_ptr<Shape<dim>> &&shape,
                     double                        angle,
                     const Tensor<1, 3>           &axis,
                     const Point<dim>             &about,
                     const Tensor<1, dim>         &translation);
    /** @} */

    /** The region enclosed by a closed triangulated surface (3D): STL,
     * ASCII or binary. Refuses a surface with an open edge, naming
     * @p file_name and the edge. */
    std::unique_ptr<Shape<3>>
    make_surface(const std::string &file_name, const std::string &where);
  } // namespace Geometry
} // namespace fmpm

#endif
