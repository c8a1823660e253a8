#ifndef dieflow_linear_solver_h
#define dieflow_linear_solver_h

#include <dieflow/parameters.h>

#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

namespace dieflow
{
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

    /// Factorises @p matrix; throws std::runtime_error if it is singular.
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
