// The nonlinear iteration: what it asks of a discrete system, Picard, Newton with a line search, their settings and their log.
#include <dieflow/base/interrupt.h>
#include <dieflow/solvers/linear_solver.h>
#include <dieflow/solvers/nonlinear_solver.h>

#include <cmath>
#include <iomanip>

namespace dieflow
{
  void
  NonlinearSolver::declare_parameters(ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Nonlinear solver");
    prm.declare_entry("Method",
                      "Newton",
                      Selection("Newton|Picard|Picard then Newton"),
                      "Newton: consistent tangent with a line search. Picard: "
                      "successive substitution, eta frozen at the last iterate "
                      "(the paper's scheme). Picard then Newton: the first "
                      "'Picard iterations' steps are Picard.");
    prm.declare_entry("Newton tangent",
                      "primal-dual",
                      Selection("primal-dual|standard"),
                      "standard: the consistent tangent of the residual. "
                      "primal-dual: the normalised strain rate D/epsdot becomes "
                      "an independent unknown at the quadrature points (Isaac, "
                      "Stadler, Ghattas 2015); same solution, far fewer "
                      "iterations for strongly shear-thinning laws (m << 1).");
    prm.declare_entry("Maximum iterations",
                      "50",
                      Integer(1),
                      "Iterations per cycle before the run stops with exit status 2.");
    prm.declare_entry("Residual tolerance",
                      "1e-8",
                      Double(0),
                      "Converged when ||R|| / ||reactions|| falls below this: the "
                      "out-of-balance force of the free dofs relative to the "
                      "forces the boundaries exert. Never below the round-off "
                      "floor that the penalty leaves, about 6e-17 x penalty "
                      "factor x sqrt(dofs), or eps || |J| |v| || (relative, the "
                      "bound of the computed residual) where that is larger, as "
                      "for strongly shear-thinning laws.");
    prm.declare_entry("Update tolerance",
                      "1e-8",
                      Double(0),
                      "Converged also when the relative Newton correction ||dv|| / "
                      "||v|| (before the line search shortens it) falls below "
                      "this (the paper's test uses 0.01 = 1%). The "
                      "penalty's cancellation (lambda div v, lambda ~ 1e7 eta) "
                      "puts a round-off floor of about 1e-16 x penalty factor x "
                      "sqrt(dofs) under the residual; the update test ends the "
                      "iteration when the residual cannot fall further. 0: off.");
    prm.declare_entry("Mass balance tolerance",
                      "1e-3",
                      Double(0),
                      "Where the penalty lets the metal lose more than this share "
                      "of the flow at a converged iterate, it turns augmented "
                      "(Uzawa steps to the incompressible answer; not with the "
                      "dual-weighted estimate); a converged cycle that still loses "
                      "more is NOT converged (exit status 2). The loss "
                      "is |sum of the boundary fluxes| / inflow, "
                      "or the sum over cells of |volume change| / inflow. The "
                      "forces carry a relative error of about the same "
                      "size (die2d N1: a loss of 8e-4 moves the ram force by "
                      "0.1 %, 7e-2 by 8 %), so the default matches the 0.1 % "
                      "the die forces are meant for; the default Penalty "
                      "factor (1e7) loses 1e-7 to 3e-5 on the test decks. Above "
                      "a tenth of it the run warns. 0: off.");
    prm.declare_entry("Picard iterations",
                      "2",
                      Integer(0),
                      "Picard steps before Newton for Method = Picard then Newton.");
    prm.declare_entry("Line search",
                      "true",
                      Bool(),
                      "Backtracking line search on ||R|| for Newton steps (Armijo).");
    prm.declare_entry("Maximum line search steps",
                      "8",
                      Integer(1, 50),
                      "Halvings of the Newton step before a Picard step is taken "
                      "instead.");
    prm.leave_subsection();
  }



  NonlinearSolver::Method
  NonlinearSolver::method_named(const std::string &name)
  {
    return name == "Picard" ? Method::picard : name == "Picard then Newton" ? Method::picard_then_newton : Method::newton;
  }



  NonlinearSolver::NewtonTangent
  NonlinearSolver::tangent_named(const std::string &name)
  {
    return name == "standard" ? NewtonTangent::standard : NewtonTangent::primal_dual;
  }



  void
  NonlinearSolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Nonlinear solver");
    method                    = method_named(prm.get("Method"));
    newton_tangent            = tangent_named(prm.get("Newton tangent"));
    maximum_iterations        = prm.get_integer("Maximum iterations");
    residual_tolerance        = prm.get_double("Residual tolerance");
    update_tolerance          = prm.get_double("Update tolerance");
    picard_iterations         = prm.get_integer("Picard iterations");
    mass_balance_tolerance    = prm.get_double("Mass balance tolerance");
    line_search               = prm.get_bool("Line search");
    maximum_line_search_steps = prm.get_integer("Maximum line search steps");
    require(residual_tolerance > 0 || update_tolerance > 0,
            "Nonlinear solver/Residual tolerance",
            "and Update tolerance are both zero: nothing could ever converge");
    prm.leave_subsection();
  }



  namespace
  {
    const char *
    name(const Linearization l)
    {
      return l == Linearization::newton ? "Newton" : "Picard";
    }

    void
    log_iteration(std::ostream &log, const IterationRecord &r, const bool first)
    {
      std::ostringstream line;
      line << "    it " << std::setw(2) << r.iteration << "  " << std::setw(6) << name(r.linearization)
           << "  |R|/|F| " << std::scientific << std::setprecision(3) << r.residual;
      if (!first)
        line << "  |dv|/|v| " << r.update << "  step " << std::fixed << std::setprecision(3) << r.step;
      if (r.state_changes.total() > 0)
        line << "  active set changes " << r.state_changes.normal << ", stick/slip changes "
             << r.state_changes.tangential;
      log << line.str() << std::endl;
    }
    /// Why the iteration stopped at its limit, and what to change: the
    /// contact if its states kept changing or cycled, else the limit.
    std::string
    not_converged_message(const std::vector<IterationRecord> &history,
                          const double                         residual,
                          const NonlinearSystem &              system,
                          const unsigned int                   maximum_iterations,
                          const std::vector<std::string> &     method_changes)
    {
      std::ostringstream why;
      why << "no convergence in " << history.back().iteration << " iterations (relative residual "
          << std::scientific << std::setprecision(2) << residual << ")";
      StateChanges recent;
      bool         still_changing = history.size() >= 3;
      for (unsigned int i = history.size() > 5 ? history.size() - 5 : 0; i < history.size(); ++i)
        {
          recent.normal += history[i].state_changes.normal;
          recent.tangential += history[i].state_changes.tangential;
        }
      for (unsigned int i = history.size() >= 2 ? history.size() - 2 : 0; i < history.size(); ++i)
        still_changing &= history[i].state_changes.total() > 0;
      const std::string contact_note = system.state_note();
      if (still_changing || !contact_note.empty())
        {
          why << "; the contact did not settle (" << recent.normal << " active-set and " << recent.tangential
              << " stick/slip changes in the last five iterations"
              << (contact_note.empty() ? "" : "; " + contact_note) << "): " << one_of_changes(system.contact_changes(), "");
        }
      else
        {
          std::vector<std::string> changes = method_changes;
          changes.insert(changes.begin(),
                         "raise Nonlinear solver/Maximum iterations (it is " + std::to_string(maximum_iterations) + ")");
          why << "; " << one_of_changes(changes, "");
        }
      return why.str();
    }
  } // namespace



  std::vector<std::string>
  NonlinearSolver::method_changes() const
  {
    std::vector<std::string> changes;
    if (newton_tangent == NewtonTangent::standard && method != Method::picard)
      changes.emplace_back("set Nonlinear solver/Newton tangent = primal-dual");
    if (method == Method::newton)
      changes.emplace_back("set Nonlinear solver/Method = Picard then Newton");
    else if (method == Method::picard_then_newton)
      changes.emplace_back("raise Nonlinear solver/Picard iterations (it is " + std::to_string(picard_iterations) + ")");
    return changes;
  }



  double
  NonlinearSolver::line_search_step(NonlinearSystem &             system,
                                    const dealii::Vector<double> &v,
                                    const dealii::Vector<double> &update,
                                    dealii::Vector<double> &      trial,
                                    const double                  residual) const
  {
    // g(a) = du . R(v + a du) is the slope of the dissipation potential along
    // du (for problems with a symmetric Jacobian, which minimise it); g(0) < 0
    // for a descent direction. A step is accepted when the potential has
    // surely decreased (g(a) <= |g(0)|/2, its linear model), or when the
    // residual norm has (Armijo), the only test for non-variational friction.
    // Otherwise the step shrinks to the secant root of g, within [a/10, a/2].
    const double           g0 = -(update * system.minus_residual());
    // Only a symmetric Jacobian is the Hessian of a potential whose slope g
    // measures descent; slipping friction is not variational.
    const bool variational = system.jacobian_is_symmetric();
    dealii::Vector<double> minus_residual(v.size());
    double                 step = 1;
    for (unsigned int i = 0; i < maximum_line_search_steps; ++i)
      {
        trial = v;
        trial.add(step, update);
        system.set_trial_step(step);
        const double r = system.residual(trial, minus_residual);
        const double g = -(update * minus_residual);
        if (std::isfinite(r) && std::isfinite(g) &&
            ((variational && g0 < 0 && g <= 0.5 * std::abs(g0)) || r <= (1. - 1e-4 * step) * residual))
          return step;
        const double secant = (g0 < 0 && g > g0) ? step * g0 / (g0 - g) : 0.5 * step;
        step                = std::min(0.5 * step, std::max(0.1 * step, secant));
      }
    return 0;
  }



  NonlinearResult
  NonlinearSolver::solve(NonlinearSystem &system, dealii::Vector<double> &v, std::ostream &log) const
  {
    NonlinearResult result;
    double          last_update = std::numeric_limits<double>::infinity();
    // The Newton correction before the line search shortened it: a step cut
    // to nearly nothing moves the solution little without converging it,
    // and the update test would report a stalled iteration converged
    // (tests/newton_stalled_line_search; doc/benchmarks.md).
    double          last_correction = std::numeric_limits<double>::infinity();
    double          last_step   = 1;
    dealii::Vector<double> update(v.size()), trial(v.size());

    for (unsigned int k = 0;; ++k)
      {
        const StateChanges changes = system.update_state(v);
        const bool         newton_now =
          (method == Method::newton) || (method == Method::picard_then_newton && k >= picard_iterations);
        Linearization linearization = newton_now ? Linearization::newton : Linearization::picard;

        const double residual = system.assemble_system(v, linearization);
        result.history.push_back({k, linearization, residual, last_update, last_step, changes});
        log_iteration(log, result.history.back(), k == 0);
        result.iterations = k;

        if (!std::isfinite(residual))
          {
            std::vector<std::string> changes = system.law_changes();
            for (const auto &change : method_changes())
              changes.push_back(change);
            result.failure = "the residual is not a number at iteration " + std::to_string(k) +
                             ": the iterate left the range of the viscosity law; " +
                             one_of_changes(changes, "check the Material entries (the law is evaluated outside its range)");
            return result;
          }
        // A linear problem (Newtonian, no contact) is solved by its first
        // Newton step up to round-off.
        const bool linear_done = (k > 0 && system.is_linear());
        const double tolerance = std::max(residual_tolerance, system.residual_floor());
        if (changes.total() == 0 &&
            (residual <= tolerance || (k > 0 && last_correction <= update_tolerance) || linear_done) &&
            system.constraints_settled())
          {
            result.converged = true;
            return result;
          }
        if (interrupt::requested())
          {
            result.interrupted = true;
            result.failure     = "stopped by " + interrupt::signal_name() + " at iteration " + std::to_string(k);
            return result;
          }
        if (k == maximum_iterations)
          {
            result.failure =
              not_converged_message(result.history, residual, system, maximum_iterations, method_changes());
            return result;
          }
        const auto solved = [&]() {
          try
            {
              system.solve(update, residual);
              ++result.linear_solves;
              return true;
            }
          catch (const ResourceFailure &failure)
            {
              result.failure = std::string(failure.what()) + " (at iteration " + std::to_string(k) + ")";
              return false;
            }
          catch (const SolverFailure &failure)
            {
              result.failure =
                std::string(failure.what()) + " at iteration " + std::to_string(k) +
                (linearization == Linearization::newton ?
                   "; the tangent lost its definiteness far from the solution: " +
                     one_of_changes(method_changes(), "set Nonlinear solver/Method = Picard") :
                   "; the Picard matrix is singular: most often the boundary conditions leave a rigid motion "
                   "free (every part traction free or slipping), see Boundary conditions in doc/user-guide.md");
              return false;
            }
        };
        if (!solved())
          return result;
        double step = 1;

        // Once the update is small, Newton is in its quadratic regime and a
        // line search only measures round-off.
        const bool small_update = update.l2_norm() <= 1e-6 * v.l2_norm();
        if (linearization == Linearization::newton && line_search && !small_update)
          {
            step = line_search_step(system, v, update, trial, residual);
            if (step == 0)
              {
                // The Newton direction does not descend from here (far from
                // the solution, or at a kink of the contact law): take a
                // Picard step, which the positive definite secant matrix
                // makes safe.
                log << "    line search found no descent: Picard step instead" << std::endl;
                linearization = Linearization::picard;
                system.assemble_system(v, linearization);
                if (!solved())
                  return result;
                step = 1;
              }
          }
        // A trust bound: no update changes a velocity by more than a hundred
        // times the larger of the largest prescribed speed and the current
        // largest speed (a 95% reduction makes the metal 20 times faster
        // than the ram); a longer Newton step is an overshoot.
        const double scale = system.velocity_scale();
        const double bound = 100 * std::max(scale, v.linfty_norm());
        if (scale > 0 && step * update.linfty_norm() > bound)
          {
            step = bound / update.linfty_norm();
            log << "    update limited to a hundred times the larger of the prescribed and the current "
                   "largest speed (step "
                << std::fixed << std::setprecision(3) << step << ")" << std::defaultfloat << std::endl;
          }
        system.accept_step(v, update, step, linearization);
        v.add(step, update);
        last_update = step * update.l2_norm() / std::max(v.l2_norm(), 1e-300);
        last_correction = update.l2_norm() / std::max(v.l2_norm(), 1e-300);
        last_step   = step;
        if (!std::isfinite(last_update) || (scale > 0 && v.linfty_norm() > 1e4 * scale))
          {
            // Where the contact states still changed as it diverged, the
            // friction's coupling drove it: on the extreme corpus a bound
            // that does not follow the normal force (Tresca) converged four
            // of five such decks, Picard's steps first one (doc/stress.md).
            std::vector<std::string> changes = method_changes();
            const auto &             history = result.history;
            if (history.size() >= 2 && history.back().state_changes.total() > 0 &&
                history[history.size() - 2].state_changes.total() > 0)
              for (const auto &change : system.contact_changes())
                changes.push_back(change);
            std::ostringstream why;
            why << "the iteration diverges at iteration " << k + 1
                << ": the velocity exceeds ten thousand times the largest prescribed speed; "
                << one_of_changes(changes,
                              "check that the boundary conditions hold the metal in place (a free part "
                              "facing a prescribed velocity lets it run away)");
            result.failure    = why.str();
            result.iterations = k + 1;
            return result;
          }
      }
  }
} // namespace dieflow
