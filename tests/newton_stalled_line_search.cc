// Newton's update test (|dv|/|v| <= Update tolerance) measures the Newton
// correction, not the step the line search took of it: a correction cut
// to almost nothing moves the solution little without converging it. (A 3D
// bar, in a trial of another contact linearisation, stalled at a relative
// residual of 3e-3 with line-search steps of 1e-3 to 1e-4 and was reported
// converged.) A scripted one-unknown system whose residual falls along the
// correction only within 1e-4 of the iterate (the line search halves the
// unit correction 14 times): the run must stop NOT converged at its
// iteration limit. The same system with a correction of 1e-9 of the
// solution, taken whole, converges by the update test.
#include <dieflow/solvers/nonlinear_solver.h>

#include "report.h"
#include "scripted_system.h"

#include <cmath>
#include <sstream>

using namespace dieflow;

namespace
{
  class StalledSystem : public OneUnknownSystem
  {
  public:
    explicit StalledSystem(const double correction)
      : correction(correction)
    {}

    double
    assemble_system(const dealii::Vector<double> &v, const Linearization) override
    {
      anchor = v[0];
      r[0]   = 1;
      return 1e-3; // never below the residual tolerance
    }
    // The slope g(a) = du . R(v + a du) is negative (descent) only within
    // 1e-4 of the iterate.
    double
    residual(const dealii::Vector<double> &trial, dealii::Vector<double> &minus_residual) override
    {
      minus_residual.reinit(1);
      minus_residual[0] = std::abs(trial[0] - anchor) <= 1e-4 ? 0. : -1.;
      return 1e-3;
    }
    void
    solve(dealii::Vector<double> &update, const double) override
    {
      update.reinit(1);
      update[0] = correction;
    }

  private:
    const double correction;
    double       anchor = 0;
  };

  NonlinearResult
  run(const double correction, std::string &log_text)
  {
    NonlinearSolver solver;
    solver.method                    = NonlinearSolver::Method::newton;
    solver.maximum_iterations        = 10;
    solver.maximum_line_search_steps = 20;
    solver.residual_tolerance        = 1e-8;
    solver.update_tolerance          = 1e-4;
    StalledSystem          system(correction);
    dealii::Vector<double> v(1);
    v[0] = 1;
    std::ostringstream log;
    const NonlinearResult result = solver.solve(system, v, log);
    log_text                     = log.str();
    return result;
  }
} // namespace

int
main()
{
  std::string           log;
  const NonlinearResult stalled = run(1, log);
  report("unit correction cut to a step of 2^-14 each iteration: not converged, stopped at the limit of 10",
         !stalled.converged && stalled.iterations == 10 && std::abs(stalled.history.back().step - std::pow(0.5, 14)) < 1e-15);
  const NonlinearResult small = run(1e-9, log);
  report("correction 1e-9 of the solution, taken whole: converged by the update test at iteration 1",
         small.converged && small.iterations == 1);
}
