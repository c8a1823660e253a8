#ifndef dieflow_saddle_point_solver_h
#define dieflow_saddle_point_solver_h

#include <dieflow/flow/mixed_penalty.h>
#include <dieflow/solvers/iterative_solver.h>
#include <dieflow/solvers/rigid_body_modes.h>

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace dieflow
{
  /**
   * The penalised update equation of the stable pair, solved through its
   * mixed form (MixedPenalty)
   *   [ A   B^T ] [du]   [b_v]
   *   [ B  -C   ] [dp] = [b_p],   C = M/lambda (block diagonal),
   * by GMRES, right-preconditioned with the block upper-triangular
   *   P = [ A^  B^T ]      A^: one V-cycle of algebraic multigrid on A
   *       [ 0  -S^  ],     (Trilinos ML, smoothed aggregation with the
   *                         rigid-body modes as near-null space),
   *   S^ = M (1/eta_K + 1/lambda_K) per cell,
   * the Schur complement B A^-1 B^T + C with A^-1 replaced by the inverse
   * viscosity: spectrally equivalent for the Stokes operator of an
   * inf-sup stable pair, uniformly in h and lambda (Elman, Silvester,
   * Wathen, Finite Elements and Fast Iterative Solvers, 2nd ed., ch. 4;
   * ASPECT's Stokes solver). Exact to invert: M is block diagonal.
   * Right preconditioning keeps the residual GMRES measures the true one.
   *
   * The pressure unknowns and equations are scaled by s_K = eta_K / h_K,
   * which gives both blocks the units of a nodal force, so that the
   * relative residual weighs the momentum and the divergence alike.
   */
  template <int dim>
  class SaddlePointSolver
  {
  public:
    /// What one solve did.
    struct Info
    {
      bool         converged  = false;
      unsigned int iterations = 0;
    };

    /// The velocity's rigid-body modes (rigid_body_modes()).
    void
    set_rigid_body_modes(std::vector<double> modes);

    /**
     * Solves from du = dp = 0 until the scaled residual is below
     * @p tolerance times the scaled right-hand side; reports failure (no
     * exception) after @p max_iterations.
     */
    Info
    solve(const dealii::SparseMatrix<double> &A,
          const MixedPenalty<dim> &           blocks,
          const dealii::Vector<double> &      rhs_velocity,
          const dealii::Vector<double> &      rhs_pressure,
          dealii::Vector<double> &            du,
          dealii::Vector<double> &            dp,
          const double                        tolerance,
          const unsigned int                  max_iterations);

  private:
    MpiOnFirstUse                             mpi;
    std::vector<double>                       modes;
    dealii::TrilinosWrappers::SparseMatrix    velocity_matrix;
    dealii::TrilinosWrappers::PreconditionAMG velocity_preconditioner;
  };
} // namespace dieflow

#endif
