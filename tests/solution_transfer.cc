// Solution transfer between refinement cycles: die2d N1 (contact with
// friction), cycle 1 of a run that starts on 8 cells across and refines
// globally, against a cold start on the same mesh (8 cells across refined
// once). The warm start is the previous cycle's solution interpolated to the
// new mesh, with the previous contact states; the cold start is the
// prescribed velocity with zero inside and every wall node in contact.
//  - Both must reach the same discrete solution (ram force to 1e-8).
//  - The warm start is far closer to it: ||v_start - v|| / ||v|| below a
//    tenth of the cold start's.
//  - It needs fewer Newton iterations.
//  - Its residual after the first Newton step is far below the cold
//    start's (a fifth). (The residual of the interpolated field itself is
//    not: interpolating a Q1 field onto finer cells leaves div v != 0 at the
//    new cell centres, which the penalty, lambda = 1e7 eta, turns into large
//    nodal forces that the first step removes.)
#include "report.h"

#include <cmath>

using namespace dieflow;

int
main()
{
  const RunSummary warm = run_deck_text("subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = 8\n end\nend\n"
                                        "subsection Refinement\n set Cycles = 2\nend\n");
  const RunSummary cold = run_deck_text("subsection Mesh\n set Global refinements = 1\n"
                                        " subsection Die2d\n  set Layout = blocks\n  set Cells across = 8\n end\nend\n");
  const CycleSummary &w = warm.cycles.back(), &c = cold.cycles.back();
  report("both converge on the same mesh", warm.converged && cold.converged && w.dofs == c.dofs);
  report("same solution (ram force to 1e-8)",
         std::abs(w.boundary_force.at(1)[0] - c.boundary_force.at(1)[0]) < 1e-8 * c.boundary_force.at(1)[0]);
  report("warm start ten times closer to the solution", w.start_distance < 0.1 * c.start_distance);
  report("fewer Newton iterations", w.nonlinear_iterations < c.nonlinear_iterations);
  report("residual after the first step a fifth of the cold start's",
         w.history.size() > 1 && c.history.size() > 1 && w.history[1].residual < 0.2 * c.history[1].residual);
}
