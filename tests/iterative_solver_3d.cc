// The iterative solvers in 3D give the direct solver's answer: the round-bar quarter (Coulomb friction on the die) at degree 2 (mixed form, p-multigrid) to the Newton tolerance, at degree 1 (augmented Lagrangian) to the penalty's compressibility.
//
// parameters/roundbar-held-land.prm as the quarter model of doc/three-dimensional.md
// (graded, q = 2.5), 4 cells across, one cycle: 6,405 unknowns at degree 2.
// At degree 2 both methods solve the same nonlinear problem (the penalty
// form on the projected divergence) to the same Newton tolerance, so they
// must reach the same contact states (stick, slip and separated nodes) and
// the same ram force, die forces and outlet flux to the Newton tolerance
// (1e-6 relative; the iterative solves are inexact, so not to round-off),
// the iterative run without falling back to the direct solver.
#include "report.h"
#include "round_bar.h"

#include <cmath>
#include <iostream>
#include <string>

using namespace dieflow;

namespace
{
  RunSummary
  quarter(const unsigned int degree, const std::string &method)
  {
    return run_deck_text("set Dimension = 3\n" + round_bar_mesh("round bar quarter") +
                         "subsection Material\n  set Law = Newtonian\n  set Viscosity = 0.278\nend\n"
                         "subsection Boundary conditions\n"
                         "  set Symmetry ids = 5\n  set Slip wall ids =\n  set Prescribed velocity ids = 1\n"
                         "  set Traction free ids = 2\n"
                         "  subsection Prescribed velocity 1\n    set Velocity = 190; 0; 0\n  end\n"
                         "end\n"
                         "subsection Contact\n"
                         "  set Die ids = 3, 4\n  set Normal enforcement = active set\n  set Friction law = Coulomb\n"
                         "  set Friction coefficients = 3: 0.001, 4: 0.1\n"
                         "end\n"
                         "subsection Discretisation\n  set Velocity degree = " +
                         std::to_string(degree) +
                         "\nend\n"
                         "subsection Linear solver\n  set Method = " +
                         method +
                         "\nend\n"
                         "subsection Refinement\n  set Cycles = 1\n  set Probe point =\nend\n");
  }

  double
  force(const CycleSummary &c, const BoundaryId id, const unsigned int component)
  {
    return c.boundary_force.at(id)[component];
  }
} // namespace

int
main()
{
  {
    const RunSummary direct    = quarter(2, "direct");
    const RunSummary iterative = quarter(2, "iterative");
    const bool       both      = direct.converged && iterative.converged;
    report("degree 2: both converge, the iterative run with the iterative method and no direct fallback",
           both && iterative.cycles[0].linear_method == "iterative" &&
             iterative.cycles[0].linear_counts.direct_fallbacks == 0 && direct.cycles[0].linear_method == "direct");
    if (both)
      {
        const CycleSummary &d = direct.cycles[0], &i = iterative.cycles[0];
        report("degree 2: the same contact states (stick, slip, separated nodes; some slip)",
               d.contact_nodes.stick == i.contact_nodes.stick && d.contact_nodes.slip == i.contact_nodes.slip &&
                 d.contact_nodes.separated == i.contact_nodes.separated && d.contact_nodes.slip > 0);
        const double ram = std::abs(force(d, 1, 0));
        report("degree 2: the same ram force (1e-6)", relative_gap(force(i, 1, 0), force(d, 1, 0)) < 1e-6);
        bool dies = true;
        for (const BoundaryId id : {BoundaryId(3), BoundaryId(4)})
          for (unsigned int k = 0; k < 3; ++k)
            dies = dies && std::abs(force(i, id, k) - force(d, id, k)) < 1e-6 * ram;
        report("degree 2: the same die forces, every component (1e-6 of the ram force)", dies);
        report("degree 2: the same outlet flux (1e-6)", relative_gap(i.flux.at(2), d.flux.at(2)) < 1e-6);
      }
  }
  {
    // Degree 1: the augmented-Lagrangian form is more nearly incompressible
    // than the direct solver's penalty form (divergence ratio 6.8e-9
    // against 2.5e-6 measured), so the two answers differ by the penalty's
    // compressibility: 5.3e-5 in the ram force and the outlet flux
    // (measured); in 2D the forces agree within 1e-4 (doc/user-guide.md).
    // Its Krylov solves do not converge here and fall back to the direct
    // solver (12 measured; doc/three-dimensional.md, "Left"): this checks
    // the answer, not the speed.
    const RunSummary direct    = quarter(1, "direct");
    const RunSummary iterative = quarter(1, "iterative");
    const bool       both      = direct.converged && iterative.converged;
    report("degree 1: both converge, the iterative run with the augmented-Lagrangian form",
           both && iterative.cycles[0].linear_method == "iterative" && direct.cycles[0].linear_method == "direct");
    if (both)
      {
        const CycleSummary &d = direct.cycles[0], &i = iterative.cycles[0];
        report("degree 1: the same contact states", d.contact_nodes.stick == i.contact_nodes.stick &&
                                                      d.contact_nodes.slip == i.contact_nodes.slip &&
                                                      d.contact_nodes.separated == i.contact_nodes.separated);
        report("degree 1: the ram force and outlet flux within 1e-4, a smaller divergence ratio",
               relative_gap(force(i, 1, 0), force(d, 1, 0)) < 1e-4 && relative_gap(i.flux.at(2), d.flux.at(2)) < 1e-4 &&
                 i.divergence_ratio < d.divergence_ratio);
      }
  }
}
