// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Reading a scene: its sources, the two passes, errors that name the line.

#include <fmpm/parameters.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

namespace fmpm
{
  namespace
  {
    /** The message of a deal.II exception without its source location. */
    std::string
    message_of(const ExceptionBase &e)
    {
      std::ostringstream out;
      e.print_info(out);
      // Drop the indentation and trailing newlines deal.II adds.
      std::string text  = out.str();
      const auto  first = text.find_first_not_of(" \n\t");
      const auto  last  = text.find_last_not_of(" \n\t");
      return first == std::string::npos ? text :
                                          text.substr(first, last - first + 1);
    }
  } // namespace



  std::string
  error_message(const std::exception &e)
  {
    if (const auto *deal_ii = dynamic_cast<const ExceptionBase *>(&e))
      return message_of(*deal_ii);
    return e.what();
  }



  namespace
  {
    /** The text of a scene source: a file, or standard input for "-". */
    std::string
    read_source(const std::string &file)
    {
      if (file == "-")
        return std::string(std::istreambuf_iterator<char>(std::cin),
                           std::istreambuf_iterator<char>());
      AssertThrow(!std::filesystem::is_directory(file),
                  ExcMessage("The scene file <" + file +
                             "> is a directory, not a parameter file. Give "
                             "a text .prm file (see fmpm "
                             "--print-default-scene)."));
      std::ifstream in(file);
      AssertThrow(in,
                  ExcMessage("Cannot open the scene file <" + file +
                             ">: no such file or not readable."));
      return std::string(std::istreambuf_iterator<char>(in),
                         std::istreambuf_iterator<char>());
    }

    /**
     * Refuse a source that is not a parameter file: binary data, or text
     * without a single 'set', 'subsection' or 'include' line (a mesh or a
     * results file given by mistake), which deal.II would otherwise accept
     * as a scene with every parameter at its default value.
     */
    void
    check_is_parameter_file(const std::string &name,
                            const std::string &text,
                            const bool         is_override)
    {
      for (const char c : text)
        AssertThrow(c == '\t' || c == '\n' || c == '\r' || c == '\f' ||
                      c == '\v' || static_cast<unsigned char>(c) >= 32,
                    ExcMessage("The scene file <" + name +
                               "> is not a parameter file: it holds binary "
                               "data. Give a text .prm file with 'set' and "
                               "'subsection' lines (see fmpm "
                               "--print-default-scene)."));
      std::istringstream in(text);
      std::string        line;
      bool               only_comments = true;
      while (std::getline(in, line))
        {
          std::istringstream words(line);
          std::string        first;
          words >> first;
          if (first == "set" || first == "subsection" || first == "include")
            return;
          only_comments = only_comments && (first.empty() || first[0] == '#');
        }
      // An empty or comment-only override changes nothing (its settings
      // commented out); as the scene itself it is a mistake.
      if (only_comments && is_override)
        return;
      AssertThrow(false,
                  ExcMessage("The scene file <" + name +
                             "> is not a parameter file: it has no 'set' or "
                             "'subsection' line. Give a text .prm file "
                             "(see fmpm --print-default-scene)."));
    }

    std::string
    lower_case(std::string text)
    {
      for (char &c : text)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return text;
    }

    /** Levenshtein distance of @p a and @p b, ignoring case. */
    unsigned int
    edit_distance(const std::string &a, const std::string &b)
    {
      std::vector<unsigned int> previous(b.size() + 1), current(b.size() + 1);
      for (unsigned int j = 0; j <= b.size(); ++j)
        previous[j] = j;
      for (unsigned int i = 1; i <= a.size(); ++i)
        {
          current[0] = i;
          for (unsigned int j = 1; j <= b.size(); ++j)
            current[j] = std::min(
              {previous[j] + 1,
               current[j - 1] + 1,
               previous[j - 1] +
                 (std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                      std::tolower(static_cast<unsigned char>(b[j - 1])) ?
                    0u :
                    1u)});
          std::swap(previous, current);
        }
      return previous[b.size()];
    }

    /**
     * The subsections (@p subsections true) or entries declared in @p prm
     * inside the subsection @p path, from deal.II's PRM listing.
     */
    std::vector<std::string>
    declared_names(const ParameterHandler         &prm,
                   const std::vector<std::string> &path,
                   const bool                      subsections)
    {
      std::stringstream listing;
      prm.print_parameters(listing, ParameterHandler::PRM);
      std::vector<std::string> current, names;
      std::string              line;
      while (std::getline(listing, line))
        {
          line = Utilities::trim(line.substr(0, line.find('#')));
          if (line.rfind("subsection ", 0) == 0)
            {
              const std::string name = Utilities::trim(line.substr(11));
              if (subsections && current == path)
                names.push_back(name);
              current.push_back(name);
            }
          else if (line == "end" && !current.empty())
            current.pop_back();
          else if (line.rfind("set ", 0) == 0 && !subsections &&
                   current == path)
            names.push_back(
              Utilities::trim(line.substr(4, line.find('=') - 4)));
        }
      return names;
    }

    /**
     * For deal.II's errors about an undeclared entry or subsection at a
     * line of @p text: " Did you mean ...?" with the declared names nearest
     * to the one written, or the names declared there; empty otherwise.
     */
    std::string
    nearest_names_hint(const ParameterHandler &prm,
                       const std::string      &text,
                       const std::string      &message)
    {
      const std::string entry_marker = "No entry with name <";
      const std::string section_marker =
        "There is no such subsection to be entered: ";
      const std::string line_marker = "Line <";
      const auto        line_at     = message.find(line_marker);
      if (line_at == std::string::npos)
        return "";
      const unsigned int line_number = static_cast<unsigned int>(
        std::atoi(message.c_str() + line_at + line_marker.size()));
      std::string written;
      bool        subsection = false;
      if (const auto at = message.find(entry_marker); at != std::string::npos)
        {
          const auto begin = at + entry_marker.size();
          written = message.substr(begin, message.find('>', begin) - begin);
        }
      else if (const auto at = message.find(section_marker);
               at != std::string::npos)
        {
          written = Utilities::trim(message.substr(at + section_marker.size(),
                                                   message.find('\n', at) - at -
                                                     section_marker.size()));
          // deal.II names the subsection with its path: "Mass matrix.Fmmp".
          if (written.find('.') != std::string::npos)
            written = written.substr(written.rfind('.') + 1);
          subsection = true;
        }
      else
        return "";

      // The subsection path in force at that line.
      std::vector<std::string> path;
      std::istringstream       in(text);
      std::string              line;
      for (unsigned int number = 1;
           number < line_number && std::getline(in, line);
           ++number)
        {
          line = Utilities::trim(line.substr(0, line.find('#')));
          if (line.rfind("subsection ", 0) == 0)
            path.push_back(Utilities::trim(line.substr(11)));
          else if (line == "end" && !path.empty())
            path.pop_back();
        }
      const std::vector<std::string> names =
        declared_names(prm, path, subsection);
      if (names.empty())
        return "";
      std::vector<std::pair<unsigned int, std::string>> ranked;
      const std::string lower_written = lower_case(written);
      for (const auto &name : names)
        {
          const unsigned int distance = edit_distance(written, name);
          const bool         contains =
            !lower_written.empty() &&
            (lower_case(name).find(lower_written) != std::string::npos ||
             lower_written.find(lower_case(name)) != std::string::npos);
          if (contains ||
              distance <= std::max<std::size_t>(2, written.size() / 3))
            ranked.emplace_back(contains ? 0 : distance, name);
        }
      std::sort(ranked.begin(), ranked.end());
      std::string where;
      for (const auto &name : path)
        where += (where.empty() ? "" : "/") + name;
      where = where.empty() ? "at the top level" : "in '" + where + "'";
      std::string hint;
      if (!ranked.empty())
        {
          hint = "\n    Did you mean ";
          for (unsigned int i = 0; i < std::min<std::size_t>(3, ranked.size());
               ++i)
            hint += (i > 0 ? " or '" : "'") + ranked[i].second + "'";
          hint += "?";
        }
      else
        {
          hint = "\n    " +
                 std::string(subsection ? "Subsections" : "Parameters") + " " +
                 where + ": ";
          for (unsigned int i = 0; i < names.size(); ++i)
            hint += (i > 0 ? ", '" : "'") + names[i] + "'";
          hint += ".";
        }
      return hint;
    }

    void
    parse_source(ParameterHandler  &prm,
                 const std::string &text,
                 const std::string &name,
                 const bool         skip_undefined)
    {
      std::istringstream in(text);
      try
        {
          prm.parse_input(in, name, "", skip_undefined);
        }
      catch (const ExceptionBase &e)
        {
          const std::string message = message_of(e);
          AssertThrow(false,
                      ExcMessage("Error in the scene <" + name + ">:\n    " +
                                 message +
                                 nearest_names_hint(prm, text, message)));
        }
    }
  } // namespace



  namespace
  {
    /**
     * The files a scene names ('include' lines, 'Mesh/File name' and
     * 'Body N/File name') are relative to the scene file's folder: @p text with
     * those relative paths made absolute against the folder of @p scene_file.
     */
    std::string
    with_paths_relative_to(const std::string &text,
                           const std::string &scene_file)
    {
      const std::filesystem::path folder =
        std::filesystem::absolute(scene_file).parent_path();
      const auto resolved = [&folder](const std::string &file) {
        const std::filesystem::path path(file);
        return file.empty() || path.is_absolute() ?
                 file :
                 (folder / path).lexically_normal().string();
      };
      std::vector<std::string> path;
      std::istringstream       in(text);
      std::ostringstream       out;
      std::string              line;
      while (std::getline(in, line))
        {
          const std::string code =
            Utilities::trim(line.substr(0, line.find('#')));
          const std::string comment = line.find('#') == std::string::npos ?
                                        "" :
                                        line.substr(line.find('#'));
          if (code.rfind("subsection ", 0) == 0)
            path.push_back(Utilities::trim(code.substr(11)));
          else if (code == "end" && !path.empty())
            path.pop_back();
          else if (code.rfind("include ", 0) == 0)
            line = "include " + resolved(Utilities::trim(code.substr(8))) +
                   (comment.empty() ? "" : " " + comment);
          else if (code.rfind("set ", 0) == 0 &&
                   (path == std::vector<std::string>{"Mesh"} ||
                    (path.size() == 1 && path[0].rfind("Body ", 0) == 0)) &&
                   code.find('=') != std::string::npos &&
                   Utilities::trim(code.substr(4, code.find('=') - 4)) ==
                     "File name")
            line = "  set File name = " +
                   resolved(Utilities::trim(code.substr(code.find('=') + 1))) +
                   (comment.empty() ? "" : " " + comment);
          out << line << '\n';
        }
      return out.str();
    }
  } // namespace



  std::vector<std::pair<std::string, std::string>>
  load_scene_sources(const std::vector<std::string> &files)
  {
    std::vector<std::pair<std::string, std::string>> sources;
    if (files.empty())
      sources.emplace_back("default scene", default_scene());
    for (const auto &file : files)
      {
        sources.emplace_back(file == "-" ? "standard input" : file,
                             read_source(file));
        check_is_parameter_file(sources.back().first,
                                sources.back().second,
                                sources.size() > 1);
        if (file != "-")
          sources.back().second =
            with_paths_relative_to(sources.back().second, file);
      }
    return sources;
  }



  namespace
  {
    /** Where a scene writes a subsection or sets a parameter. */
    struct SceneLine
    {
      std::string  path; // "Boundary conditions/Moving wall 1"
      std::string  source;
      unsigned int line;
    };

    /**
     * The subsections a scene writes and the parameters it sets, each with
     * its full path, following deal.II's syntax ('subsection', 'end',
     * 'set', '#' comments, 'include' of another file).
     */
    void
    scan_scene_text(const std::string      &text,
                    const std::string      &source,
                    std::vector<SceneLine> &subsections,
                    std::vector<SceneLine> &settings,
                    const unsigned int      depth = 0)
    {
      std::vector<std::string> path;
      std::istringstream       in(text);
      std::string              line;
      unsigned int             number = 0;
      const auto               joined = [&path](const std::string &last) {
        std::string result;
        for (const auto &name : path)
          result += name + "/";
        return result + last;
      };
      while (std::getline(in, line))
        {
          ++number;
          line = Utilities::trim(line.substr(0, line.find('#')));
          if (line.rfind("subsection ", 0) == 0)
            {
              const std::string name = Utilities::trim(line.substr(11));
              subsections.push_back({joined(name), source, number});
              path.push_back(name);
            }
          else if (line == "end")
            {
              if (!path.empty())
                path.pop_back();
            }
          else if (line.rfind("set ", 0) == 0)
            {
              const std::string entry = line.substr(4);
              settings.push_back(
                {joined(Utilities::trim(entry.substr(0, entry.find('=')))),
                 source,
                 number});
            }
          else if (line.rfind("include ", 0) == 0 && depth < 10)
            {
              const std::string file = Utilities::trim(line.substr(8));
              std::ifstream     included(file);
              if (included)
                scan_scene_text(std::string(std::istreambuf_iterator<char>(
                                              included),
                                            std::istreambuf_iterator<char>()),
                                file,
                                subsections,
                                settings,
                                depth + 1);
            }
        }
    }

    /**
     * Every numbered subsection a scene announces with 'Number of ...' must
     * be written (deal.II would give an unwritten one its default values: a
     * silent default body), and every one written must be announced.
     */
    void
    check_numbered_subsections(
      const std::vector<std::pair<std::string, std::string>> &sources,
      const SceneSize                                        &size)
    {
      std::vector<SceneLine> subsections, settings;
      for (const auto &source : sources)
        scan_scene_text(source.second, source.first, subsections, settings);

      struct Family
      {
        std::string  count_parameter; // "Number of bodies"
        std::string  parent;          // "" or "Boundary conditions/"
        std::string  name;            // "Body"
        unsigned int count;
      };
      const std::vector<Family> families = {
        {"Number of bodies", "", "Body", size.n_bodies},
        {"Number of materials", "", "Material", size.n_materials},
        {"Number of moving walls",
         "Boundary conditions/",
         "Moving wall",
         size.n_moving_walls},
        {"Number of tractions",
         "Boundary conditions/",
         "Traction",
         size.n_tractions}};
      for (const Family &family : families)
        {
          const std::string prefix = family.parent + family.name + " ";
          std::vector<bool> written(family.count, false);
          for (const SceneLine &subsection : subsections)
            {
              if (subsection.path.rfind(prefix, 0) != 0)
                continue;
              const std::string index = subsection.path.substr(prefix.size());
              if (index.empty() ||
                  index.find_first_not_of("0123456789") != std::string::npos)
                continue;
              const unsigned long n = std::stoul(index);
              AssertThrow(n < family.count,
                          ExcMessage(
                            "Line <" + std::to_string(subsection.line) +
                            "> of <" + subsection.source +
                            "> opens 'subsection " + family.name + " " + index +
                            "', but '" + family.count_parameter + " = " +
                            std::to_string(family.count) + "' declares only " +
                            (family.count == 0 ?
                               std::string("none") :
                               family.name + " 0 to " + family.name + " " +
                                 std::to_string(family.count - 1)) +
                            ". Set '" + family.count_parameter + " = " +
                            std::to_string(n + 1) +
                            "' (at the top level of the scene) or remove the "
                            "subsection."));
              written[n] = true;
            }
          // A count the scene leaves at its default announces nothing.
          const SceneLine *announced = nullptr;
          for (const SceneLine &setting : settings)
            if (setting.path == family.count_parameter)
              announced = &setting;
          if (announced == nullptr)
            continue;
          for (unsigned int n = 0; n < family.count; ++n)
            AssertThrow(
              written[n],
              ExcMessage("Line <" + std::to_string(announced->line) + "> of <" +
                         announced->source + "> sets '" +
                         family.count_parameter + " = " +
                         std::to_string(family.count) +
                         "' but the scene has no 'subsection " + family.parent +
                         family.name + " " + std::to_string(n) +
                         "': write that subsection (an unwritten one would "
                         "silently take every default value) or lower '" +
                         family.count_parameter + "'."));
        }
    }
  } // namespace



  SceneSize
  read_scene_size(
    const std::vector<std::pair<std::string, std::string>> &sources)
  {
    ParameterHandler size_prm;
    SceneSize::declare_parameters(size_prm);
    for (const auto &source : sources)
      parse_source(size_prm, source.second, source.first, true);
    SceneSize size;
    size.parse_parameters(size_prm);
    return size;
  }



  void
  read_scene(const std::vector<std::pair<std::string, std::string>> &sources,
             ParameterHandler                                       &prm,
             Parameters                                             &parameters)
  {
    // Pass 1: how many bodies and materials, and which dimension.
    const SceneSize size = read_scene_size(sources);
    check_numbered_subsections(sources, size);

    // Pass 2: everything, strictly.
    Parameters::declare_parameters(prm, size);
    for (const auto &source : sources)
      parse_source(prm, source.second, source.first, false);
    try
      {
        parameters.parse_parameters(prm);
      }
    catch (const ExceptionBase &e)
      {
        std::string where;
        for (const auto &source : sources)
          where += (where.empty() ? "" : ", ") + source.first;
        AssertThrow(false,
                    ExcMessage("Error in the scene <" + where + ">:\n    " +
                               message_of(e)));
      }
  }
} // namespace fmpm
