// The iterative solvers' operators across the MPI processes: vectors divided among them (RowLayout), products by each process's rows with the border's entries exchanged (RowBlockMatrix), an ML hierarchy.
#ifndef dieflow_row_blocks_h
#define dieflow_row_blocks_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/partitioner.h>
#include <deal.II/base/subscriptor.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <memory>
#include <vector>

namespace dieflow
{
  /// A vector divided among the MPI processes, each holding its entries (RowLayout).
  using DistributedVector = dealii::LinearAlgebra::distributed::Vector<double>;

  /**
   * How the n entries of a vector space (in the program's numbering, the
   * "whole" index) are divided among the MPI processes, and so a
   * DistributedVector of it: either blocks of consecutive rows
   * (processes::owned_rows(n, block): the velocity, numbered by the cells'
   * parts; p-multigrid's Q1 space), or groups of consecutive entries each
   * held by the process of its cell (the mixed form's pressure modes,
   * numbered cell after cell, a cell's part not a block of them). A
   * process's entries are its part of the distributed vector, in the order
   * of their whole indices; the parts follow each other in the order of the
   * ranks, so for groups the distributed vector's index of an entry is not
   * its whole index. With one process, every entry in its place.
   */
  class RowLayout
  {
  public:
    using size_type = dealii::types::global_dof_index;

    /// Collective. Process r holds processes::owned_rows(n, block).
    void
    reinit_rows(const size_type n, const unsigned int block = 1);

    /// Group g (the entries [g group_size, (g + 1) group_size)) is held by
    /// process owner_of_group[g] (the same on every process; a process
    /// may hold none).
    void
    reinit_groups(const std::vector<unsigned int> &owner_of_group, const unsigned int group_size);

    size_type
    size() const
    {
      return n;
    }
    /// This process's entries.
    size_type
    n_local() const
    {
      return local_size;
    }
    /// The whole index of this process's k-th entry.
    size_type
    whole_index(const size_type k) const
    {
      return !grouped ? first + k : size_type(own_groups[k / group]) * group + k % group;
    }
    /// Rows: this process's entries are [first_whole(), first_whole() + n_local()).
    bool
    contiguous() const
    {
      return !grouped;
    }
    size_type
    first_whole() const
    {
      return first;
    }
    /// The process that holds entry @p i and where in its part.
    unsigned int
    owner(const size_type i) const;
    size_type
    local_index(const size_type i) const;
    /// Groups: the groups this process holds (its cells), in order.
    const std::vector<unsigned int> &
    groups() const
    {
      return own_groups;
    }
    unsigned int
    group_size() const
    {
      return group;
    }

    /// @p v sized to this layout (zero).
    void
    reinit(DistributedVector &v) const;
    /// @p v's entries from the vector @p whole that every process holds.
    void
    extract(const dealii::Vector<double> &whole, DistributedVector &v) const;
    /// Collective. @p whole (sized n) made of every process's entries of @p v:
    /// the same bits on every process.
    void
    gather(const DistributedVector &v, dealii::Vector<double> &whole) const;

  private:
    size_type    n = 0, local_size = 0, first = 0;
    /// Groups: their size; rows: the block their ends are multiples of.
    unsigned int group = 1, row_block = 1;
    bool         grouped = false;
    /// Rows: where each process's block starts (P + 1 entries, the last n).
    std::vector<size_type> starts;
    /// Groups: each group's process and its place among that process's groups.
    std::vector<unsigned int> owner_of_group, place_of_group;
    /// Groups: this process's.
    std::vector<unsigned int> own_groups;
    /// Groups: each process's first entry in the distributed vector.
    std::vector<size_type> offsets;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> partitioner;
  };



  /**
   * The entries of a DistributedVector (layout @p columns) that a matrix's
   * rows held by this process (layout @p rows) read and other processes
   * hold: the ghost layer of the parts' border. reinit() agrees once per
   * pattern which entries each process sends to which; import() brings
   * them, with this process's own, into a vector indexed by the whole
   * numbering (one message each way per neighbouring process).
   */
  class ColumnImport
  {
  public:
    /// Collective.
    void
    reinit(const dealii::SparsityPattern &pattern, const RowLayout &rows, const RowLayout &columns);

    /// Collective. whole[j] = src's entry j for every column j this
    /// process's rows read (the other entries of whole are left as they are).
    void
    import(const DistributedVector &src, dealii::Vector<double> &whole) const;

  private:
    const RowLayout *columns = nullptr;
    /// For each process: the local indices of what this one sends it, and
    /// the whole indices of what it receives from it.
    std::vector<std::vector<unsigned int>>                    send_local;
    std::vector<std::vector<dealii::types::global_dof_index>> receive_whole;
    mutable std::vector<std::vector<double>>                  send_buffers, receive_buffers;
  };



  /**
   * y = M x for a sparse matrix M and DistributedVectors x (layout
   * @p columns) and y (layout @p rows): each process computes its entries
   * of y from its rows of M as they are (among its threads), on P > 1
   * after ColumnImport has brought the entries of x those rows read. No copy of M is made: an earlier version copied
   * each block into a distributed Trilinos matrix at every solve, whose
   * graph set-up and Epetra's product with its column import cost more
   * than the product saved (doc/parallel.md). Only this process's rows of
   * M are read: the system matrix holds sums in no others
   * (processes::RowSums). The matrix interface PreconditionChebyshev
   * (which subscribes to it, given its diagonal) and the Krylov solvers need.
   */
  class RowBlockMatrix : public dealii::Subscriptor
  {
  public:
    using size_type  = dealii::types::global_dof_index;
    using value_type = double;

    /// Collective. Refers to @p matrix, @p rows and @p columns (kept alive
    /// and unchanged by the caller while this is used), and agrees the
    /// exchanges its products need, which depend on the pattern alone.
    void
    reinit(const dealii::SparseMatrix<double> &matrix, const RowLayout &rows, const RowLayout &columns);

    /// Refers to @p matrix, of the pattern reinit() was given (new values,
    /// as in each Newton iteration on one mesh): the exchanges are kept.
    /// Not collective.
    void
    reinit_values(const dealii::SparseMatrix<double> &matrix);

    /// Whether @p matrix may be given to reinit_values(): its pattern the
    /// object reinit() was given, of the same size and number of entries
    /// (a pattern made anew in place for another mesh seldom keeps both).
    /// Not collective, and a pattern that holds other processes' rows only
    /// at the border (RowSums) may change on some processes alone: a
    /// caller that agrees anew on its verdict reduces it over the processes.
    bool
    has_pattern_of(const dealii::SparseMatrix<double> &matrix) const;

    /// The matrix (on P > 1 its sums in this process's rows alone).
    const dealii::SparseMatrix<double> &
    whole() const
    {
      return *matrix;
    }

    /// How the rows (and a product's entries) are divided.
    const RowLayout &
    row_layout() const
    {
      return *rows;
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

    /// M_ij, for PreconditionChebyshev's serial fallback, which reads every
    /// row's diagonal: never taken here, as its diagonal is given
    /// (inverse_diagonal()); on P > 1 the other processes' rows are NaN.
    double
    el(const size_type i, const size_type j) const
    {
      return matrix->el(i, j);
    }

    /// dst = M src.
    void
    vmult(DistributedVector &dst, const DistributedVector &src) const;
    /// dst += M src.
    void
    vmult_add(DistributedVector &dst, const DistributedVector &src) const;
    /// dst = b - M x.
    void
    residual(DistributedVector &dst, const DistributedVector &x, const DistributedVector &b) const;
    /// A square matrix's diagonal inverted, in this process's rows.
    void
    inverse_diagonal(DistributedVector &d) const;

  private:
    enum class Product
    {
      set,
      add,
      residual
    };
    /// dst's entries: M src, dst + M src, or b - M src.
    void
    multiply(DistributedVector &dst, const DistributedVector &src, const DistributedVector *b, const Product what) const;

    const dealii::SparseMatrix<double> *matrix  = nullptr;
    const RowLayout *                   rows    = nullptr;
    const double *                      values  = nullptr;
    /// The pattern reinit() agreed the exchanges for: rows, columns, entries.
    std::array<std::size_t, 3>          agreed_shape{};
    ColumnImport                        import;
    /// The entries of src this process's rows read, at their whole indices.
    mutable dealii::Vector<double> whole_src;
  };



  /**
   * One ML smoothed-aggregation V-cycle for a velocity block with the
   * rigid-body modes (and further near-null vectors) as near-null space
   * (initialize_with_rigid_body_modes()), built across the processes where
   * there are several: each process's block of rows (whole nodes: blocks of
   * @p pde_equations rows) in a distributed Trilinos matrix, ML's hierarchy
   * over all of them, the vectors in the layout of those rows
   * (RowLayout::reinit_rows(m, pde_equations)). With @p pde_equations
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
    vmult(DistributedVector &dst, const DistributedVector &src) const;

  private:
    dealii::IndexSet                          rows;
    dealii::TrilinosWrappers::SparseMatrix    copy;
    dealii::TrilinosWrappers::PreconditionAMG amg;
    std::vector<double>                       local_modes;
  };
} // namespace dieflow

#endif
