// The penalty term of the Q2-P1disc pair in mixed form: the blocks B and B^T, the cell masses M_K, and lambda, eta and h per cell.
#ifndef dieflow_mixed_penalty_h
#define dieflow_mixed_penalty_h

#include <dieflow/base/processes.h>
#include <dieflow/solvers/row_blocks.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace dieflow
{
  /**
   * The penalty term of the stable pair (velocity degree 2, P1disc
   * pressure) in mixed form. Per cell K the penalty is
   *   lambda (P div v)(P div w) = lambda (B_K v)^T M_K^-1 (B_K w)
   * (PressureProjection); with the pressure coefficients p = lambda M^-1 B v
   * as unknowns the penalised update equation J du = b becomes
   *   [ A   B^T      ] [du]   [b_v]
   *   [ B  -M/lambda ] [dp] = [b_p],
   * whose elimination of dp gives back J = A + lambda B^T M^-1 B. This holds
   * the blocks the flow assembly produces instead of the penalty's matrix
   * term: B (pressure rows, the velocity columns condensed with the update
   * constraints), B^T with the rows of slipping friction nodes transformed
   * as the velocity rows are and condensed, the cell masses M_K, and per
   * cell lambda_K, the mean viscosity eta_K and the size h_K (for the
   * Schur complement's preconditioner, see SaddlePointSolver).
   *
   * The pressure unknowns are numbered cell after cell,
   * active_cell_index() * n_modes + m, as PressureProjection::project_all().
   */
  template <int dim>
  class MixedPenalty
  {
  public:
    /// Sizes the blocks for @p dof_handler's mesh and @p modes_per_cell
    /// pressure coefficients per cell (PressureProjection::n_modes_for());
    /// @p hanging: the hanging-node constraints (the pattern's).
    void
    reinit(const dealii::DoFHandler<dim> &          dof_handler,
           const dealii::AffineConstraints<double> &hanging,
           const unsigned int                       modes_per_cell);

    /// Zeroes the matrices and the cell data before an assembly.
    void
    clear_values();

    /// After an assembly in which each MPI process set its own cells: the
    /// sums, the whole blocks on every process (processes::sum()) but B^T,
    /// summed into and held in each process's own rows (processes::RowSums).
    void
    sum_over_processes();

    unsigned int
    n_pressure() const
    {
      return n_cells * n_modes;
    }

    /// dst_K = factor_K M_K src_K on every cell.
    void
    mass_vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src, const dealii::Vector<double> &factor) const;

    /// dst_K = factor_K M_K^-1 src_K on every cell.
    void
    inverse_mass_vmult(dealii::Vector<double> &      dst,
                       const dealii::Vector<double> &src,
                       const dealii::Vector<double> &factor) const;

    /// The cell masses M_K or their inverses.
    enum class CellBlock
    {
      mass,
      inverse_mass
    };
    /// dst_K = factor_K M_K src_K (or M_K^-1) on this process's cells:
    /// @p dst and @p src in @p pressure's layout
    /// (RowLayout::reinit_groups(part, n_modes)), @p factor per cell.
    void
    cell_vmult(const CellBlock which, DistributedVector &dst, const DistributedVector &src,
               const dealii::Vector<double> &factor, const RowLayout &pressure) const;

    /// |B^T| lambda |M^-1| |B| |v| (entrywise absolute values): a bound of
    /// the penalty term's share of |J| |v|, for the round-off bound.
    dealii::Vector<double>
    penalty_magnitude(const dealii::Vector<double> &v) const;

    /// Stores the cell's M_K, M_K^-1, lambda_K, eta_K, h_K (called by the assembly's copier).
    void
    set_cell(const unsigned int                cell,
             const dealii::FullMatrix<double> &mass,
             const dealii::FullMatrix<double> &inverse_mass,
             const double                      penalty,
             const double                      viscosity,
             const double                      size);

    unsigned int n_modes = 0;
    unsigned int n_cells = 0;
    dealii::SparsityPattern      divergence_pattern, gradient_pattern;
    /// B (n_pressure x n_dofs).
    dealii::SparseMatrix<double> divergence;
    /// B^T, rows transformed and condensed (n_dofs x n_pressure); on P > 1
    /// each process's own rows (its pattern RowSums's).
    dealii::SparseMatrix<double> gradient;
    /// lambda_K, eta_K, h_K.
    dealii::Vector<double> penalty, viscosity, size;
    /// The process that assembles each cell (its part; 0 on one process):
    /// the holder of its pressure modes in the iterative solver.
    std::vector<unsigned int> part;

  private:
    std::vector<double> masses, inverse_masses;
    processes::RowSums  gradient_sums;
  };
} // namespace dieflow

#endif
