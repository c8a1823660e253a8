// A two-level p-multigrid cycle for the Q2 velocity block: Chebyshev smoothing on Q2, one AMG V-cycle on the Q1 Galerkin operator.
#ifndef dieflow_p_multigrid_h
#define dieflow_p_multigrid_h

#include <dieflow/base/processes.h>
#include <dieflow/solvers/rigid_body_modes.h>
#include <dieflow/solvers/row_blocks.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/diagonal_matrix.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <vector>

namespace dieflow
{
  /**
   * Into @p entries (n_c x n_c), the entries of P^T A P (P: @p embedding)
   * that this process's block of fine rows (processes::owned_rows()) adds,
   * whatever the constraints: for a fine row i, the columns of P's row i
   * times those of (A P)'s row i. @p A must hold those rows whole.
   */
  void
  galerkin_entries(const dealii::SparsityPattern &A, const dealii::SparsityPattern &embedding,
                   dealii::DynamicSparsityPattern &entries);

  /**
   * @p coarse_matrix = P^T D A D P (P: @p embedding, D = diag(@p free)),
   * into @p coarse_matrix's pattern, which must hold the entries that each
   * process's fine rows add (galerkin_entries(); on one process deal.II's
   * product's pattern, SparseMatrix::mmult then Tmmult, holds them): each
   * MPI process sums the terms of its block of fine rows
   * (processes::owned_rows()), and @p sums sums the partial products into
   * each process's own coarse rows (RowSums::sum()).
   */
  void
  galerkin_product(const dealii::SparseMatrix<double> &A,
                   const dealii::SparseMatrix<double> &embedding,
                   const dealii::Vector<double> &      free,
                   const processes::RowSums &          sums,
                   dealii::SparseMatrix<double> &      coarse_matrix);



  /**
   * A two-level p-multigrid cycle for the Q2 velocity block A (the
   * condensed Newton matrix of the mixed form):
   *   x  = S b                       (Chebyshev smoothing on Q2, from 0)
   *   x += P A_1^ P^T (b - A x)      (coarse correction on Q1)
   *   x += S (b - A x)               (the same smoothing again),
   * with P the embedding of the Q1 velocity space of the same mesh into the
   * Q2 one (exact: Q1 is a subspace of Q2), its rows of constrained Q2
   * dofs zero (the condensed system's unknowns are the unconstrained
   * dofs), A_1 = P^T A P the Galerkin operator (which carries the contact,
   * slip and friction rows of A as they are), and A_1^ one ML
   * smoothed-aggregation V-cycle on it (four Chebyshev sweeps per level)
   * with the rigid-body modes (and the flow, see initialize()) as
   * near-null space. Algebraic
   * multigrid copes with the short stencil of a Q1 operator better than
   * with Q2's (Heys, Manteuffel, McCormick, Olson, J. Comput. Phys. 204
   * (2005) 520; the "hybrid multigrid" of Kronbichler and Wall, SIAM J.
   * Sci. Comput. 40 (2018) A3423).
   */
  template <int dim>
  class PMultigrid
  {
  public:
    /// The Q1 space and the embedding P, for a mesh (call when it changes).
    void
    reinit(const dealii::DoFHandler<dim> &dof_handler);

    /**
     * The hierarchy for @p A, whose constrained rows are those of
     * @p constraints. @p flow (optional): the velocity A is the Newton
     * tangent at, added to the near-null space. For a law whose stress is
     * homogeneous of degree m in the strain rate (Norton-Hoff, sigma = 2 K
     * (sqrt(3) epsdot_eq)^(m-1) epsdot, eq. (3) of the paper), Euler's
     * theorem gives A v = m A_S v at that velocity v (A_S the secant,
     * Picard, matrix; the standard tangent everywhere, the primal-dual one
     * once its dual strain rate S has settled on D/r, as near the
     * solution): along the flow the tangent's stiffness is m times that
     * across it, and smoothed aggregation coarsens well only what its
     * near-null space spans (with the flow a strongly shear-thinning law
     * takes fewer Krylov iterations per solve; doc/benchmarks.md). Not for
     * a Newtonian law (m = 1: no softer direction, only more memory).
     */
    void
    initialize(const RowBlockMatrix &                    A,
               const dealii::AffineConstraints<double> &constraints,
               const dealii::Vector<double> *           flow = nullptr);

    /// dst = the cycle applied to src (both in the layout of A's rows).
    void
    vmult(DistributedVector &dst, const DistributedVector &src) const;

  private:
    dealii::FESystem<dim>                     coarse_fe{dealii::FE_Q<dim>(1), dim};
    /// On P > 1 numbered part by part, as the flow's dofs
    /// (processes::number_dofs_by_part()).
    dealii::DoFHandler<dim>                   coarse_dofs;
    std::vector<double>                       coarse_modes;
    /// The Q2 dof at the vertex of each Q1 dof (P's entry 1 in its column).
    std::vector<dealii::types::global_dof_index> vertex_dof;
    dealii::SparsityPattern                   embedding_pattern;
    dealii::SparseMatrix<double>              embedding;
    /// P^T on P > 1 processes, to restrict by rows as P prolongs: only the
    /// coarse rows this process owns, those it computes (one process
    /// restricts with P, Tvmult).
    dealii::SparsityPattern                   restriction_pattern;
    dealii::SparseMatrix<double>              restriction;
    /// Kept per mesh; the matrices A P and A_1 hold values only during
    /// initialize(). On P > 1 processes A_1's pattern is each process's
    /// own coarse rows whole and its fine rows' entries in the others'
    /// (coarse_sums), and A P is never formed.
    dealii::SparsityPattern                   product_pattern, coarse_pattern;
    processes::RowSums                        coarse_sums;
    dealii::SparseMatrix<double>              product, coarse_matrix;
    bool                                      patterns_built = false;
    /// The Q1 space divided as ML's rows (whole nodes); P and P^T across the processes.
    RowLayout                                 coarse_layout;
    RowBlockMatrix                            prolongation_rows, restriction_rows;
    /// 1 on A's unconstrained rows, 0 on the others (this process's rows).
    DistributedVector                         free;
    /// A (the saddle-point solver's), its products divided among the MPI processes.
    const RowBlockMatrix *                    matrix = nullptr;
    dealii::PreconditionChebyshev<RowBlockMatrix, DistributedVector, dealii::DiagonalMatrix<DistributedVector>> smoother;
    RowBlockAMG                               coarse_amg;
    mutable DistributedVector                 residual, coarse_residual, coarse_correction;
  };
} // namespace dieflow

#endif
