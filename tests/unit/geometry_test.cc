// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Bodies of any shape: the material points of a ring, an L-shape, a plate
// with a hole, a rotated ellipse, a level set, an oblique cylinder, a
// sphere given as a closed STL surface and a disk given as a Gmsh mesh of
// triangles have the exact volume within 1 % at 2 points per cell
// direction, and mass = density x volume; bad shapes are refused with a
// message naming the body and what is wrong.

#include <fmpm/geometry/shape.h>
#include <fmpm/particle_properties.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/numbers.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene_helpers.h"
#include <gtest/gtest.h>

using namespace fmpm_tests;

namespace
{
  struct Filled
  {
    double volume = 0;
    double mass   = 0;
  };

  /** Fill Body 0 of @p shape (and @p file) on a unit-cube mesh of @p n
   * cells a side, 2 points per cell direction, density 2000. */
  template <int dim>
  Filled
  fill(const std::string &shape,
       const std::string &file      = "",
       const unsigned int n         = 40,
       const std::string &constants = "")
  {
    const std::string scene =
      "set Dimension = " + std::to_string(dim) +
      "\nsubsection Mesh\n set Lower corner = " +
      (dim == 2 ? "0, 0" : "0, 0, 0") +
      "\n set Upper corner = " + (dim == 2 ? "1, 1" : "1, 1, 1") +
      "\n set Subdivisions = " +
      (dim == 2 ? std::to_string(n) + ", " + std::to_string(n) :
                  std::to_string(n) + ", " + std::to_string(n) + ", " +
                    std::to_string(n)) +
      "\nend\nsubsection Material 0\n set Density = 2000\nend\n"
      "subsection Body 0\n set Shape = " +
      shape + "\n set File name = " + file +
      "\n set Points per cell = 2\n set Function constants = " + constants +
      "\n set Initial velocity = " + (dim == 2 ? "0, 0" : "0, 0, 0") +
      "\nend\nsubsection Time\n set Maximum number of steps = 1\n set End "
      "time = 1e-9\nend\n" +
      output_overrides("output-geometry");
    ParameterHandler prm;
    auto             simulator = make_simulator<dim>({}, scene, prm);
    simulator->run();
    const auto &points = fmpm_tests::inspect(*simulator).get_material_points();
    Filled      filled;
    for (unsigned int k = 0; k < points.n_points(); ++k)
      {
        const auto p = points.record(k);
        filled.volume += p[fmpm::PropertyIndex<dim>::initial_volume];
        filled.mass += p[fmpm::PropertyIndex<dim>::mass];
      }
    filled.volume = Utilities::MPI::sum(filled.volume, MPI_COMM_WORLD);
    filled.mass   = Utilities::MPI::sum(filled.mass, MPI_COMM_WORLD);
    return filled;
  }

  template <int dim>
  void
  expect_volume(const std::string &shape,
                const double       exact,
                const std::string &file      = "",
                const unsigned int n         = 40,
                const std::string &constants = "")
  {
    const Filled filled = fill<dim>(shape, file, n, constants);
    EXPECT_NEAR(filled.volume, exact, 0.01 * exact) << shape;
    EXPECT_NEAR(filled.mass, 2000 * filled.volume, 1e-12 * filled.mass)
      << shape;
  }

  /** The message of the exception that @p f throws. */
  template <typename F>
  std::string
  error_of(const F &f)
  {
    try
      {
        f();
      }
    catch (const std::exception &e)
      {
        // One line: the message as words separated by single spaces.
        std::istringstream words(e.what());
        std::string        word, text;
        while (words >> word)
          text += (text.empty() ? "" : " ") + word;
        return text;
      }
    return "";
  }
} // namespace



TEST(Geometry, RingLShapePlateWithHoleHaveExactVolumes)
{
  const double pi = numbers::PI;
  expect_volume<2>("disk(0.5, 0.5; 0.3) - disk(0.5, 0.5; 0.15)",
                   pi * (0.09 - 0.0225));
  expect_volume<2>(
    "polygon(0.1, 0.1; 0.9, 0.1; 0.9, 0.4; 0.4, 0.4; 0.4, 0.9; 0.1, 0.9)",
    0.39);
  expect_volume<2>("box(0.5, 0.25; 0.4, 0.15) + box(0.25, 0.65; 0.15, 0.25)",
                   0.39);
  expect_volume<2>("box(0.5, 0.5; 0.4, 0.25) - disk(0.5, 0.5; 0.1)",
                   0.4 - pi * 0.01);
  expect_volume<2>("rotate(30; ellipse(0.5, 0.5; 0.3, 0.1))", pi * 0.03);
  expect_volume<2>("expression(\"(x-0.5)^2 + (y-0.5)^2 - r^2\") * "
                   "halfspace(0.5, 0.5; 0, -1)",
                   0.5 * pi * 0.0625,
                   "",
                   40,
                   "r=0.25");
  expect_volume<2>("translate(0.1, -0.1; cylinder(0.2, 0.4; 0.6, 0.8; 0.1))",
                   0.2 * std::sqrt(0.32));
}



TEST(Geometry, ObliqueCylinderHasExactVolume)
{
  // Axis (0.5, 0.4, 0) long, radius 0.2.
  expect_volume<3>("cylinder(0.25, 0.3, 0.5; 0.75, 0.7, 0.5; 0.2)",
                   numbers::PI * 0.04 * std::sqrt(0.41),
                   "",
                   32);
}



namespace
{
  /** The triangles of an ASCII STL file. */
  std::vector<std::array<Point<3>, 3>>
  read_ascii_stl(const std::string &file)
  {
    std::ifstream                        in(file);
    std::string                          word;
    std::vector<std::array<Point<3>, 3>> triangles;
    std::array<Point<3>, 3>              t;
    unsigned int                         n = 0;
    while (in >> word)
      if (word == "vertex")
        {
          in >> t[n % 3][0] >> t[n % 3][1] >> t[n % 3][2];
          if (++n % 3 == 0)
            triangles.push_back(t);
        }
    return triangles;
  }
} // namespace



// The enclosed volume of the shipped icosphere (exact: the sum of the
// signed tetrahedra of its faces with the origin), from the ASCII file and
// from the same triangles written as a binary STL.
TEST(Geometry, ClosedSurfaceHasItsEnclosedVolume)
{
  const std::string ascii     = parameter_dir + "meshes/sphere.stl";
  const auto        triangles = read_ascii_stl(ascii);
  ASSERT_EQ(triangles.size(), 320u);
  double exact = 0;
  for (const auto &t : triangles)
    exact += (t[0] * cross_product_3d(t[1], t[2])) / 6;
  exact = std::abs(exact);
  expect_volume<3>("surface(file)", exact, ascii, 20);

  const std::string binary = "output-geometry-sphere-binary.stl";
  {
    std::ofstream     out(binary, std::ios::binary);
    const std::string header(80, ' ');
    out.write(header.data(), 80);
    const std::uint32_t n = triangles.size();
    out.write(reinterpret_cast<const char *>(&n), 4);
    for (const auto &t : triangles)
      {
        std::array<float, 12> values{};
        for (unsigned int v = 0; v < 3; ++v)
          for (unsigned int d = 0; d < 3; ++d)
            values[3 + 3 * v + d] = t[v][d];
        out.write(reinterpret_cast<const char *>(values.data()), 48);
        out.write("\0\0", 2);
      }
  }
  expect_volume<3>("surface(file) - sphere(0.5, 0.5, 0.5; 0.1)",
                   exact - 4. / 3 * numbers::PI * 0.001,
                   binary,
                   20);

  // One triangle less: open, refused naming the file and an edge.
  const std::string open = "output-geometry-open.stl";
  {
    std::ofstream out(open);
    out << "solid open\n";
    for (unsigned int i = 1; i < triangles.size(); ++i)
      {
        out << "facet normal 0 0 0\nouter loop\n";
        for (const auto &p : triangles[i])
          out << "vertex " << p << "\n";
        out << "endloop\nendfacet\n";
      }
    out << "endsolid open\n";
  }
  const std::string message =
    error_of([&] { fill<3>("surface(file)", open, 4); });
  EXPECT_NE(message.find("Body 0/File name = <" + open +
                         "> is not a closed surface: the edge"),
            std::string::npos)
    << message;
}



// A disk of triangles read from a Gmsh file (independent of the
// background mesh): the points' volumes sum to the mesh's area exactly and
// to the disk's within 1 %.
TEST(Geometry, GmshTriangleMeshBodyHasItsVolume)
{
  const std::string file = parameter_dir + "meshes/disk_triangles.msh";
  // The mesh's area: rings of 6k nodes, a polygon of 48 sides outside.
  const double polygon = 0.5 * 48 * 0.09 * std::sin(2 * numbers::PI / 48);
  const Filled filled  = fill<2>("mesh", file, 13);
  EXPECT_NEAR(filled.volume, polygon, 1e-12);
  EXPECT_NEAR(filled.volume, numbers::PI * 0.09, 0.01 * numbers::PI * 0.09);
  EXPECT_NEAR(filled.mass, 2000 * polygon, 1e-9);
}



// A Wavefront OBJ surface: a box of six quadrilateral faces (split into
// triangles; its sides 0.4 x 0.5 x 0.25 put no point on a face's diagonal)
// holds its volume exactly; the shipped sphere's triangles written as OBJ
// (negative vertex indices) give the STL's volume; a face less is refused
// as open.
TEST(Geometry, ObjSurfaceHasItsEnclosedVolume)
{
  const auto write_box = [](const std::string &file, const bool closed) {
    std::ofstream out(file);
    out << "# a box\n";
    for (unsigned int v = 0; v < 8; ++v)
      out << "v " << (v & 1 ? 0.7 : 0.3) << ' ' << (v & 2 ? 0.75 : 0.25) << ' '
          << (v & 4 ? 0.6 : 0.35) << '\n';
    out << "f 1/1/1 3/1/1 4/1/1 2/1/1\nf 5 6 8 7\nf 1 2 6 5\n"
           "f 3 7 8 4\nf 1 5 7 3\n";
    if (closed)
      out << "f 2 4 8 6\n";
  };
  const std::string box = "output-geometry-box.obj";
  write_box(box, true);
  const Filled filled = fill<3>("surface(file)", box, 20);
  EXPECT_NEAR(filled.volume, 0.4 * 0.5 * 0.25, 1e-12);

  const auto triangles = read_ascii_stl(parameter_dir + "meshes/sphere.stl");
  double     exact     = 0;
  const std::string sphere = "output-geometry-sphere.obj";
  {
    std::ofstream out(sphere);
    for (const auto &t : triangles)
      {
        exact += (t[0] * cross_product_3d(t[1], t[2])) / 6;
        for (const auto &p : t)
          out << "v " << p << '\n';
        out << "f -3 -2 -1\n";
      }
  }
  exact = std::abs(exact);
  expect_volume<3>("surface(file)", exact, sphere, 20);

  const std::string open = "output-geometry-open.obj";
  write_box(open, false);
  const std::string message =
    error_of([&] { fill<3>("surface(file)", open, 4); });
  EXPECT_NE(message.find("Body 0/File name = <" + open +
                         "> is not a closed surface: the edge"),
            std::string::npos)
    << message;
}



// Gmsh physical groups pick the cells of a body: a rectangle of two
// quadrilaterals tagged 1 (left) and 2 (right) gives two bodies of their own
// materials; each body's points fill its group's area exactly, with its
// material's density. A group the file does not have is refused, naming
// the groups it has.
TEST(Geometry, GmshPhysicalGroupsPickBodyAndMaterial)
{
  const std::string file =
    (std::filesystem::current_path() / "geometry_two_groups.msh").string();
  {
    std::ofstream out(file);
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n"
           "1 0.2 0.2 0\n2 0.5 0.2 0\n3 0.8 0.2 0\n"
           "4 0.2 0.8 0\n5 0.5 0.8 0\n6 0.8 0.8 0\n$EndNodes\n"
           "$Elements\n2\n1 3 2 1 1 1 2 5 4\n2 3 2 2 2 2 3 6 5\n"
           "$EndElements\n";
  }
  const auto scene = [&](const std::string &groups_1) {
    return "set Dimension = 2\nset Number of bodies = 2\nset Number of "
           "materials = 2\nsubsection Mesh\n set Subdivisions = 10, 10\nend\n"
           "subsection Material 0\n set Density = 2000\nend\n"
           "subsection Material 1\n set Density = 500\nend\n"
           "subsection Body 0\n set Shape = mesh\n set File name = " +
           file +
           "\n set Physical groups = 1\nend\n"
           "subsection Body 1\n set Shape = mesh\n set File name = " +
           file + "\n set Physical groups = " + groups_1 +
           "\n set Material = 1\nend\n"
           "subsection Time\n set Maximum number of steps = 1\n set End "
           "time = 1e-9\nend\n" +
           output_overrides("output-geometry");
  };
  ParameterHandler prm;
  auto             simulator = make_simulator<2>({}, scene("2"), prm);
  simulator->run();
  using Index = fmpm::PropertyIndex<2>;
  std::array<double, 2> volume{}, mass{};
  const auto &points = fmpm_tests::inspect(*simulator).get_material_points();
  for (unsigned int k = 0; k < points.n_points(); ++k)
    {
      const auto         p    = points.record(k);
      const unsigned int body = p[Index::body_id];
      volume[body] += p[Index::initial_volume];
      mass[body] += p[Index::mass];
      EXPECT_EQ(static_cast<unsigned int>(p[Index::material_id]), body);
      // Body 0 is the left half, body 1 the right half.
      EXPECT_EQ(points.position[k][0] < 0.5, body == 0);
    }
  for (unsigned int b = 0; b < 2; ++b)
    {
      volume[b] = Utilities::MPI::sum(volume[b], MPI_COMM_WORLD);
      mass[b]   = Utilities::MPI::sum(mass[b], MPI_COMM_WORLD);
      EXPECT_NEAR(volume[b], 0.18, 1e-12);
    }
  EXPECT_NEAR(mass[0], 2000 * 0.18, 1e-9);
  EXPECT_NEAR(mass[1], 500 * 0.18, 1e-9);

  const std::string m = error_of([&] {
    ParameterHandler prm_bad;
    make_simulator<2>({}, scene("3"), prm_bad)->run();
  });
  EXPECT_NE(m.find("Body 1/File name = <" + file +
                   "> has no cell of physical group 3 (Physical groups); "
                   "its cells' groups are: 1, 2."),
            std::string::npos)
    << m;
}



TEST(Geometry, BadShapesAreRefusedNamingTheBody)
{
  const auto message = [](const std::string &shape,
                          const std::string &file = "") {
    return error_of([&] { fill<2>(shape, file, 4); });
  };
  std::string m = message("polygon(0.1, 0.1; 0.9, 0.9; 0.9, 0.1; 0.1, 0.9)");
  EXPECT_NE(m.find("Body 0/Shape: the polygon intersects itself: edge 0"),
            std::string::npos)
    << m;
  m = message("disk(0.5, 0.5; 0.3) - torus(0.5, 0.5; 1)");
  EXPECT_NE(m.find("Body 0/Shape = disk(0.5, 0.5; 0.3) - torus(0.5, 0.5; 1) "
                   "is not a shape: unknown shape 'torus' at character 23"),
            std::string::npos)
    << m;
  m = message("disk(0.5, 0.5)");
  EXPECT_NE(m.find("disk(...) takes center; radius (2D)"), std::string::npos)
    << m;
  m = message("polygon(file)", "no-such-polygon.txt");
  EXPECT_NE(m.find("Body 0/File name = <no-such-polygon.txt> cannot be read"),
            std::string::npos)
    << m;
  m = message("mesh", "no-such-mesh.msh");
  EXPECT_NE(m.find("Body 0/File name = <no-such-mesh.msh> cannot be read"),
            std::string::npos)
    << m;
  m = message("disk(0.9, 0.5; 0.3)");
  EXPECT_NE(m.find("Body 0 reaches outside the mesh"), std::string::npos) << m;
}
