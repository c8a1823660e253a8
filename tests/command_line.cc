// The command line (interface.md): --help and --print-parameters exit 0,
// an unknown option or a missing deck exit 1 with one line on stderr, and a
// bad deck named without a directory (in the working directory) exits 1
// at once with its message (this once hung: the file name in deal.II's
// message was replaced by itself forever), and so does an output directory
// that cannot be created (it once ended in an internal error, exit 3).
// Under mpirun -np 1 it runs as without a launcher.
#include <dieflow/problem/run.h>

#include "report.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

using namespace dieflow;

namespace
{
  /// Exit status and what went to stderr (stdout is swallowed).
  std::pair<int, std::string>
  run(std::vector<std::string> arguments)
  {
    std::vector<char *> argv;
    for (auto &a : arguments)
      argv.push_back(a.data());
    std::ostringstream out, err;
    std::streambuf *   cout_buffer = std::cout.rdbuf(out.rdbuf());
    std::streambuf *   cerr_buffer = std::cerr.rdbuf(err.rdbuf());
    const int          status      = run_command_line(argv.size(), argv.data());
    std::cout.rdbuf(cout_buffer);
    std::cerr.rdbuf(cerr_buffer);
    return {status, err.str()};
  }

  bool
  one_line(const std::string &text)
  {
    return !text.empty() && text.find('\n') == text.size() - 1;
  }
} // namespace

int
main()
{
  report("--help exits 0", run({"dieflow", "--help"}).first == 0);
  report("--print-parameters exits 0", run({"dieflow", "--print-parameters"}).first == 0);
  const auto unknown = run({"dieflow", "--frobnicate"});
  report("an unknown option exits 1", unknown.first == 1);
  const auto missing = run({"dieflow", "no-such-deck.prm"});
  report("a missing deck exits 1 with one line", missing.first == 1 && one_line(missing.second));
  std::cout << missing.second;
  std::ofstream("bad.prm") << "subsection Material\n set Viscosity = nan\nend\n";
  const auto bad = run({"dieflow", "bad.prm"});
  report("a bad deck in the working directory exits 1 with one line", bad.first == 1 && one_line(bad.second));
  std::cout << bad.second;
  std::ofstream("unwritable.prm") << "set Output directory = /dev/null/results\n";
  const auto unwritable = run({"dieflow", "unwritable.prm"});
  report("an output directory that cannot be created exits 1 with one line naming it, not 3",
         unwritable.first == 1 && one_line(unwritable.second) &&
           unwritable.second.find("Output directory") != std::string::npos);
  std::cout << unwritable.second;

  // What Open MPI's mpirun -np 1 sets: one process runs as without a
  // launcher (MPI is not started; tests/mpi_processes runs more).
  setenv("OMPI_COMM_WORLD_SIZE", "1", 1);
  setenv("OMPI_COMM_WORLD_RANK", "0", 1);
  report("as the only process (mpirun -np 1): the deck is read as without mpirun",
         run({"dieflow", "no-such-deck.prm"}) == missing);
  unsetenv("OMPI_COMM_WORLD_SIZE");
  unsetenv("OMPI_COMM_WORLD_RANK");
}
