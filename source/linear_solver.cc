#include <dieflow/linear_solver.h>

#include <stdexcept>

namespace dieflow
{
  void
  LinearSolver::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    prm.declare_entry("Method",
                      "direct",
                      dealii::Patterns::Selection("direct"),
                      "direct: sparse LU factorisation (UMFPACK), robust for any "
                      "penalty and any friction state.");
    prm.leave_subsection();
  }



  void
  LinearSolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    method = prm.get("Method");
    prm.leave_subsection();
  }



  void
  LinearSolver::factorize(const dealii::SparseMatrix<double> &matrix)
  {
    try
      {
        direct.initialize(matrix);
      }
    catch (const std::exception &)
      {
        // UMFPACK's own text is a page of generic advice; what matters here
        // is that the Jacobian is singular (or memory ran out).
        throw SolverFailure("the sparse direct solver (UMFPACK) could not factorise the "
                            "linearised system: it is singular, or memory ran out");
      }
  }



  void
  LinearSolver::solve(const dealii::Vector<double> &rhs, dealii::Vector<double> &solution)
  {
    solution = rhs;
    direct.solve(solution);
  }
} // namespace dieflow
