// A nonlinear system of one unknown whose residual, Jacobian and updates a
// test scripts, to drive NonlinearSolver into one behaviour at a time
// (a stall, a failure of each kind). It holds -R in r; it is nonlinear
// (so Newton iterates), has no state that follows the iterate, and never
// changes contact states unless the test overrides update_state().
#ifndef dieflow_tests_scripted_system_h
#define dieflow_tests_scripted_system_h

#include <dieflow/solvers/nonlinear_solver.h>

#include <deal.II/lac/vector.h>

class OneUnknownSystem : public dieflow::NonlinearSystem
{
public:
  dieflow::StateChanges
  update_state(dealii::Vector<double> &) override
  {
    return {};
  }
  const dealii::Vector<double> &
  minus_residual() const override
  {
    return r;
  }
  bool
  is_linear() const override
  {
    return false;
  }
  void
  accept_step(const dealii::Vector<double> &,
              const dealii::Vector<double> &,
              const double,
              const dieflow::Linearization) override
  {}

protected:
  dealii::Vector<double> r = dealii::Vector<double>(1);
};

#endif
