// The mixed form's update equation by block-preconditioned GMRES: a multigrid cycle for the velocity block, a scaled mass for the Schur complement.
#ifndef dieflow_saddle_point_solver_h
#define dieflow_saddle_point_solver_h

#include <dieflow/solvers/mixed_penalty.h>
#include <dieflow/solvers/iterative_solver.h>
#include <dieflow/solvers/p_multigrid.h>
#include <dieflow/solvers/rigid_body_modes.h>
#include <dieflow/solvers/row_blocks.h>

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <vector>

namespace dieflow
{
  /**
   * The penalised update equation of the stable pair, solved through its
   * mixed form (MixedPenalty)
   *   [ A   B^T ] [du]   [b_v]
   *   [ B  -C   ] [dp] = [b_p],   C = M/lambda (block diagonal),
   * by GMRES, right-preconditioned with the block upper-triangular
   *   P = [ A^  B^T ]      A^: one p-multigrid cycle (PMultigrid: Q2
   *       [ 0  -S^  ],     smoothing, AMG on the Q1 Galerkin operator), or
   *                         one V-cycle of algebraic multigrid on A itself
   *                         (Trilinos ML, smoothed aggregation with the
   *                         rigid-body modes as near-null space),
   *   S^ = M (1/eta_K + 1/lambda_K) per cell,
   * the Schur complement B A^-1 B^T + C with A^-1 replaced by the inverse
   * viscosity: spectrally equivalent for the Stokes operator of an
   * inf-sup stable pair, uniformly in h and lambda (Elman, Silvester,
   * Wathen, Finite Elements and Fast Iterative Solvers, 2nd ed., ch. 4;
   * ASPECT's Stokes solver). Exact to invert: M is block diagonal.
   * Right preconditioning keeps the residual GMRES measures the true one.
   * GMRES keeps 32 vectors (a restart every 30 iterations: its vectors
   * are most of the solver's memory); a solve not done after 100 goes on
   * with 100 (a restart every 98) where they fit in half the free memory,
   * as short restarts stagnate where the velocity cycle is weak (strong viscosity
   * contrasts).
   *
   * A^ is either one cycle (a fixed linear map: GMRES), or, with an inner
   * tolerance, an inner Krylov solve of A with that cycle as its
   * preconditioner (CG where A is symmetric, GMRES where slipping friction
   * makes it non-symmetric) to that relative residual: a preconditioner
   * that changes with its argument, hence flexible GMRES outside (ASPECT's
   * "expensive" Stokes solver). The inner solve makes the outer count that
   * of an exact A (the Schur approximation's alone, doc/benchmarks.md) at
   * the price of the inner iterations.
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
      /// With an inner solve: its iterations, summed over the outer ones.
      unsigned int inner_iterations = 0;
      /// The scaled residual at the end over the scaled right-hand side.
      double residual_reduction = 1;
      /// The velocity block's preconditioner's set-up, wall time.
      double setup_seconds = 0;
    };

    /**
     * 0: A^ is one V-cycle. Otherwise the relative residual to which each
     * application of A^ solves A (inner CG or GMRES, at most
     * max_inner_iterations, accepting what it reached then).
     */
    double       inner_tolerance      = 0;
    unsigned int max_inner_iterations = 200;

    /// A new mesh (called before its first solve): the layouts of the
    /// vectors and the exchanges of the products, which depend on the
    /// mesh alone, are agreed anew at the next solve, not at every one.
    void
    reinit();

    /// The velocity's rigid-body modes (rigid_body_modes()).
    void
    set_rigid_body_modes(std::vector<double> modes);

    /// A^ by p-multigrid (PMultigrid) on this mesh instead of AMG on A.
    void
    use_p_multigrid(const dealii::DoFHandler<dim> &dof_handler);

    /**
     * Solves from du = dp = 0 until the scaled residual is below
     * @p tolerance times the scaled right-hand side; reports failure (no
     * exception) after @p max_iterations. @p symmetric: A = A^T (the inner
     * solve may use CG). @p constraints: those whose rows A has condensed,
     * and @p flow: the velocity A is the tangent at, null for a Newtonian
     * material (p-multigrid's near-null space, PMultigrid::initialize()).
     */
    Info
    solve(const dealii::SparseMatrix<double> &       A,
          const dealii::AffineConstraints<double> &  constraints,
          const dealii::Vector<double> *             flow,
          const MixedPenalty<dim> &           blocks,
          const dealii::Vector<double> &      rhs_velocity,
          const dealii::Vector<double> &      rhs_pressure,
          dealii::Vector<double> &            du,
          dealii::Vector<double> &            dp,
          const bool                          symmetric,
          const double                        tolerance,
          const unsigned int                  max_iterations);

  private:
    MpiOnFirstUse                             mpi;
    std::vector<double>                       modes;
    /// How the vectors are divided among the MPI processes: the velocity as
    /// A's rows, the pressure modes by their cells' parts (each process
    /// holds its part of every Krylov vector).
    RowLayout                                 velocity_layout, pressure_layout;
    /// A, B^T and B, their products divided among the MPI processes (before
    /// p_multigrid, which refers to A's).
    RowBlockMatrix                            velocity_block, gradient_block, divergence_block;
    /// Whether the layouts and the products' exchanges are those of this
    /// mesh (reinit() clears it).
    bool                                      mesh_agreed = false;
    RowBlockAMG                               velocity_preconditioner;
    std::unique_ptr<PMultigrid<dim>>          p_multigrid;
  };
} // namespace dieflow

#endif
