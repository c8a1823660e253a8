// 3D friction on a curved die against an independent computation: the round bar's quarter model against the axisymmetric run.
//
// The round bar (38 to 9.5 mm through a 70-degree cone, a land, Newtonian,
// Coulomb mu = 0.1 on the container and 0.3 on the die face and land)
// computed twice: as a 3D quarter (Source = round bar quarter: its die a
// polygonal cone whose nodes stick or slip in 2D tangent planes, with
// slip directions of their own) and axisymmetric (die2d's section: the
// friction of the 2D code path, weighted 2 pi r). Both discretise the
// same problem on meshes of the same cells across; they are no copy of
// each other's numbers, and differ by the discretisations: at 4 cells
// across the quarter's section has 2.5 % less area than the circle.
//
// Checked on the die face and land (id 4): the friction force summed over
// the die's nodes, int |t_t| dA, four quarters against the axisymmetric
// one, within 3 % (measured -1.3 % at 4 across, -0.3 % at 8, so a
// discretisation difference that falls with the mesh). Both runs have
// sticking and slipping nodes (the container sticks, the die face and land
// do both). Broken: mu x 0.9 in 3D only fails the check. (The
// friction per normal force, int |t_t| dA / int |t_n| dA, agrees within
// 0.6 % at 4 across, but with mu x 0.9 in 3D it still did within 1.5 %:
// not checked.) (The container's sticking
// friction is a reaction dominated by the ram/container corner and agrees
// neither way nor with the mesh: 47.9 against 18.9 kN at 4 across, 31.3
// against 41.7 kN at 8; it is not checked. doc/three-dimensional.md.)
#include <dieflow/problem/run.h>

#include "report.h"
#include "round_bar.h"

#include <cmath>
#include <iomanip>
#include <iostream>
#include <string>

using namespace dieflow;

namespace
{
  RunSummary
  round_bar(const bool quarter)
  {
    return run_deck_text(
      std::string(quarter ? "set Dimension = 3\n" : "set Dimension = 2\nset Geometry = axisymmetric\n") +
      round_bar_mesh(quarter ? "round bar quarter" : "die2d") +
      "subsection Material\n  set Law = Newtonian\n  set Viscosity = 0.278\nend\n"
      "subsection Boundary conditions\n"
      "  set Symmetry ids = 5\n  set Slip wall ids =\n  set Prescribed velocity ids = 1\n"
      "  set Traction free ids = 2\n" +
      (quarter ? "  set Traction = 0; 0; 0\n" : "") + "  subsection Prescribed velocity 1\n    set Velocity = " +
      (quarter ? "190; 0; 0" : "190; 0") +
      "\n  end\n"
      "end\n"
      "subsection Contact\n"
      "  set Die ids = 3, 4\n  set Friction law = Coulomb\n"
      "  set Friction coefficients = 3: 0.1, 4: 0.3\n"
      "end\n"
      "subsection Discretisation\n  set Velocity degree = 2\nend\n"
      "subsection Linear solver\n  set Method = direct\nend\n"
      "subsection Refinement\n  set Cycles = 1\n  set Probe point =\nend\n");
  }
} // namespace

int
main()
{
  const RunSummary quarter = round_bar(true), axisymmetric = round_bar(false);
  report("both converge", quarter.converged && axisymmetric.converged);
  if (!(quarter.converged && axisymmetric.converged))
    return 0;
  const CycleSummary &q = quarter.cycles[0], &a = axisymmetric.cycles[0];
  report("both have sticking and slipping contact nodes",
         q.contact_nodes.stick > 0 && q.contact_nodes.slip > 0 && a.contact_nodes.stick > 0 && a.contact_nodes.slip > 0);
  const double friction_q = 4 * q.die_friction_force.at(4), friction_a = a.die_friction_force.at(4);
  report("the die's friction force, four quarters against the axisymmetric run, within 3 %",
         std::abs(friction_q / friction_a - 1) < 0.03);
  std::cout << "the die's friction force (axisymmetric): " << std::setprecision(3) << friction_a << " N" << std::endl;
}
