// SIGINT and SIGTERM: the first ends a run cleanly after its current iteration, with its results; a second ends it at once.
#ifndef dieflow_interrupt_h
#define dieflow_interrupt_h

#include <string>

namespace dieflow
{
  /**
   * SIGINT and SIGTERM end a run cleanly: the first one only raises a flag
   * (and says so on stderr), which the nonlinear iteration and the cycle
   * loop check; the run then post-processes its last iterate and writes
   * summary.json marked "interrupted": true (exit status 2). A second
   * signal takes the default action at once (a factorisation can take
   * minutes between two checks).
   */
  namespace interrupt
  {
    /// Installs the handlers of SIGINT and SIGTERM.
    void
    install_handlers();

    /// Whether a signal asked the run to stop.
    bool
    requested();

    /// "SIGINT" or "SIGTERM", the signal that asked ("" if none).
    std::string
    signal_name();

    /// Forgets a request (a new run in the same process).
    void
    clear();
  } // namespace interrupt
} // namespace dieflow

#endif
