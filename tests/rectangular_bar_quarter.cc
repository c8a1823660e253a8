// The rectangular bar quarter (Mesh/Source = rectangular bar quarter), two
// independent checks of the mesh and of 3D contact on a die with two walls
// that meet along an edge:
//
// 1. Plane strain: without a reduction in z (Inlet half width = Outlet half
//    width) the mesh is the die2d section of the same Cells across extruded
//    in z, so with the z walls (ids 6, 7) as frictionless symmetry planes
//    the discrete solution is the 2D one (the argument of
//    tests/die2d_extruded): forces per unit width, flux and contact zones
//    equal the plane-strain run's to the solver tolerance (1e-6).
// 2. Mirror symmetry: the bar converging from 19 to 4.75 in y (70 degrees)
//    and from 10 to 6 in z, and the bar with y and z exchanged (the same
//    die length), are mirror images through the plane y = z, and so are
//    their meshes (the layout is symmetric in the two directions; the
//    vertex numbering is not). With every wall a frictionless die, the ram
//    force, the outlet flux and the contact zones agree, and the y wall of
//    the one carries the z wall's normal force of the other, to the solver
//    tolerance. Nodes on the edge where the two die walls meet hold both
//    normals and slide along it; the node where that edge meets the die
//    entry is held by four walls (two container walls, two die faces), one
//    more than the dimension, and its reaction is split by least norm
//    (normal_components(); the Gram matrix of four normals in 3D is
//    singular, and the split was NaN before).
// 3. Mirror symmetry with Coulomb friction (degree 1), mu = 0.1 on every
//    wall, and mu = 0.1 on the die faces with 0.001 or 0 on the containers:
//    the edge nodes carry both walls' friction (each wall's share of a node
//    at rest in proportion to its bound), and both runs settle without
//    breaking a cycle of the states, in the same contact zones, with the
//    same ram force to the solver tolerance. Before the edge fix they
//    differed by 0.08 % (mu = 0.1 everywhere); with the containers' 0.001
//    and 0 they differed by 6e-5 and 4e-4 until slip was solved by the
//    semismooth Newton method on the carried friction force (the mirror
//    run of 0 broke a cycle of the states, that of 0.001 did not converge
//    in 50 iterations; doc/three-dimensional.md).
#include <dieflow/problem/run.h>

#include "report.h"

#include <cmath>
#include <sstream>
#include <string>

using namespace dieflow;

namespace
{
  double
  gap(const double a, const double b)
  {
    return std::abs(a - b) / std::max(std::abs(b), 1e-300);
  }

  std::string
  die2d_block(const double h_i, const double h_o, const double angle, const double w_i, const double w_o)
  {
    std::ostringstream s;
    s.precision(17);
    s << "subsection Mesh\n subsection Die2d\n  set Inlet half height = " << h_i
      << "\n  set Outlet half height = " << h_o << "\n  set Die angle = " << angle
      << "\n  set Inlet half width = " << w_i << "\n  set Outlet half width = " << w_o
      << "\n  set Cells across = 4\n  set Cells in depth = 4\n end\nend\n";
    return s.str();
  }

  const std::string material = "subsection Material\n set Law = Newtonian\n set Viscosity = 0.278\nend\n";
  const std::string inflow_3d =
    " set Prescribed velocity ids = 1\n set Traction free ids = 2\n subsection Prescribed velocity 1\n"
    "  set Velocity = 190; 0; 0\n end\nend\n";

  CycleSummary
  plane_strain(const unsigned int degree)
  {
    return run_deck_text(material + "subsection Mesh\n subsection Die2d\n  set Cells across = 4\n end\nend\n"
                         "subsection Contact\n set Die ids = 3, 4\n set Friction coefficients = 3: 0.1, 4: 0.1\n"
                         "end\nsubsection Discretisation\n set Velocity degree = " +
                         std::to_string(degree) +
                         "\nend\nsubsection Boundary conditions\n set Symmetry ids = 5\n"
                         " set Prescribed velocity ids = 1\n set Traction free ids = 2\n"
                         " subsection Prescribed velocity 1\n  set Velocity = 190; 0\n end\nend\n")
      .cycles.back();
  }

  CycleSummary
  bar(const std::string &die2d, const std::string &die_ids, const std::string &symmetry_ids,
      const std::string &friction, const unsigned int degree)
  {
    return run_deck_text("set Dimension = 3\n" + material + die2d +
                         "subsection Mesh\n set Source = rectangular bar quarter\nend\n"
                         "subsection Contact\n set Die ids = " + die_ids + "\n set Friction coefficients = " +
                         friction + "\nend\nsubsection Discretisation\n set Velocity degree = " +
                         std::to_string(degree) + "\nend\nsubsection Boundary conditions\n set Symmetry ids = " +
                         symmetry_ids + "\n" + inflow_3d)
      .cycles.back();
  }
} // namespace

int
main()
{
  for (const unsigned int degree : {1u, 2u})
    {
      const std::string name = "plane strain, degree " + std::to_string(degree) + ": ";
      const CycleSummary plane = plane_strain(degree);
      const CycleSummary slab =
        bar(die2d_block(19, 4.75, 70, 1, 1), "3, 4", "5, 6, 7", "3: 0.1, 4: 0.1", degree);
      report(name + "both converge", plane.converged && slab.converged);
      // The ram and the container wall share the corner node at B, whose
      // reaction the extrapolation splits differently along a line (2D) and
      // over a surface (3D) for degree 2 (tests/die2d_extruded); their sum
      // and everything on the die agree.
      report(name + "ram and container wall together: x force per unit width equal (1e-6)",
             gap(slab.boundary_force.at(1)[0] + slab.boundary_force.at(3)[0],
                 plane.boundary_force.at(1)[0] + plane.boundary_force.at(3)[0]) < 1e-6);
      report(name + "die normal and friction forces per unit width equal (1e-6)",
             gap(slab.die_normal_force.at(4), plane.die_normal_force.at(4)) < 1e-6 &&
               gap(slab.die_friction_force.at(4), plane.die_friction_force.at(4)) < 1e-6);
      report(name + "outlet flux per unit width equal (1e-6)", gap(slab.flux.at(2), plane.flux.at(2)) < 1e-6);
      const unsigned int per_line = 4 * degree + 1;
      report(name + "contact zones: every 2D node is a line of " + std::to_string(per_line) +
               " nodes in the same state",
             slab.contact_nodes.stick == per_line * plane.contact_nodes.stick &&
               slab.contact_nodes.slip == per_line * plane.contact_nodes.slip &&
               slab.contact_nodes.separated == per_line * plane.contact_nodes.separated);
    }

  // The same die length x_d = (19 - 4.75)/tan(70 deg) in both bars: the
  // exchanged bar's y angle is atan((10 - 6)/x_d).
  const double pi         = std::acos(-1.);
  const double x_d        = (19 - 4.75) / std::tan(70 * pi / 180);
  const double angle_6_10 = std::atan2(10 - 6, x_d) * 180 / pi;
  const std::string friction = "3: 0, 4: 0, 6: 0, 7: 0";
  for (const unsigned int degree : {1u, 2u})
    {
      const std::string  name = "mirror y <-> z, degree " + std::to_string(degree) + ": ";
      const CycleSummary a    = bar(die2d_block(19, 4.75, 70, 10, 6), "3, 4, 6, 7", "5", friction, degree);
      const CycleSummary b    = bar(die2d_block(10, 6, angle_6_10, 19, 4.75), "3, 4, 6, 7", "5", friction, degree);
      report(name + "both converge", a.converged && b.converged);
      report(name + "ram force equal (1e-6)", gap(a.boundary_force.at(1)[0], b.boundary_force.at(1)[0]) < 1e-6);
      report(name + "outlet flux equal (1e-6)", gap(a.flux.at(2), b.flux.at(2)) < 1e-6);
      report(name + "y walls of the one carry the z walls' normal forces of the other (1e-6)",
             gap(a.die_normal_force.at(4), b.die_normal_force.at(7)) < 1e-6 &&
               gap(a.die_normal_force.at(7), b.die_normal_force.at(4)) < 1e-6 &&
               gap(a.die_normal_force.at(3), b.die_normal_force.at(6)) < 1e-6 &&
               gap(a.die_normal_force.at(6), b.die_normal_force.at(3)) < 1e-6);
      report(name + "the same contact zones",
             a.contact_nodes.stick == b.contact_nodes.stick && a.contact_nodes.slip == b.contact_nodes.slip &&
               a.contact_nodes.separated == b.contact_nodes.separated);
      const auto touching = [](const CycleSummary &c, const BoundaryId id) {
        return c.contact_length.at(id)[1] + c.contact_length.at(id)[2];
      };
      report(name + "both die walls in contact, the y wall's area the other's z wall's (1e-6)",
             touching(a, 4) > 0 && touching(a, 7) > 0 && gap(touching(a, 4), touching(b, 7)) < 1e-6 &&
               gap(touching(a, 7), touching(b, 4)) < 1e-6);
    }

  for (const auto &[walls, coulomb] :
       std::vector<std::pair<std::string, std::string>>{{"mu = 0.1 on every wall", "3: 0.1, 4: 0.1, 6: 0.1, 7: 0.1"},
                                                        {"die faces 0.1, containers 0.001", "3: 0.001, 4: 0.1, 6: 0.001, 7: 0.1"},
                                                        {"die faces 0.1, containers frictionless", "3: 0, 4: 0.1, 6: 0, 7: 0.1"}})
  {
    const std::string  name = "mirror y <-> z, Coulomb " + walls + ", degree 1: ";
    const CycleSummary a = bar(die2d_block(19, 4.75, 70, 10, 6), "3, 4, 6, 7", "5", coulomb, 1);
    const CycleSummary b = bar(die2d_block(10, 6, angle_6_10, 19, 4.75), "3, 4, 6, 7", "5", coulomb, 1);
    report(name + "both converge, no cycle of the states broken",
           a.converged && b.converged && a.held_in_contact + a.regularised_friction + b.held_in_contact +
                                             b.regularised_friction == 0);
    report(name + "ram force equal (1e-6)", gap(a.boundary_force.at(1)[0], b.boundary_force.at(1)[0]) < 1e-6);
    report(name + "the same contact zones (stick, slip, separated)",
           a.contact_nodes.stick == b.contact_nodes.stick && a.contact_nodes.slip == b.contact_nodes.slip &&
             a.contact_nodes.separated == b.contact_nodes.separated);
    report(name + "y walls of the one carry the z walls' friction of the other (1e-6)",
           gap(a.die_friction_force.at(4), b.die_friction_force.at(7)) < 1e-6 &&
             gap(a.die_friction_force.at(7), b.die_friction_force.at(4)) < 1e-6);
  }
}
