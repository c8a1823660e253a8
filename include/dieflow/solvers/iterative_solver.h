// Krylov solves (CG or GMRES) preconditioned by Trilinos ML's algebraic multigrid, for the augmented-Lagrangian form; MPI on first use.
#ifndef dieflow_iterative_solver_h
#define dieflow_iterative_solver_h

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace dieflow
{
  /// What one iterative solve did.
  struct IterativeSolveInfo
  {
    bool         converged  = false;
    unsigned int iterations = 0;
    /// The preconditioner's set-up, wall time.
    double setup_seconds = 0;
  };

  /// Initialises MPI if nobody has (Trilinos needs it even for one
  /// process; the program does not initialise it, see main.cc) and
  /// finalises it at exit.
  struct MpiOnFirstUse
  {
    MpiOnFirstUse();
  };

  /// Smoothed aggregation for a velocity block (Chebyshev smoothing, two
  /// sweeps, the components' @p constant_modes as near-null space, or
  /// none given to initialize_with_rigid_body_modes(); @p higher_order:
  /// Q2 and up), as ASPECT sets it up.
  dealii::TrilinosWrappers::PreconditionAMG::AdditionalData
  velocity_amg_data(const std::vector<std::vector<bool>> &constant_modes, const bool higher_order);

  /**
   * A Krylov method preconditioned by algebraic multigrid (Trilinos ML,
   * smoothed aggregation on the constant modes of each velocity component,
   * Chebyshev smoothing): CG for symmetric systems, GMRES when slipping
   * friction makes them non-symmetric.
   *
   * Only for the augmented-Lagrangian form of the flow problem (see
   * DieFlowProblem::update_multiplier()), whose penalty r is about 1e3
   * times the viscosity: with the full penalty lambda = 1e7 eta the
   * near-incompressible modes are invisible to AMG's smoothers and CG
   * stalls.
   *
   * On several MPI processes (processes.h) the system, replicated there,
   * is solved across them: each process takes its block of rows
   * (processes::owned_rows()) into a distributed Trilinos matrix, ML builds
   * its hierarchy across the processes, the Krylov method runs on
   * distributed vectors, and the solution is gathered to every process.
   */
  class IterativeSolver
  {
  public:
    /// The velocity components' constant modes (whole_mesh::constant_modes()).
    void
    set_constant_modes(const std::vector<std::vector<bool>> &modes);

    /**
     * Solves @p matrix x = @p rhs (from x = 0) until the residual is below
     * @p tolerance times |rhs|; reports failure (no exception) after
     * @p max_iterations iterations.
     */
    IterativeSolveInfo
    solve(const dealii::SparseMatrix<double> &matrix,
          const bool                          symmetric,
          const dealii::Vector<double> &      rhs,
          dealii::Vector<double> &            solution,
          const double                        tolerance,
          const unsigned int                  max_iterations);

  private:
    /// The Krylov solve across the MPI processes (see the class).
    IterativeSolveInfo
    solve_across_processes(const dealii::SparseMatrix<double> &matrix,
                           const bool                          symmetric,
                           const dealii::Vector<double> &      rhs,
                           dealii::Vector<double> &            solution,
                           const double                        target,
                           const unsigned int                  max_iterations);

    /// First member: the preconditioner needs MPI.
    MpiOnFirstUse mpi;
    /// Across processes: this process's rows of the matrix (ML keeps a pointer to it).
    dealii::TrilinosWrappers::SparseMatrix    distributed_matrix;
    std::vector<std::vector<bool>>            constant_modes;
    dealii::TrilinosWrappers::PreconditionAMG preconditioner;
  };
} // namespace dieflow

#endif
