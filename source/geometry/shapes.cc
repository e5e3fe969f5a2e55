// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Primitive shapes, their combinations and rigid transformations.

#include <fmpm/function_parser.h>
#include <fmpm/geometry/shape.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/geometry_info.h>
#include <deal.II/physics/transformations.h>

#include <algorithm>
#include <cmath>

namespace fmpm
{
  namespace Geometry
  {
    template <int dim>
    bool
    is_bounded(const BoundingBox<dim> &box, const unsigned int d)
    {
      return box.lower_bound(d) > -unbounded && box.upper_bound(d) < unbounded;
    }



    namespace
    {
      template <int dim>
      BoundingBox<dim>
      whole_space()
      {
        Point<dim> lower, upper;
        for (unsigned int d = 0; d < dim; ++d)
          {
            lower[d] = -unbounded;
            upper[d] = unbounded;
          }
        return BoundingBox<dim>(std::make_pair(lower, upper));
      }



      template <int dim>
      class Box : public Shape<dim>
      {
      public:
        Box(const Point<dim> &center, const Tensor<1, dim> &half_lengths)
          : center(center)
          , half_lengths(half_lengths)
        {}

        bool
        inside(const Point<dim> &x) const override
        {
          for (unsigned int d = 0; d < dim; ++d)
            if (std::abs(x[d] - center[d]) > half_lengths[d])
              return false;
          return true;
        }

        BoundingBox<dim>
        bounding_box() const override
        {
          return BoundingBox<dim>(
            std::make_pair(center - half_lengths, center + half_lengths));
        }

      private:
        const Point<dim>     center;
        const Tensor<1, dim> half_lengths;
      };



      template <int dim>
      class Ellipsoid : public Shape<dim>
      {
      public:
        Ellipsoid(const Point<dim> &center, const Tensor<1, dim> &semi_axes)
          : center(center)
          , semi_axes(semi_axes)
        {}

        bool
        inside(const Point<dim> &x) const override
        {
          double r2 = 0;
          for (unsigned int d = 0; d < dim; ++d)
            r2 += std::pow((x[d] - center[d]) / semi_axes[d], 2);
          return r2 <= 1.0;
        }

        BoundingBox<dim>
        bounding_box() const override
        {
          return BoundingBox<dim>(
            std::make_pair(center - semi_axes, center + semi_axes));
        }

      private:
        const Point<dim>     center;
        const Tensor<1, dim> semi_axes;
      };



      template <int dim>
      class Cylinder : public Shape<dim>
      {
      public:
        Cylinder(const Point<dim> &p0, const Point<dim> &p1, double radius)
          : p0(p0)
          , axis(p1 - p0)
          , radius(radius)
        {}

        bool
        inside(const Point<dim> &x) const override
        {
          const Tensor<1, dim> r = x - p0;
          const double         t = (r * axis) / axis.norm_square();
          if (t < 0 || t > 1)
            return false;
          return (r - t * axis).norm_square() <= radius * radius;
        }

        BoundingBox<dim>
        bounding_box() const override
        {
          // The end disks reach r sqrt(1 - a_d^2/|a|^2) in direction d.
          const Point<dim> p1 = p0 + axis;
          Point<dim>       lower, upper;
          for (unsigned int d = 0; d < dim; ++d)
            {
              const double reach =
                radius *
                std::sqrt(
                  std::max(0., 1. - axis[d] * axis[d] / axis.norm_square()));
              lower[d] = std::min(p0[d], p1[d]) - reach;
              upper[d] = std::max(p0[d], p1[d]) + reach;
            }
          return BoundingBox<dim>(std::make_pair(lower, upper));
        }

      private:
        const Point<dim>     p0;
        const Tensor<1, dim> axis;
        const double         radius;
      };



      template <int dim>
      class HalfSpace : public Shape<dim>
      {
      public:
        HalfSpace(const Point<dim> &point, const Tensor<1, dim> &normal)
          : point(point)
          , normal(normal)
        {}

        bool
        inside(const Point<dim> &x) const override
        {
          return (x - point) * normal <= 0;
        }

        BoundingBox<dim>
        bounding_box() const override
        {
          return whole_space<dim>();
        }

      private:
        const Point<dim>     point;
        const Tensor<1, dim> normal;
      };



      template <int dim>
      class LevelSet : public Shape<dim>
      {
      public:
        LevelSet(const std::string                   &expression,
                 const std::map<std::string, double> &constants,
                 const std::string                   &where)
          : function(1)
        {
          parse_function(function,
                         where,
                         expression,
                         expression,
                         FunctionParser<dim>::default_variable_names(),
                         constants,
                         false,
                         std::string("an expression in x, y") +
                           (dim == 3 ? ", z" : ""));
        }

        bool
        inside(const Point<dim> &x) const override
        {
          return function.value(x) <= 0;
        }

        BoundingBox<dim>
        bounding_box() const override
        {
          return whole_space<dim>();
        }

      private:
        FunctionParser<dim> function;
      };



      template <int dim>
      class Combined : public Shape<dim>
      {
      public:
        Combined(Combination                                combination,
                 std::vector<std::unique_ptr<Shape<dim>>> &&parts)
          : combination(combination)
          , parts(std::move(parts))
        {}

        bool
        inside(const Point<dim> &x) const override
        {
          switch (combination)
            {
              case Combination::union_of:
                for (const auto &part : parts)
                  if (part->inside(x))
                    return true;
                return false;
              case Combination::intersection_of:
                for (const auto &part : parts)
                  if (!part->inside(x))
                    return false;
                return true;
              default:
                if (!parts[0]->inside(x))
                  return false;
                for (unsigned int i = 1; i < parts.size(); ++i)
                  if (parts[i]->inside(x))
                    return false;
                return true;
            }
        }

        BoundingBox<dim>
        bounding_box() const override
        {
          BoundingBox<dim> box = parts[0]->bounding_box();
          if (combination == Combination::union_of)
            for (unsigned int i = 1; i < parts.size(); ++i)
              box.merge_with(parts[i]->bounding_box());
          else if (combination == Combination::intersection_of)
            for (unsigned int i = 1; i < parts.size(); ++i)
              {
                const BoundingBox<dim> other = parts[i]->bounding_box();
                Point<dim>             lower, upper;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    lower[d] =
                      std::max(box.lower_bound(d), other.lower_bound(d));
                    upper[d] = std::max(lower[d],
                                        std::min(box.upper_bound(d),
                                                 other.upper_bound(d)));
                  }
                box = BoundingBox<dim>(std::make_pair(lower, upper));
              }
          return box;
        }

      private:
        const Combination                        combination;
        std::vector<std::unique_ptr<Shape<dim>>> parts;
      };



      template <int dim>
      Tensor<2, dim>
      rotation_matrix(const double angle, const Tensor<1, 3> &axis)
      {
        if constexpr (dim == 2)
          {
            (void)axis;
            return Physics::Transformations::Rotations::rotation_matrix_2d(
              angle);
          }
        else
          return Physics::Transformations::Rotations::rotation_matrix_3d(
            axis / axis.norm(), angle);
      }



      /** x = about + R (X - about) + translation for X of the original
       * shape. */
      template <int dim>
      class Transformed : public Shape<dim>
      {
      public:
        Transformed(std::unique_ptr<Shape<dim>> &&shape,
                    const double                  angle,
                    const Tensor<1, 3>           &axis,
                    const Point<dim>             &about,
                    const Tensor<1, dim>         &translation)
          : shape(std::move(shape))
          , rotation(rotation_matrix<dim>(angle, axis))
          , about(about)
          , translation(translation)
        {}

        bool
        inside(const Point<dim> &x) const override
        {
          return shape->inside(about +
                               transpose(rotation) * (x - translation - about));
        }

        BoundingBox<dim>
        bounding_box() const override
        {
          const BoundingBox<dim> box = shape->bounding_box();
          for (unsigned int d = 0; d < dim; ++d)
            if (!is_bounded(box, d))
              return whole_space<dim>();
          Point<dim> lower, upper;
          for (unsigned int d = 0; d < dim; ++d)
            {
              lower[d] = std::numeric_limits<double>::max();
              upper[d] = -std::numeric_limits<double>::max();
            }
          for (unsigned int v = 0;
               v < dealii::GeometryInfo<dim>::vertices_per_cell;
               ++v)
            {
              const Point<dim> x =
                about + rotation * (box.vertex(v) - about) + translation;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  lower[d] = std::min(lower[d], x[d]);
                  upper[d] = std::max(upper[d], x[d]);
                }
            }
          return BoundingBox<dim>(std::make_pair(lower, upper));
        }

      private:
        const std::unique_ptr<Shape<dim>> shape;
        const Tensor<2, dim>              rotation;
        const Point<dim>                  about;
        const Tensor<1, dim>              translation;
      };
    } // namespace



    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_box(const Point<dim> &center, const Tensor<1, dim> &half_lengths)
    {
      return std::make_unique<Box<dim>>(center, half_lengths);
    }



    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_ellipsoid(const Point<dim> &center, const Tensor<1, dim> &semi_axes)
    {
      return std::make_unique<Ellipsoid<dim>>(center, semi_axes);
    }



    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_cylinder(const Point<dim> &p0, const Point<dim> &p1, double radius)
    {
      return std::make_unique<Cylinder<dim>>(p0, p1, radius);
    }



    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_half_space(const Point<dim> &point, const Tensor<1, dim> &normal)
    {
      return std::make_unique<HalfSpace<dim>>(point, normal);
    }



    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_level_set(const std::string                   &expression,
                   const std::map<std::string, double> &constants,
                   const std::string                   &where)
    {
      return std::make_unique<LevelSet<dim>>(expression, constants, where);
    }



    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_combination(Combination                                combination,
                     std::vector<std::unique_ptr<Shape<dim>>> &&parts)
    {
      return std::make_unique<Combined<dim>>(combination, std::move(parts));
    }



    template <int dim>
    std::unique_ptr<Shape<dim>>
    make_transformed(std::unique_ptr<Shape<dim>> &&shape,
                     const double                  angle,
                     const Tensor<1, 3>           &axis,
                     const Point<dim>             &about,
                     const Tensor<1, dim>         &translation)
    {
      return std::make_unique<Transformed<dim>>(
        std::move(shape), angle, axis, about, translation);
    }



#define FMPM_INSTANTIATE(dim)                                                  \
  template bool is_bounded<dim>(const BoundingBox<dim> &, const unsigned int); \
  template std::unique_ptr<Shape<dim>> make_box<dim>(const Point<dim> &,       \
                                                     const Tensor<1, dim> &);  \
  template std::unique_ptr<Shape<dim>> make_ellipsoid<dim>(                    \
    const Point<dim> &, const Tensor<1, dim> &);                               \
  template std::unique_ptr<Shape<dim>> make_cylinder<dim>(const Point<dim> &,  \
                                                          const Point<dim> &,  \
                                                          double);             \
  template std::unique_ptr<Shape<dim>> make_half_space<dim>(                   \
    const Point<dim> &, const Tensor<1, dim> &);                               \
  template std::unique_ptr<Shape<dim>> make_level_set<dim>(                    \
    const std::string &,                                                       \
    const std::map<std::string, double> &,                                     \
    const std::string &);                                                      \
  template std::unique_ptr<Shape<dim>> make_combination<dim>(                  \
    Combination, std::vector<std::unique_ptr<Shape<dim>>> &&);                 \
  template std::unique_ptr<Shape<dim>> make_transformed<dim>(                  \
    std::unique_ptr<Shape<dim>> &&,                                            \
    double,                                                                    \
    const Tensor<1, 3> &,                                                      \
    const Point<dim> &,                                                        \
    const Tensor<1, dim> &);
    FMPM_INSTANTIATE(2)
    FMPM_INSTANTIATE(3)
#undef FMPM_INSTANTIATE
  } // namespace Geometry
} // namespace fmpm
