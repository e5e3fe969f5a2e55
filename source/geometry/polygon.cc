// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Polygons (2D): vertices from the scene or a file; the inside test is the
// even-odd rule (a horizontal ray crosses the boundary an odd number of
// times), which holds for any simple polygon, convex or not.

#include <fmpm/geometry/shape.h>
#include <fmpm/parameters.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <fstream>
#include <sstream>

namespace fmpm
{
  namespace Geometry
  {
    namespace
    {
      /** Twice the signed area of (a, b, c). */
      double
      orientation(const Point<2> &a, const Point<2> &b, const Point<2> &c)
      {
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
      }

      bool
      on_segment(const Point<2> &a, const Point<2> &b, const Point<2> &p)
      {
        return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) &&
               std::min(a[1], b[1]) <= p[1] && p[1] <= std::max(a[1], b[1]);
      }

      /** Whether the closed segments ab and cd share a point. */
      bool
      segments_meet(const Point<2> &a,
                    const Point<2> &b,
                    const Point<2> &c,
                    const Point<2> &d)
      {
        const double o1 = orientation(a, b, c), o2 = orientation(a, b, d),
                     o3 = orientation(c, d, a), o4 = orientation(c, d, b);
        if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) &&
            ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
          return true;
        return (o1 == 0 && on_segment(a, b, c)) ||
               (o2 == 0 && on_segment(a, b, d)) ||
               (o3 == 0 && on_segment(c, d, a)) ||
               (o4 == 0 && on_segment(c, d, b));
      }

      std::string
      point_text(const Point<2> &p)
      {
        return "(" + format_number(p[0], 8) + ", " + format_number(p[1], 8) +
               ")";
      }



      class Polygon : public Shape<2>
      {
      public:
        explicit Polygon(const std::vector<Point<2>> &vertices)
          : vertices(vertices)
        {
          Point<2> lower = vertices[0], upper = vertices[0];
          for (const Point<2> &v : vertices)
            for (unsigned int d = 0; d < 2; ++d)
              {
                lower[d] = std::min(lower[d], v[d]);
                upper[d] = std::max(upper[d], v[d]);
              }
          box = BoundingBox<2>(std::make_pair(lower, upper));
        }

        bool
        inside(const Point<2> &x) const override
        {
          if (!box.point_inside(x))
            return false;
          // Even-odd rule, with a half-open rule for vertices on the ray.
          bool               odd = false;
          const unsigned int n   = vertices.size();
          for (unsigned int i = 0, j = n - 1; i < n; j = i++)
            {
              const Point<2> &a = vertices[i], &b = vertices[j];
              if ((a[1] > x[1]) != (b[1] > x[1]) &&
                  x[0] < (b[0] - a[0]) * (x[1] - a[1]) / (b[1] - a[1]) + a[0])
                odd = !odd;
            }
          return odd;
        }

        BoundingBox<2>
        bounding_box() const override
        {
          return box;
        }

      private:
        const std::vector<Point<2>> vertices;
        BoundingBox<2>              box;
      };
    } // namespace



    std::unique_ptr<Shape<2>>
    make_polygon(const std::vector<Point<2>> &given_vertices,
                 const std::string           &where)
    {
      std::vector<Point<2>> vertices = given_vertices;
      // A closing vertex equal to the first is allowed.
      if (vertices.size() > 1 && vertices.front() == vertices.back())
        vertices.pop_back();
      AssertThrow(vertices.size() >= 3,
                  ExcMessage(where +
                             ": a polygon needs at least three "
                             "distinct vertices; it has " +
                             std::to_string(vertices.size()) + "."));
      const unsigned int n = vertices.size();
      for (unsigned int i = 0; i < n; ++i)
        AssertThrow(vertices[i] != vertices[(i + 1) % n],
                    ExcMessage(where + ": polygon vertices " +
                               std::to_string(i) + " and " +
                               std::to_string((i + 1) % n) + " coincide at " +
                               point_text(vertices[i]) + "."));
      // Every pair of edges that are not neighbours must not meet;
      // neighbours meet only at their shared vertex (no fold back).
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = i + 1; j < n; ++j)
          {
            const Point<2> &a = vertices[i], &b = vertices[(i + 1) % n];
            const Point<2> &c = vertices[j], &d = vertices[(j + 1) % n];
            const bool      neighbours = (j == i + 1) || (i == 0 && j == n - 1);
            bool            meet       = false;
            if (!neighbours)
              meet = segments_meet(a, b, c, d);
            else
              {
                // Neighbours fold back when they are collinear and
                // overlap beyond the shared vertex.
                const Point<2> &shared = (j == i + 1) ? b : a;
                const Point<2> &p      = (j == i + 1) ? a : b;
                const Point<2> &q      = (j == i + 1) ? d : c;
                meet                   = orientation(p, shared, q) == 0 &&
                       (q - shared) * (p - shared) > 0;
              }
            AssertThrow(!meet,
                        ExcMessage(where +
                                   ": the polygon intersects itself: "
                                   "edge " +
                                   std::to_string(i) + " " + point_text(a) +
                                   "-" + point_text(b) + " meets edge " +
                                   std::to_string(j) + " " + point_text(c) +
                                   "-" + point_text(d) +
                                   ". Give the vertices in order along "
                                   "the boundary."));
          }
      return std::make_unique<Polygon>(vertices);
    }



    std::vector<Point<2>>
    read_polygon_file(const std::string &file_name, const std::string &where)
    {
      std::ifstream in(file_name);
      AssertThrow(in.good(),
                  ExcMessage(where + " = <" + file_name +
                             "> cannot be read: the polygon's vertex file "
                             "is missing or not readable."));
      std::vector<Point<2>> vertices;
      std::string           line;
      unsigned int          line_number = 0;
      while (std::getline(in, line))
        {
          ++line_number;
          line = line.substr(0, line.find('#'));
          std::replace(line.begin(), line.end(), ',', ' ');
          if (Utilities::trim(line).empty())
            continue;
          std::istringstream values(line);
          Point<2>           p;
          std::string        rest;
          AssertThrow((values >> p[0] >> p[1]) && !(values >> rest),
                      ExcMessage(where + " = <" + file_name + ">, line " +
                                 std::to_string(line_number) +
                                 ": expected two numbers 'x y' (a "
                                 "polygon vertex), found '" +
                                 Utilities::trim(line) + "'."));
          vertices.push_back(p);
        }
      return vertices;
    }
  } // namespace Geometry
} // namespace fmpm
