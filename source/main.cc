// dieflow: steady viscoplastic flow through rigid dies with unilateral,
// frictional contact. See README.md and `dieflow --help`.
#include <dieflow/run.h>

#include <deal.II/base/mpi.h>

int
main(int argc, char **argv)
{
  // Trilinos and PETSc need MPI initialised even for one process; one
  // thread per core for assembly.
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, dealii::numbers::invalid_unsigned_int);
  return dieflow::run_command_line(argc, argv);
}
