// Operators of the replicated systems applied across the MPI processes: each computes its block of rows, the result gathered (a sparse matrix, an ML hierarchy).
#include <dieflow/base/processes.h>
#include <dieflow/solvers/rigid_body_modes.h>
#include <dieflow/solvers/row_blocks.h>

#include <deal.II/base/parallel.h>

#include <Teuchos_ParameterList.hpp>

#include <algorithm>

namespace dieflow
{
  namespace
  {
    /// The first index of @p set, a contiguous range (0 where it is empty:
    /// a process may own no rows of a small block).
    std::size_t
    first_index(const dealii::IndexSet &set)
    {
      return set.n_elements() > 0 ? set.nth_index_in_set(0) : 0;
    }
  } // namespace



  RowBlockMatrix::RowBlockMatrix(const dealii::SparseMatrix<double> &matrix)
  {
    reinit(matrix);
  }



  void
  RowBlockMatrix::reinit(const dealii::SparseMatrix<double> &m)
  {
    matrix = &m;
    diagonal.reinit(0);
    if (processes::n() == 1)
      return;
    const dealii::IndexSet rows = processes::owned_rows(m.m());
    first_row                   = first_index(rows);
    end_row                     = first_row + rows.n_elements();
    values                      = processes::matrix_values(m);
    if (m.m() == m.n())
      {
        diagonal.reinit(m.m());
        for (size_type i = first_row; i < end_row; ++i)
          diagonal[i] = m.el(i, i);
        processes::gather(diagonal);
      }
  }



  void
  RowBlockMatrix::multiply_own_rows(dealii::Vector<double> &dst, const dealii::Vector<double> &src, const bool add) const
  {
    if (first_row == end_row)
      return;
    const dealii::SparsityPattern &pattern = matrix->get_sparsity_pattern();
    const double *const            x       = src.begin();
    double *const                  y       = dst.begin();
    // The rows in chunks among this process's threads, as deal.II's own
    // product divides them.
    dealii::parallel::apply_to_subranges(
      first_row,
      end_row,
      [&](const size_type begin, const size_type end) {
        for (size_type i = begin; i < end; ++i)
          {
            const unsigned int length = pattern.row_length(i);
            double             sum    = add ? y[i] : 0.;
            if (length > 0)
              {
                const double *const row = values + pattern.begin(i)->global_index();
                for (unsigned int k = 0; k < length; ++k)
                  sum += row[k] * x[pattern.column_number(i, k)];
              }
            y[i] = sum;
          }
      },
      1000);
  }



  void
  RowBlockMatrix::vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const
  {
    if (processes::n() == 1)
      {
        matrix->vmult(dst, src);
        return;
      }
    if (dst.size() != matrix->m())
      dst.reinit(matrix->m());
    multiply_own_rows(dst, src, false);
    processes::gather(dst);
  }



  void
  RowBlockMatrix::vmult_add(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const
  {
    if (processes::n() == 1)
      {
        matrix->vmult_add(dst, src);
        return;
      }
    AssertDimension(dst.size(), matrix->m());
    multiply_own_rows(dst, src, true);
    processes::gather(dst);
  }



  void
  RowBlockMatrix::residual(dealii::Vector<double> &      dst,
                           const dealii::Vector<double> &x,
                           const dealii::Vector<double> &b) const
  {
    if (processes::n() == 1)
      {
        matrix->residual(dst, x, b);
        return;
      }
    vmult(dst, x);
    dst.sadd(-1., 1., b);
  }



  template <int dim>
  void
  RowBlockAMG::initialize(const dealii::SparseMatrix<double> &                              matrix,
                          const std::vector<double> &                                       modes,
                          const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &data,
                          const unsigned int                                                pde_equations,
                          const unsigned int                                                prolongator_sweeps)
  {
    if (processes::n() == 1)
      {
        initialize_with_rigid_body_modes<dim>(amg, copy, matrix, modes, data, pde_equations, prolongator_sweeps);
        return;
      }
    // Whole nodes per process: ML aggregates the pde_equations rows of a node together.
    block = pde_equations;
    rows  = processes::owned_rows(matrix.m(), block);
    // A pattern made afresh: on one it knows, Trilinos's copy would keep
    // the old value where the new one is zero.
    amg.clear();
    copy.clear();
    copy.reinit(rows, rows, matrix, processes::communicator());
    Teuchos::ParameterList              parameters;
    std::unique_ptr<Epetra_MultiVector> constant_modes;
    data.set_parameters(parameters, constant_modes, copy);
    // ML reads this process's rows of each near-null vector, one after the
    // other, while initialize() builds the hierarchy.
    const std::size_t n = matrix.m(), n_local = rows.n_elements(), n_modes = modes.size() / n;
    const std::size_t first = first_index(rows);
    // (at least one entry: ML stops a process whose null space pointer is null)
    local_modes.resize(std::max<std::size_t>(1, n_modes * n_local));
    for (std::size_t k = 0; k < n_modes; ++k)
      for (std::size_t i = 0; i < n_local; ++i)
        local_modes[k * n_local + i] = modes[k * n + first + i];
    parameters.set("null space: type", "pre-computed");
    parameters.set("null space: dimension", static_cast<int>(n_modes));
    parameters.set("null space: vectors", local_modes.data());
    if (pde_equations > 1)
      parameters.set("PDE equations", static_cast<int>(pde_equations));
    parameters.set("aggregation: smoothing sweeps", static_cast<int>(prolongator_sweeps));
    amg.initialize(copy, parameters);
  }



  void
  RowBlockAMG::vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const
  {
    if (processes::n() == 1)
      {
        amg.vmult(dst, src);
        return;
      }
    dealii::TrilinosWrappers::MPI::Vector x(rows, processes::communicator()), y(x);
    std::copy(src.begin() + first_index(rows), src.begin() + first_index(rows) + rows.n_elements(), x.begin());
    amg.vmult(y, x);
    if (dst.size() != src.size())
      dst.reinit(src.size());
    std::copy(y.begin(), y.end(), dst.begin() + first_index(rows));
    processes::gather(dst, block);
  }

  template void
  RowBlockAMG::initialize<2>(const dealii::SparseMatrix<double> &,
                             const std::vector<double> &,
                             const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &,
                             const unsigned int,
                             const unsigned int);
  template void
  RowBlockAMG::initialize<3>(const dealii::SparseMatrix<double> &,
                             const std::vector<double> &,
                             const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &,
                             const unsigned int,
                             const unsigned int);
} // namespace dieflow
