#ifndef dieflow_linear_solver_h
#define dieflow_linear_solver_h

#include <dieflow/parameters.h>

#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <stdexcept>

namespace dieflow
{
  /// A linear system that could not be solved (singular, or out of memory).
  class SolverFailure : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /**
   * Solves the linearised systems J du = -R. Direct: UMFPACK (SuiteSparse)
   * through deal.II, for any matrix, symmetric or not.
   */
  class LinearSolver
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    /// Factorises @p matrix; throws SolverFailure if it cannot.
    void
    factorize(const dealii::SparseMatrix<double> &matrix);

    /// Solves with the last factorisation.
    void
    solve(const dealii::Vector<double> &rhs, dealii::Vector<double> &solution);

    std::string method = "direct";

  private:
    dealii::SparseDirectUMFPACK direct;
  };
} // namespace dieflow

#endif
