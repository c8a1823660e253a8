// Frictionless contact where the metal presses everywhere is the slip wall
// of the core program: die2d with a free outlet, the die face and land (4) as
// slip walls, and the container wall (3) either a slip wall or a die in
// frictionless unilateral contact. The metal presses on the whole container
// wall, so every contact node stays active, the constraints are the same
// (the corner C at rest in both), and the two discrete solutions must agree
// to round-off (1e-8 relative: the penalty's round-off floor is
// 3e-17 x 1e7 x sqrt(738 dofs) = 8e-9).
#include <dieflow/problem/run.h>

#include "report.h"

#include <cmath>
#include <fstream>
#include <sstream>

using namespace dieflow;

namespace
{
  CycleSummary
  run(const std::string &walls)
  {
    return run_deck_text("subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = 8\n end\nend\n" + walls)
      .cycles.back();
  }
} // namespace

int
main()
{
  const CycleSummary slip = run("subsection Boundary conditions\n set Slip wall ids = 3, 4\nend\n"
                                "subsection Contact\n set Die ids =\nend\n");
  const CycleSummary contact = run("subsection Boundary conditions\n set Slip wall ids = 4\nend\n"
                                   "subsection Contact\n set Die ids = 3\n set Friction coefficients = 3: 0\nend\n");
  report("both converge", slip.converged && contact.converged);
  report("every container node stays in contact", contact.contact_nodes.separated == 0 && contact.contact_nodes.slip > 0);
  double gap = 0;
  for (const auto &[id, force] : slip.boundary_force)
    for (unsigned int d = 0; d < 2; ++d)
      gap = std::max(gap, std::abs(force[d] - contact.boundary_force.at(id)[d]));
  report("every boundary force agrees (1e-8 of the ram force)", gap < 1e-8 * slip.boundary_force.at(1)[0]);
  report("the container's normal force is its reaction",
         std::abs(contact.die_normal_force.at(3) + slip.boundary_force.at(3)[1]) < 1e-8 * slip.boundary_force.at(1)[0]);
  report("no friction", contact.die_friction_force.at(3) == 0);
}
