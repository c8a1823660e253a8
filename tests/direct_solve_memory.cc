// A direct solve that would not fit in the memory left (an address-space limit, as ulimit -v sets) is refused with the sizes, or solved iteratively with Method = auto: the process is never killed.
//
// The test limits its own address space (setrlimit(RLIMIT_AS), what
// `ulimit -v` sets) to what it maps at its start plus 0.5 GB, and runs
// die2d N1 at degree 2 on 48 cells across (96,418 unknowns). Measured on
// this deck (doc/benchmarks.md, "Direct solves and the memory left"): with
// the check removed, the direct run factorises at 0.8 GB and fails at
// 0.6 and 0.7 GB (UMFPACK cannot allocate: "singular, or memory ran out"),
// and at 0.5 GB hangs in OpenBLAS; with the check it is refused at 0.7 GB
// and below, before its second factorisation or its first. So here:
//  - Method = direct: not converged (exit status 2), the failure naming
//    Linear solver/Method and the sizes in GB, no exception escaping;
//  - Method = auto (which by size alone would take the direct solver at
//    this size): converged, the iterative method on this mesh, the same
//    ram force as an unlimited direct run of the same deck (to 1e-6,
//    the Newton tolerance), which runs last, with the limit lifted.
// Checked that it fails: without the check before a factorisation the
// test hangs (ended by its alarm); with auto's choice by size alone the
// auto run is refused (its check NO).
#include "report.h"

#include <dieflow/solvers/iterative_solver.h>
#include <dieflow/solvers/linear_solver.h>

#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

using namespace dieflow;

namespace
{
  RunSummary
  die2d(const std::string &method)
  {
    return run_deck_text("subsection Mesh\n  set Corner refinements = 0\n  subsection Die2d\n    set Cells across = 48\n"
                         "  end\nend\n"
                         "subsection Discretisation\n  set Velocity degree = 2\nend\n"
                         "subsection Linear solver\n  set Method = " +
                         method +
                         "\n  set Iterative from dofs = 10000000\nend\n"
                         "subsection Refinement\n  set Cycles = 1\nend\n");
  }
} // namespace

int
main()
{
  // MPI (for the iterative solver) starts before the limit: Open MPI maps
  // its shared segments as it starts, and fails to start under the limit.
  const MpiOnFirstUse mpi;
  // A hang (OpenBLAS retries for ever where it cannot map its buffers)
  // ends the test: the alarm's signal fails it.
  alarm(240);
  struct rlimit unlimited;
  getrlimit(RLIMIT_AS, &unlimited);
  struct rlimit limited = unlimited;
  limited.rlim_cur      = static_cast<rlim_t>(mapped_memory() + 0.5e9);
  setrlimit(RLIMIT_AS, &limited);

  const RunSummary refused = die2d("direct");
  report("Method = direct beyond the memory left: not converged",
         !refused.converged && refused.cycles.size() == 1 && !refused.cycles[0].converged);
  report("its failure names Linear solver/Method and the sizes",
         refused.failure.find("Linear solver/Method: the direct solver's factorisation of 96418 unknowns needs about") !=
             std::string::npos &&
           refused.failure.find(" GB free") != std::string::npos);

  const RunSummary automatic = die2d("auto");
  report("Method = auto: converged, iteratively on this mesh",
         automatic.converged && automatic.cycles.back().linear_method == "iterative");

  setrlimit(RLIMIT_AS, &unlimited);
  const RunSummary direct = die2d("direct");
  report("without the limit the direct run converges, to the same ram force as auto's (1e-6)",
         direct.converged && direct.cycles.back().linear_method == "direct" &&
           relative_gap(named_value(automatic.cycles.back().quantities, "F_x[1]"),
                        named_value(direct.cycles.back().quantities, "F_x[1]")) < 1e-6);
}
