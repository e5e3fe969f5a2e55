// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_parameter_entries_h
#define fmpm_parameter_entries_h

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/patterns.h>

#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

/**
 * @file
 * What every declare_parameters() uses to write a default once: the
 * default is a member initializer of its struct, and the entry's default
 * text is made from it (Lethe's `const X defaults;`). Numbers are written as
 * the user would write them (format_number), selections through their
 * SelectionNames.
 */

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The names of a Patterns::Selection, in the order of the values of
   * @p Enum (0, 1, ...): the choice is resolved to the enum when parsed.
   */
  template <typename Enum, std::size_t n>
  struct SelectionNames
  {
    const char *names[n];

    /** "a|b|c" for Patterns::Selection. */
    std::string
    pattern() const
    {
      std::string text;
      for (const char *name : names)
        text += (text.empty() ? "" : "|") + std::string(name);
      return text;
    }

    /** The name of @p value, as the parameter file writes it. */
    std::string
    name(const Enum value) const
    {
      return names[static_cast<std::size_t>(value)];
    }

    /** The value named @p name (one of the pattern's names). */
    Enum
    value(const std::string &name) const
    {
      for (std::size_t i = 0; i < n; ++i)
        if (name == names[i])
          return static_cast<Enum>(i);
      AssertThrow(false,
                  ExcMessage("<" + name + "> is not one of " + pattern()));
      return static_cast<Enum>(0);
    }
  };

  /**
   * @brief A number as error messages print it: the shortest text that reads
   * back as the same double, in the form of printf's %g with a short
   * exponent ("0.3", "-5", "2.1e11", "-1e308", "1e-5"), so that a value is
   * echoed as the user wrote it rather than with std::to_string's six fixed
   * decimals (a 300-digit "-1e308", or "0.000000" for 1e-9). Computed
   * values (a stable time step) pass @p max_digits = 6 to round.
   */
  std::string
  format_number(const double value, const unsigned int max_digits = 17);

  /** @brief The text of a boolean default: "true" or "false". */
  std::string
  bool_text(const bool value);

  /**
   * @brief The first @p n entries of @p values separated by ", " (numbers
   * as format_number() writes them): the default of a list entry.
   */
  template <typename Number>
  std::string
  list_text(const std::vector<Number> &values, const std::size_t n)
  {
    static_assert(std::is_arithmetic_v<Number>, "a list of numbers");
    std::string text;
    for (std::size_t i = 0; i < n && i < values.size(); ++i)
      {
        if constexpr (std::is_floating_point_v<Number>)
          text += (i ? ", " : "") + format_number(values[i]);
        else
          text += (i ? ", " : "") + std::to_string(values[i]);
      }
    return text;
  }

  /** @brief The first @p n entries of the list @p text ("0, 0, 0" -> "0, 0").
   */
  std::string
  first_components(const std::string &text, const unsigned int n);

  /** @brief A list of exactly @p dim doubles. */
  Patterns::List
  point_pattern(const unsigned int dim);

  /** @brief The doubles of the list entry @p name. */
  std::vector<double>
  get_doubles(ParameterHandler &prm, const std::string &name);

  /** @brief "Body 0", "Material 2", ...: names of numbered subsections. */
  std::string
  numbered_subsection(const std::string &name, const unsigned int index);
} // namespace fmpm

#endif
