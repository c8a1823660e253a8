// The iterative method for velocity degree 2 (Linear solver/Method =
// iterative: the penalty's mixed form, GMRES with the block-triangular
// AMG / pressure-mass preconditioner, SaddlePointSolver) against the direct
// one (the penalised system factorised). Both solve the same discrete
// problem, so they agree up to the Newton tolerance, not the penalty's
// compressibility (the augmented Lagrangian of degree 1 differs from the
// penalty solution by 1e-5; this method by round-off):
//  - die2d N1 (Newtonian; contact with slipping Coulomb friction: the
//    momentum rows of slipping nodes are transformed, GMRES on a
//    non-symmetric system), two adaptive cycles: same contact states, ram
//    force, die forces and probe velocity within 1e-7 (measured 2e-10;
//    Newton stops at a relative residual of about 1e-8, and both runs
//    stop there);
//  - die2d P1 (Norton-Hoff m = 0.2, viscosity varying by 1e4): converges,
//    every quantity within 5e-4 (measured 1.9e-4). Not 1e-7: where Newton
//    projects v onto a changed active set, the penalty form's pressure
//    lambda P div v jumps by lambda P div of that move and the mixed form's
//    carried pressure does not, so the iterations take different paths.
//    On the land of P1 the contact pressure is nearly zero over many nodes,
//    so the contact tolerances (the dead band of 1e-6 of the largest nodal
//    force) admit more than one converged active set: the runs end with 22
//    and 29 separated nodes, and the forces differ by up to 1.9e-4 (with
//    the AMG's constant near-null space instead of the rigid-body modes
//    they ended one node apart, 2e-5). The bound says the two methods land
//    on the same solution up to that ambiguity, not to round-off;
//  - an exact solution: plane Poiseuille flow lies in the Q2 space, so the
//    discrete solution is exact; the iterative one must be too (L2 error
//    below 1e-8 of the unit speed, as the direct solver's test asks);
//  - the outer GMRES iterations per solve stay below a bound on two
//    meshes (frictionless die2d, 8 and 16 cells across; the bound is twice
//    the most measured, so that it catches a preconditioner that stopped
//    working, not round-off): with the default p-multigrid cycle on the
//    velocity block (measured 12 and 16) and with AMG on the Q2 block
//    (22 and 28, with N1's answer as above);
//  - with the inner solve of the velocity block (Velocity block = inner
//    solve): N1's answer as above, and outer iterations per solve below a
//    tighter bound on the same two meshes;
//  - viscosity contrast (Norton-Hoff m = 0.05, frictionless die2d, 16
//    cells across): the ram force and the probe velocity are the direct
//    ones within 1e-7 (measured 7e-9 and 9e-9), the die forces within
//    2e-3 (measured 9.2e-4 on the land's die, where the contact pressure
//    is about zero over many nodes and the runs end with different
//    separated ones: the path decides which, and it moved with each change
//    of the iterative solves: 1.8e-4 before the coarse AMG's change below,
//    3.6e-4 before the forcing term kept its absolute accuracy),
//    and the outer iterations per solve stay at most 45 (measured 27; 74
//    before the coarse AMG took the flow as a near-null vector and
//    aggregated across all connections, so the bound catches a return of
//    that weakness; on 8 cells across the Q1 problem is small enough for
//    ML's direct coarse solve, and both took 40);
//  - penalty factor 1e10 (die2d N1, 16 cells across): the iterative method
//    converges in at most 3 Newton iterations more than the direct one
//    (measured 8 against 7; 18 when the solves' tolerance did not shrink
//    with the penalty, and no convergence in 50 on 32 cells across: the
//    carried pressure takes up lambda x a solve's residual), and every
//    quantity agrees within 1e-4 (the ram force 3e-7; the container's
//    friction force, a thousandth of the ram's, 2e-5: at this penalty the
//    direct solution itself carries round-off of about eps x 1e10);
//  - Method = auto: direct below 'Iterative from dofs', iterative from it on.
#include <dieflow/problem/run.h>

#include "report.h"

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <limits>

using namespace dieflow;

namespace
{
  std::string
  die2d(const unsigned int across)
  {
    return "subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = " + std::to_string(across) +
           "\n end\nend\nsubsection Discretisation\n set Velocity degree = 2\nend\n";
  }
  /// The die2d material P (Norton-Hoff, K = 0.834) with rate sensitivity m.
  std::string
  norton_hoff(const std::string &m)
  {
    return "subsection Material\n set Law = Norton-Hoff\n set Consistency K = 0.834\n set Rate sensitivity m = " + m +
           "\n set Minimum strain rate = 1e-4\nend\n";
  }
  const std::string p1 = norton_hoff("0.2");
  const std::string frictionless =
    "subsection Contact\n set Friction coefficients = 3: 0, 4: 0\nend\n";

  RunSummary
  run(const std::string &deck, const std::string &method, const unsigned int cycles = 1)
  {
    return run_deck_text(deck + "subsection Refinement\n set Cycles = " + std::to_string(cycles) +
                         "\n set Strategy = adaptive\nend\nsubsection Linear solver\n" + method + "end\n");
  }

  /// Every quantity (the ram force, each die's normal and friction force, the probe's v_x) within @p tolerance.
  bool
  agree(const CycleSummary &d, const CycleSummary &i, const double tolerance)
  {
    return quantities_agree(i, d, tolerance) && d.quantities.back().first == "v_x(probe)";
  }

  unsigned int
  most_iterations_per_solve(const RunSummary &run)
  {
    // A cycle without an iterative solve has nothing to bound: it fails
    // the bound (the largest count), so the checks cannot pass vacuously.
    unsigned int most = 0;
    for (const auto &c : run.cycles)
      most = c.linear_counts.iterative_solves == 0 ?
               std::numeric_limits<unsigned int>::max() :
               std::max(most, c.linear_counts.krylov_iterations / c.linear_counts.iterative_solves);
    return run.cycles.empty() ? std::numeric_limits<unsigned int>::max() : most;
  }

  /**
   * The preconditioner's rate over a run, free of the forcing term: the
   * most Krylov iterations per decade of residual reduction of any cycle,
   * and the fewest decades per solve (at least 2 where every solve
   * converged: Newton's forcing term never asks less than 1e-2).
   */
  std::pair<double, double>
  rate(const RunSummary &run)
  {
    double most = 0, fewest = std::numeric_limits<double>::infinity();
    for (const auto &c : run.cycles)
      {
        const auto &n = c.linear_counts;
        if (n.iterative_solves == 0 || n.residual_decades <= 0)
          return {std::numeric_limits<double>::infinity(), 0.};
        most   = std::max(most, n.krylov_iterations / n.residual_decades);
        fewest = std::min(fewest, n.residual_decades / n.iterative_solves);
      }
    return {most, fewest};
  }
} // namespace



int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const RunSummary direct    = run(die2d(8), " set Method = direct\n", 2);
  const RunSummary iterative = run(die2d(8), " set Method = iterative\n", 2);
  report("N1: both converge", direct.converged && iterative.converged);
  for (unsigned int c = 0; c < 2; ++c)
    {
      const CycleSummary &d = direct.cycles[c], &i = iterative.cycles[c];
      const std::string   cycle = "N1 cycle " + std::to_string(c) + ": ";
      report(cycle + "the iterative run used the iterative method, without falling back",
             i.linear_method == "iterative" && d.linear_method == "direct" && i.linear_counts.direct_fallbacks == 0);
      report(cycle + "same contact states",
             d.contact_nodes.separated == i.contact_nodes.separated && d.contact_nodes.stick == i.contact_nodes.stick &&
               d.contact_nodes.slip == i.contact_nodes.slip);
      report(cycle + "ram force, die forces and probe velocity within 1e-7", agree(d, i, 1e-7));
    }

  const RunSummary p1_direct    = run(die2d(8) + p1, " set Method = direct\n");
  const RunSummary p1_iterative = run(die2d(8) + p1, " set Method = iterative\n");
  report("P1: both converge", p1_direct.converged && p1_iterative.converged);
  report("P1: ram force, die forces and probe velocity within 5e-4", agree(p1_direct.cycles[0], p1_iterative.cycles[0], 5e-4));

  const RunSummary poiseuille = run_deck_text(
    "subsection Mesh\n set Source = box\n subsection Box\n  set Lower corner = 0, 0\n  set Upper corner = 2, 1\n"
    "  set Subdivisions = 8, 4\n end\nend\nsubsection Material\n set Law = Newtonian\n set Viscosity = 1\nend\n"
    "subsection Boundary conditions\n set Prescribed velocity ids = 1, 2, 4\n set Symmetry ids = 3\n"
    " set Slip wall ids =\n set Traction free ids =\n set Body force = 1; 0\n"
    " subsection Prescribed velocity 1\n  set Velocity = 0.5*(1-y^2); 0\n end\n"
    " subsection Prescribed velocity 2\n  set Velocity = 0.5*(1-y^2); 0\n end\n"
    " subsection Prescribed velocity 4\n  set Velocity = 0; 0\n end\nend\n"
    "subsection Refinement\n set Cycles = 2\nend\nsubsection Contact\n set Die ids =\nend\n"
    "subsection Verification\n set Exact velocity = 0.5*(1-y^2); 0\nend\n"
    "subsection Discretisation\n set Velocity degree = 2\nend\nsubsection Linear solver\n set Method = iterative\nend\n");
  report("Poiseuille (exact in Q2): converges with the iterative method",
         poiseuille.converged && poiseuille.cycles[0].linear_method == "iterative");
  report("Poiseuille: exact on both meshes (L2 error below 1e-8)",
         *poiseuille.cycles[0].velocity_l2_error < 1e-8 && *poiseuille.cycles[1].velocity_l2_error < 1e-8);

  const RunSummary   coarse_run = run(die2d(8) + frictionless, " set Method = iterative\n");
  const RunSummary   fine_run   = run(die2d(16) + frictionless, " set Method = iterative\n");
  const unsigned int coarse     = most_iterations_per_solve(coarse_run);
  const unsigned int fine       = most_iterations_per_solve(fine_run);
  report("p-multigrid: outer iterations per solve at most 32 on 8 and 16 cells across", coarse <= 32 && fine <= 32);
  const auto coarse_rate = rate(coarse_run), fine_rate = rate(fine_run);
  // Measured 3.5 and 4.3 iterations per decade (3.7-3.8 decades per solve);
  // 6.05 on die2d N1 at 32 cells across (doc/benchmarks.md).
  report("p-multigrid: at least 2 decades of residual per solve, at most 6 Krylov iterations per decade, on 8 and 16 "
         "cells across",
         coarse_rate.second >= 2 && fine_rate.second >= 2 && coarse_rate.first <= 6 && fine_rate.first <= 6);
  const std::string amg = " set Method = iterative\n set Velocity multigrid = AMG\n";
  const RunSummary  amg_n1 = run(die2d(8), amg, 2);
  report("AMG on the Q2 block: N1's ram force, die forces and probe velocity as the direct solver's within 1e-7",
         amg_n1.converged && amg_n1.cycles[1].linear_counts.direct_fallbacks == 0 && agree(direct.cycles[1], amg_n1.cycles[1], 1e-7));
  const unsigned int amg_coarse = most_iterations_per_solve(run(die2d(8) + frictionless, amg));
  const unsigned int amg_fine   = most_iterations_per_solve(run(die2d(16) + frictionless, amg));
  report("AMG on the Q2 block: outer iterations per solve at most 60 on 8 and 16 cells across",
         amg_coarse <= 60 && amg_fine <= 60);

  // The inner solve of the velocity block (flexible GMRES outside): the
  // same answer, and outer iterations that are the Schur approximation's
  // alone, so they stay nearly constant from 8 to 16 cells across
  // (measured 12 and 9 with the p-multigrid cycle and inexact Newton, 19
  // and 16 with the Q2 AMG and fixed tolerances; the bound covers both).
  const std::string inner = " set Method = iterative\n set Velocity block = inner solve\n";
  const RunSummary  inner_8  = run(die2d(8), inner, 2);
  const RunSummary  inner_16 = run(die2d(16), inner);
  report("inner solve: converges without falling back",
         inner_8.converged && inner_16.converged && inner_8.cycles[1].linear_counts.direct_fallbacks == 0 &&
           inner_16.cycles[0].linear_counts.direct_fallbacks == 0 && inner_8.cycles[1].linear_counts.inner_iterations > 0);
  report("inner solve: ram force, die forces and probe velocity of N1 as the direct solver's within 1e-7",
         agree(direct.cycles[1], inner_8.cycles[1], 1e-7));
  report("inner solve: outer iterations per solve at most 40 on 8 and 16 cells across",
         most_iterations_per_solve(inner_8) <= 40 && most_iterations_per_solve(inner_16) <= 40);

  // Viscosity contrast: Norton-Hoff m = 0.05 (nearly rigid-plastic),
  // frictionless die2d, 16 cells across, p-multigrid.
  const std::string contrast = norton_hoff("0.05");
  const RunSummary contrast_direct    = run(die2d(16) + frictionless + contrast, " set Method = direct\n");
  const RunSummary contrast_iterative = run(die2d(16) + frictionless + contrast, " set Method = iterative\n");
  report("m = 0.05: both converge, the iterative method without falling back",
         contrast_direct.converged && contrast_iterative.converged &&
           contrast_iterative.cycles[0].linear_counts.direct_fallbacks == 0);
  const CycleSummary &cd = contrast_direct.cycles[0], &ci = contrast_iterative.cycles[0];
  report("m = 0.05: ram force and probe velocity within 1e-7, die forces within 2e-3",
         agree(cd, ci, 2e-3) && relative_gap(ci.quantities.front().second, cd.quantities.front().second) < 1e-7 &&
           relative_gap(ci.quantities.back().second, cd.quantities.back().second) < 1e-7);
  report("m = 0.05: outer iterations per solve at most 45 on 16 cells across",
         most_iterations_per_solve(contrast_iterative) <= 45);

  const std::string stiff         = "subsection Material\n set Penalty factor = 1e10\nend\n";
  const RunSummary  stiff_direct  = run(die2d(16) + stiff, " set Method = direct\n");
  const RunSummary  stiff_mixed   = run(die2d(16) + stiff, " set Method = iterative\n");
  report("penalty factor 1e10: both converge, the iterative method in at most 3 Newton iterations more",
         stiff_direct.converged && stiff_mixed.converged &&
           stiff_mixed.cycles[0].nonlinear_iterations <= stiff_direct.cycles[0].nonlinear_iterations + 3);
  report("penalty factor 1e10: ram force, die forces and probe velocity within 1e-4",
         agree(stiff_direct.cycles[0], stiff_mixed.cycles[0], 1e-4));

  const RunSummary below = run(die2d(8), " set Method = auto\n set Iterative from dofs = 1000000\n");
  const RunSummary above = run(die2d(8), " set Method = auto\n set Iterative from dofs = 100\n");
  report("auto: direct below the threshold, iterative from it on",
         below.cycles[0].linear_method == "direct" && above.cycles[0].linear_method == "iterative");
}
