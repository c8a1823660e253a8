// Linear solver/Maximum iterations: a Krylov solve that reaches the limit is
// given up and solved again by the direct solver (where that fits, as
// here), so the run still converges to the same answer:
//  - degree 2 (the mixed form's GMRES), die2d N1, 8 cells across: with a
//    limit of 3 (every solve takes more: 12-16 measured) at least one
//    solve falls back, no partial step is taken (the fallback fits), and
//    the ram force, die forces and probe velocity are those of the run
//    with the default limit (no fallback) within 1e-7, the bound of
//    tests/mixed_form_solver for the direct and the iterative solver on
//    this scene (both stop at Newton's relative residual of about 1e-8);
//  - degree 1 (the augmented Lagrangian's CG / GMRES): with a limit of 2,
//    solves fall back, and the answer is the default run's within 1e-7 (the
//    fallback factorises the same augmented system);
//  - a negative limit is refused with a message naming the entry (the
//    program prints it and exits with 1).
#include <dieflow/problem/run.h>

#include "report.h"

#include <deal.II/base/mpi.h>

using namespace dieflow;

namespace
{
  RunSummary
  run(const unsigned int degree, const std::string &limit)
  {
    return run_deck_text("subsection Mesh\n subsection Die2d\n  set Cells across = 8\n end\nend\n"
                         "subsection Discretisation\n set Velocity degree = " +
                         std::to_string(degree) +
                         "\nend\nsubsection Linear solver\n set Method = iterative\n set Maximum iterations = " + limit +
                         "\nend\n");
  }
} // namespace



int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  for (const auto &[degree, limit] : std::vector<std::pair<unsigned int, std::string>>{{2, "3"}, {1, "2"}})
    {
      const std::string   name     = "degree " + std::to_string(degree) + ": ";
      const CycleSummary  standard = run(degree, "0").cycles.back();
      const CycleSummary  limited  = run(degree, limit).cycles.back();
      const LinearSolverCounts &counts   = limited.linear_counts;
      report(name + "the default limit converges without a fallback",
             standard.converged && standard.linear_counts.direct_fallbacks == 0);
      report(name + "with a limit of " + limit + ": converged, solves fell back to the direct solver, no partial step",
             limited.converged && counts.direct_fallbacks > 0 && counts.partial_steps == 0);
      report(name + "the same ram force, die forces and probe velocity (1e-7)", quantities_agree(standard, limited, 1e-7));
    }
  try
    {
      run(2, "-1");
      report("Maximum iterations = -1 is refused", false);
    }
  catch (const std::exception &e) // the deck's pattern (ParameterHandler) refuses it
    {
      report("Maximum iterations = -1 is refused, naming the entry",
             std::string(e.what()).find("Maximum iterations") != std::string::npos);
    }
}
