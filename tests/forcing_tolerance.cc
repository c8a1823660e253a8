// The inexact Newton method's tolerance for an iterative solve
// (LinearSolverParameters::forcing_tolerance()), against its definition:
//  - 0.1 x Newton's relative residual r, between 'Iterative tolerance'
//    (1e-6) and 1e-2, both scaled by 1e7 / penalty factor above 1e7;
//  - after a solve on the same mesh (tolerance t0 at residual r0), a
//    residual that grew (contact states that changed) gets an absolute
//    accuracy t r no looser than t0 r0, and never a tolerance below the
//    tightest: the numbers are those of die2d at 320 cells across, where
//    the residual jumped from 0.157 to 1.146 and the plain forcing term
//    (1e-2 of 1.146) let some 400 nodes trade stick and slip at every
//    Newton iteration (doc/benchmarks.md);
//  - a residual that fell gets the forcing term alone;
//  - 'Inexact Newton = false': the tightest tolerance, whatever the history.
// The comparisons allow 1e-12 relative (a product and a quotient of
// doubles).
#include <dieflow/solvers/linear_solver.h>

#include "report.h"

#include <deal.II/base/mpi.h>

using namespace dieflow;

namespace
{
  bool
  equal(const double a, const double b)
  {
    return relative_gap(a, b) <= 1e-12;
  }
} // namespace



int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  LinearSolverParameters solver;
  report("forcing term 0.1 r: r = 1e-3 gives 1e-4", equal(solver.forcing_tolerance(1e-3, 1e7), 1e-4));
  report("capped at 1e-2 (r = 0.5) and floored at 1e-6 (r = 1e-9)",
         equal(solver.forcing_tolerance(0.5, 1e7), 1e-2) && equal(solver.forcing_tolerance(1e-9, 1e7), 1e-6));
  report("penalty factor 1e10: 0.1 r x 1e-3 (r = 1e-3: 1e-7), floor 1e-9",
         equal(solver.forcing_tolerance(1e-3, 1e10), 1e-7) && equal(solver.forcing_tolerance(1e-9, 1e10), 1e-9));

  const double t0 = solver.forcing_tolerance(0.157, 1e7);
  const double t1 = solver.forcing_tolerance(1.146, 1e7, t0, 0.157);
  report("a residual that grew (0.157 -> 1.146): the previous absolute accuracy, t r = t0 r0 = 1.57e-3",
         equal(t1 * 1.146, t0 * 0.157) && equal(t1 * 1.146, 1.57e-3) && t1 < solver.forcing_tolerance(1.146, 1e7));
  report("a residual that fell (1.146 -> 0.0346): the forcing term alone, 3.46e-3",
         equal(solver.forcing_tolerance(0.0346, 1e7, t1, 1.146), 3.46e-3));
  report("a jump of 1e5 after a solve at 1e-6: no tolerance below 1e-6",
         equal(solver.forcing_tolerance(1., 1e7, 1e-6, 1e-5), 1e-6));
  report("penalty factor 1e10, a jump: t r = t0 r0, no tolerance below 1e-9",
         equal(solver.forcing_tolerance(0.2, 1e10, 1e-5, 0.1) * 0.2, 1e-6) &&
           equal(solver.forcing_tolerance(0.2, 1e10, 1e-9, 0.1), 1e-9));

  solver.inexact_newton = false;
  report("Inexact Newton = false: 1e-6 at every residual and history",
         equal(solver.forcing_tolerance(0.5, 1e7), 1e-6) && equal(solver.forcing_tolerance(0.5, 1e7, 1e-2, 0.1), 1e-6));
  return 0;
}
