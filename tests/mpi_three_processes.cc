// The decks on 3 MPI processes against 1 (the 3D deck on 2 as well): the answer does not depend on the process count.
//
// tests/mpi_processes compares 2 processes with 1 on these decks (and checks
// the files and refusals); this one adds 3, where a process's part borders
// two others and the contact nodes on the parts' borders are seen from
// three sides. The systems differ from one process's by round-off (the
// order of the sums, MUMPS against CHOLMOD / UMFPACK), the converged answers
// by the Newton tolerance (|R|/|F| ~ 1e-8 and |dv|/|v| 1e-8): every quantity
// within 1e-6 of one process's, as in tests/mpi_processes. Checked:
//  - die2d N1, degree 2, the land holding the metal (parameters/
//    die2d-held-land.prm, 2 adaptive cycles, Coulomb friction) on 3
//    processes: the same cells, Newton iterations and contact states
//    (stick, slip, separated nodes) per cycle, the ram and die forces and
//    the probe's exit velocity within 1e-6;
//  - the round bar, axisymmetric (parameters/roundbar-held-land.prm), on 3:
//    the same;
//  - the rectangular bar quarter, 3D, Coulomb friction, degree 2
//    (parameters/rectbar3d.prm at 4 x 2 cells), on 2 and 3: the same
//    contact states and Newton iterations, the forces and the velocity at
//    a point in the land within 1e-6;
//  - a Target error run (die2d held land, 1e-3) stops at the same cycle on
//    3 processes as on 1, before the last.
#include "mpi_runs.h"

using namespace mpi_runs;



int
main(int argc, char **argv)
{
  // One process of a run launched below.
  if (const int status = launched_process(argc, argv); status >= 0)
    return status;

  double gap = 0;
  {
    const std::string deck =
      shipped_deck("die2d-held-land.prm", {"set Write VTU = false", "set Cycles          = 2"});
    report("die2d N1 held land (degree 2, 2 cycles, Coulomb) on 3 processes: the same cells, Newton iterations and "
           "contact states per cycle, forces and probe velocity within 1e-6 of one process's",
           same_answer(launch("die2d", deck, 1), launch("die2d", deck, 3), 1e-6, true, gap));
  }
  {
    const std::string deck = shipped_deck("roundbar-held-land.prm", {"set Write VTU = false"});
    report("round bar, axisymmetric (held land), on 3 processes: as on 1",
           same_answer(launch("roundbar", deck, 1), launch("roundbar", deck, 3), 1e-6, true, gap));
  }
  {
    // The velocity at (18, 2, 3) mm: in the land (x from 5.19 to 20.19 mm,
    // its half height 4.75 and half width 6), off the planes of symmetry.
    const std::string deck = shipped_deck("rectbar3d.prm",
                                          {"set Write VTU = false",
                                           "set Cells across = 4",
                                           "set Cells in depth = 2"}) +
                             "\nsubsection Refinement\n  set Probe point = 18, 2, 3\nend\n";
    const Run one = launch("rectbar3d", deck, 1), two = launch("rectbar3d", deck, 2),
              three = launch("rectbar3d", deck, 3);
    const bool probed = one.summary.is_object() && !one.summary["cycles"].empty() &&
                        one.summary["cycles"][0]["quantities"].contains("v_x(probe)");
    report("rectangular bar quarter, 3D, Coulomb friction, degree 2, on 2 and 3 processes: the same contact states and "
           "Newton iterations, forces and velocity in the land within 1e-6 of one process's",
           probed && same_answer(one, two, 1e-6, true, gap) && same_answer(one, three, 1e-6, true, gap));
  }
  {
    const std::string deck = target_error_deck();
    report("Target error = 1e-3 (die2d held land): stops at the same cycle on 3 processes as on 1, before the last",
           same_stopping_cycle(launch("target", deck, 1), launch("target", deck, 3)));
  }
}
