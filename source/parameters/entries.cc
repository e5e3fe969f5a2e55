// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// Helpers of every declare_parameters() and parse_parameters().

#include <fmpm/parameters.h>

#include <deal.II/base/numbers.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>

namespace fmpm
{
  std::string
  bool_text(const bool value)
  {
    return value ? "true" : "false";
  }



  std::string
  first_components(const std::string &text, const unsigned int n)
  {
    const std::vector<std::string> entries =
      Utilities::split_string_list(text, ',');
    std::string result;
    for (unsigned int i = 0; i < n && i < entries.size(); ++i)
      result += (i ? ", " : "") + entries[i];
    return result;
  }



  Patterns::List
  point_pattern(const unsigned int dim)
  {
    return Patterns::List(Patterns::Double(), dim, dim, ",");
  }



  std::vector<double>
  get_doubles(ParameterHandler &prm, const std::string &name)
  {
    return Utilities::string_to_double(
      Utilities::split_string_list(prm.get(name)));
  }



  std::map<std::string, double>
  parse_function_constants(const std::string &text, const std::string &where)
  {
    // pi is always available in the expressions.
    std::map<std::string, double> constants{{"pi", numbers::PI}};
    for (const auto &entry : Utilities::split_string_list(text, ','))
      {
        const auto pair = Utilities::split_string_list(entry, '=');
        AssertThrow(pair.size() == 2,
                    ExcMessage(where + ": <" + entry +
                               "> is not of the form name=value."));
        constants[pair[0]] = Utilities::string_to_double(pair[1]);
      }
    return constants;
  }



  std::string
  to_function_expressions(const std::string &value)
  {
    if (value.find(';') != std::string::npos)
      return value;
    std::string result;
    for (const auto &component : Utilities::split_string_list(value, ','))
      result += (result.empty() ? "" : ";") + component;
    return result;
  }



  std::string
  format_number(const double value, const unsigned int max_digits)
  {
    if (!std::isfinite(value))
      return std::isnan(value) ? "nan" : (value > 0 ? "inf" : "-inf");
    // The fewest significant digits that read back as the same double
    // (17 always do).
    std::string text;
    for (unsigned int digits = 1; digits <= std::min(max_digits, 17u); ++digits)
      {
        std::ostringstream out;
        out << std::setprecision(digits) << value;
        text = out.str();
        if (std::strtod(text.c_str(), nullptr) == value)
          break;
      }
    // "1e+308" -> "1e308", "1e-05" -> "1e-5".
    const auto e = text.find('e');
    if (e == std::string::npos)
      return text;
    // Below 1e6 without exponent: "10", "1500", not "1e1", "1.5e3".
    const int exponent_value = std::atoi(text.c_str() + e + 1);
    if (exponent_value >= 0 && exponent_value < 6)
      {
        std::ostringstream out;
        // %g switches to an exponent only at precision <= exponent.
        out << std::setprecision(exponent_value + 1) << value;
        return out.str();
      }
    std::string exponent = text.substr(e + 1);
    const bool  negative = !exponent.empty() && exponent[0] == '-';
    if (!exponent.empty() && (exponent[0] == '-' || exponent[0] == '+'))
      exponent.erase(0, 1);
    exponent.erase(0,
                   std::min(exponent.find_first_not_of('0'),
                            exponent.size() - 1));
    return text.substr(0, e + 1) + (negative ? "-" : "") + exponent;
  }



  std::string
  numbered_subsection(const std::string &name, const unsigned int index)
  {
    return name + " " + std::to_string(index);
  }
} // namespace fmpm
