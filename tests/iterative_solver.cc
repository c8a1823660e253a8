// The iterative method (Linear solver/Method = iterative: the augmented
// Lagrangian with AMG-preconditioned CG/GMRES) against the direct one (the
// penalty method with a sparse factorisation):
//  - die2d N1 (Newtonian; contact with slipping Coulomb friction, so GMRES
//    on non-symmetric systems), two adaptive cycles (the multiplier, as the
//    cell stress, is carried to the refined mesh): same contact states; ram
//    force and die forces equal up to the penalty method's compressibility
//    (its divergence ratio is 1e-6; the forces differ by about 1e-5, 1e-4
//    is allowed); the augmented Lagrangian drives the divergence ratio below
//    its tolerance (1e-7), ten times below the penalty's;
//  - die2d P1 (Norton-Hoff m = 0.2, viscosity varying by 1e4): converges
//    with the contact inequalities, ram force within 1e-4 (measured 4e-5;
//    a few nodes at the land's separation point, whose reactions are at the
//    dead band, may change state, so states are not compared);
//  - Method = auto picks direct below 'Iterative from dofs', iterative
//    from it on.
#include <dieflow/problem/run.h>

#include "report.h"

#include <deal.II/base/mpi.h>

#include <cmath>

using namespace dieflow;

namespace
{
  const std::string coarse = "subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = 8\n end\nend\n";
  const std::string p1     = "subsection Material\n set Law = Norton-Hoff\n set Consistency K = 0.834\n"
                         " set Rate sensitivity m = 0.2\n set Minimum strain rate = 1e-4\nend\n";

  RunSummary
  run(const std::string &deck, const std::string &method, const unsigned int cycles = 1)
  {
    return run_deck_text(coarse + deck + "subsection Refinement\n set Cycles = " + std::to_string(cycles) +
                         "\n set Strategy = adaptive\nend\nsubsection Linear solver\n" + method + "end\n");
  }

  double
  gap(const double a, const double b)
  {
    return std::abs(a / b - 1);
  }

  bool
  contact_laws_hold(const CycleSummary &c)
  {
    return c.contact_penetration < 1e-12 && c.contact_tension == 0 && c.friction_excess < 1e-12 &&
           c.friction_power < 1e-12;
  }
} // namespace



int
main(int argc, char **argv)
{
  // Trilinos (the AMG preconditioner) needs MPI, even on one process.
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const RunSummary direct    = run("", " set Method = direct\n", 2);
  const RunSummary iterative = run("", " set Method = iterative\n", 2);
  report("N1: both converge", direct.converged && iterative.converged);
  for (unsigned int c = 0; c < 2; ++c)
    {
      const CycleSummary &d = direct.cycles[c], &i = iterative.cycles[c];
      const std::string   cycle = "N1 cycle " + std::to_string(c) + ": ";
      report(cycle + "the iterative run used the iterative method",
             i.linear_method == "iterative" && d.linear_method == "direct");
      report(cycle + "same contact states",
             d.contact_nodes.separated == i.contact_nodes.separated && d.contact_nodes.stick == i.contact_nodes.stick &&
               d.contact_nodes.slip == i.contact_nodes.slip);
      report(cycle + "ram force within 1e-4", gap(i.boundary_force.at(1)[0], d.boundary_force.at(1)[0]) < 1e-4);
      report(cycle + "die forces within 1e-4",
             gap(i.die_normal_force.at(4), d.die_normal_force.at(4)) < 1e-4 &&
               gap(i.die_friction_force.at(4), d.die_friction_force.at(4)) < 1e-4);
      report(cycle + "divergence ratio below 1e-7 and below the penalty's",
             i.divergence_ratio < 1e-7 && i.divergence_ratio < 0.1 * d.divergence_ratio);
      report(cycle + "contact inequalities hold", contact_laws_hold(i));
    }

  const RunSummary p1_direct    = run(p1, " set Method = direct\n");
  const RunSummary p1_iterative = run(p1, " set Method = iterative\n");
  const auto &     d = p1_direct.cycles.back(), &i = p1_iterative.cycles.back();
  report("P1: both converge", p1_direct.converged && p1_iterative.converged);
  report("P1: ram force within 1e-4", gap(i.boundary_force.at(1)[0], d.boundary_force.at(1)[0]) < 1e-4);
  report("P1: divergence ratio below 1e-7", i.divergence_ratio < 1e-7);
  report("P1: contact inequalities hold", contact_laws_hold(i));

  const RunSummary below = run("", " set Method = auto\n set Iterative from dofs = 1000000\n");
  const RunSummary above = run("", " set Method = auto\n set Iterative from dofs = 100\n");
  report("auto: direct below the threshold, iterative from it on",
         below.cycles[0].linear_method == "direct" && above.cycles[0].linear_method == "iterative");
}
