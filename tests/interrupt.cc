// SIGINT and SIGTERM end a run with outputs a script can read: exit status
// 2, summary.json complete (it parses as JSON) and marked "interrupted":
// true, the reason named, no half-written file left; a signal between two
// cycles keeps the converged cycle. And an output file that is being
// rewritten when the process dies leaves the previous complete file.
// Signals are raised by the test itself at fixed points (before the run,
// or when the log reaches the end of cycle 0), so the output is the same
// on every run.
#include <dieflow/base/interrupt.h>
#include <dieflow/base/atomic_file.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include "report.h"

#include <csignal>
#include <filesystem>

using namespace dieflow;

namespace
{
  const std::string deck = "set Output directory = results\n"
                           "set Write VTU = false\n"
                           "subsection Mesh\n"
                           "  subsection Die2d\n"
                           "    set Layout = blocks\n"
                           "    set Cells across = 4\n"
                           "  end\n"
                           "end\n"
                           "subsection Material\n"
                           "  set Law = Norton-Hoff\n"
                           "end\n"
                           "subsection Refinement\n"
                           "  set Cycles = 3\n"
                           "end\n";

  /// Exit status of the command line on deck.prm (its stdout and stderr swallowed).
  int
  run_command()
  {
    std::ofstream("deck.prm") << deck;
    std::string        name = "dieflow", file = "deck.prm";
    char *             argv[] = {name.data(), file.data()};
    std::ostringstream out, err;
    std::streambuf *   cout_buffer = std::cout.rdbuf(out.rdbuf());
    std::streambuf *   cerr_buffer = std::cerr.rdbuf(err.rdbuf());
    const int          status      = run_command_line(2, argv);
    std::cout.rdbuf(cout_buffer);
    std::cerr.rdbuf(cerr_buffer);
    return status;
  }

  /// results/summary.json read as JSON (throws if it is not complete JSON).
  boost::property_tree::ptree
  summary_json()
  {
    boost::property_tree::ptree tree;
    boost::property_tree::read_json("results/summary.json", tree);
    return tree;
  }

  bool
  no_partial_files()
  {
    for (const auto &entry : std::filesystem::directory_iterator("results"))
      if (entry.path().extension() == ".partial")
        return false;
    return true;
  }

} // namespace



int
main()
{
  // A signal before the run: it stops at its first iteration.
  interrupt::install_handlers();
  std::cout << std::flush;
  std::raise(SIGTERM);
  const int status = run_command();
  report("SIGTERM: exit status 2", status == 2);
  bool parses = true, marked = false, named = false;
  try
    {
      const auto tree = summary_json();
      marked          = tree.get<std::string>("interrupted") == "true" && tree.get<std::string>("converged") == "false";
      named           = tree.get<std::string>("failure").find("stopped by SIGTERM at iteration") != std::string::npos;
    }
  catch (const std::exception &)
    {
      parses = false;
    }
  report("SIGTERM: summary.json is complete JSON", parses);
  report("SIGTERM: marked interrupted and not converged, the signal named", marked && named);
  report("SIGTERM: the study table written, no partial file left",
         std::filesystem::exists("results/study.txt") && no_partial_files());

  // A signal at the end of cycle 0: cycle 0 is kept, cycle 1 never starts.
  interrupt::clear();
  std::ofstream("deck.prm") << deck;
  ParameterHandler prm;
  read_deck("deck.prm", prm);
  SignalAtCycleEnd   buffer;
  std::ostream       log(&buffer);
  const RunSummary   summary = run_deck(prm, ".", log);
  report("SIGINT after cycle 0: one cycle, converged, kept",
         summary.cycles.size() == 1 && summary.cycles[0].converged);
  report("SIGINT after cycle 0: the run interrupted before cycle 1",
         summary.interrupted && !summary.converged && summary.failure == "stopped by SIGINT before cycle 1");
  report("SIGINT after cycle 0: summary.json says so",
         summary_json().get<std::string>("interrupted") == "true" && summary_json().get_child("cycles").size() == 1);

  // No signal: the same deck runs to the end.
  interrupt::clear();
  report("no signal: exit status 0, three cycles, not interrupted",
         run_command() == 0 && summary_json().get<std::string>("interrupted") == "false" &&
           summary_json().get_child("cycles").size() == 3);

  // A writer that dies before commit() leaves the old file whole.
  const std::string before = [] {
    std::ifstream      in("results/summary.json");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }();
  {
    AtomicFile file("results/summary.json");
    file.stream() << "{\n  \"conver";
  }
  std::ifstream      in("results/summary.json");
  std::ostringstream after;
  after << in.rdbuf();
  report("a write cut short leaves the previous summary.json, and no partial file",
         after.str() == before && no_partial_files());
}
