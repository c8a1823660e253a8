// The direct solve of the Newton system across MPI processes: MUMPS through PETSc, each process owning a block of rows.
#ifndef dieflow_distributed_direct_solver_h
#define dieflow_distributed_direct_solver_h

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>

namespace dieflow
{
  /**
   * Solves J x = b (or J^T x = b) by MUMPS's multifrontal LU across the
   * run's processes (processes.h): process r owns the rows
   * [N r / P, N (r + 1) / P) of the matrix, which every process holds whole
   * (the replicated system of processes::sum()), and MUMPS factorises them
   * together, its fronts and their memory divided among the processes.
   * The solution is gathered onto every process (the same bits everywhere).
   *
   * Per mesh the matrix's pattern is fixed: the first factorisation analyses
   * it (MUMPS's ordering and symbolic factorisation), the later ones of the
   * same pattern reuse that analysis, as the serial path reuses CHOLMOD's and
   * UMFPACK's (LinearSolver). reset() forgets it.
   */
  class DistributedDirectSolver
  {
  public:
    DistributedDirectSolver();
    ~DistributedDirectSolver();

    /// Forgets the pattern (a new mesh).
    void
    reset();

    /// Factorises @p matrix (the same on every process); throws
    /// SolverFailure where MUMPS cannot (singular, or out of memory).
    void
    factorize(const dealii::SparseMatrix<double> &matrix);

    /// Solves with the last factorisation (@p transpose: with J^T).
    void
    solve(const dealii::Vector<double> &rhs, dealii::Vector<double> &solution, const bool transpose);

    bool
    has_factorisation() const;

  private:
    struct Petsc;
    std::unique_ptr<Petsc> petsc;
  };
} // namespace dieflow

#endif
