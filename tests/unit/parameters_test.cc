// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Checks fmpm::read_scene: the built-in default scene parses (2 bodies);
// later sources override earlier ones; 'Number of bodies' and 'Dimension'
// size the declared parameters; and every kind of error (unknown parameter,
// value outside its pattern, malformed line, non-positive density, a body
// made of a non-existing material, a gmsh mesh without a readable file)
// throws with a message naming the problem and where it is; numbers in the
// messages are short; files that are not parameter files are refused.

#include <fmpm/parameters.h>

#include <deal.II/base/parameter_handler.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace
{
  using namespace dealii;
  using Sources = std::vector<std::pair<std::string, std::string>>;

  /** The default scene followed by @p text as the source @p name. */
  Sources
  default_plus(const std::string &name, const std::string &text)
  {
    return {{"default scene", fmpm::default_scene()}, {name, text}};
  }

  /** read_scene into a fresh ParameterHandler; returns the Parameters. */
  fmpm::Parameters
  read(const Sources &sources)
  {
    ParameterHandler prm;
    fmpm::Parameters parameters;
    fmpm::read_scene(sources, prm, parameters);
    return parameters;
  }

  /**
   * Expect read_scene to throw with a message containing each of @p words;
   * returns the message.
   */
  std::string
  expect_error(const Sources &sources, const std::vector<std::string> &words)
  {
    std::string message;
    try
      {
        read(sources);
        ADD_FAILURE() << "read_scene did not throw; expected an error naming <"
                      << words.front() << ">";
      }
    catch (const std::exception &e)
      {
        message = fmpm::error_message(e);
        for (const auto &word : words)
          EXPECT_NE(message.find(word), std::string::npos)
            << "the message does not contain <" << word << ">:\n"
            << message;
      }
    return message;
  }



  TEST(ReadScene, DefaultScene)
  {
    ParameterHandler prm;
    fmpm::Parameters parameters;
    fmpm::read_scene({{"default scene", fmpm::default_scene()}},
                     prm,
                     parameters);
    EXPECT_EQ(parameters.size.dimension, 2u);
    EXPECT_EQ(parameters.size.n_bodies, 2u);
    EXPECT_EQ(parameters.size.n_materials, 1u);
    ASSERT_EQ(parameters.bodies.size(), 2u);
    ASSERT_EQ(parameters.materials.size(), 1u);
    EXPECT_EQ(parameters.bodies[0].shape, fmpm::BodyParameters::Shape::sphere);
    EXPECT_EQ(parameters.bodies[1].shape, fmpm::BodyParameters::Shape::sphere);
    EXPECT_EQ(parameters.bodies[1].center, (std::vector<double>{0.75, 0.75}));
    EXPECT_EQ(parameters.materials[0].model_name, "linear elastic");
    EXPECT_DOUBLE_EQ(parameters.materials[0].density, 1000.0);
    EXPECT_EQ(parameters.mesh.type, fmpm::MeshParameters::Type::box);
    EXPECT_EQ(parameters.mesh.subdivisions,
              (std::vector<unsigned int>{20, 20}));
    EXPECT_EQ(parameters.mesh.upper_corner, (std::vector<double>{1, 1}));
    EXPECT_DOUBLE_EQ(parameters.time.end_time, 3.0);
    EXPECT_DOUBLE_EQ(parameters.time.courant_number, 0.4);
    EXPECT_EQ(parameters.method.particle_update, "flip");
    EXPECT_EQ(parameters.boundary_conditions.fixed.size(), 4u);

    // The plugin parameters are declared and set in the ParameterHandler.
    prm.enter_subsection("Material 0");
    prm.enter_subsection("Linear elastic");
    EXPECT_DOUBLE_EQ(prm.get_double("Young's modulus"), 1000.0);
    prm.leave_subsection();
    prm.leave_subsection();
  }



  TEST(ReadScene, LaterSourcesOverrideEarlierOnes)
  {
    const std::string      end_time = "subsection Time\n"
                                      "  set End time = 0.5\n"
                                      "end\n";
    const fmpm::Parameters later    = read(default_plus("override", end_time));
    EXPECT_DOUBLE_EQ(later.time.end_time, 0.5);
    // Only what the override sets changes.
    EXPECT_DOUBLE_EQ(later.time.courant_number, 0.4);
    EXPECT_EQ(later.bodies.size(), 2u);

    // The other order: the default scene wins.
    const fmpm::Parameters earlier =
      read({{"override", end_time}, {"default scene", fmpm::default_scene()}});
    EXPECT_DOUBLE_EQ(earlier.time.end_time, 3.0);

    // Three sources: the last one wins.
    const fmpm::Parameters last =
      read({{"default scene", fmpm::default_scene()},
            {"override", end_time},
            {"last", "subsection Time\n set End time = 0.25\nend\n"}});
    EXPECT_DOUBLE_EQ(last.time.end_time, 0.25);
  }



  TEST(ReadScene, NumberOfBodiesDeclaresBodySubsections)
  {
    const fmpm::Parameters three =
      read(default_plus("three bodies",
                        "set Number of bodies = 3\n"
                        "subsection Body 2\n"
                        "  set Shape        = box\n"
                        "  set Center       = 0.5, 0.1\n"
                        "  set Half lengths = 0.3, 0.05\n"
                        "end\n"));
    EXPECT_EQ(three.size.n_bodies, 3u);
    ASSERT_EQ(three.bodies.size(), 3u);
    EXPECT_EQ(three.bodies[2].shape, fmpm::BodyParameters::Shape::box);
    EXPECT_EQ(three.bodies[2].center, (std::vector<double>{0.5, 0.1}));
    EXPECT_EQ(three.bodies[2].half_lengths, (std::vector<double>{0.3, 0.05}));
    EXPECT_EQ(three.bodies[2].material, 0u);
    // The bodies of the default scene are unchanged.
    EXPECT_EQ(three.bodies[0].shape, fmpm::BodyParameters::Shape::sphere);

    // Without 'Number of bodies = 3' there is no 'Body 2'.
    expect_error(default_plus("no third body",
                              "subsection Body 2\n"
                              "  set Shape = box\n"
                              "end\n"),
                 {"Body 2", "no third body"});
  }



  TEST(ReadScene, DimensionSizesTheVectors)
  {
    // Defaults follow the dimension.
    const fmpm::Parameters three_d = read({{"3d", "set Dimension = 3\n"}});
    EXPECT_EQ(three_d.size.dimension, 3u);
    EXPECT_EQ(three_d.mesh.lower_corner.size(), 3u);
    EXPECT_EQ(three_d.mesh.subdivisions.size(), 3u);
    ASSERT_EQ(three_d.bodies.size(), 1u);
    EXPECT_EQ(three_d.bodies[0].center.size(), 3u);
    EXPECT_EQ(three_d.gravity.size(), 3u);

    // The default scene gives two components: wrong in 3D.
    expect_error(default_plus("3d", "set Dimension = 3\n"),
                 {"Lower corner", "default scene"});
  }



  TEST(ReadScene, UnknownParameter)
  {
    const std::string message = expect_error(default_plus("typo.prm",
                                                          "# a comment\n"
                                                          "subsection Time\n"
                                                          "  set End tiem = 2\n"
                                                          "end\n"),
                                             {"End tiem", "typo.prm", "3"});
    EXPECT_NE(message.find("Line <3>"), std::string::npos) << message;
    // The nearest declared names of the subsection of that line.
    EXPECT_NE(message.find("Did you mean 'End time'?"), std::string::npos)
      << message;

    expect_error(default_plus("top.prm", "set Number of bodys = 2\n"),
                 {"Number of bodys", "top.prm", "'Number of bodies'"});
    // A part of a name: every name containing it.
    expect_error(default_plus("part.prm",
                              "subsection Time\n  set Courant = 0.2\nend\n"),
                 {"'Courant number' or 'Courant number limit'"});
    // A subsection, inside another one.
    expect_error(default_plus("section.prm",
                              "subsection Mass matrix\n"
                              "  subsection Fmmp\n  end\nend\n"),
                 {"Fmmp", "Did you mean 'Fmpm'"});
    // Nothing near: the names declared there.
    expect_error(default_plus("far.prm",
                              "subsection Timer\n  set Colour = red\nend\n"),
                 {"Parameters in 'Timer': 'Type'."});
  }



  // Scenes name files relative to their own folder ('include' and
  // 'Mesh/File name'); a comment-only override changes nothing.
  TEST(ReadScene, FilesRelativeToTheSceneFolder)
  {
    const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / "fmpm-relative-paths-test";
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder / "parts");
    std::ofstream(folder / "scene.prm")
      << "include parts/time.prm # the end time\n"
         "subsection Mesh\n  set Type = gmsh\n  set File name = "
         "parts/mesh.msh\nend\n";
    std::ofstream(folder / "parts" / "time.prm")
      << "subsection Time\n  set End time = 0.125\nend\n";
    std::ofstream(folder / "parts" / "mesh.msh") << "not read here\n";
    std::ofstream(folder / "comments.prm") << "# set End time = 7\n\n";
    const auto cwd = std::filesystem::current_path();
    std::filesystem::current_path(std::filesystem::temp_directory_path());
    Sources sources;
    try
      {
        sources =
          fmpm::load_scene_sources({(folder / "scene.prm").string(),
                                    (folder / "comments.prm").string()});
      }
    catch (...)
      {
        std::filesystem::current_path(cwd);
        throw;
      }
    std::filesystem::current_path(cwd);
    sources.insert(sources.begin(), {"default scene", fmpm::default_scene()});
    const fmpm::Parameters parameters = read(sources);
    EXPECT_EQ(parameters.time.end_time, 0.125);
    EXPECT_EQ(parameters.mesh.file_name,
              (folder / "parts" / "mesh.msh").lexically_normal().string());
    std::filesystem::remove_all(folder);
  }



  TEST(ReadScene, ValueOutsidePattern)
  {
    expect_error(default_plus("dimension.prm", "set Dimension = 4\n"),
                 {"Dimension", "4", "dimension.prm"});
    // Above the stable limit 1 (whether the pattern or a later check
    // refuses it).
    expect_error(default_plus("courant.prm",
                              "subsection Time\n"
                              "  set Courant number = 2\n"
                              "end\n"),
                 {"Courant number", "2", "courant.prm"});
    expect_error(default_plus("courant.prm",
                              "subsection Time\n"
                              "  set Courant number = -0.5\n"
                              "end\n"),
                 {"Courant number", "-0.5", "courant.prm", "Line <2>"});
    expect_error(default_plus("model.prm",
                              "subsection Material 0\n"
                              "  set Model name = rubber\n"
                              "end\n"),
                 {"Model name", "rubber", "model.prm"});
    // Names the parameter, the value and the allowed shape functions.
    expect_error(default_plus("shape.prm",
                              "subsection Shape function\n"
                              "  set Type = gimp\n"
                              "end\n"),
                 {"Type", "gimp", "shape.prm", "classic|ugimp|cpgimp|cpdi"});
    expect_error(default_plus("corner.prm",
                              "subsection Mesh\n"
                              "  set Lower corner = 0, 0, 0\n"
                              "end\n"),
                 {"Lower corner", "corner.prm"});
  }



  TEST(ReadScene, MalformedLine)
  {
    expect_error(default_plus("malformed.prm",
                              "subsection Time\n"
                              "  End time 2\n"
                              "end\n"),
                 {"malformed.prm", "Line <2>"});
    expect_error(default_plus("unbalanced.prm",
                              "subsection Time\n"
                              "  set End time = 2\n"),
                 {"unbalanced.prm"});
  }



  TEST(ReadScene, NonPositiveDensity)
  {
    for (const std::string density : {"0", "-5"})
      expect_error(default_plus("density.prm",
                                "subsection Material 0\n"
                                "  set Density = " +
                                  density + "\n" + "end\n"),
                   {"Material 0/Density", "density.prm"});
  }



  TEST(ReadScene, BodyOfNonExistingMaterial)
  {
    expect_error(default_plus("material.prm",
                              "subsection Body 1\n"
                              "  set Material = 1\n"
                              "end\n"),
                 {"Body 1/Material", "1"});

    // Two materials announced, the second not written: an error naming
    // the missing subsection, not a silent default material.
    expect_error(default_plus("material.prm",
                              "set Number of materials = 2\n"
                              "subsection Body 1\n"
                              "  set Material = 1\n"
                              "end\n"),
                 {"Number of materials = 2", "'subsection Material 1'"});

    // With two materials written it is fine.
    const fmpm::Parameters two =
      read(default_plus("material.prm",
                        "set Number of materials = 2\n"
                        "subsection Material 1\n"
                        "end\n"
                        "subsection Body 1\n"
                        "  set Material = 1\n"
                        "end\n"));
    EXPECT_EQ(two.materials.size(), 2u);
    EXPECT_EQ(two.bodies[1].material, 1u);
    EXPECT_EQ(two.bodies[0].material, 0u);
  }



  TEST(ReadScene, GmshMeshWithoutFile)
  {
    const std::string missing = "/nonexistent/fmpm-unit-test-mesh.msh";
    expect_error(default_plus("gmsh.prm",
                              "subsection Mesh\n"
                              "  set Type      = gmsh\n"
                              "  set File name = " +
                                missing + "\nend\n"),
                 {"Mesh/File name", missing});
    expect_error(default_plus("gmsh.prm",
                              "subsection Mesh\n"
                              "  set Type = gmsh\n"
                              "end\n"),
                 {"Mesh/File name"});
  }



  TEST(ReadScene, MeshRefinement)
  {
    const fmpm::Parameters parameters =
      read(default_plus("refinement.prm",
                        "subsection Mesh refinement\n"
                        "  set Strategy      = material boundary\n"
                        "  set Minimum level = 1\n"
                        "  set Maximum level = 4\n"
                        "  set Interval      = 7\n"
                        "end\n"
                        "subsection Mesh\n"
                        "  set Random distortion = 0.2\n"
                        "end\n"));
    EXPECT_EQ(parameters.refinement.strategy,
              fmpm::MeshRefinementParameters::Strategy::material_boundary);
    EXPECT_EQ(parameters.refinement.minimum_level, 1u);
    EXPECT_EQ(parameters.refinement.maximum_level, 4u);
    EXPECT_EQ(parameters.refinement.interval, 7u);
    EXPECT_DOUBLE_EQ(parameters.mesh.distortion, 0.2);
    EXPECT_EQ(read(default_plus("none.prm", "")).refinement.strategy,
              fmpm::MeshRefinementParameters::Strategy::none);

    expect_error(default_plus("strategy.prm",
                              "subsection Mesh refinement\n"
                              "  set Strategy = everywhere\n"
                              "end\n"),
                 {"Strategy", "everywhere", "material points", "kelly"});
    expect_error(default_plus("levels.prm",
                              "subsection Mesh refinement\n"
                              "  set Strategy      = kelly\n"
                              "  set Minimum level = 3\n"
                              "  set Maximum level = 2\n"
                              "end\n"),
                 {"Mesh refinement/Maximum level", "Minimum level"});
    expect_error(default_plus("levels.prm",
                              "subsection Mesh refinement\n"
                              "  set Strategy      = material points\n"
                              "  set Maximum level = 1\n"
                              "end\n"
                              "subsection Mesh\n"
                              "  set Initial global refinement = 2\n"
                              "end\n"),
                 {"Mesh refinement/Maximum level",
                  "Initial global refinement"});
    expect_error(default_plus("fractions.prm",
                              "subsection Mesh refinement\n"
                              "  set Refine fraction  = 0.7\n"
                              "  set Coarsen fraction = 0.4\n"
                              "end\n"),
                 {"Refine fraction", "Coarsen fraction"});
    expect_error(default_plus("distortion.prm",
                              "subsection Mesh\n"
                              "  set Random distortion = 0.8\n"
                              "end\n"),
                 {"Random distortion", "0.8"});
  }



  // Numbers in error messages read as written or in short scientific form,
  // not as std::to_string's fixed six decimals (a 300-digit -1e308).
  TEST(FormatNumber, ShortestFormThatReadsBack)
  {
    EXPECT_EQ(fmpm::format_number(-1e308), "-1e308");
    EXPECT_EQ(fmpm::format_number(-5), "-5");
    EXPECT_EQ(fmpm::format_number(0.3), "0.3");
    EXPECT_EQ(fmpm::format_number(0.5), "0.5");
    EXPECT_EQ(fmpm::format_number(1e-9), "1e-9");
    EXPECT_EQ(fmpm::format_number(2.1e11), "2.1e11");
    EXPECT_EQ(fmpm::format_number(1234.5), "1234.5");
    EXPECT_EQ(fmpm::format_number(-2.5e-300), "-2.5e-300");
    // Integers and short numbers below 1e6 without an exponent.
    EXPECT_EQ(fmpm::format_number(10), "10");
    EXPECT_EQ(fmpm::format_number(1000), "1000");
    EXPECT_EQ(fmpm::format_number(-1500), "-1500");
    EXPECT_EQ(fmpm::format_number(100000), "100000");
    EXPECT_EQ(fmpm::format_number(1e6), "1e6");
    // Values that need all 17 digits keep them, unless rounded on request.
    EXPECT_EQ(std::stod(fmpm::format_number(1. / 3)), 1. / 3);
    EXPECT_EQ(fmpm::format_number(1. / 3, 6), "0.333333");
    EXPECT_EQ(fmpm::format_number(0.0023570226039551584, 6), "0.00235702");
  }



  // Error messages of the parameter checks use that form.
  TEST(ReadScene, NumbersInMessagesAsWritten)
  {
    const std::string message =
      expect_error(default_plus("density.prm",
                                "subsection Material 0\n"
                                "  set Density = -1e308\n"
                                "end\n"),
                   {"Material 0/Density = -1e308 is not positive"});
    EXPECT_LT(message.size(), 200u) << message;
    expect_error(default_plus("courant.prm",
                              "subsection Time\n"
                              "  set Courant number = 1.25\n"
                              "end\n"),
                 {"Time/Courant number = 1.25 is above"});
  }



  // The first pass of read_scene gives the numbered subsections' counts
  // (what --print-parameters scene.prm declares).
  TEST(ReadScene, SceneSizeFromTheFirstPass)
  {
    const fmpm::SceneSize size = fmpm::read_scene_size(
      default_plus("counts.prm",
                   "set Dimension = 3\n"
                   "set Number of materials = 3\n"
                   "set Number of moving walls = 2\n"
                   "set Number of tractions = 1\n"
                   "subsection Material 2\n  set Density = -1\nend\n"));
    EXPECT_EQ(size.dimension, 3u);
    EXPECT_EQ(size.n_bodies, 2u);
    EXPECT_EQ(size.n_materials, 3u);
    EXPECT_EQ(size.n_moving_walls, 2u);
    EXPECT_EQ(size.n_tractions, 1u);
  }



  // A file that is not a parameter file is refused, naming the file: binary
  // data, or text without any 'set' or 'subsection' line (a mesh file).
  TEST(LoadSceneSources, RefusesFilesThatAreNotParameterFiles)
  {
    const std::string binary = "output-not-prm.bin";
    {
      std::ofstream out(binary, std::ios::binary);
      const char    bytes[] = {'\x7f', 'E', 'L', 'F', '\0', '\x02', 's'};
      out.write(bytes, sizeof(bytes));
      out << "\nset End time = 1\n";
    }
    const std::string mesh = "output-not-prm.msh";
    {
      std::ofstream out(mesh);
      out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n# set nothing\n";
    }
    const std::string scene = "output-is-prm.prm";
    {
      std::ofstream out(scene);
      out << "# comment\n  set End time = 1 # indented\n";
    }
    for (const auto &file_and_words :
         std::vector<std::pair<std::string, std::string>>{
           {binary, "binary data"}, {mesh, "no 'set' or 'subsection' line"}})
      try
        {
          fmpm::load_scene_sources({scene, file_and_words.first});
          ADD_FAILURE() << file_and_words.first << " was accepted";
        }
      catch (const std::exception &e)
        {
          const std::string message = fmpm::error_message(e);
          EXPECT_NE(message.find("<" + file_and_words.first +
                                 "> is not a parameter file"),
                    std::string::npos)
            << message;
          EXPECT_NE(message.find(file_and_words.second), std::string::npos)
            << message;
        }
    EXPECT_EQ(fmpm::load_scene_sources({scene}).size(), 1u);
  }
} // namespace
