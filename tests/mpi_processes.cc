// The same decks on 1, 2 and 3 MPI processes (mpirun): the same answer to the nonlinear solver's tolerance, one set of files, and the refusals.
//
// This program launches itself under mpirun (`--deck FILE`: one process of
// a run) and compares what the runs write (summary.json). The processes
// divide the flow's cell terms and the direct solve (doc/parallel.md), so
// the systems differ from one process's by round-off in the order of the
// sums and in the factorisation (MUMPS against CHOLMOD / UMFPACK): every
// iterate differs by round-off, and the converged answers by the Newton
// tolerance. Checked:
//  - die2d N1, degree 2, the land holding the metal (parameters/
//    die2d-held-land.prm: 4 adaptive cycles, Coulomb friction) on 1 and 2
//    processes: every quantity (ram force, die forces, probe velocity)
//    within 1e-6 of one process's (Newton stops at |R|/|F| ~ 1e-8 and
//    |dv|/|v| 1e-8; measured 2e-7 on an AMD EPYC), the same Newton
//    iterations per cycle and the same contact states (stick, slip,
//    separated nodes), the same cells per cycle (the refinement's marking
//    of the same indicators);
//  - the round bar, axisymmetric (parameters/roundbar-held-land.prm), on 2;
//  - a 3D deck with Coulomb friction (the rectangular bar quarter,
//    parameters/rectbar3d.prm at 4 x 2 cells, degree 2) on 2;
//  - an exact solution: adaptive Norton-Hoff Poiseuille flow (tests/
//    adaptive_poiseuille.prm) on 2 and 3: the same L2 errors (1e-6) and
//    cells;
//  - a Target error run stops at the same cycle on 2 as on 1;
//  - the dual-weighted indicator (an adjoint solve with J^T) refines the
//    same cells on 2 as on 1;
//  - one summary.json, a VTU piece per process and cycle (their cells
//    together one process's) listed by a .pvtu, no partial or probe files;
//  - degree 1's iterative solver (the augmented Lagrangian, ML across the
//    processes) on die2d N1 and P1 on 2 and 3 processes: every solve
//    iterative, the same cells, iterations and contact states as on 1,
//    quantities within 1e-6; N1 against the direct solver within 1e-4;
//  - the refusals on 2 processes, one line each, exit 1: a run in time,
//    degree 2's iterative solver, fewer than two cells per process.
#include <dieflow/problem/run.h>

#include "report.h"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace
{
  using Json = nlohmann::json;

  /// The text of parameters/@p name with @p changes: each "set Entry = value"
  /// replaces the entry's line (which must be there), in the order given.
  std::string
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

  /// The deck tests/@p name without its Output directory and its Test subsection (the check driver's).
  std::string
  test_deck(const std::string &name)
  {
    const std::string text = file_contents(std::string(SOURCE_DIR) + "/" + name);
    return std::regex_replace(std::regex_replace(text, std::regex("set Output directory[^\\n]*"), ""),
                              std::regex("subsection Test[\\s\\S]*"), "");
  }

  struct Run
  {
    int         status = -1;
    Json        summary;
    std::string error;
    std::string directory;
  };

  /// Runs @p deck (a text) on @p processes MPI processes in the folder @p name.
  Run
  launch(const std::string &name, const std::string &deck, const unsigned int processes)
  {
    Run run;
    run.directory = name + "-" + std::to_string(processes);
    std::filesystem::remove_all(run.directory);
    std::filesystem::create_directories(run.directory);
    const std::string output = "set Output directory = " + run.directory + "/results";
    const std::regex  entry("set Output directory[^\\n]*");
    std::ofstream(run.directory + "/deck.prm")
      << (std::regex_search(deck, entry) ? std::regex_replace(deck, entry, output) : output + "\n" + deck);
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    const std::string command = "mpirun --oversubscribe --bind-to none -np " + std::to_string(processes) + " " + self +
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

  double
  relative(const double a, const double b)
  {
    return a == b ? 0. : std::abs(a - b) / std::max(std::abs(a), std::abs(b));
  }

  /// Whether @p b's cycles reproduce @p a's: the same cells and Newton
  /// iterations (@p same_iterations), the same contact states, every
  /// quantity (@p with_quantities) and the errors against an exact solution
  /// within @p tolerance; the largest relative gap into @p gap.
  bool
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

  /// The cells a .vtu file of deal.II's holds (the sum over its pieces); 0 if none or no file.
  long
  vtu_cells(const std::string &file)
  {
    const std::string text  = file_contents(file);
    const std::regex  piece("NumberOfCells=\"([0-9]+)\"");
    long              cells = 0;
    for (auto m = std::sregex_iterator(text.begin(), text.end(), piece); m != std::sregex_iterator(); ++m)
      cells += std::stol((*m)[1]);
    return cells;
  }

  bool
  one_line(const std::string &text)
  {
    return !text.empty() && text.find('\n') == text.size() - 1;
  }
} // namespace



int
main(int argc, char **argv)
{
  // One process of a run launched below.
  if (argc == 3 && std::string(argv[1]) == "--deck")
    {
      char *arguments[] = {argv[0], argv[2], nullptr};
      return dieflow::run_command_line(2, arguments);
    }
  // The suite runs as root (CI): Open MPI's mpirun refuses it otherwise.
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  unsetenv("DEAL_II_NUM_THREADS");

  double gap = 0;
  {
    const std::string deck = shipped_deck("die2d-held-land.prm", {"set Write VTU = true"});
    const Run         one = launch("die2d", deck, 1), two = launch("die2d", deck, 2);
    report("die2d N1 held land (degree 2, 4 cycles, Coulomb) on 1 and 2 processes: each converges (exit 0)",
           one.status == 0 && two.status == 0);
    const auto processes = [](const Run &run) { return run.summary.is_object() ? run.summary.value("processes", 0) : 0; };
    report("  summary.json says how many processes ran", processes(one) == 1 && processes(two) == 2);
    report("  2 processes: the same cells, Newton iterations and contact states per cycle, forces and probe velocity "
           "within 1e-6 of one process's",
           same_answer(one, two, 1e-6, true, gap));
    bool files = true;
    for (const auto &entry : std::filesystem::recursive_directory_iterator(two.directory + "/results"))
      {
        const std::string file = entry.path().filename().string();
        files = files && file.find(".partial") == std::string::npos && file.find("write-check") == std::string::npos;
      }
    // Each process writes the piece of the cells it assembles; the pieces
    // together hold as many (subdivided) cells as one process's file.
    bool whole = true;
    for (unsigned int c = 0; c < 4; ++c)
      {
        const std::string stem = "/results/solution-0" + std::to_string(c);
        const long        all  = vtu_cells(one.directory + stem + ".vtu");
        const long pieces = vtu_cells(two.directory + stem + ".0000.vtu") + vtu_cells(two.directory + stem + ".0001.vtu");
        const std::string list = file_contents(two.directory + stem + ".pvtu");
        whole = whole && all > 0 && vtu_cells(two.directory + stem + ".0000.vtu") > 0 &&
                vtu_cells(two.directory + stem + ".0001.vtu") > 0 && pieces == all &&
                list.find("solution-0" + std::to_string(c) + ".0001.vtu") != std::string::npos &&
                !std::filesystem::exists(two.directory + stem + ".vtu");
      }
    const std::string pvd = file_contents(two.directory + "/results/solution.pvd");
    report("  2 processes: a .vtu piece per process and cycle, listed by a .pvtu the .pvd names, their cells together "
           "those of one process's .vtu",
           whole && pvd.find("solution-03.pvtu") != std::string::npos);
    report("  2 processes: summary.json and the pvd whole, no partial or probe files",
           files && std::filesystem::exists(two.directory + "/results/solution.pvd"));
    const std::string screen = file_contents(two.directory + "/out.txt");
    std::size_t       converged = 0;
    for (std::size_t at = screen.find("\nconverged;"); at != std::string::npos; at = screen.find("\nconverged;", at + 1))
      ++converged;
    report("  2 processes: the screen's closing line written once", converged == 1);
  }
  {
    const std::string deck = shipped_deck("roundbar-held-land.prm", {"set Write VTU = false"});
    report("round bar, axisymmetric (held land), on 2 processes: as on 1",
           same_answer(launch("roundbar", deck, 1), launch("roundbar", deck, 2), 1e-6, true, gap));
  }
  {
    const std::string deck =
      shipped_deck("rectbar3d.prm", {"set Write VTU = false", "set Cells across = 4", "set Cells in depth = 2"});
    // The 3D contact's early iterations enter and leave the active set by
    // round-off decisions far from the answer: the converged state and the
    // answer agree, the path (its iteration count) may not.
    report("rectangular bar quarter, 3D, Coulomb friction, degree 2, on 2 processes: the same contact states and "
           "answer as on 1",
           same_answer(launch("rectbar3d", deck, 1), launch("rectbar3d", deck, 2), 1e-6, false, gap));
  }
  {
    const std::string plain = test_deck("adaptive_poiseuille.prm");
    const Run one = launch("poiseuille", plain, 1), two = launch("poiseuille", plain, 2),
              three = launch("poiseuille", plain, 3);
    // Its quantities are the net forces of the flow's parts, sums that
    // cancel to 1e-3 of their terms: compared by the errors.
    report("adaptive Norton-Hoff Poiseuille flow (an exact solution, 9 cycles) on 2 and 3 processes: the same cells, "
           "L2 and H1 errors within 1e-6 of one process's",
           same_answer(one, two, 1e-6, true, gap, false) && same_answer(one, three, 1e-6, true, gap, false) &&
             two.summary["cycles"].back()["velocity_l2_error"].is_number());
  }
  {
    const std::string deck =
      shipped_deck("die2d-held-land.prm", {"set Write VTU = false", "set Cycles          = 8"}) +
      "\nsubsection Refinement\n  set Target error = 1e-3\nend\n";
    const Run one = launch("target", deck, 1), two = launch("target", deck, 2);
    report("Target error = 1e-3 (die2d held land): stops at the same cycle on 2 processes as on 1, before the last",
           one.status == 0 && two.status == 0 && one.summary.is_object() && two.summary.is_object() &&
             one.summary["cycles"].size() == two.summary["cycles"].size() && one.summary["cycles"].size() < 8);
  }
  {
    // The dual-weighted indicator solves the adjoint with J^T (MUMPS's transposed solve).
    const std::string deck = shipped_deck(
      "die2d-held-land.prm", {"set Write VTU = false", "set Cycles          = 3", "set Indicator       = dual weighted"});
    report("die2d held land refined by the dual-weighted indicator (an adjoint solve) on 2 processes: the same cells "
           "and answer as on 1",
           same_answer(launch("dual", deck, 1), launch("dual", deck, 2), 1e-6, true, gap));
  }

  {
    // The augmented Lagrangian's Krylov solves with ML across processes
    // (degree 1, Method = iterative): die2d N1 (Newtonian, slipping Coulomb
    // friction: GMRES) and P1 (Norton-Hoff m = 0.2: the viscosity varies by
    // 1e4), 8 cells across, 3 adaptive cycles, as tests/iterative_solver.
    // Each solve stops at its tolerance (1e-6 and looser in the inexact
    // Newton's first steps) and the partitioned hierarchy differs, so the
    // iterates differ at that level; Newton's converged answers agree to
    // its tolerance (measured 1.5e-8 and 7e-9 on an AMD EPYC).
    const std::string coarse  = "subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = 8\n end\nend\n"
                                "subsection Refinement\n set Cycles = 3\n set Strategy = adaptive\nend\n";
    const std::string p1      = "subsection Material\n set Law = Norton-Hoff\n set Consistency K = 0.834\n"
                                " set Rate sensitivity m = 0.2\n set Minimum strain rate = 1e-4\nend\n";
    const auto        solver  = [](const std::string &method) {
      return "subsection Linear solver\n set Method = " + method + "\nend\n";
    };
    const auto iterative_everywhere = [](const Run &run) {
      bool all = run.summary.is_object() && !run.summary["cycles"].empty();
      for (const auto &cycle : all ? run.summary["cycles"] : Json::array())
        all = all && cycle["linear_solver"]["method"] == "iterative" && cycle["linear_solver"]["iterative_solves"] > 0 &&
              cycle["linear_solver"]["direct_fallbacks"] == 0;
      return all;
    };
    for (const auto &[name, law] : {std::pair{"N1", std::string()}, std::pair{"P1", p1}})
      {
        const std::string deck = coarse + law + solver("iterative");
        const Run one = launch(std::string("iterative-") + name, deck, 1),
                  two = launch(std::string("iterative-") + name, deck, 2),
                  three = launch(std::string("iterative-") + name, deck, 3);
        report(std::string("die2d ") + name + ", degree 1, Method = iterative (ML across processes) on 2 and 3 "
                 "processes: every solve iterative, none falling back to MUMPS",
               iterative_everywhere(two) && iterative_everywhere(three));
        report("  the same cells, Newton iterations and contact states per cycle as on 1, quantities within 1e-6",
               same_answer(one, two, 1e-6, true, gap) && same_answer(one, three, 1e-6, true, gap));
        if (law.empty())
          {
            // The direct method solves the penalty form, compressible at a
            // divergence ratio of 1e-6: tests/iterative_solver's 1e-4.
            report("  N1 on 2 processes against the direct solver on 1: the same cells and contact states, "
                   "quantities within 1e-4",
                   same_answer(launch("direct-N1", coarse + solver("direct"), 1), two, 1e-4, false, gap));
          }
      }
  }

  // The refusals.
  const std::string one_cell =
    std::regex_replace(test_deck("adaptive_poiseuille.prm"), std::regex("Subdivisions = 8, 4"), "Subdivisions = 1, 1");
  const std::string incremental =
    shipped_deck("upsetting-incremental.prm", {"set Write VTU = false"});
  const std::string iterative =
    shipped_deck("die2d-held-land.prm", {"set Write VTU = false"}) + "\nsubsection Linear solver\n  set Method = iterative\nend\n";
  // (degree 2: the mixed form is not distributed)
  for (const auto &[what, deck, entry] :
       {std::tuple{"a run in time", incremental, "Problem"},
        std::tuple{"Linear solver/Method = iterative at degree 2", iterative, "Linear solver/Method"},
        std::tuple{"a mesh of one cell", one_cell, "Mesh"}})
    {
      const Run run = launch("refused", deck, 2);
      report(std::string("on 2 processes, ") + what + ": exit 1, one line naming " + entry,
             run.status == 1 && one_line(run.error) && run.error.find("error: " + std::string(entry)) != std::string::npos);
      std::cout << run.error;
    }
}
