// Linear solver/Reuse factorisation from dofs: a Newton step solved by GMRES on an earlier factorisation.
//  - LinearSolver::solve_step on a 50 x 50 five-point Laplacian A (plus a
//    shift): the first step factorises A; a low-rank nonsymmetric change B
//    of A (three rows) is solved by GMRES on A's factorisation, with B's
//    own residual |b - B y| below the asked 1e-10 |b| (computed here, not
//    GMRES's estimate) and y the direct solution of B within 1e-8 (the
//    residual times B's condition, about 1e3 with the shift); B asked for
//    1e-17, which no solve reaches, is factorised after GMRES gave up;
//    a change C of every row (each off-diagonal entry turned) is factorised
//    without trying GMRES (more rows changed than its 10 iterations leave
//    room for), and C's LU factorisation serves E (C with B's change) as
//    A's Cholesky one served B; a moved mesh (reset() with the same
//    pattern) keeps the ordering (no new symbolic analysis) but factorises
//    its next step, and another pattern is analysed anew; has_factorisation()
//    (the last step's factorisation, which the dual-weighted estimate's
//    adjoint solve takes) is false after a step by GMRES and after a move.
//  - die2d (4 cells across, degree 2, Norton-Hoff m = 0.2, the paper's
//    friction) with reuse from 1 unknown: steps were solved by GMRES
//    (2 of 10 measured), and the ram force, die forces and probe velocity
//    are those of the run that factorises every step within 1e-6 (both
//    converge to Newton's relative residual of 1e-8: the force to 1e-6,
//    as in tests/deck_entries_paths), and not bit for bit.
#include <dieflow/solvers/linear_solver.h>

#include "report.h"

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_pattern.h>

using namespace dieflow;

namespace
{
  constexpr unsigned int side = 50;

  unsigned int
  index(const unsigned int i, const unsigned int j)
  {
    return i * side + j;
  }

  /// The five-point pattern of a side x side grid.
  void
  make_pattern(dealii::SparsityPattern &pattern, const bool with_diagonals)
  {
    dealii::DynamicSparsityPattern dsp(side * side);
    for (unsigned int i = 0; i < side; ++i)
      for (unsigned int j = 0; j < side; ++j)
        for (int di = -1; di <= 1; ++di)
          for (int dj = -1; dj <= 1; ++dj)
            if ((di == 0 || dj == 0 || with_diagonals) && i + di < side && j + dj < side)
              dsp.add(index(i, j), index(i + di, j + dj));
    pattern.copy_from(dsp);
  }

  /// A: 4.2 on the diagonal (the Laplacian shifted by 0.2), -1 to each neighbour.
  void
  laplacian(dealii::SparseMatrix<double> &A)
  {
    for (unsigned int r = 0; r < A.m(); ++r)
      for (auto e = A.begin(r); e != A.end(r); ++e)
        e->value() = e->column() == r ? 4.2 : -1.;
  }

  double
  relative_residual(const dealii::SparseMatrix<double> &A, const dealii::Vector<double> &x, const dealii::Vector<double> &b)
  {
    dealii::Vector<double> r(b.size());
    A.vmult(r, x);
    r -= b;
    return r.l2_norm() / b.l2_norm();
  }

  double
  relative_difference(const dealii::Vector<double> &x, const dealii::Vector<double> &y)
  {
    dealii::Vector<double> d(x);
    d -= y;
    return d.l2_norm() / y.l2_norm();
  }

  /// x = M^-1 b by a separate solver that factorises M.
  dealii::Vector<double>
  direct(const dealii::SparseMatrix<double> &M, const dealii::Vector<double> &b)
  {
    LinearSolverParameters parameters;
    LinearSolver           solver(parameters);
    dealii::Vector<double> x;
    solver.factorize(M, false);
    solver.solve(b, x);
    return x;
  }

  RunSummary
  die2d(const std::string &reuse_from)
  {
    return run_deck_text("subsection Mesh\n subsection Die2d\n  set Cells across = 4\n end\nend\n"
                         "subsection Discretisation\n set Velocity degree = 2\nend\n"
                         "subsection Material\n set Law = Norton-Hoff\n set Rate sensitivity m = 0.2\nend\n"
                         "subsection Linear solver\n set Reuse factorisation from dofs = " +
                         reuse_from + "\nend\n");
  }
} // namespace



int
main()
{
  dealii::SparsityPattern pattern, other_pattern;
  make_pattern(pattern, false);
  make_pattern(other_pattern, true);
  dealii::SparseMatrix<double> A(pattern), B(pattern), C(pattern), E(pattern), D(other_pattern);
  laplacian(A);
  laplacian(B);
  laplacian(C);
  // B: three rows changed (a low-rank, nonsymmetric change).
  for (const unsigned int r : {index(10, 10), index(25, 30), index(40, 5)})
    for (auto e = B.begin(r); e != B.end(r); ++e)
      e->value() *= (e->column() == r ? 1.5 : 0.3);
  // C: every coupling turned nonsymmetric (i < j: -1 -> +1.5).
  for (unsigned int r = 0; r < C.m(); ++r)
    for (auto e = C.begin(r); e != C.end(r); ++e)
      if (e->column() > r)
        e->value() = 1.5;
  // E: C with B's three rows changed.
  E.copy_from(C);
  for (const unsigned int r : {index(10, 10), index(25, 30), index(40, 5)})
    for (auto e = E.begin(r); e != E.end(r); ++e)
      e->value() *= (e->column() == r ? 1.5 : 0.3);
  for (unsigned int r = 0; r < D.m(); ++r)
    for (auto e = D.begin(r); e != D.end(r); ++e)
      e->value() = e->column() == r ? 9. : -1.;
  dealii::Vector<double> b(side * side);
  for (unsigned int i = 0; i < b.size(); ++i)
    b[i] = std::sin(0.37 * i) + 0.5;

  LinearSolverParameters parameters;
  parameters.reuse_threshold = 1;
  LinearSolver           solver(parameters);
  dealii::Vector<double> x;
  solver.solve_step(A, true, b, x, 1e-10);
  report("the first step factorises A (no factorisation to reuse), its solve exact (1e-12)",
         solver.counts.cholesky_factorisations == 1 && solver.counts.reused_solves == 0 &&
           relative_residual(A, x, b) < 1e-12);

  solver.solve_step(B, false, b, x, 1e-10);
  report("B (three rows changed): solved by GMRES on A's factorisation, no new factorisation, and A's is not "
         "offered as the last step's (has_factorisation)",
         solver.counts.reused_solves == 1 && solver.counts.reuse_refactorised == 0 &&
           solver.counts.cholesky_factorisations + solver.counts.lu_factorisations == 1 && !solver.has_factorisation());
  report("B's own residual below the asked 1e-10", relative_residual(B, x, b) < 1e-10);
  report("B's direct solution (1e-8)", relative_difference(x, direct(B, b)) < 1e-8);

  // B again, asked for 1e-17 (below round-off): GMRES is tried, cannot
  // get there in its 10 iterations, and B is factorised.
  solver.solve_step(B, false, b, x, 1e-17);
  report("B asked for 1e-17: GMRES tried and given up, B factorised (the last step's), its solve exact (1e-12)",
         solver.counts.reuse_refactorised == 1 && solver.counts.lu_factorisations == 1 && solver.has_factorisation() &&
           solver.counts.reused_solves == 1 && relative_residual(B, x, b) < 1e-12);

  solver.solve_step(C, false, b, x, 1e-10);
  report("C (every row changed): factorised without trying GMRES, its solve exact (1e-12)",
         solver.counts.reuse_refactorised == 1 && solver.counts.reused_solves == 1 &&
           solver.counts.lu_factorisations == 2 && relative_residual(C, x, b) < 1e-12);

  solver.solve_step(E, false, b, x, 1e-10);
  report("E (C's rows changed): GMRES on C's LU factorisation, its residual below 1e-10, E's direct solution (1e-8)",
         solver.counts.reused_solves == 2 && solver.counts.lu_factorisations == 2 && relative_residual(E, x, b) < 1e-10 &&
           relative_difference(x, direct(E, b)) < 1e-8);

  const unsigned int analyses = solver.counts.symbolic_analyses;
  // E factorised, then its own matrix on the moved mesh, which the old
  // factorisation solves exactly: a moved mesh's first step factorises
  // all the same.
  solver.factorize(E, false);
  const bool offered_before_move = solver.has_factorisation();
  solver.reset(E);
  const bool offered_after_move = solver.has_factorisation();
  solver.solve_step(E, false, b, x, 1e-10);
  report("a moved mesh (same pattern): its factorisation, offered before the move, not after; its ordering kept, "
         "its first step factorised, no GMRES tried",
         offered_before_move && !offered_after_move && solver.counts.symbolic_analyses == analyses &&
           solver.counts.lu_factorisations == 4 &&
           solver.counts.reused_solves == 2 && solver.counts.reuse_refactorised == 1 &&
           relative_residual(E, x, b) < 1e-12);
  solver.reset(D);
  solver.solve_step(D, false, b, x, 1e-10);
  report("another pattern: analysed anew and factorised",
         solver.counts.symbolic_analyses == analyses + 1 && solver.counts.lu_factorisations == 5 &&
           solver.counts.reused_solves == 2 && relative_residual(D, x, b) < 1e-12);

  const RunSummary   every_step = die2d("0");
  const RunSummary   reusing    = die2d("1");
  unsigned int       reused = 0, reused_every_step = 0;
  for (const auto &cycle : reusing.cycles)
    reused += cycle.linear_counts.reused_solves;
  for (const auto &cycle : every_step.cycles)
    reused_every_step += cycle.linear_counts.reused_solves;
  report("die2d: both converge; reuse from 1 unknown solved steps by GMRES, reuse 0 none",
         every_step.converged && reusing.converged && reused > 0 && reused_every_step == 0);
  const double gap = relative_gap(named_value(reusing.cycles.back().quantities, "F_x[1]"),
                                  named_value(every_step.cycles.back().quantities, "F_x[1]"));
  report("die2d: the same ram force, die forces and probe velocity (1e-6), not bit for bit",
         quantities_agree(every_step.cycles.back(), reusing.cycles.back(), 1e-6) && gap > 0);
}
