// Decks of the exact flows the unit tests share (as text for run_deck_text).
#ifndef dieflow_tests_exact_flows_h
#define dieflow_tests_exact_flows_h

#include <string>

/**
 * The Couette layer slipping on a Coulomb wall (couette_slip.prm): a layer
 * of thickness 1 dragged at U = 1 over the die (id 3, mu = 0.5), pressed on
 * it with p_n = 1 by its weight; u = 0.5 + 0.5 y, wall shear 0.5.
 */
inline const std::string couette_slip_deck =
  "subsection Mesh\n set Source = box\n subsection Box\n  set Lower corner = 0, 0\n  set Upper corner = 4, 1\n"
  "  set Subdivisions = 8, 4\n end\nend\n"
  "subsection Material\n set Law = Newtonian\n set Viscosity = 1\nend\n"
  "subsection Boundary conditions\n set Prescribed velocity ids = 1, 2, 4\n set Symmetry ids =\n"
  " set Slip wall ids =\n set Traction free ids =\n set Body force = 0; -1\n"
  " subsection Prescribed velocity 1\n  set Velocity = 0.5 + 0.5*y; 0\n end\n"
  " subsection Prescribed velocity 2\n  set Velocity = 0.5 + 0.5*y; 0\n end\n"
  " subsection Prescribed velocity 4\n  set Velocity = 1; 0\n  set Components = x\n end\nend\n"
  "subsection Contact\n set Die ids = 3\n set Friction coefficients = 3: 0.5\nend\n";

/**
 * Plane Stokes sink flow towards the apex (2, 0) of a wedge on the
 * trapezoid of sink_flow.prm, the inclined die (id 3) frictionless, the
 * outlet with the exact traction: the inlet force F_x[1] = -0.4.
 */
inline std::string
sink_flow_deck(const unsigned int refinements)
{
  return "subsection Mesh\n set Source = gmsh\n set Gmsh file = " + std::string(SOURCE_DIR) +
         "/meshes/sink_trapezoid.msh\n set Global refinements = " + std::to_string(refinements) +
         "\nend\n"
         "subsection Material\n set Law = Newtonian\n set Viscosity = 1\n set Penalty factor = 1e8\nend\n"
         "subsection Boundary conditions\n set Prescribed velocity ids = 1\n set Symmetry ids = 5\n"
         " set Slip wall ids =\n set Traction free ids =\n set Traction ids = 2\n"
         " set Traction = -2*(1/((x-2)^2+y^2) - 2*(x-2)^2/((x-2)^2+y^2)^2); 4*(x-2)*y/((x-2)^2+y^2)^2\n"
         " subsection Prescribed velocity 1\n  set Velocity = -(x-2)/((x-2)^2+y^2); -y/((x-2)^2+y^2)\n end\nend\n"
         "subsection Contact\n set Die ids = 3\n set Friction coefficients = 3: 0\nend\n";
}

#endif
