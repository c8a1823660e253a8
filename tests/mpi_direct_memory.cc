// A direct solve across MPI processes that would not fit in the memory left is refused with the sizes, or solved iteratively with Method = auto: MUMPS's analysis weighed before it allocates.
//
// Each of 2 processes limits its address space (setrlimit(RLIMIT_AS), what
// `ulimit -v` sets) to what it maps once MPI has started plus 0.3 GB
// (tests/mpi_runs.h), and runs die2d N1 at degree 2 on 48 cells across
// (96,418 unknowns). MUMPS's analysis gives each process 104 MB for the
// factorisation (INFO(15); MUMPS then allocates exactly that, INFOG(18) =
// INFOG(16), measured with -mat_mumps_icntl_4 2 on an AMD EPYC), more than
// the room left once the run has assembled and OpenBLAS's buffers are kept
// back (by hand: 0.00 GB at 0.3 GB, 0.09 GB at 0.45 GB). So:
//  - Method = direct: not converged (exit status 2), the failure naming
//    Linear solver/Method, MUMPS's need and the address space's room;
//  - Method = auto (which by size alone would take the direct solver at
//    this size): converged, iterative on this mesh (its trial analysis
//    weighs the factorisation at more than half the room), to the same ram
//    force as an unlimited direct run on 2 processes (1e-6, the Newton
//    tolerance).
// Checked that it fails: without the weighing (memory_ratio() taken as 0)
// the refused run hangs in its first factorisation (ended by ctest's
// timeout, 600 s, before the launched processes had their alarm, now 300 s).
#include "mpi_runs.h"

using namespace mpi_runs;

namespace
{
  std::string
  die2d(const std::string &method)
  {
    return "subsection Mesh\n  set Corner refinements = 0\n  subsection Die2d\n    set Cells across = 48\n  end\nend\n"
           "subsection Discretisation\n  set Velocity degree = 2\nend\n"
           "subsection Linear solver\n  set Method = " +
           method +
           "\n  set Iterative from dofs = 10000000\nend\n"
           "subsection Refinement\n  set Cycles = 1\nend\n"
           "set Write VTU = false\n";
  }

  double
  ram_force(const Run &run)
  {
    return run.summary["cycles"].back()["quantities"]["F_x[1]"].get<double>();
  }
} // namespace



int
main(int argc, char **argv)
{
  if (const int status = launched_process(argc, argv); status >= 0)
    return status;

  constexpr double room = 0.3;
  const Run        refused = launch("refused", die2d("direct"), 2, room);
  report("2 processes, Method = direct beyond the memory left: not converged (exit 2)",
         refused.status == 2 && refused.summary.is_object() && !refused.summary["converged"].get<bool>());
  const std::string failure = refused.summary.value("failure", "");
  report("  its failure names Linear solver/Method, MUMPS's need for 96418 unknowns and the address space's room",
         failure.find("Linear solver/Method: MUMPS's factorisation of 96418 unknowns needs about ") != std::string::npos &&
           failure.find("GB its address space may still take (ulimit -v)") != std::string::npos);
  std::cout << failure.substr(0, failure.find("needs about")) << "..." << std::endl;

  const Run automatic = launch("auto", die2d("auto"), 2, room);
  report("2 processes, Method = auto: converged, iteratively on this mesh",
         automatic.status == 0 && automatic.summary["cycles"].back()["linear_solver"]["method"] == "iterative");

  const Run direct = launch("direct", die2d("direct"), 2);
  report("  without the limit the direct run converges, to the same ram force as auto's (1e-6)",
         direct.status == 0 && automatic.status == 0 &&
           direct.summary["cycles"].back()["linear_solver"]["method"] == "direct" &&
           relative(ram_force(automatic), ram_force(direct)) < 1e-6);
}
