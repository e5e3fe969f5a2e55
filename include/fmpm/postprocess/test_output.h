// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_postprocess_test_output_h
#define fmpm_postprocess_test_output_h

#include <fmpm/postprocess/interface.h>

#include <deal.II/base/conditional_ostream.h>

#include <memory>
#include <string>

namespace fmpm
{
  namespace Postprocess
  {
    /**
     * @brief The test output of a run (Test mode = true; the tests/prm
     * reference outputs), on standard output of rank 0: where a resumed run
     * resumed, one line per output (step, t, mass, momentum, kinetic and
     * strain energy), and at the end every point's id, position and
     * velocity sorted by id, or the failure.
     */
    template <int dim>
    class TestOutput : public Interface<dim>
    {
    public:
      void
      start() override;

      void
      execute(const GlobalStatistics<dim> &statistics) override;

      void
      end_of_run(const std::string       &status,
                 const SimulationFailure *failure) override;

    private:
      /** Standard output on rank 0. */
      ConditionalOStream &
      out();

      std::unique_ptr<ConditionalOStream> stream;
    };
  } // namespace Postprocess
} // namespace fmpm

#endif
