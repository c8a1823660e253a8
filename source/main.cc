// dieflow: steady viscoplastic flow through rigid dies with unilateral,
// frictional contact. See README.md and `dieflow --help`.
#include <dieflow/problem/run.h>

int
main(int argc, char **argv)
{
  // MPI is not initialised here: only Trilinos (the iterative linear
  // solver) needs it, and it initialises it on first use
  // (IterativeSolver), which spares the direct path MPI's start-up.
  return dieflow::run_command_line(argc, argv);
}
