// The same decks on 1, 2 and 3 MPI processes (mpirun): the same answer to the nonlinear solver's tolerance, one set of files, and the refusals.
//
// This program launches itself under mpirun (`--deck FILE`: one process of
// a run, tests/mpi_runs.h) and compares what the runs write (summary.json). The processes
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
//    same cells on 2 as on 1, and the dual-weighted estimate (only
//    reported) agrees within 1e-6 of the ram force (measured 2.4e-7 N/mm
//    of 2470: 1e-10; the dual's interpolations left to deal.II's, which
//    on the shared mesh see a process's cells alone, gave 0 and -6.9
//    where one process gives -0.054 and -0.0073);
//  - one summary.json, a VTU piece per process and cycle (their cells
//    together one process's) listed by a .pvtu, no partial or probe files;
//  - the iterative solvers across processes: tests/mpi_iterative_solvers;
//  - the refusals on 2 processes, one line each, exit 1: a run in time,
//    fewer than two cells per process, and 2 processes started by another
//    MPI's launcher (each of which sees itself alone).
#include "mpi_runs.h"

using namespace mpi_runs;



int
main(int argc, char **argv)
{
  // One process of a run launched below.
  if (const int status = launched_process(argc, argv); status >= 0)
    return status;

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
    const std::string deck = target_error_deck();
    report("Target error = 1e-3 (die2d held land): stops at the same cycle on 2 processes as on 1, before the last",
           same_stopping_cycle(launch("target", deck, 1), launch("target", deck, 2)));
  }
  {
    // The dual-weighted indicator solves the adjoint with J^T (MUMPS's transposed solve).
    // The dual-weighted estimate (the adjoint at degree + 1: its pattern and
    // interpolations over every cell, whole_mesh.h) is only reported, so no
    // hash compares it across processes: compared here.
    const std::string deck =
      shipped_deck("die2d-held-land.prm",
                   {"set Write VTU = false", "set Cycles          = 3", "set Indicator       = dual weighted"}) +
      "\nsubsection Refinement\n  set Dual-weighted estimate = true\nend\n";
    const Run  one = launch("dual", deck, 1), two = launch("dual", deck, 2);
    const bool answer = same_answer(one, two, 1e-6, true, gap);
    report("die2d held land refined by the dual-weighted indicator (an adjoint solve) on 2 processes: the same cells "
           "and answer as on 1",
           answer);
    bool estimates = answer;
    for (unsigned int c = 0; estimates && c < one.summary["cycles"].size(); ++c)
      {
        // At the ram force's scale: the estimate is a small sum of larger
        // parts (-0.0073 in the second cycle), whose round-off it keeps.
        const Json &  cycle = one.summary["cycles"][c];
        const Json &  x = cycle["dual_weighted_error"], &y = two.summary["cycles"][c]["dual_weighted_error"];
        const double force = std::abs(cycle["quantities"]["F_x[1]"].get<double>());
        estimates = x.is_number() && y.is_number() && std::abs(x.get<double>() - y.get<double>()) < 1e-6 * force;
      }
    report("  its dual-weighted estimate of the ram force's error per cycle within 1e-6 of the ram force of one "
           "process's",
           estimates);
  }

  // The refusals.
  const std::string one_cell =
    std::regex_replace(test_deck("adaptive_poiseuille.prm"), std::regex("Subdivisions = 8, 4"), "Subdivisions = 1, 1");
  const std::string incremental =
    shipped_deck("upsetting-incremental.prm", {"set Write VTU = false"});
  for (const auto &[what, deck, entry] :
       {std::tuple{"a run in time", incremental, "Problem"},
        std::tuple{"a mesh of one cell", one_cell, "Mesh"}})
    {
      const Run run = launch("refused", deck, 2);
      report(std::string("on 2 processes, ") + what + ": exit 1, one line naming " + entry,
             run.status == 1 && one_line(run.error) && run.error.find("error: " + std::string(entry)) != std::string::npos);
      std::cout << run.error;
    }

  // Another MPI's launcher (MPICH's Hydra, whose PMI_SIZE and PMI_RANK
  // Open MPI does not read): its 2 processes each see MPI's world as 1.
  // Launched here by hand, as Hydra would, without mpirun.
  std::filesystem::create_directories("mismatch");
  std::ofstream("mismatch/deck.prm") << test_deck("adaptive_poiseuille.prm") << "\nset Output directory = mismatch/results\n";
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  std::vector<int>  status;
  std::vector<std::string> lines;
  for (const char *rank : {"0", "1"})
    {
      const std::string err     = std::string("mismatch/err") + rank + ".txt";
      const int         exit_is = std::system(("env -u OMPI_COMM_WORLD_SIZE PMI_SIZE=2 PMI_RANK=" + std::string(rank) + " " +
                                       self + " --deck mismatch/deck.prm > /dev/null 2> " + err)
                                        .c_str());
      status.push_back(WIFEXITED(exit_is) ? WEXITSTATUS(exit_is) : -1);
      lines.push_back(file_contents(err));
    }
  report("2 processes of another MPI's launcher, each seeing itself alone: exit 1 on both, one line from the first "
         "naming the processes started and seen, no results",
         status == std::vector<int>{1, 1} && one_line(lines[0]) &&
           lines[0].find("error: the launcher started 2 processes, but MPI (") != std::string::npos &&
           lines[0].find(") sees 1") != std::string::npos && lines[1].empty() &&
           !std::filesystem::exists("mismatch/results/summary.json"));
}
