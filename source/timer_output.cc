// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/timer_output.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace fmpm
{
  TimerOutput::TimerOutput(ConditionalOStream   &stream,
                           const OutputFrequency frequency,
                           const OutputType)
    : stream(stream)
    , frequency(frequency)
    , construction(Clock::now())
  {}



  TimerOutput::~TimerOutput()
  {
    try
      {
        while (!active.empty())
          leave(active.back());
        if (frequency == summary)
          print_summary();
      }
    catch (...)
      {}
  }



  unsigned int
  TimerOutput::section_index(const std::string &name)
  {
    const auto found = index_of.find(name);
    if (found != index_of.end())
      return found->second;
    sections.emplace_back();
    sections.back().name = name;
    index_of.emplace(name, sections.size() - 1);
    return sections.size() - 1;
  }



  void
  TimerOutput::enter_subsection(const std::string &section_name)
  {
    const unsigned int section = section_index(section_name);
    AssertThrow(!sections[section].running,
                ExcMessage("The timer section <" + section_name +
                           "> is entered while it is running."));
    enter(section);
  }



  void
  TimerOutput::leave_subsection(const std::string &section_name)
  {
    AssertThrow(!active.empty(),
                ExcMessage("No timer section is running to leave."));
    if (section_name.empty())
      {
        leave(active.back());
        return;
      }
    const auto found = index_of.find(section_name);
    AssertThrow(found != index_of.end() && sections[found->second].running,
                ExcMessage("The timer section <" + section_name +
                           "> is left but was not entered."));
    leave(found->second);
  }



  std::map<std::string, double>
  TimerOutput::get_summary_data(const OutputData kind) const
  {
    std::map<std::string, double> data;
    for (const Section &section : sections)
      data[section.name] =
        kind == n_calls ? static_cast<double>(section.n_calls) :
                          std::chrono::duration<double>(section.total).count();
    return data;
  }



  double
  TimerOutput::wall_time() const
  {
    return std::chrono::duration<double>(Clock::now() - construction).count();
  }



  void
  TimerOutput::print_summary() const
  {
    // deal.II's table (TimerOutput::print_summary, wall times), sections by
    // name; the name column as wide as the longest name (at least 32).
    std::size_t name_width = 32;
    for (const Section &section : sections)
      name_width = std::max(name_width, section.name.size() + 1);
    const std::string  name_rule(name_width + 1, '-');
    const std::string  wide_blank(name_width - 32, ' ');
    const double       total = wall_time();
    std::ostringstream out;
    out << "\n\n"
        << "+" << name_rule << "------------"
        << "+------------+------------+\n"
        << "| Total wallclock time elapsed since start    " << wide_blank << "|"
        << std::setw(10) << std::setprecision(3) << std::right << total
        << "s |            |\n"
        << "|                                             " << wide_blank
        << "|            |            |\n"
        << "| Section" << std::string(name_width - 7, ' ') << "| no. calls |"
        << "  wall time | % of total |\n"
        << "+" << name_rule << "+-----------+"
        << "------------+------------+";
    for (const auto &entry : index_of)
      {
        const Section &section = sections[entry.second];
        const double   seconds =
          std::chrono::duration<double>(section.total).count();
        std::string name = section.name;
        name.resize(name_width, ' ');
        out << '\n'
            << "| " << name << "| " << std::setw(9) << section.n_calls << " |"
            << std::setw(10) << std::setprecision(3) << seconds << "s |"
            << std::setw(10);
        // Below 0.1 %: 0 (as deal.II prints it).
        const double fraction = total > 0 ? seconds / total : 0;
        if (fraction > 0.001)
          out << std::setprecision(2) << 100 * fraction;
        else
          out << 0.0;
        out << "% |";
      }
    out << '\n'
        << "+" << name_rule << "+-----------+"
        << "------------+------------+\n"
        << '\n';
    stream << out.str() << std::flush;
  }



  void
  TimerOutput::disable_output()
  {
    frequency = never;
  }
} // namespace fmpm
