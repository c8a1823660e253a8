// SIGINT and SIGTERM: the first ends a run cleanly after its current iteration, with its results; a second ends it at once.
#include <dieflow/base/interrupt.h>
#include <dieflow/base/processes.h>

#include <deal.II/base/mpi.h>

#include <csignal>
#include <unistd.h>

namespace dieflow
{
  namespace interrupt
  {
    namespace
    {
      volatile std::sig_atomic_t received = 0;

      extern "C" void
      handle(const int signal)
      {
        if (received != 0)
          {
            std::signal(signal, SIG_DFL);
            std::raise(signal);
            return;
          }
        received = signal;
        // Only async-signal-safe calls here: write(2), not iostreams.
        constexpr char message[] =
          "\ndieflow: interrupted: stopping after the current iteration and writing the results "
          "(signal again to stop at once)\n";
        [[maybe_unused]] const auto written = ::write(STDERR_FILENO, message, sizeof(message) - 1);
      }
    } // namespace



    void
    install_handlers()
    {
      std::signal(SIGINT, handle);
      std::signal(SIGTERM, handle);
    }



    bool
    requested()
    {
      // A signal reaches the processes of a run at different times: each
      // check asks all of them, so that they stop at the same iteration.
      // The agreed signal is the one that stopped the run.
      if (processes::n() > 1)
        {
          const int signal = dealii::Utilities::MPI::max(static_cast<int>(received), processes::communicator());
          if (signal != 0 && received == 0)
            received = signal;
        }
      return received != 0;
    }



    std::string
    signal_name()
    {
      return received == SIGINT ? "SIGINT" : received == SIGTERM ? "SIGTERM" : "";
    }



    void
    clear()
    {
      received = 0;
    }
  } // namespace interrupt
} // namespace dieflow
