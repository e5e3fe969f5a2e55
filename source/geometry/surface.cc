// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The region enclosed by a closed triangulated surface (STL, ASCII or
// binary). A point is inside when rays from it along +x, +y and +z cross the
// surface an odd number of times, decided by a vote of the three rays, so
// that a ray through an edge or vertex (counted twice or not at all) is
// outvoted. For each ray direction a grid of columns over the other two
// coordinates lists the triangles whose projection meets each column: a
// ray tests only the triangles of its column.

#include <fmpm/geometry/shape.h>
#include <fmpm/parameters.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace fmpm
{
  namespace Geometry
  {
    namespace
    {
      using Triangle = std::array<Point<3>, 3>;

      std::string
      point_text(const Point<3> &p)
      {
        return "(" + format_number(p[0], 8) + ", " + format_number(p[1], 8) +
               ", " + format_number(p[2], 8) + ")";
      }

      /** The triangles of an STL file, binary or ASCII. */
      std::vector<Triangle>
      read_stl(const std::string &file_name, const std::string &where)
      {
        std::ifstream in(file_name, std::ios::binary);
        AssertThrow(in.good(),
                    ExcMessage(where + " = <" + file_name +
                               "> cannot be read: the surface file is "
                               "missing or not readable."));
        const std::string     bytes((std::istreambuf_iterator<char>(in)),
                                std::istreambuf_iterator<char>());
        std::vector<Triangle> triangles;
        // Binary: an 80-byte header, the count, 50 bytes per triangle.
        if (bytes.size() >= 84)
          {
            std::uint32_t n = 0;
            std::memcpy(&n, bytes.data() + 80, 4);
            if (bytes.size() == 84 + 50 * static_cast<std::size_t>(n))
              {
                triangles.resize(n);
                for (std::size_t t = 0; t < n; ++t)
                  for (unsigned int v = 0; v < 3; ++v)
                    for (unsigned int d = 0; d < 3; ++d)
                      {
                        float value;
                        std::memcpy(&value,
                                    bytes.data() + 84 + 50 * t + 12 * (v + 1) +
                                      4 * d,
                                    4);
                        triangles[t][v][d] = value;
                      }
                return triangles;
              }
          }
        std::istringstream text(bytes);
        std::string        word;
        text >> word;
        AssertThrow(word == "solid",
                    ExcMessage(where + " = <" + file_name +
                               "> is not an STL file: neither binary (80 "
                               "bytes, a count, 50 bytes per triangle) nor "
                               "ASCII (starting with 'solid')."));
        Triangle     triangle;
        unsigned int n_vertices = 0;
        while (text >> word)
          if (word == "vertex")
            {
              Point<3> &p = triangle[n_vertices % 3];
              AssertThrow(text >> p[0] >> p[1] >> p[2],
                          ExcMessage(where + " = <" + file_name +
                                     ">: a 'vertex' without three numbers "
                                     "(triangle " +
                                     std::to_string(triangles.size()) + ")."));
              if (++n_vertices % 3 == 0)
                triangles.push_back(triangle);
            }
        AssertThrow(n_vertices % 3 == 0,
                    ExcMessage(where + " = <" + file_name +
                               ">: the last facet has fewer than three "
                               "vertices."));
        return triangles;
      }



      /** The triangles of a Wavefront OBJ file: its 'v x y z' vertices
       * and 'f i j k ...' faces (1-based or negative indices, 'i/t/n'
       * forms; a polygon face split into a fan of triangles). */
      std::vector<Triangle>
      read_obj(const std::string &file_name, const std::string &where)
      {
        std::ifstream in(file_name);
        AssertThrow(in.good(),
                    ExcMessage(where + " = <" + file_name +
                               "> cannot be read: the surface file is "
                               "missing or not readable."));
        std::vector<Point<3>> vertices;
        std::vector<Triangle> triangles;
        std::string           line;
        unsigned int          line_number = 0;
        while (std::getline(in, line))
          {
            ++line_number;
            std::istringstream words(line);
            std::string        keyword;
            if (!(words >> keyword))
              continue;
            const std::string at = where + " = <" + file_name + ">, line " +
                                   std::to_string(line_number) + ": ";
            if (keyword == "v")
              {
                Point<3> p;
                AssertThrow(words >> p[0] >> p[1] >> p[2],
                            ExcMessage(at + "a vertex 'v' needs three "
                                            "numbers."));
                vertices.push_back(p);
              }
            else if (keyword == "f")
              {
                std::vector<Point<3>> corners;
                std::string           corner;
                while (words >> corner)
                  {
                    int index = 0;
                    try
                      {
                        index = std::stoi(corner.substr(0, corner.find('/')));
                      }
                    catch (const std::exception &)
                      {
                        AssertThrow(false,
                                    ExcMessage(at + "'" + corner +
                                               "' is not a vertex index."));
                      }
                    const long resolved =
                      index < 0 ? static_cast<long>(vertices.size()) + index :
                                  index - 1;
                    AssertThrow(index != 0 && resolved >= 0 &&
                                  resolved < static_cast<long>(vertices.size()),
                                ExcMessage(at + "vertex index " + corner +
                                           " names no vertex read so far (" +
                                           std::to_string(vertices.size()) +
                                           ")."));
                    corners.push_back(vertices[resolved]);
                  }
                AssertThrow(corners.size() >= 3,
                            ExcMessage(at + "a face needs at least three "
                                            "vertices."));
                for (unsigned int k = 1; k + 1 < corners.size(); ++k)
                  triangles.push_back(
                    {{corners[0], corners[k], corners[k + 1]}});
              }
          }
        return triangles;
      }



      class Surface : public Shape<3>
      {
      public:
        Surface(const std::vector<Triangle> &triangles)
          : triangles(triangles)
        {
          Point<3> lower = triangles[0][0], upper = triangles[0][0];
          for (const Triangle &t : triangles)
            for (const Point<3> &p : t)
              for (unsigned int d = 0; d < 3; ++d)
                {
                  lower[d] = std::min(lower[d], p[d]);
                  upper[d] = std::max(upper[d], p[d]);
                }
          box = BoundingBox<3>(std::make_pair(lower, upper));
          // About one triangle per column on a surface of n triangles
          // spread over the two coordinates: sqrt(n) columns a side.
          n_columns = std::max<unsigned int>(
            1, std::min<unsigned int>(1024, std::sqrt(triangles.size())));
          for (unsigned int axis = 0; axis < 3; ++axis)
            {
              auto &grid = column_triangles[axis];
              grid.assign(n_columns * n_columns, {});
              for (unsigned int t = 0; t < triangles.size(); ++t)
                {
                  std::array<unsigned int, 2> first, last;
                  for (unsigned int k = 0; k < 2; ++k)
                    {
                      const unsigned int d  = (axis + 1 + k) % 3;
                      double             lo = triangles[t][0][d], hi = lo;
                      for (const Point<3> &p : triangles[t])
                        {
                          lo = std::min(lo, p[d]);
                          hi = std::max(hi, p[d]);
                        }
                      first[k] = column(lo, d);
                      last[k]  = column(hi, d);
                    }
                  for (unsigned int i = first[0]; i <= last[0]; ++i)
                    for (unsigned int j = first[1]; j <= last[1]; ++j)
                      grid[i * n_columns + j].push_back(t);
                }
            }
        }

        bool
        inside(const Point<3> &x) const override
        {
          if (!box.point_inside(x))
            return false;
          unsigned int votes = 0;
          for (unsigned int axis = 0; axis < 3; ++axis)
            votes += odd_crossings(x, axis);
          return votes >= 2;
        }

        BoundingBox<3>
        bounding_box() const override
        {
          return box;
        }

      private:
        std::vector<Triangle> triangles;
        BoundingBox<3>        box;
        unsigned int          n_columns;
        /** For rays along each axis, the triangles meeting each column. */
        std::array<std::vector<std::vector<unsigned int>>, 3> column_triangles;

        unsigned int
        column(const double coordinate, const unsigned int d) const
        {
          const double width = box.upper_bound(d) - box.lower_bound(d);
          if (width <= 0)
            return 0;
          const double s = (coordinate - box.lower_bound(d)) / width;
          return std::min<unsigned int>(n_columns - 1,
                                        std::max(0., s * n_columns));
        }

        /** Whether the ray from @p x along +axis crosses the surface an odd
         * number of times. */
        bool
        odd_crossings(const Point<3> &x, const unsigned int axis) const
        {
          const unsigned int a = (axis + 1) % 3, b = (axis + 2) % 3;
          const auto        &list =
            column_triangles[axis]
                            [column(x[a], a) * n_columns + column(x[b], b)];
          bool odd = false;
          for (const unsigned int t : list)
            {
              const Triangle &tri = triangles[t];
              // Barycentric weights of (x_a, x_b) in the projected
              // triangle.
              const double e0 = (tri[1][a] - x[a]) * (tri[2][b] - x[b]) -
                                (tri[2][a] - x[a]) * (tri[1][b] - x[b]);
              const double e1 = (tri[2][a] - x[a]) * (tri[0][b] - x[b]) -
                                (tri[0][a] - x[a]) * (tri[2][b] - x[b]);
              const double e2 = (tri[0][a] - x[a]) * (tri[1][b] - x[b]) -
                                (tri[1][a] - x[a]) * (tri[0][b] - x[b]);
              const bool hit = (e0 >= 0 && e1 >= 0 && e2 >= 0) ||
                               (e0 <= 0 && e1 <= 0 && e2 <= 0);
              const double sum = e0 + e1 + e2;
              if (!hit || sum == 0)
                continue;
              const double crossing =
                (e0 * tri[0][axis] + e1 * tri[1][axis] + e2 * tri[2][axis]) /
                sum;
              if (crossing > x[axis])
                odd = !odd;
            }
          return odd;
        }
      };
    } // namespace



    std::unique_ptr<Shape<3>>
    make_surface(const std::string &file_name, const std::string &where)
    {
      std::string extension = std::filesystem::path(file_name).extension();
      std::transform(extension.begin(),
                     extension.end(),
                     extension.begin(),
                     [](const unsigned char c) { return std::tolower(c); });
      const std::vector<Triangle> triangles = extension == ".obj" ?
                                                read_obj(file_name, where) :
                                                read_stl(file_name, where);
      AssertThrow(!triangles.empty(),
                  ExcMessage(where + " = <" + file_name +
                             "> holds no triangle."));
      // Closed: every edge (between vertices with equal coordinates) is
      // shared by exactly two triangles.
      std::map<std::array<double, 3>, unsigned int> vertex_index;
      std::vector<Point<3>>                         vertices;
      const auto index = [&](const Point<3> &p) {
        const std::array<double, 3> key{{p[0], p[1], p[2]}};
        const auto [it, is_new] = vertex_index.emplace(key, vertices.size());
        if (is_new)
          vertices.push_back(p);
        return it->second;
      };
      std::map<std::pair<unsigned int, unsigned int>, unsigned int> n_uses;
      std::vector<std::pair<unsigned int, unsigned int>>            edge_order;
      for (const Triangle &t : triangles)
        for (unsigned int v = 0; v < 3; ++v)
          {
            const unsigned int i = index(t[v]), j = index(t[(v + 1) % 3]);
            const auto edge = std::make_pair(std::min(i, j), std::max(i, j));
            if (n_uses[edge]++ == 0)
              edge_order.push_back(edge);
          }
      for (const auto &edge : edge_order)
        AssertThrow(n_uses[edge] == 2,
                    ExcMessage(
                      where + " = <" + file_name +
                      "> is not a closed surface: the edge " +
                      point_text(vertices[edge.first]) + "-" +
                      point_text(vertices[edge.second]) + " belongs to " +
                      std::to_string(n_uses[edge]) +
                      " triangle(s), not 2. A body needs a closed "
                      "(watertight) surface; close it in the CAD or mesh "
                      "tool."));
      return std::make_unique<Surface>(triangles);
    }
  } // namespace Geometry
} // namespace fmpm
