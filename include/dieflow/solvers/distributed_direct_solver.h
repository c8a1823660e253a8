// The direct solve of the Newton system across MPI processes: MUMPS through PETSc, each process owning a block of rows.
#ifndef dieflow_distributed_direct_solver_h
#define dieflow_distributed_direct_solver_h

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <string>

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
   * UMFPACK's (LinearSolver). reset() forgets it. The analysis says what
   * the factorisation will take on each process, weighed against the memory
   * free before MUMPS allocates it (LinearSolver refuses a factorisation
   * that would not fit, as it does CHOLMOD's and UMFPACK's on one process).
   */
  class DistributedDirectSolver
  {
  public:
    DistributedDirectSolver();
    ~DistributedDirectSolver();

    /// Forgets the pattern (a new mesh).
    void
    reset();

    /**
     * Collective. MUMPS's analysis of @p matrix's pattern (and values: it
     * scales and permutes by them), unless its pattern's was made since
     * reset(); true where it was made now. Then weighs the memory the
     * factorisation will take, from the analysis (INFO(15), each process's
     * share), against the memory free: the sum over a machine's processes
     * against its free memory (LinearSolver::machine_memory(), shared) and
     * each process's share against its address space's room
     * (LinearSolver::address_space_room()). Throws SolverFailure where
     * MUMPS cannot analyse it.
     */
    bool
    analyse(const dealii::SparseMatrix<double> &matrix);

    /// After analyse(): the memory the factorisation needs over the memory
    /// free, the worst of the machines' and processes' (the same on every
    /// process; 0 where nothing is known of the memory free) ...
    double
    memory_ratio() const;

    /// ... and the words for it ("MUMPS's factorisation of N unknowns needs
    /// about X GB on ..., more than the Y GB free there").
    const std::string &
    memory_need() const;

    /// Factorises @p matrix (the same on every process; analyse() first if
    /// its pattern was not); throws SolverFailure where MUMPS cannot
    /// (singular, or out of memory).
    void
    factorize(const dealii::SparseMatrix<double> &matrix);

    /// Solves with the last factorisation (@p transpose: with J^T).
    void
    solve(const dealii::Vector<double> &rhs, dealii::Vector<double> &solution, const bool transpose);

    bool
    has_factorisation() const;

  private:
    /// analyse()'s weighing of the memory.
    void
    weigh_memory();

    struct Petsc;
    std::unique_ptr<Petsc> petsc;
  };
} // namespace dieflow

#endif
