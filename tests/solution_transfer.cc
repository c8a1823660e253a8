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
//  - Its first Newton step is far shorter than the cold start's (a tenth
//    of ||dv|| / ||v||), and revises a tenth as many contact states. (Not
//    the residual of the interpolated field: interpolating onto finer cells
//    leaves div v != 0 at the new cell centres, which the penalty,
//    lambda = 1e7 eta, turns into large nodal forces that the first step
//    removes; nor the residual after that step, which is measured in the
//    states the step revised.)
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
  const bool stepped = w.history.size() > 1 && c.history.size() > 1;
  report("first step a tenth of the cold start's", stepped && w.history[1].update < 0.1 * c.history[1].update);
  report("a tenth as many state changes after it",
         stepped && 10 * w.history[1].state_changes.total() <= c.history[1].state_changes.total());
}
