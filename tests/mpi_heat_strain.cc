// Heat and the accumulated strain on 2 MPI processes: the same answer as on one.
//
// The heat equation and the strain's transport are replicated (every
// process solves them whole, doc/parallel.md), but their fields enter the
// flow's cell terms, which each process assembles for its own cells, and
// their patterns and interpolations go over the whole mesh (whole_mesh.h):
// a field that one process saw only on its cells would change the flow
// stress there and the answer. Checked, against one process, the same
// cells, Newton iterations and contact states per cycle, every force
// within 1e-6 of the largest force and every other quantity (the exit's
// and the largest temperature, the exit's strain, the extrudate) within
// 1e-6 of itself: the Newton tolerance (|R|/|F| ~ 1e-8), as in
// tests/mpi_processes (measured on an AMD EPYC: the forces 1.3e-8 and
// 1.9e-7 of the largest, T_max 1.8e-9):
//  - die2d hot (parameters/die2d-hot.prm, 2 of its 4 cycles): aluminium,
//    Sellars-Tegart, the steady heat equation coupled to the flow by the
//    temperature's effect on the flow stress, with the free surface;
//  - cold wire drawing with hardening (parameters/wiredrawing-cold.prm,
//    2 of its 3 cycles): axisymmetric, the flow stress from the strain
//    accumulated along the streamlines.
// Checked that it fails: the whole-mesh sparsity pattern (whole_mesh.h,
// the heat's and the strain's) made over a process's own cells, as deal.II's
// make_sparsity_pattern makes it on the shared mesh: both lines NO (die2d
// hot not converged on 2 processes; the wire's run hung, until the
// launched processes' alarm, as processes::failed_together() was broken at
// the same time).
#include "mpi_runs.h"

#include <cmath>

using namespace mpi_runs;

namespace
{
  /// Whether @p deck on 2 processes gives what it gives on 1: the same
  /// cells, Newton iterations and contact states per cycle (same_answer()),
  /// each force within @p tolerance of the cycle's largest force (a force
  /// near zero, as the inlet's axial force in wire drawing, 1e-4 N of 7,749,
  /// is round-off on both), every other quantity within @p tolerance of
  /// itself; the quantities @p needed among them.
  bool
  same_on_two(const std::string &name, const std::string &deck, const std::vector<std::string> &needed)
  {
    constexpr double tolerance = 1e-6;
    const Run        one = launch(name, deck, 1), two = launch(name, deck, 2);
    double           gap = 0;
    if (!same_answer(one, two, tolerance, true, gap, false))
      return false;
    for (unsigned int c = 0; c < one.summary["cycles"].size(); ++c)
      {
        const Json &x = one.summary["cycles"][c]["quantities"], &y = two.summary["cycles"][c]["quantities"];
        double      largest_force = 0;
        for (const auto &[quantity, value] : x.items())
          if (quantity.rfind("F_", 0) == 0)
            largest_force = std::max(largest_force, std::abs(value.get<double>()));
        for (const auto &quantity : needed)
          if (!x.contains(quantity) || !y.contains(quantity))
            return false;
        for (const auto &[quantity, value] : x.items())
          {
            const double a = value.get<double>(), b = y[quantity].get<double>();
            gap = std::max(gap, quantity.rfind("F_", 0) == 0 ? std::abs(a - b) / largest_force : relative(a, b));
          }
      }
    return gap < tolerance;
  }
} // namespace

int
main(int argc, char **argv)
{
  if (const int status = launched_process(argc, argv); status >= 0)
    return status;

  report("die2d hot (steady heat, Sellars-Tegart, free surface) on 2 processes: the same cells, Newton iterations, "
         "contact states, forces and temperatures within 1e-6 as on 1",
         same_on_two("die2d-hot",
                     shipped_deck("die2d-hot.prm", {"set Cycles          = 2"}) + "\nset Write VTU = false\n",
                     {"T_exit", "T_max", "F_x[1]"}));
  report("cold wire drawing (hardening with the accumulated strain, axisymmetric) on 2 processes: the same as on 1",
         same_on_two("wiredrawing",
                     shipped_deck("wiredrawing-cold.prm", {"set Cycles          = 2", "set Write VTU        = false"}),
                     {"eps_exit", "F_x[2]"}));
}
