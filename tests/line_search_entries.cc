// Nonlinear solver/Line search and Maximum line search steps, read from a
// deck, on the scalar residual R(v) = atan(v) from v = 3, where Newton's
// full step overshoots (v - atan(v)(1 + v^2) = -9.4904786, then 124, and on
// to overflow: the classic divergence of Newton on atan beyond |v| = 1.39).
// Line search on (default, 8 steps): the first step is cut (the secant root
// of the slope, 0.46 of the correction) and the iteration converges without
// a Picard step. Line search = false: the full step, |R| = atan(9.4904786)
// = 1.4658 at iteration 1, and the iteration diverges. Maximum line search
// steps = 1: the one trial (the full step) is refused, a Picard step is
// taken instead, and the secant matrix atan(v)/v makes that step land on
// the root v = 0: converged at iteration 1.
#include <dieflow/solvers/nonlinear_solver.h>

#include "report.h"
#include "scripted_system.h"

#include <cmath>
#include <sstream>

using namespace dieflow;

namespace
{
  class ArcTangent : public OneUnknownSystem
  {
  public:
    double
    assemble_system(const dealii::Vector<double> &v, const Linearization linearization) override
    {
      // Newton: R'(v) = 1/(1 + v^2); Picard: the secant R(v)/v.
      jacobian = linearization == Linearization::newton ? 1. / (1. + v[0] * v[0]) :
                 v[0] != 0                              ? std::atan(v[0]) / v[0] :
                                                          1.;
      return residual(v, r);
    }
    double
    residual(const dealii::Vector<double> &trial, dealii::Vector<double> &minus_residual) override
    {
      minus_residual.reinit(1);
      minus_residual[0] = -std::atan(trial[0]);
      return std::abs(minus_residual[0]);
    }
    void
    solve(dealii::Vector<double> &update, const double) override
    {
      update.reinit(1);
      update[0] = r[0] / jacobian;
    }

  private:
    double jacobian = 1;
  };

  struct Run
  {
    NonlinearResult result;
    double          v;
    std::string     log;
  };

  Run
  run(const std::string &entries)
  {
    ParameterHandler prm;
    NonlinearSolver::declare_parameters(prm);
    prm.parse_input_from_string("subsection Nonlinear solver\nset Residual tolerance = 1e-10\n" + entries + "end\n");
    NonlinearSolver solver;
    solver.parse_parameters(prm);
    ArcTangent             system;
    dealii::Vector<double> v(1);
    v[0] = 3;
    std::ostringstream log;
    Run                run;
    run.result = solver.solve(system, v, log);
    run.v      = v[0];
    run.log    = log.str();
    return run;
  }

  bool
  picard_substituted(const Run &run)
  {
    return run.log.find("Picard step instead") != std::string::npos;
  }
} // namespace

int
main()
{
  const Run searched = run("");
  report("Line search (default): converged to v = 0 without a Picard step",
         searched.result.converged && std::abs(searched.v) < 1e-10 && !picard_substituted(searched));
  report("its first step cut to the secant root of the slope (0.46 of the correction)",
         searched.result.history.size() > 1 && std::abs(searched.result.history[1].step - 0.46) < 0.01);

  const Run full = run("set Line search = false\n");
  report("Line search = false: the full step, |R| = atan(9.4904786) at iteration 1",
         full.result.history.size() > 1 && full.result.history[1].step == 1 &&
           std::abs(full.result.history[1].residual - std::atan(10 * std::atan(3.) - 3)) < 1e-12);
  report("and the iteration diverges (not converged)", !full.result.converged && !full.result.failure.empty());

  const Run one = run("set Maximum line search steps = 1\n");
  report("Maximum line search steps = 1: the full step refused, a Picard step instead",
         picard_substituted(one) && one.log.find("Picard step instead") == one.log.rfind("Picard step instead"));
  report("which lands on the root: converged at iteration 1", one.result.converged && one.result.iterations == 1 &&
                                                                 std::abs(one.v) < 1e-14);
}
