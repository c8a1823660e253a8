// Symmetry: die2d extruded in z (one layer of cells between the planes
// z = 0 and z = 1, both Symmetry ids, i.e. frictionless side planes) is the
// plane-strain problem. Its discrete solution is the 2D one: the 2D field
// extended constantly in z with v_z = 0 satisfies every 3D equation (a test
// function phi(x, y) psi(z) gives the 2D equation times int psi dz; the
// z equations vanish or are constrained), the Q1 cell mean of div v of an
// extruded cell is the 2D one, and every contact node of the 2D wall is a
// line of nodes in 3D with the same state and force per unit depth. So the
// forces per unit depth, the fluxes, and the contact zones agree to the
// solver's tolerance (1e-6 relative here), for Coulomb friction (slip and
// stick along the die, whose wall nodes in 3D also lie on a symmetry
// plane), with velocity degree 1 and 2; but for how a corner node's
// reaction is split between the ram and the container wall (see below).
#include <dieflow/problem/run.h>

#include "report.h"

#include <cmath>
#include <string>

using namespace dieflow;

namespace
{
  const std::string common = "subsection Mesh\n subsection Die2d\n  set Cells across = 4\n end\nend\n"
                             "subsection Material\n set Law = Newtonian\n set Viscosity = 0.278\nend\n"
                             "subsection Contact\n set Die ids = 3, 4\n set Friction coefficients = 3: 0.1, 4: 0.1\nend\n";

  CycleSummary
  run(const unsigned int dim, const unsigned int degree)
  {
    const std::string discretisation =
      "subsection Discretisation\n set Velocity degree = " + std::to_string(degree) + "\nend\n";
    if (dim == 2)
      return run_deck_text(common + discretisation +
                           "subsection Boundary conditions\n set Symmetry ids = 5\n set Prescribed velocity ids = 1\n"
                           " set Traction free ids = 2\n subsection Prescribed velocity 1\n  set Velocity = 190; 0\n"
                           " end\nend\n")
        .cycles.back();
    return run_deck_text("set Dimension = 3\n" + common + discretisation +
                         "subsection Boundary conditions\n set Symmetry ids = 5, 6, 7\n set Prescribed velocity ids = 1\n"
                         " set Traction free ids = 2\n subsection Prescribed velocity 1\n  set Velocity = 190; 0; 0\n"
                         " end\nend\n")
      .cycles.back();
  }

  double
  gap(const double a, const double b)
  {
    return std::abs(a - b) / std::max(std::abs(b), 1e-300);
  }
} // namespace

int
main()
{
  for (const unsigned int degree : {1u, 2u})
    {
      const CycleSummary plane = run(2, degree), slab = run(3, degree);
      const std::string  name  = "degree " + std::to_string(degree) + ": ";
      report(name + "both converge", plane.converged && slab.converged);
      // The inlet and the container wall meet at a corner node whose
      // reaction is split between them by extrapolating the wall's traction
      // (postprocess.cc): along the wall line in 2D, over the wall surface
      // in 3D. For degree 1 the two extrapolations coincide; for degree 2 a
      // quadratic along the line differs from a least-squares plane by a
      // share of that one node's force (4e-4 of the ram force here). Their
      // sum is the same in both, as is everything on the die (id 4).
      // (In y also the axis's share at the inlet corner A varies so; the
      // axis, frictionless, takes no x.)
      const double plane_sum = plane.boundary_force.at(1)[0] + plane.boundary_force.at(3)[0];
      const double slab_sum  = slab.boundary_force.at(1)[0] + slab.boundary_force.at(3)[0];
      report(name + "ram and container wall together: x force per unit depth equal (1e-6)",
             gap(slab_sum, plane_sum) < 1e-6);
      report(name + "ram force per unit depth equal (" + (degree == 1 ? "1e-6" : "1e-3") + ")",
             gap(slab.boundary_force.at(1)[0], plane.boundary_force.at(1)[0]) < (degree == 1 ? 1e-6 : 1e-3));
      report(name + "die normal and friction forces per unit depth equal (1e-6)",
             gap(slab.die_normal_force.at(4), plane.die_normal_force.at(4)) < 1e-6 &&
               gap(slab.die_friction_force.at(4), plane.die_friction_force.at(4)) < 1e-6);
      report(name + "outlet flux per unit depth equal (1e-6)", gap(slab.flux.at(2), plane.flux.at(2)) < 1e-6);
      report(name + "no force across the side planes but their pressure: F_x, F_y vanish there",
             std::abs(slab.boundary_force.at(6)[0]) + std::abs(slab.boundary_force.at(6)[1]) <
               1e-8 * std::abs(slab.boundary_force.at(1)[0]));
      // Each 2D contact node is a line of nodes: (layers + 1) per node for degree 1, (2 layers + 1) for 2.
      const unsigned int per_line = degree + 1;
      report(name + "contact zones: every 2D node is a line of " + std::to_string(per_line) + " nodes in the same state",
             slab.contact_nodes.stick == per_line * plane.contact_nodes.stick &&
               slab.contact_nodes.slip == per_line * plane.contact_nodes.slip &&
               slab.contact_nodes.separated == per_line * plane.contact_nodes.separated);
    }
}
