// Results do not depend on the number of threads (issue 10, item 4). The
// cell assembly (flow terms, residuals, the mixed form's blocks) runs on
// deal.II's WorkStream, whose copier adds the cells' contributions into the
// global matrix and vectors one at a time in cell order, whatever thread
// computed them; the Kelly estimator does the same. deal.II's own thread
// count changes the arithmetic (cell similarity in FEValues on one thread,
// the partial sums of long vector reductions): threads::use() fixes it and
// limits the running threads through TBB (threads.h). So a run on one
// thread and a run on two must agree bitwise, not to a tolerance: any
// difference means a sum whose order depends on the scheduling (without
// the fixed count they differ by 1e-10 relative). Compared with ==:
// every quantity of interest, every part's boundary force and flux, the
// contact counts and the Newton iteration counts, on
//  - die2d N1, velocity degree 2, direct solver, two Kelly cycles (hanging
//    nodes, contact with slipping friction, solution transfer; 24 cells
//    across, 24k unknowns);
//  - the same with the iterative mixed-form solver (the AMG hierarchy is
//    built from the assembled matrix: a reordered sum would change it);
//  - the round bar P1, degree 1, axisymmetric (the weighted integrals, the
//    mean-dilatation penalty, a power law's Newton tangent).
#include <dieflow/base/threads.h>

#include <deal.II/base/multithread_info.h>

#include "report.h"

#include <deal.II/base/mpi.h>

using namespace dieflow;

namespace
{
  // 24 cells across: over 16,384 unknowns, where deal.II's vector
  // reductions split into partial sums.
  const std::string die2d_n1 =
    "subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = 24\n end\nend\n"
    "subsection Discretisation\n set Velocity degree = 2\nend\n"
    "subsection Refinement\n set Cycles = 2\n set Strategy = adaptive\nend\n";

  RunSummary
  run_on_threads(const std::string &deck, const unsigned int n)
  {
    threads::use(n);
    return run_deck_text(deck);
  }

  bool
  bitwise_equal(const RunSummary &a, const RunSummary &b)
  {
    bool same = a.converged && b.converged && a.cycles.size() == b.cycles.size();
    for (unsigned int c = 0; same && c < a.cycles.size(); ++c)
      {
        const CycleSummary &x = a.cycles[c], &y = b.cycles[c];
        same = x.dofs == y.dofs && x.quantities == y.quantities && x.boundary_force == y.boundary_force &&
               x.flux == y.flux && x.die_normal_force == y.die_normal_force &&
               x.die_friction_force == y.die_friction_force && x.contact_nodes.separated == y.contact_nodes.separated &&
               x.contact_nodes.stick == y.contact_nodes.stick && x.contact_nodes.slip == y.contact_nodes.slip &&
               x.nonlinear_iterations == y.nonlinear_iterations &&
               x.linear_counts.krylov_iterations == y.linear_counts.krylov_iterations;
      }
    return same;
  }

  void
  check(const std::string &name, const std::string &deck)
  {
    const RunSummary one = run_on_threads(deck, 1);
    const RunSummary two = run_on_threads(deck, 2);
    report(name + ": the second run on two threads", threads::running() == 2 && two.threads == 2 && one.threads == 1);
    report(name + ": one and two threads give bitwise the same results", bitwise_equal(one, two));
  }
} // namespace



int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  check("die2d N1, degree 2, direct", die2d_n1);
  check("die2d N1, degree 2, iterative", die2d_n1 + "subsection Linear solver\n set Method = iterative\nend\n");
  check("round bar P1, degree 1",
        "set Geometry = axisymmetric\n"
        "subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = 8\n end\nend\n"
        "subsection Material\n set Law = Norton-Hoff\n set Consistency K = 0.834\n"
        " set Rate sensitivity m = 0.2\n set Minimum strain rate = 1e-4\nend\n"
        "subsection Refinement\n set Cycles = 2\n set Strategy = adaptive\nend\n");
}
