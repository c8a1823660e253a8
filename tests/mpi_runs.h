// Runs of a deck on P MPI processes for the tests (the test program launches itself under mpirun), and the comparison of their summary.json files.
#ifndef dieflow_tests_mpi_runs_h
#define dieflow_tests_mpi_runs_h

#include <dieflow/problem/run.h>
#include <dieflow/solvers/linear_solver.h>

#include "report.h"

#include <nlohmann/json.hpp>

#include <mpi.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace mpi_runs
{
  using Json = nlohmann::json;

  /// The text of parameters/@p name with @p changes: each "set Entry = value"
  /// replaces the entry's line (which must be there), in the order given.
  inline std::string
  shipped_deck(const std::string &name, const std::vector<std::string> &changes)
  {
    std::string text = file_contents(std::string(SOURCE_DIR) + "/../parameters/" + name);
    for (const auto &change : changes)
      {
        const std::string entry = change.substr(4, change.find('=') - 4);
        const std::regex  line("\\n(\\s*)set " + std::regex_replace(entry, std::regex("\\s+$"), "") + "\\s*=[^\\n]*");
        if (!std::regex_search(text, line))
          {
            std::cout << "the deck " << name << " has no entry " << entry << std::endl;
            std::exit(1);
          }
        text = std::regex_replace(text, line, "\n$1" + change, std::regex_constants::format_first_only);
      }
    return text;
  }

  struct Run
  {
    int         status = -1;
    Json        summary;
    std::string error;
    std::string directory;
  };

  /// Runs @p deck (a text) on @p processes MPI processes in the folder @p name;
  /// @p room_gb > 0: each process's address space limited to what it maps
  /// once MPI has started plus that many GB (launched_process());
  /// @p prepare, if given, is called with the run's Output directory
  /// (made, empty) before the run.
  inline Run
  launch(const std::string &                             name,
         const std::string &                             deck,
         const unsigned int                              processes,
         const double                                    room_gb = 0,
         const std::function<void(const std::string &)> &prepare = {})
  {
    Run run;
    run.directory = name + "-" + std::to_string(processes);
    std::filesystem::remove_all(run.directory);
    std::filesystem::create_directories(run.directory + "/results");
    if (prepare)
      prepare(run.directory + "/results");
    const std::string output = "set Output directory = " + run.directory + "/results";
    const std::regex  entry("set Output directory[^\\n]*");
    std::ofstream(run.directory + "/deck.prm")
      << (std::regex_search(deck, entry) ? std::regex_replace(deck, entry, output) : output + "\n" + deck);
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    const std::string room = room_gb > 0 ? "-x DIEFLOW_TEST_ROOM_GB=" + std::to_string(room_gb) + " " : "";
    const std::string command = "mpirun --oversubscribe --bind-to none -np " + std::to_string(processes) + " " + room + self +
                                " --deck " + run.directory + "/deck.prm > " + run.directory + "/out.txt 2> " +
                                run.directory + "/err.txt";
    const int status = std::system(command.c_str());
    run.status       = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    // The program's lines (mpirun adds its own where a process exits non-zero).
    std::istringstream error(file_contents(run.directory + "/err.txt"));
    for (std::string line; std::getline(error, line);)
      if (line.rfind("dieflow:", 0) == 0)
        run.error += line + "\n";
    std::ifstream summary(run.directory + "/results/summary.json");
    if (summary)
      run.summary = Json::parse(summary);
    return run;
  }

  inline double
  relative(const double a, const double b)
  {
    return a == b ? 0. : std::abs(a - b) / std::max(std::abs(a), std::abs(b));
  }

  /// Whether @p b's cycles reproduce @p a's: the same cells and Newton
  /// iterations (@p same_iterations), the same contact states, every
  /// quantity (@p with_quantities) and the errors against an exact solution
  /// within @p tolerance; the largest relative gap into @p gap.
  inline bool
  same_answer(const Run &   a,
              const Run &   b,
              const double  tolerance,
              const bool    same_iterations,
              double &      gap,
              const bool    with_quantities = true)
  {
    gap = 0;
    if (a.status != 0 || b.status != 0 || !a.summary.is_object() || !b.summary.is_object() ||
        a.summary["cycles"].size() != b.summary["cycles"].size() || a.summary["cycles"].empty())
      return false;
    bool same = true;
    for (unsigned int c = 0; c < a.summary["cycles"].size(); ++c)
      {
        const Json &x = a.summary["cycles"][c], &y = b.summary["cycles"][c];
        same = same && x["cells"] == y["cells"] && x["contact_nodes"] == y["contact_nodes"];
        if (same_iterations)
          same = same && x["nonlinear_iterations"] == y["nonlinear_iterations"];
        if (with_quantities)
          for (const auto &[name, value] : x["quantities"].items())
            gap = std::max(gap, relative(value.get<double>(), y["quantities"][name].get<double>()));
        for (const char *error : {"velocity_l2_error", "velocity_h1_error"})
          if (x.contains(error) && x[error].is_number())
            gap = std::max(gap, relative(x[error].get<double>(), y[error].get<double>()));
      }
    return same && gap < tolerance;
  }

  /// The adaptive cycles target_error_deck() allows.
  constexpr unsigned int target_error_cycles = 8;

  /// die2d held land (up to target_error_cycles adaptive cycles) with Target error = 1e-3.
  inline std::string
  target_error_deck()
  {
    return shipped_deck("die2d-held-land.prm",
                        {"set Write VTU = false", "set Cycles          = " + std::to_string(target_error_cycles)}) +
           "\nsubsection Refinement\n  set Target error = 1e-3\nend\n";
  }

  /// Whether the target_error_deck() runs @p a and @p b both converged and
  /// stopped at the same cycle, before the last.
  inline bool
  same_stopping_cycle(const Run &a, const Run &b)
  {
    return a.status == 0 && b.status == 0 && a.summary.is_object() && b.summary.is_object() &&
           a.summary["cycles"].size() == b.summary["cycles"].size() && a.summary["cycles"].size() < target_error_cycles;
  }

  /// The cells a .vtu file of deal.II's holds (the sum over its pieces); 0 if none or no file.
  inline long
  vtu_cells(const std::string &file)
  {
    const std::string text  = file_contents(file);
    const std::regex  piece("NumberOfCells=\"([0-9]+)\"");
    long              cells = 0;
    for (auto m = std::sregex_iterator(text.begin(), text.end(), piece); m != std::sregex_iterator(); ++m)
      cells += std::stol((*m)[1]);
    return cells;
  }

  inline bool
  one_line(const std::string &text)
  {
    return !text.empty() && text.find('\n') == text.size() - 1;
  }


  /// Where this program was launched by launch() (`--deck FILE`): runs that
  /// process of the deck and returns its exit status; else -1, after setting
  /// what mpirun needs in the suite (root, as CI runs it; no thread count).
  inline int
  launched_process(int argc, char **argv)
  {
    if (argc == 3 && std::string(argv[1]) == "--deck")
      {
        char *arguments[] = {argv[0], argv[2], nullptr};
        // A process that hangs (waiting for another in a collective, or,
        // below, unable to map what it asks for) is ended by the alarm's
        // signal, and mpirun ends the run: a test fails instead of waiting
        // for ctest's timeout.
        alarm(300);
        const char *room  = std::getenv("DIEFLOW_TEST_ROOM_GB");
        if (room == nullptr)
          return dieflow::run_command_line(2, arguments);
        // MPI first: Open MPI maps its shared segments as it starts, and
        // fails to start under a limit (the run leaves it to this program).
        int provided = 0;
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
        struct rlimit limit;
        getrlimit(RLIMIT_AS, &limit);
        limit.rlim_cur = static_cast<rlim_t>(dieflow::mapped_memory() + 1e9 * std::atof(room));
        setrlimit(RLIMIT_AS, &limit);
        const int status = dieflow::run_command_line(2, arguments);
        MPI_Finalize();
        return status;
      }
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    unsetenv("DEAL_II_NUM_THREADS");
    return -1;
  }
} // namespace mpi_runs

#endif
