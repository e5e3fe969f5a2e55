// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_function_parser_h
#define fmpm_function_parser_h

#include <deal.II/base/function_parser.h>

#include <map>
#include <string>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief Initialize @p function from the value of a scene parameter and
   * parse it now (muparser parses on the first evaluation), so that a bad
   * expression stops the set-up with one message:
   * "<parameter> = <value> is not <expected>: <muparser's message> at
   * character N of <the expression>" (N counted from 1 in that component's
   * expression). deal.II's own report of the parse error (written to
   * std::cerr, with muparser's error code where the column belongs) is
   * not printed.
   *
   * @param function the parser, constructed with its number of components
   * @param parameter the parameter's path, e.g. "Body 0/Initial velocity"
   * @param value the parameter's value as the scene writes it
   * @param expressions @p value as FunctionParser expressions (components
   * separated by ';', to_function_expressions())
   * @param variables FunctionParser's variable names ("x,y,t", ...)
   * @param constants the expressions' constants
   * @param time_dependent whether the last variable is the time
   * @param expected what the value must be, e.g. "2 expressions in x, y, t"
   */
  template <int dim>
  void
  parse_function(FunctionParser<dim>                 &function,
                 const std::string                   &parameter,
                 const std::string                   &value,
                 const std::string                   &expressions,
                 const std::string                   &variables,
                 const std::map<std::string, double> &constants,
                 const bool                           time_dependent,
                 const std::string                   &expected);
} // namespace fmpm

#endif
