// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The shape formulas of 'Body N/Shape': a recursive-descent parser of
//   formula  := term { ('+' | '-') term }
//   term     := factor { '*' factor }
//   factor   := '(' formula ')' | name '(' argument { ';' argument } ')'
//   argument := formula | "text" | file | number { ',' number }

#include <fmpm/geometry/shape.h>
#include <fmpm/parameters.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace fmpm
{
  namespace Geometry
  {
    namespace
    {
      template <int dim>
      struct Argument
      {
        std::vector<double>         numbers;
        std::unique_ptr<Shape<dim>> shape;
        std::string                 text;
        bool                        is_text = false;
        bool                        is_file = false;
      };



      template <int dim>
      class Parser
      {
      public:
        Parser(const std::string &formula, const ShapeContext &context)
          : formula(formula)
          , context(context)
        {}

        std::unique_ptr<Shape<dim>>
        parse()
        {
          auto shape = parse_formula();
          skip_space();
          if (position != formula.size())
            fail("unexpected '" + formula.substr(position, 1) +
                 "' (expected '+', '-', '*' or the end)");
          return shape;
        }

      private:
        const std::string  &formula;
        const ShapeContext &context;
        std::size_t         position = 0;

        [[noreturn]] void
        fail(const std::string &what) const
        {
          AssertThrow(false,
                      ExcMessage(
                        context.where + " = " + formula + " is not a shape: " +
                        what + " at character " + std::to_string(position + 1) +
                        ". Shapes: box(center; half lengths), sphere(center; "
                        "radius), ellipsoid(center; semi-axes), "
                        "cylinder(end; end; radius), polygon(x0, y0; x1, y1; "
                        "...) or polygon(file), halfspace(point; normal), "
                        "expression(\"f(x, y, z)\"), surface(file), "
                        "rotate(angle; [axis;] [point;] shape), "
                        "translate(displacement; shape), combined with + "
                        "(union), - (difference), * (intersection) and "
                        "parentheses."));
          std::abort();
        }

        void
        skip_space()
        {
          while (position < formula.size() &&
                 std::isspace(static_cast<unsigned char>(formula[position])))
            ++position;
        }

        /** The next non-space character, or 0 at the end. */
        char
        peek()
        {
          skip_space();
          return position < formula.size() ? formula[position] : 0;
        }

        void
        expect(const char c)
        {
          if (peek() != c)
            fail(std::string("expected '") + c + "'" +
                 (position < formula.size() ?
                    ", found '" + formula.substr(position, 1) + "'" :
                    ", found the end"));
          ++position;
        }

        std::string
        name()
        {
          skip_space();
          const std::size_t start = position;
          while (position < formula.size() &&
                 (std::isalnum(static_cast<unsigned char>(formula[position])) ||
                  formula[position] == '_'))
            ++position;
          return formula.substr(start, position - start);
        }

        std::unique_ptr<Shape<dim>>
        parse_formula()
        {
          auto left = parse_term();
          while (peek() == '+' || peek() == '-')
            {
              const Combination combination = formula[position] == '+' ?
                                                Combination::union_of :
                                                Combination::difference_of;
              ++position;
              std::vector<std::unique_ptr<Shape<dim>>> parts;
              parts.push_back(std::move(left));
              parts.push_back(parse_term());
              left = make_combination<dim>(combination, std::move(parts));
            }
          return left;
        }

        std::unique_ptr<Shape<dim>>
        parse_term()
        {
          auto left = parse_factor();
          while (peek() == '*')
            {
              ++position;
              std::vector<std::unique_ptr<Shape<dim>>> parts;
              parts.push_back(std::move(left));
              parts.push_back(parse_factor());
              left = make_combination<dim>(Combination::intersection_of,
                                           std::move(parts));
            }
          return left;
        }

        std::unique_ptr<Shape<dim>>
        parse_factor()
        {
          if (peek() == '(')
            {
              ++position;
              auto shape = parse_formula();
              expect(')');
              return shape;
            }
          const std::size_t start      = position;
          const std::string shape_name = name();
          if (shape_name.empty())
            fail("expected a shape name or '('");
          expect('(');
          std::vector<Argument<dim>> arguments;
          arguments.push_back(parse_argument());
          while (peek() == ';')
            {
              ++position;
              arguments.push_back(parse_argument());
            }
          expect(')');
          return build(shape_name, std::move(arguments), start);
        }

        Argument<dim>
        parse_argument()
        {
          Argument<dim> argument;
          const char    c = peek();
          if (c == '"')
            {
              const std::size_t end = formula.find('"', position + 1);
              if (end == std::string::npos)
                fail("a text without its closing '\"'");
              argument.text = formula.substr(position + 1, end - position - 1);
              argument.is_text = true;
              position         = end + 1;
              return argument;
            }
          if (std::isalpha(static_cast<unsigned char>(c)) || c == '(')
            {
              const std::size_t start = position;
              if (name() == "file")
                {
                  argument.is_file = true;
                  return argument;
                }
              position       = start;
              argument.shape = parse_formula();
              return argument;
            }
          argument.numbers.push_back(number());
          while (peek() == ',')
            {
              ++position;
              argument.numbers.push_back(number());
            }
          return argument;
        }

        double
        number()
        {
          skip_space();
          const char  *begin = formula.c_str() + position;
          char        *end   = nullptr;
          const double value = std::strtod(begin, &end);
          if (end == begin || !std::isfinite(value))
            fail("expected a number");
          position += end - begin;
          return value;
        }

        /** The arguments' kinds as a word list, for messages. */
        void
        check_count(const std::string                &shape_name,
                    const std::vector<Argument<dim>> &arguments,
                    const std::vector<unsigned int>  &counts,
                    const std::string                &usage,
                    const std::size_t                 start)
        {
          bool ok = arguments.size() == counts.size();
          for (unsigned int i = 0; ok && i < counts.size(); ++i)
            ok = !arguments[i].shape && !arguments[i].is_text &&
                 !arguments[i].is_file &&
                 arguments[i].numbers.size() == counts[i];
          if (!ok)
            {
              position = start;
              fail(shape_name + "(...) takes " + usage + " (" +
                   std::to_string(dim) + "D)");
            }
        }

        static Point<dim>
        to_point(const std::vector<double> &values)
        {
          Point<dim> p;
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = values[d];
          return p;
        }

        /** box, sphere, ellipsoid, cylinder, halfspace and expression
         * (null for another name). */
        std::unique_ptr<Shape<dim>>
        build_primitive(const std::string                &shape_name,
                        const std::vector<Argument<dim>> &arguments,
                        const std::size_t                 start)
        {
          const unsigned int D        = dim;
          const auto         positive = [&](const std::vector<double> &values,
                                    const std::string         &what) {
            for (const double v : values)
              if (!(v > 0))
                {
                  position = start;
                  fail(shape_name + "(...): the " + what + " must be positive");
                }
          };
          if (shape_name == "box" || shape_name == "rectangle")
            {
              check_count(
                shape_name, arguments, {D, D}, "center; half lengths", start);
              positive(arguments[1].numbers, "half lengths");
              return make_box<dim>(to_point(arguments[0].numbers),
                                   to_point(arguments[1].numbers));
            }
          if (shape_name == "sphere" || shape_name == "disk" ||
              shape_name == "circle")
            {
              check_count(
                shape_name, arguments, {D, 1}, "center; radius", start);
              positive(arguments[1].numbers, "radius");
              Tensor<1, dim> radii;
              for (unsigned int d = 0; d < dim; ++d)
                radii[d] = arguments[1].numbers[0];
              return make_ellipsoid<dim>(to_point(arguments[0].numbers), radii);
            }
          if (shape_name == "ellipsoid" || shape_name == "ellipse")
            {
              check_count(
                shape_name, arguments, {D, D}, "center; semi-axes", start);
              positive(arguments[1].numbers, "semi-axes");
              return make_ellipsoid<dim>(to_point(arguments[0].numbers),
                                         to_point(arguments[1].numbers));
            }
          if (shape_name == "cylinder")
            {
              check_count(shape_name,
                          arguments,
                          {D, D, 1},
                          "end point; end point; radius",
                          start);
              positive(arguments[2].numbers, "radius");
              const Point<dim> p0 = to_point(arguments[0].numbers),
                               p1 = to_point(arguments[1].numbers);
              if (p0 == p1)
                {
                  position = start;
                  fail("cylinder(...): its two end points coincide");
                }
              return make_cylinder<dim>(p0, p1, arguments[2].numbers[0]);
            }
          if (shape_name == "halfspace")
            {
              check_count(
                shape_name, arguments, {D, D}, "point; outward normal", start);
              const Tensor<1, dim> normal = to_point(arguments[1].numbers);
              if (normal.norm() == 0)
                {
                  position = start;
                  fail("halfspace(...): its normal is zero");
                }
              return make_half_space<dim>(to_point(arguments[0].numbers),
                                          normal);
            }
          if (shape_name == "expression")
            {
              if (arguments.size() != 1 || !arguments[0].is_text)
                {
                  position = start;
                  fail("expression(...) takes one quoted expression, e.g. "
                       "expression(\"x*x + y*y - 0.01\")");
                }
              return make_level_set<dim>(arguments[0].text,
                                         context.constants,
                                         context.where + " (expression \"" +
                                           arguments[0].text + "\")");
            }
          return nullptr;
        }

        /** polygon(vertices) or polygon(file) (2D). */
        std::unique_ptr<Shape<dim>>
        build_polygon(const std::vector<Argument<dim>> &arguments,
                      const std::size_t                 start)
        {
          if constexpr (dim == 2)
            {
              std::vector<Point<2>> vertices;
              if (arguments.size() == 1 && arguments[0].is_file)
                {
                  if (context.file_name.empty())
                    {
                      position = start;
                      fail("polygon(file) needs the body's 'File name' "
                           "(" +
                           context.file_parameter + ")");
                    }
                  vertices = read_polygon_file(context.file_name,
                                               context.file_parameter);
                }
              else
                for (const auto &argument : arguments)
                  {
                    if (argument.shape || argument.is_text ||
                        argument.is_file || argument.numbers.size() != 2)
                      {
                        position = start;
                        fail("polygon(...) takes vertices 'x, y' "
                             "separated by ';', or 'file'");
                      }
                    vertices.emplace_back(argument.numbers[0],
                                          argument.numbers[1]);
                  }
              return make_polygon(vertices, context.where);
            }
          else
            {
              position = start;
              fail("polygon(...) is a 2D shape; in 3D use a prism as "
                   "the intersection of half-spaces or a surface(file)");
            }
        }

        /** surface(file) (3D). */
        std::unique_ptr<Shape<dim>>
        build_surface(const std::vector<Argument<dim>> &arguments,
                      const std::size_t                 start)
        {
          if constexpr (dim == 3)
            {
              if (arguments.size() != 1 || !arguments[0].is_file ||
                  context.file_name.empty())
                {
                  position = start;
                  fail("surface(file) reads the body's 'File name' (" +
                       context.file_parameter + ")");
                }
              return make_surface(context.file_name, context.file_parameter);
            }
          else
            {
              position = start;
              fail("surface(file) is a 3D shape; in 2D use "
                   "polygon(file)");
            }
        }

        /** rotate(angle; [axis (3D);] [point;] shape). */
        std::unique_ptr<Shape<dim>>
        build_rotated(std::vector<Argument<dim>> &&arguments,
                      const std::size_t            start)
        {
          // rotate(angle; [axis (3D);] [point;] shape)
          const unsigned int n  = arguments.size();
          bool               ok = n >= 2 && arguments[n - 1].shape &&
                    arguments[0].numbers.size() == 1;
          const unsigned int first_point = (dim == 3) ? 2 : 1;
          ok = ok && (dim == 2 || (n >= 3 && arguments[1].numbers.size() == 3));
          ok = ok && (n == first_point + 1 ||
                      (n == first_point + 2 &&
                       arguments[first_point].numbers.size() == dim));
          if (!ok)
            {
              position = start;
              fail(std::string("rotate(...) takes ") +
                   (dim == 2 ? "angle; [point;] shape" :
                               "angle; axis; [point;] shape") +
                   " (angle in degrees, counterclockwise)");
            }
          Tensor<1, 3> axis;
          axis[2] = 1;
          if constexpr (dim == 3)
            for (unsigned int d = 0; d < 3; ++d)
              axis[d] = arguments[1].numbers[d];
          if (axis.norm() == 0)
            {
              position = start;
              fail("rotate(...): the rotation axis is zero");
            }
          std::unique_ptr<Shape<dim>> shape = std::move(arguments[n - 1].shape);
          Point<dim>                  about;
          if (n == first_point + 2)
            about = to_point(arguments[first_point].numbers);
          else
            {
              const BoundingBox<dim> box = shape->bounding_box();
              for (unsigned int d = 0; d < dim; ++d)
                if (!is_bounded(box, d))
                  {
                    position = start;
                    fail("rotate(...) of an unbounded shape needs the "
                         "point to rotate about");
                  }
              about = box.center();
            }
          return make_transformed<dim>(std::move(shape),
                                       arguments[0].numbers[0] * numbers::PI /
                                         180.,
                                       axis,
                                       about,
                                       Tensor<1, dim>());
        }

        /** translate(displacement; shape). */
        std::unique_ptr<Shape<dim>>
        build_translated(std::vector<Argument<dim>> &&arguments,
                         const std::size_t            start)
        {
          if (arguments.size() != 2 || arguments[0].numbers.size() != dim ||
              !arguments[1].shape)
            {
              position = start;
              fail("translate(...) takes displacement; shape");
            }
          Tensor<1, 3> axis;
          axis[2] = 1;
          return make_transformed<dim>(std::move(arguments[1].shape),
                                       0,
                                       axis,
                                       Point<dim>(),
                                       to_point(arguments[0].numbers));
        }

        std::unique_ptr<Shape<dim>>
        build(const std::string           &shape_name,
              std::vector<Argument<dim>> &&arguments,
              const std::size_t            start)
        {
          if (std::unique_ptr<Shape<dim>> shape =
                build_primitive(shape_name, arguments, start))
            return shape;
          if (shape_name == "polygon")
            return build_polygon(arguments, start);
          if (shape_name == "surface")
            return build_surface(arguments, start);
          if (shape_name == "rotate")
            return build_rotated(std::move(arguments), start);
          if (shape_name == "translate")
            return build_translated(std::move(arguments), start);
          position = start;
          fail("unknown shape '" + shape_name + "'");
        }
      };
    } // namespace



    template <int dim>
    std::unique_ptr<Shape<dim>>
    parse_shape(const std::string &formula, const ShapeContext &context)
    {
      return Parser<dim>(formula, context).parse();
    }



    template std::unique_ptr<Shape<2>>
    parse_shape<2>(const std::string &, const ShapeContext &);
    template std::unique_ptr<Shape<3>>
    parse_shape<3>(const std::string &, const ShapeContext &);
  } // namespace Geometry
} // namespace fmpm
