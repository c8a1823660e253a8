// The deck's checkpoint entries of a run in time: how often, and where to go on from.
#ifndef dieflow_incremental_checkpoint_h
#define dieflow_incremental_checkpoint_h

#include <dieflow/base/parameters.h>

#include <string>

namespace dieflow
{
  /**
   * Checkpoints of an incremental run (subsection Incremental): the state at
   * the end of a converged step, from which a run goes on to the same result
   * as one that was not stopped (DieFlowProblem::save_checkpoint(),
   * load_checkpoint(); source/incremental/checkpoint.cc). One file,
   * Output directory/checkpoint.dat, replaced atomically: every Checkpoint
   * interval steps, at the last step, and when SIGINT or SIGTERM stops the
   * run between steps.
   */
  struct CheckpointParameters
  {
    /// Write every this many steps (0: only at the last step and when stopped).
    unsigned int interval = 10;
    /// The checkpoint to go on from ("": start at t = 0), as the deck gives it.
    std::string restart_from;

    /// Declares the entries in the current subsection (Incremental).
    static void
    declare_parameters(ParameterHandler &prm);
    /// Reads them; @p deck_directory resolves a relative Restart from.
    void
    parse_parameters(ParameterHandler &prm, const std::string &deck_directory);

    /// Whether step @p n of @p n_steps writes a checkpoint.
    bool
    due(const unsigned int n, const unsigned int n_steps) const
    {
      return n == n_steps || (interval > 0 && n % interval == 0);
    }
  };
} // namespace dieflow

#endif
