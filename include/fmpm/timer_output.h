// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_timer_output_h
#define fmpm_timer_output_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/exceptions.h>

#include <chrono>
#include <map>
#include <string>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief The wall time of named sections of a run and deal.II's
   * TimerOutput table of them: the part of dealii::TimerOutput's interface
   * that fmpm uses (Scope, enter_subsection(), leave_subsection(),
   * get_summary_data(), print_summary(), disable_output()), declared in
   * namespace fmpm so that `TimerOutput` there names this class.
   *
   * dealii::TimerOutput (9.4) reads the process CPU time (getrusage over
   * all threads) at every start and stop of a section, also when it
   * reports wall times only; with the map look-ups around it, one section
   * entry cost 5-6 µs, about 4.5 µs of them outside the section
   * (doc/benchmarks.md, "Timer coverage"). Steps of small scenes take
   * 100-200 µs and enter about 20 sections. This class reads only the
   * steady clock, at the last moment on entry and the first on leaving.
   *
   * The times are this rank's. Sections may nest (each is timed on its
   * own); the table lists them by name.
   */
  class TimerOutput
  {
  public:
    /** When the table is printed: never, or at destruction. */
    enum OutputFrequency
    {
      never,
      summary
    };

    /** What the table shows: wall times (the only choice). */
    enum OutputType
    {
      wall_times
    };

    /** The data get_summary_data() returns. */
    enum OutputData
    {
      total_wall_time,
      n_calls
    };

    /** Enters a section on construction and leaves it on destruction. */
    class Scope
    {
    public:
      Scope(TimerOutput &timer, const std::string &section_name);

      ~Scope();

      /** Leave the section before the end of the scope. */
      void
      stop();

    private:
      TimerOutput &timer;
      unsigned int section;
      bool         running = true;
    };

    /** The clock of the total time starts here. */
    TimerOutput(ConditionalOStream   &stream,
                const OutputFrequency frequency,
                const OutputType      type);

    /** Prints the table unless the frequency is never or output is off. */
    ~TimerOutput();

    void
    enter_subsection(const std::string &section_name);

    /** Leave the section @p section_name, or without a name the one
     * entered last. */
    void
    leave_subsection(const std::string &section_name = "");

    /** Seconds (or calls) per section name. */
    std::map<std::string, double>
    get_summary_data(const OutputData kind) const;

    /** Seconds since construction. */
    double
    wall_time() const;

    /** deal.II's wall-time table: total, then one row per section. */
    void
    print_summary() const;

    /** No table at destruction. */
    void
    disable_output();

  private:
    using Clock = std::chrono::steady_clock;

    struct Section
    {
      std::string       name;
      unsigned long     n_calls = 0;
      Clock::duration   total   = Clock::duration::zero();
      Clock::time_point start;
      bool              running = false;
    };

    /** The index of the section @p name, created on first use. */
    unsigned int
    section_index(const std::string &name);

    void
    enter(const unsigned int section);

    void
    leave(const unsigned int section);

    ConditionalOStream                 &stream;
    OutputFrequency                     frequency;
    Clock::time_point                   construction;
    std::vector<Section>                sections;
    std::map<std::string, unsigned int> index_of;
    /** Sections entered and not yet left, in order. */
    std::vector<unsigned int> active;
  };



  inline void
  TimerOutput::enter(const unsigned int section)
  {
    Section &s = sections[section];
    Assert(!s.running,
           ExcMessage("The timer section <" + s.name +
                      "> is entered while it is running."));
    ++s.n_calls;
    s.running = true;
    active.push_back(section);
    s.start = Clock::now();
  }



  inline void
  TimerOutput::leave(const unsigned int section)
  {
    const Clock::time_point now = Clock::now();
    Section                &s   = sections[section];
    if (!s.running)
      return;
    s.total += now - s.start;
    s.running = false;
    for (auto a = active.rbegin(); a != active.rend(); ++a)
      if (*a == section)
        {
          active.erase(std::next(a).base());
          break;
        }
  }



  inline TimerOutput::Scope::Scope(TimerOutput       &timer_output,
                                   const std::string &section_name)
    : timer(timer_output)
    , section(timer_output.section_index(section_name))
  {
    timer.enter(section);
  }



  inline TimerOutput::Scope::~Scope()
  {
    stop();
  }



  inline void
  TimerOutput::Scope::stop()
  {
    if (running)
      timer.leave(section);
    running = false;
  }

  /**
   * @brief Whether the section @p name is a sub-section, "<part>: <detail>"
   * (point store, contact): it runs within another section (a stage
   * of the step, set-up, mesh adaptation, a checkpoint), and sums of the
   * sections leave it out.
   */
  inline bool
  is_timer_subsection(const std::string &name)
  {
    return name.find(": ") != std::string::npos;
  }
} // namespace fmpm

#endif
