// Globalisation by continuation in the friction: a mesh whose Newton iteration fails is solved again from frictionless, the friction raised in stages.
#include <dieflow/problem/problem.h>

#include <iomanip>

namespace dieflow
{
  template <int dim>
  NonlinearResult
  DieFlowProblem<dim>::continue_in_friction(const Vector<double> &start, NonlinearResult failed, CycleSummary &cycle)
  {
    // Coulomb friction with mu of order 1 and above on a coarse die: the
    // linearised coupling of the bound mu |F_n| to the normal force makes
    // whole walls trade contact and separation, stick and slip, from one
    // iteration to the next, and Newton's iteration from the frictionless
    // start need not find the solution (doc/stress.md: 38 of 240 extreme
    // decks, mu 1 to 5). Two globalisations, in turn, from the cycle's
    // start: (1) the bound frozen at each iteration's normal force (a
    // Tresca law that each iteration renews: Coulomb at its fixed point,
    // without the coupling that reverses the friction of a linearised
    // step); (2) with it, continuation: the frictionless problem first,
    // which converges where the friction made it fail, then the friction
    // raised in stages, each solved from the last converged one (its
    // solution is within Newton's reach of the next where the path is
    // continuous; where not, the stages shrink and the run fails as
    // before). Only the stage at the deck's friction is the deck's
    // problem: its solution is reported, judged by the same tests.
    const ContactParameters &deck = parameters.contact;
    if (failed.converged || failed.interrupted || contact.empty() || !deck.friction_continuation ||
        !deck.has_friction() || start.size() != velocity.size())
      return failed;
    const bool fixed_point_first = deck.law == FrictionLaw::Kind::coulomb && !deck.uses_penalty() &&
                                   deck.coulomb_coupling != ContactParameters::CoulombCoupling::fixed_point;
    log << "  Newton's method failed at the deck's friction: again from the start"
        << (fixed_point_first ? " with Coulomb's bound frozen at each iteration's normal force (fixed point), then" :
                                "")
        << " by continuation from the frictionless problem (Contact/Friction continuation)" << std::endl;
    unsigned int                 iterations = failed.iterations, linear_solves = failed.linear_solves;
    std::vector<IterationRecord> history    = failed.history;
    const auto                   account    = [&](const NonlinearResult &result) {
      iterations += result.iterations;
      linear_solves += result.linear_solves;
      history.insert(history.end(), result.history.begin(), result.history.end());
    };
    const auto from_start = [&]() {
      // The states setup() gives (every die node in contact and slipping),
      // revised from the start's reactions as in the first solve: the
      // failed iterate's are those of a problem that did not settle.
      velocity = start;
      contact.restart_states();
      states_from_previous_mesh = false;
    };
    // The stages: the deck's friction at the fixed point, then from 0.
    contact.freeze_bounds(deck.law == FrictionLaw::Kind::coulomb && !deck.uses_penalty());
    from_start();
    Vector<double>  good_velocity;
    ContactSet<dim> good_contact;
    double          good_scale = -1, scale = fixed_point_first ? 1 : 0, increment = 0.25;
    // A stage that fails halves the increment; below an eighth of the
    // deck's friction the continuation gives up. (On the extreme corpus
    // the decks it saved took whole steps of a half; finer steps, to
    // 1/64, saved none and cost 50 iterations each.)
    NonlinearResult result;
    for (unsigned int stage = 0; increment >= 1. / 8; ++stage)
      {
        contact.set_friction_scale(scale);
        contact.release_holds();
        make_constraints();
        constraints.distribute(velocity);
        assembler.update_dual(dof_handler, velocity, nullptr, 0);
        log << "  friction x " << std::setprecision(4) << scale << std::setprecision(6) << ":" << std::endl;
        result = parameters.nonlinear_solver.solve(*this, velocity, log);
        account(result);
        if (result.converged)
          cycle.friction_stages.push_back(scale);
        if (result.interrupted || (result.converged && scale == 1))
          break;
        if (result.converged)
          {
            good_velocity = velocity;
            good_contact  = contact;
            good_scale    = scale;
            increment     = std::min(2 * increment, 0.5);
          }
        else if (good_scale < 0 && stage == 0 && fixed_point_first)
          from_start(); // the fixed point at the deck's friction failed: from frictionless
        else if (good_scale < 0)
          break; // not even the frictionless problem
        else
          {
            velocity  = good_velocity;
            contact   = good_contact;
            increment = 0.5 * increment;
          }
        scale = std::max(0., std::min(1., good_scale + increment));
      }
    contact.set_friction_scale(1);
    contact.freeze_bounds(false);
    if (result.converged || result.interrupted)
      {
        if (result.converged)
          log << "  converged at the deck's friction" << std::endl;
        result.iterations    = iterations;
        result.linear_solves = linear_solves;
        result.history       = history;
        return result;
      }
    // What was tried, before the first solve's reason and advice.
    std::ostringstream tried;
    tried << "no convergence at the deck's friction ("
          << (fixed_point_first ? "nor with Coulomb's bound at its fixed point; " : "") << "continuation from the "
          << (good_scale < 0 ? std::string("frictionless problem failed too") :
                               "frictionless problem reached " + std::to_string(static_cast<int>(100 * good_scale)) +
                                 " % of it")
          << ", Contact/Friction continuation): ";
    failed.failure = tried.str() + failed.failure;
    failed.iterations    = iterations;
    failed.linear_solves = linear_solves;
    failed.history       = history;
    return failed;
  }

  template NonlinearResult DieFlowProblem<2>::continue_in_friction(const Vector<double> &, NonlinearResult, CycleSummary &);
  template NonlinearResult DieFlowProblem<3>::continue_in_friction(const Vector<double> &, NonlinearResult, CycleSummary &);
} // namespace dieflow
