// The iterative solvers across MPI processes (mpirun, tests/mpi_runs.h): the same answer as on one process, every solve iterative.
//
// Each Krylov solve stops at its (forcing) tolerance, and the hierarchies
// ML builds across 2 or 3 processes differ from one process's, so the
// iterates differ at the solver's tolerance; Newton's converged answers
// agree to its own (|R|/|F| ~ 1e-8). Checked:
//  - degree 1's iterative solver (the augmented Lagrangian, CG / GMRES with
//    ML on a distributed Trilinos matrix) on die2d N1 and P1 (8 cells
//    across, 3 adaptive cycles) on 2 and 3 processes: every solve
//    iterative, none falling back to MUMPS, the same cells, Newton
//    iterations and contact states as on 1, quantities within 1e-6; N1
//    against the direct solver within 1e-4 (the penalty form's
//    compressibility, as tests/iterative_solver);
//  - degree 2's iterative solver (the mixed form: GMRES with the block
//    preconditioner, its products with A, B, B^T and its ML hierarchies
//    divided by rows: RowBlockMatrix, RowBlockAMG) on die2d N1 held land
//    (p-multigrid, 4 adaptive cycles, Coulomb) on 2 and 3 processes and on
//    the 3D rectangular bar quarter (AMG on Q2 with inner solves, Coulomb)
//    on 2: every solve iterative, the same answer as on 1.
// That the work is divided is not observable here (a product of the whole
// matrix on every process would pass): its time is measured in
// doc/parallel.md.
#include "mpi_runs.h"

using namespace mpi_runs;

namespace
{
  /// Whether every cycle of @p run solved its Newton systems iteratively, none falling back to the direct solver.
  bool
  iterative_everywhere(const Run &run)
  {
    bool all = run.summary.is_object() && !run.summary["cycles"].empty();
    for (const auto &cycle : all ? run.summary["cycles"] : Json::array())
      all = all && cycle["linear_solver"]["method"] == "iterative" && cycle["linear_solver"]["iterative_solves"] > 0 &&
            cycle["linear_solver"]["direct_fallbacks"] == 0;
    return all;
  }
} // namespace



int
main(int argc, char **argv)
{
  // One process of a run launched below.
  if (const int status = launched_process(argc, argv); status >= 0)
    return status;

  double gap = 0;
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

  {
    // Degree 2's iterative solver, the mixed form (GMRES with the block
    // preconditioner), across processes: every product with A, B and B^T
    // and the ML hierarchies divided by rows (RowBlockMatrix, RowBlockAMG).
    // Each solve stops at its forcing tolerance, the partitioned ML differs,
    // so the iterates differ at that level and Newton's converged answers
    // agree to its tolerance (measured 3.5e-8 and 2e-8 on an AMD EPYC).
    const std::string iterative = "\nsubsection Linear solver\n  set Method = iterative\nend\n";
    const std::string die2d = shipped_deck("die2d-held-land.prm", {"set Write VTU = false"}) + iterative;
    const Run one = launch("mixed-die2d", die2d, 1), two = launch("mixed-die2d", die2d, 2),
              three = launch("mixed-die2d", die2d, 3);
    report("die2d N1 held land, degree 2, Method = iterative (the mixed form, p-multigrid, ML on Q1 across processes) on "
           "2 and 3 processes: every solve iterative",
           iterative_everywhere(two) && iterative_everywhere(three));
    report("  the same cells, Newton iterations and contact states per cycle as on 1, quantities within 1e-6",
           same_answer(one, two, 1e-6, true, gap) && same_answer(one, three, 1e-6, true, gap));
    // (the Linear solver's Method, not the Nonlinear solver's before it)
    const std::string bar = std::regex_replace(
      shipped_deck("rectbar3d.prm", {"set Write VTU = false", "set Cells across = 4", "set Cells in depth = 2"}),
      std::regex("set Method = auto"),
      "set Method = iterative\n  set Velocity multigrid = AMG\n  set Velocity block = inner solve");
    const Run bar_two = launch("mixed-bar", bar, 2);
    report("rectangular bar quarter, 3D, Coulomb, degree 2, the mixed form with AMG on Q2 and inner solves, on 2 "
           "processes: every solve iterative, the same contact states and answer as on 1",
           iterative_everywhere(bar_two) && same_answer(launch("mixed-bar", bar, 1), bar_two, 1e-6, false, gap));
  }

}
