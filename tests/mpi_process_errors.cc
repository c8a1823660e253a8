// An error on one MPI process alone ends every process with one line; an error on every process ends them with the first's line alone.
//
// The run on 2 processes writes the solution as a .vtu piece per process
// (doc/parallel.md). A folder made beforehand where a piece goes
// (results/solution-00.000R.vtu, with a file in it) fails process R alone
// when it writes the first cycle's piece, while the other goes on into the
// second cycle's collectives. That process must end the others
// (processes::failed_together(), then MPI_Abort): the run ends with exit
// status 1 and one error line, the first, that names Output directory,
// the piece and the process (the other process, which mpirun then ends
// with a signal, may say it was interrupted). A deck error, which every process meets, ends both with the
// first process's line alone, and no process aborts the others.
// Checked that it fails: with failed_together() returning true always (the
// failing process returning as if every process had failed), the run with
// process 1's piece blocked printed no line and hung until the launched
// processes' alarm (300 s) ended it, and ctest's timeout (600 s) the test.
#include "mpi_runs.h"

using namespace mpi_runs;

namespace
{
  const std::string deck = "subsection Mesh\n  set Corner refinements = 2\n  subsection Die2d\n    set Cells across = 8\n  end\nend\n"
                           "subsection Refinement\n  set Cycles = 2\nend\n"
                           "set Write VTU = true\n";

  /// The program's error lines in @p lines (dieflow's lines on standard error).
  unsigned int
  errors(const std::string &lines)
  {
    unsigned int count = 0;
    std::istringstream in(lines);
    for (std::string line; std::getline(in, line);)
      count += line.rfind("dieflow: error:", 0) == 0 || line.rfind("dieflow: internal error:", 0) == 0;
    return count;
  }

  /// A run of the deck on 2 processes with process @p rank's first piece
  /// blocked by a folder of its name.
  Run
  blocked_piece(const unsigned int rank)
  {
    return launch("piece-" + std::to_string(rank), deck, 2, 0, [rank](const std::string &results) {
      const std::string piece = results + "/solution-00.000" + std::to_string(rank) + ".vtu";
      std::filesystem::create_directories(piece);
      std::ofstream(piece + "/keep") << "a folder where the piece goes\n";
    });
  }
} // namespace



int
main(int argc, char **argv)
{
  if (const int status = launched_process(argc, argv); status >= 0)
    return status;

  for (const unsigned int rank : {1u, 0u})
    {
      const Run         run  = blocked_piece(rank);
      const std::string name = "solution-00.000" + std::to_string(rank) + ".vtu";
      report("2 processes, process " + std::to_string(rank) + "'s .vtu piece cannot be written: the run ends, exit 1",
             run.status == 1);
      // The others, ended by mpirun's signal, may say they were interrupted: no error of theirs.
      report("  one error line, the first, naming Output directory, the piece and process " + std::to_string(rank),
             errors(run.error) == 1 && run.error.find("dieflow: error: Output directory: cannot write '") == 0 &&
               run.error.find(name + "'") != std::string::npos &&
               run.error.find("(MPI process " + std::to_string(rank) + " alone") != std::string::npos);
    }

  const Run bad = launch("bad-deck", deck + "subsection Material\n  set Viscosity = -1\nend\n", 2);
  report("2 processes, a deck error every process meets: exit 1, the first's line alone, no process ending the others",
         bad.status == 1 && one_line(bad.error) && bad.error.find("Viscosity") != std::string::npos &&
           bad.error.find("alone") == std::string::npos);
}
