// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_interface_h
#define fmpm_postprocess_interface_h

#include <fmpm/particle_update/interface.h>
#include <fmpm/postprocess/global_statistics.h>
#include <fmpm/simulator_access.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace fmpm
{
  class SimulationControl;
  class SimulationFailure;
  template <int dim>
  class ExternalLoads;
  template <int dim>
  struct ConditionReactions;
  namespace Contact
  {
    template <int dim>
    class Manager;
  }

  /**
   * @brief What a run writes at its outputs (ASPECT's postprocessors):
   * history.csv, the VTU files, the points' csv files.
   */
  namespace Postprocess
  {
    template <int dim>
    class EnergyBalance;
    template <int dim>
    class Manager;
    struct RunCounters;

    /**
     * @brief A postprocessor: called at every output of the run with the
     * statistics of that instant; keeps what it needs across a restart in
     * save()/load().
     */
    template <int dim>
    class Interface : public SimulatorAccess<dim>
    {
    public:
      /** The run starts or resumes: open files, write headers
       * (collective). */
      virtual void
      start()
      {}

      /** Write this output (collective; times itself). */
      virtual void
      execute(const GlobalStatistics<dim> &statistics) = 0;

      /** Wait for work still in flight (a background writer); rethrows
       * its error. */
      virtual void
      finish()
      {}

      /** Whether a progress line is due now (rank 0's answer counts). */
      virtual bool
      progress_due() const
      {
        return false;
      }

      /** A progress line with @p statistics: at the start, when
       * progress_due(), and at the end (collective). */
      virtual void
      progress(const GlobalStatistics<dim> &)
      {}

      /** The run stops on a signal with @p status (a kill may follow
       * within a second): write what must not be lost (collective). */
      virtual void
      stopping(const std::string &)
      {}

      /** The run ends (collective): @p status as summary.json gives it
       * ("completed", "stopped: ...", "failed: ..."), @p failure the
       * failure or nullptr. */
      virtual void
      end_of_run(const std::string &, const SimulationFailure *)
      {}

      /** Add what a checkpoint keeps to @p status_strings (rank 0's is
       * written). */
      virtual void
      save(std::map<std::string, std::string> &) const
      {}

      /** Restore from the strings save() wrote. */
      virtual void
      load(const std::map<std::string, std::string> &)
      {}

    protected:
      /** The checkpoint directory a resumed run read (empty: not
       * resumed). */
      const std::string &
      checkpoint_resumed_from() const;
      /** Time, step and the output schedule (output_number()). */
      const SimulationControl &
      get_simulation_control() const;
      /** A grid field of the last step (zero-sized unless allocated). */
      const GridVectorField &
      get_grid_field(const ParticleUpdate::GridField field) const;
      /** Whether @p field was computed in the last step. */
      bool
      grid_field_computed(const ParticleUpdate::GridField field) const;
      /** Multimaterial contact, or nullptr without it. */
      const Contact::Manager<dim> *
      get_contact() const;
      /** The reactions of the velocity conditions in the last step. */
      const ConditionReactions<dim> &
      get_reactions() const;
      /** The initial energies, the energy exchanged and dissipated. */
      const EnergyBalance<dim> &
      get_energy_balance() const;
      /** The mass matrix's history.csv values over the steps since the
       * previous output (MassMatrix::Interface::history_values(), which
       * starts the next interval). */
      std::vector<double>
      mass_matrix_history_values() const;
      /** Contact's history.csv values: the friction work since the start
       * and the contact nodes of the last correction
       * (Contact::Manager::history_values(); collective). */
      std::pair<double, double>
      contact_history_values() const;
      /** The statistics of the current state (collective). */
      GlobalStatistics<dim>
      current_statistics() const;
      /** The run's counts (steps, points, adaptations) and its wall clock
       * start. */
      const RunCounters &
      get_run_counters() const;
      /** The last checkpoint written (empty: none). */
      const std::string &
      latest_checkpoint() const;
      /** Gravity, body force, rotating frame, tractions and their work. */
      const ExternalLoads<dim> &
      get_external_loads() const;
      /** The run's postprocessors. */
      const Manager<dim> &
      get_postprocess_manager() const;
    };



    /**
     * @brief The postprocessors of a run, executed in the order they were
     * added (ASPECT's Postprocess::Manager).
     */
    template <int dim>
    class Manager
    {
    public:
      /** Connect @p postprocessor to @p simulator and keep it. */
      void
      add(std::unique_ptr<Interface<dim>> postprocessor,
          const Simulator<dim>           &simulator)
      {
        postprocessor->initialize_simulator(simulator);
        postprocessors.push_back(std::move(postprocessor));
      }

      /** Every postprocessor's output now. */
      void
      start()
      {
        for (auto &postprocessor : postprocessors)
          postprocessor->start();
      }

      /** The first postprocessor of type @p T, or nullptr. */
      template <class T>
      T *
      find() const
      {
        for (const auto &postprocessor : postprocessors)
          if (T *found = dynamic_cast<T *>(postprocessor.get()))
            return found;
        return nullptr;
      }

      void
      execute(const GlobalStatistics<dim> &statistics)
      {
        for (auto &postprocessor : postprocessors)
          postprocessor->execute(statistics);
      }

      /** Wait for the postprocessors' work in flight. */
      void
      finish()
      {
        for (auto &postprocessor : postprocessors)
          postprocessor->finish();
      }

      /** Whether a postprocessor wants a progress line now. */
      bool
      progress_due() const
      {
        bool due = false;
        for (const auto &postprocessor : postprocessors)
          due = postprocessor->progress_due() || due;
        return due;
      }

      /** A progress line (Interface::progress()). */
      void
      progress(const GlobalStatistics<dim> &statistics)
      {
        for (auto &postprocessor : postprocessors)
          postprocessor->progress(statistics);
      }

      /** The run stops on a signal (Interface::stopping()). */
      void
      stopping(const std::string &status)
      {
        for (auto &postprocessor : postprocessors)
          postprocessor->stopping(status);
      }

      /** The end of the run, with its status (Interface::end_of_run()). */
      void
      end_of_run(const std::string &status, const SimulationFailure *failure)
      {
        for (auto &postprocessor : postprocessors)
          postprocessor->end_of_run(status, failure);
      }

      void
      save(std::map<std::string, std::string> &status_strings) const
      {
        for (const auto &postprocessor : postprocessors)
          postprocessor->save(status_strings);
      }

      void
      load(const std::map<std::string, std::string> &status_strings)
      {
        for (auto &postprocessor : postprocessors)
          postprocessor->load(status_strings);
      }

    private:
      std::vector<std::unique_ptr<Interface<dim>>> postprocessors;
    };
  } // namespace Postprocess
} // namespace fmpm

#endif
