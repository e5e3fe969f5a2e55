// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/function_parser.h>
#include <fmpm/parameters.h>

#include <deal.II/base/utilities.h>
#include <deal.II/lac/vector.h>

#include <iostream>
#include <sstream>

namespace fmpm
{
  namespace
  {
    /** The text between '<' and the last '>' of the line of @p report that
     * starts with @p label ("Message:", "Position:", ...), or "". */
    std::string
    report_field(const std::string &report, const std::string &label)
    {
      std::istringstream lines(report);
      for (std::string line; std::getline(lines, line);)
        if (line.rfind(label, 0) == 0)
          {
            const auto begin = line.find('<');
            const auto end   = line.rfind('>');
            if (begin != std::string::npos && end != std::string::npos &&
                end > begin)
              return line.substr(begin + 1, end - begin - 1);
          }
      return "";
    }

    /** Sends std::cerr into a string while it lives. */
    class CerrCapture
    {
    public:
      CerrCapture()
        : saved(std::cerr.rdbuf(captured.rdbuf()))
      {}
      ~CerrCapture()
      {
        std::cerr.rdbuf(saved);
      }
      std::string
      text() const
      {
        return captured.str();
      }

    private:
      std::ostringstream captured;
      std::streambuf    *saved;
    };
  } // namespace



  template <int dim>
  void
  parse_function(FunctionParser<dim>                 &function,
                 const std::string                   &parameter,
                 const std::string                   &value,
                 const std::string                   &expressions,
                 const std::string                   &variables,
                 const std::map<std::string, double> &constants,
                 const bool                           time_dependent,
                 const std::string                   &expected)
  {
    std::string report, reason;
    {
      CerrCapture capture;
      try
        {
          function.initialize(variables,
                              expressions,
                              constants,
                              time_dependent);
          // muparser parses every component on the first evaluation.
          Vector<double> values(function.n_components);
          function.vector_value(Point<dim>(), values);
        }
      catch (const std::exception &e)
        {
          reason = error_message(e);
        }
      report = capture.text();
    }
    if (reason.empty())
      {
        std::cerr << report;
        return;
      }
    // deal.II's report of a muparser error: Message, Formula, Token,
    // Position (from 0) and Errc, each as "<...>".
    std::string       message = report_field(report, "Message:");
    const std::string formula =
      Utilities::trim(report_field(report, "Formula:"));
    const std::string position = report_field(report, "Position:");
    // Some of muparser's messages name the position (from 0) themselves.
    const auto own_position = message.find(" at position ");
    if (own_position != std::string::npos)
      message.erase(own_position);
    if (!message.empty() && !position.empty())
      {
        const unsigned int character = std::stoi(position) + 1;
        reason                       = message +
                 (character > formula.size() ?
                    " at the end of <" :
                    " at character " + std::to_string(character) + " of <") +
                 formula + ">";
      }
    else
      std::cerr << report;
    AssertThrow(false,
                ExcMessage(parameter + " = <" + value + "> is not " + expected +
                           ": " + reason));
  }



  template void
  parse_function(FunctionParser<1> &,
                 const std::string &,
                 const std::string &,
                 const std::string &,
                 const std::string &,
                 const std::map<std::string, double> &,
                 const bool,
                 const std::string &);
  template void
  parse_function(FunctionParser<2> &,
                 const std::string &,
                 const std::string &,
                 const std::string &,
                 const std::string &,
                 const std::map<std::string, double> &,
                 const bool,
                 const std::string &);
  template void
  parse_function(FunctionParser<3> &,
                 const std::string &,
                 const std::string &,
                 const std::string &,
                 const std::string &,
                 const std::map<std::string, double> &,
                 const bool,
                 const std::string &);
} // namespace fmpm
