// Operators of the replicated systems applied across the MPI processes: each computes its block of rows, the result gathered (a sparse matrix, an ML hierarchy).
#ifndef dieflow_row_blocks_h
#define dieflow_row_blocks_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/subscriptor.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace dieflow
{
  /**
   * y = M x for a sparse matrix M every process holds whole (processes.h):
   * on one process deal.II's own (threaded) product; on P processes each
   * multiplies its block of rows (processes::owned_rows()) of M as it is,
   * with x, which every process holds whole, and the blocks are gathered,
   * so every process holds the same bits of y at a P-th of the work. No
   * copy of M is made: an earlier version copied each block into a
   * distributed Trilinos matrix at every solve, whose graph set-up and
   * Epetra's product with its column import cost more than the product
   * saved (doc/parallel.md). The matrix interface PreconditionChebyshev
   * (which subscribes to it) and the Krylov solvers need (m(), el(),
   * vmult()). Only this process's rows of M are read: the system matrix
   * holds sums in no others (processes::RowSums).
   */
  class RowBlockMatrix : public dealii::Subscriptor
  {
  public:
    using size_type  = dealii::types::global_dof_index;
    using value_type = double;

    RowBlockMatrix() = default;
    explicit RowBlockMatrix(const dealii::SparseMatrix<double> &matrix);

    /// Refers to @p matrix (kept alive and unchanged by the caller while this is used).
    void
    reinit(const dealii::SparseMatrix<double> &matrix);

    /// The whole matrix.
    const dealii::SparseMatrix<double> &
    whole() const
    {
      return *matrix;
    }

    size_type
    m() const
    {
      return matrix->m();
    }
    size_type
    n() const
    {
      return matrix->n();
    }
    /// M_ij; on P > 1 the diagonal only (what PreconditionChebyshev
    /// reads), gathered by reinit() from each process's rows.
    double
    el(const size_type i, const size_type j) const
    {
      Assert(diagonal.size() == 0 || i == j, dealii::ExcMessage("on P > 1 only the diagonal"));
      return diagonal.size() > 0 ? diagonal[i] : matrix->el(i, j);
    }

    /// dst = M src.
    void
    vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const;
    /// dst += M src.
    void
    vmult_add(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const;
    /// dst = b - M x.
    void
    residual(dealii::Vector<double> &dst, const dealii::Vector<double> &x, const dealii::Vector<double> &b) const;

  private:
    /// dst's entries in this process's rows: M src (+ dst where @p add).
    void
    multiply_own_rows(dealii::Vector<double> &dst, const dealii::Vector<double> &src, const bool add) const;

    const dealii::SparseMatrix<double> *matrix = nullptr;
    /// On P > 1: this process's rows, [first_row, end_row); the matrix's
    /// values as one array (processes::matrix_values()); a square matrix's
    /// diagonal, whole.
    size_type              first_row = 0, end_row = 0;
    const double *         values    = nullptr;
    dealii::Vector<double> diagonal;
  };



  /**
   * One ML smoothed-aggregation V-cycle for a velocity block with the
   * rigid-body modes (and further near-null vectors) as near-null space
   * (initialize_with_rigid_body_modes()), built across the processes where
   * there are several: each process's block of rows (whole nodes: blocks of
   * @p pde_equations rows) in a distributed Trilinos matrix, ML's hierarchy
   * over all of them, the cycle's result gathered. With @p pde_equations
   * > 1 a process's block of rows is rounded to whole nodes: the matrix
   * must hold its sums in the rows owned_rows(m, pde_equations) gives
   * (RowSums::reinit() with that block), or in every row.
   */
  class RowBlockAMG
  {
  public:
    template <int dim>
    void
    initialize(const dealii::SparseMatrix<double> &                              matrix,
               const std::vector<double> &                                       modes,
               const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &data,
               const unsigned int                                                pde_equations      = 1,
               const unsigned int                                                prolongator_sweeps = 1);

    /// dst = one V-cycle applied to src.
    void
    vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const;

  private:
    dealii::IndexSet                          rows;
    unsigned int                              block = 1;
    dealii::TrilinosWrappers::SparseMatrix    copy;
    dealii::TrilinosWrappers::PreconditionAMG amg;
    std::vector<double>                       local_modes;
  };
} // namespace dieflow

#endif
