// Globalisation by continuation: a mesh whose Newton iteration fails is solved again, in the friction from frictionless, then in the law's rate sensitivity.
#include <dieflow/postprocess/contact_output.h>
#include <dieflow/postprocess/cycle_guards.h>
#include <dieflow/problem/problem.h>

#include <cmath>
#include <functional>
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
    // decks, mu 1 to 5). Globalisations, in turn, from the cycle's start:
    // (1) the bound frozen at each iteration's normal force (a Tresca law
    // that each iteration renews: Coulomb at its fixed point, without the
    // coupling that reverses the friction of a linearised step); (2) with
    // it, continuation: the frictionless problem first, which converges
    // where the friction made it fail, then the friction raised in stages,
    // each solved from the last converged one (its solution is within
    // Newton's reach of the next where the path is continuous; where not,
    // the stages shrink and the path gives up); (3) for a nearly
    // rigid-plastic Norton-Hoff law (m below 0.5), continuation in m at the
    // deck's friction: the law at m = 0.5, whose viscosity varies over
    // decades less, then m lowered in stages to the deck's (geometrically:
    // eta ~ rate^(m - 1), each stage the same ratio in m). Only the stage at
    // the deck's friction and law is the deck's problem: its solution is
    // reported, judged by the same tests.
    const ContactParameters &deck          = parameters.contact;
    const Material &         material      = parameters.material;
    const bool               friction_path = !contact.empty() && deck.friction_continuation && deck.has_friction();
    const bool               law_path      = material.continues_in_rate_sensitivity();
    if (failed.interrupted || start.size() != velocity.size() || (!friction_path && !law_path))
      return failed;
    // A converged state the contact guard refuses (directions held in
    // contact to end a cycle of the states that pull on the die) is a
    // failure too; where the paths do not mend it, it stands, for the guard.
    const auto refused = [&]() {
      if (contact.empty())
        return false;
      CycleSummary probe;
      summarise_contact(contact, contact.results(velocity), velocity.linfty_norm(), probe);
      return !guard_contact(probe, dim, deck, {}).failure.empty();
    };
    Vector<double>  refused_velocity;
    ContactSet<dim> refused_contact;
    if (failed.converged)
      {
        if (!refused())
          return failed;
        refused_velocity = velocity;
        refused_contact  = contact;
        log << "  the converged state breaks the contact conditions:";
      }
    else
      log << "  Newton's method failed:";
    // Coulomb's bound can be frozen (the penalty's friction has no bound to
    // freeze); the frozen stage is worth a solve unless the deck froze it.
    const bool coulomb_bound     = deck.law == FrictionLaw::Kind::coulomb && !deck.uses_penalty();
    const bool fixed_point_first = friction_path && coulomb_bound &&
                                   deck.coulomb_coupling != ContactParameters::CoulombCoupling::fixed_point;
    std::ostringstream m_start_text;
    m_start_text << Material::continuation_rate_sensitivity;
    const std::string m_from = m_start_text.str(); // the m the continuation in m starts from, as printed
    log << " again from the start"
        << (fixed_point_first ? " with Coulomb's bound frozen at each iteration's normal force (fixed point), then" : "")
        << (friction_path ? " by continuation from the frictionless problem (Contact/Friction continuation)" : "")
        << (friction_path && law_path ? ", then" : "")
        << (law_path ? " by continuation in the rate sensitivity from m = " + m_from +
                         " (Material/Rate sensitivity continuation)" :
                       std::string())
        << std::endl;
    unsigned int                 iterations = failed.iterations, linear_solves = failed.linear_solves;
    std::vector<IterationRecord> history    = failed.history;
    constexpr unsigned int       fixed_point_budget = 8;
    const auto                   solve = [&](const std::string &stage, const bool final, const unsigned int budget = 1) {
      contact.release_holds();
      make_constraints();
      constraints.distribute(velocity);
      assembler.update_dual(dof_handler, velocity, nullptr, 0);
      auto solver = parameters.nonlinear_solver;
      solver.maximum_iterations *= budget;
      log << "  " << stage;
      if (budget > 1)
        log << ", at most " << solver.maximum_iterations << " iterations";
      log << ":" << std::endl;
      NonlinearResult result = solver.solve(*this, velocity, log);
      if (result.converged && final && refused())
        {
          // At the deck's problem only the guard's verdict counts.
          log << "  its converged state breaks the contact conditions" << std::endl;
          result.converged = false;
        }
      iterations += result.iterations;
      linear_solves += result.linear_solves;
      history.insert(history.end(), result.history.begin(), result.history.end());
      return result;
    };
    const auto from_start = [&]() {
      // The states setup() gives (every die node in contact and slipping),
      // revised from the start's reactions as in the first solve: the
      // failed iterate's are those of a problem that did not settle.
      velocity = start;
      incompressibility.restart_multiplier(start);
      contact.restart_states();
      states_from_previous_mesh = false;
    };
    // One path: stage t = 0 from the start, then t raised towards 1 (the
    // deck's problem) from the last converged stage. A stage that fails
    // halves the increment; below an eighth the path gives up. (On the
    // extreme corpus the decks the friction saved took whole steps of a
    // half; finer steps, to 1/64, saved none and cost 50 iterations each;
    // in m, steps to 1/32 saved none of five decks that stop near m = 0.2.)
    // set_stage(t) poses stage t and names it (the number the log and
    // summary.json show); @p reached: the last t that converged, -1 none.
    const auto march = [&](const std::function<double(double)> &set_stage,
                           const std::string &                  name,
                           std::vector<double> &                record,
                           double &                             reached) {
      from_start();
      Vector<double>                            good_velocity;
      ContactSet<dim>                           good_contact;
      typename Incompressibility<dim>::Iterate good_pressure;
      NonlinearResult result;
      double          t = 0;
      reached           = -1;
      for (double increment = 0.25; increment >= 1. / 8;)
        {
          const double value = set_stage(t);
          std::ostringstream stage;
          stage << name << ' ' << std::setprecision(4) << value;
          result = solve(stage.str(), t == 1);
          if (result.converged)
            record.push_back(value);
          if (result.interrupted || (result.converged && t == 1))
            break;
          if (result.converged)
            {
              good_velocity = velocity;
              good_contact  = contact;
              good_pressure = incompressibility.iterate();
              reached       = t;
              increment     = std::min(2 * increment, 0.5);
            }
          else if (reached < 0)
            break; // not even the easiest stage
          else
            {
              velocity  = good_velocity;
              contact   = good_contact;
              incompressibility.restore(good_pressure);
              increment = 0.5 * increment;
            }
          t = std::min(1., reached + increment);
        }
      return result;
    };

    NonlinearResult result = failed;
    result.converged       = false;
    double friction_reached = -1, law_reached = -1;
    contact.freeze_bounds(coulomb_bound);
    if (fixed_point_first)
      {
        from_start();
        // The frozen bound's fixed point converges linearly, at a rate
        // that tends to 1 as mu grows (1/48: 0.93 per iteration once its
        // states settle, some 250 iterations from 1e-2 to the tolerance):
        // it has eight times Newton's iterations. (Measured on the extreme
        // corpus, each deck alone: 228 of 240 converge with Newton's 50,
        // 232 with 200, 233 with 400; a deck that still fails takes up to
        // 2.2 times as long, the corpus as a whole no longer: a stage that
        // diverges or cycles stops before its limit.)
        result = solve("friction x 1 (Coulomb's bound at its fixed point)", true, fixed_point_budget);
        if (result.converged)
          cycle.friction_stages.push_back(1);
      }
    if (friction_path && !result.converged && !result.interrupted)
      result = march(
        [&](const double t) {
          contact.set_friction_scale(t);
          return t;
        },
        "friction x",
        cycle.friction_stages,
        friction_reached);
    contact.set_friction_scale(1);
    // Each law's stage has the penalty and contact scales of its own
    // viscosity at the start (a penalty factor times the deck law's mean
    // viscosity is, at m = 0.5, up to a hundred times that factor: beyond
    // double precision at 1e10); the deck's stage has the deck's.
    const double m_deck = material.rate_sensitivity, m_start = Material::continuation_rate_sensitivity;
    const auto   m_at     = [&](const double t) { return m_start * std::pow(m_deck / m_start, t); };
    const double eta_deck = incompressibility.viscosity_scale();
    Material     staged   = material;
    const auto   scale_to = [&](const double eta, const Material *law) {
      incompressibility.set_viscosity_scale(eta, law);
      contact.set_scales(eta, material.penalty_factor * eta, prescribed_speed);
    };
    if (law_path && !result.converged && !result.interrupted)
      result = march(
        [&](const double t) {
          if (t == 1)
            {
              assembler.set_material(material); // the deck's law, to every bit
              scale_to(eta_deck, nullptr);
              return m_deck;
            }
          staged.set_rate_sensitivity(m_at(t));
          assembler.set_material(staged);
          scale_to(assembler.mean_viscosity(dof_handler, start), &staged);
          return staged.rate_sensitivity;
        },
        "rate sensitivity m",
        cycle.rate_sensitivity_stages,
        law_reached);
    assembler.set_material(material);
    if (law_path)
      scale_to(eta_deck, nullptr);
    contact.freeze_bounds(false);
    const auto with_totals = [&](NonlinearResult r) {
      r.iterations    = iterations;
      r.linear_solves = linear_solves;
      r.history       = history;
      return r;
    };
    if (result.converged || result.interrupted)
      {
        if (result.converged)
          log << "  converged at the deck's friction and law" << std::endl;
        return with_totals(result);
      }
    if (failed.converged)
      {
        // The paths failed: the first converged state, for the guard.
        velocity = refused_velocity;
        contact  = refused_contact;
        make_constraints();
        return with_totals(failed);
      }
    // What was tried, before the first solve's reason and advice.
    std::ostringstream tried;
    const auto         percent = [](const double t) { return std::to_string(static_cast<int>(100 * t)) + " %"; };
    tried << "no convergence at the deck's " << (friction_path ? "friction" : "law") << " (";
    if (friction_path)
      tried << (fixed_point_first ? "nor with Coulomb's bound at its fixed point; " : "") << "continuation from the "
            << (friction_reached < 0 ? std::string("frictionless problem failed too") :
                                       "frictionless problem reached " + percent(friction_reached) + " of it")
            << (law_path ? "; " : "");
    if (law_path)
      {
        std::ostringstream m;
        m << std::setprecision(3) << m_at(std::max(law_reached, 0.));
        tried << "continuation in the rate sensitivity from m = " << m_from << ' '
              << (law_reached < 0 ? "failed at m = " + m_from : "reached m = " + m.str());
      }
    tried << ", " << (friction_path ? "Contact/Friction continuation" : "")
          << (friction_path && law_path ? " and " : "") << (law_path ? "Material/Rate sensitivity continuation" : "")
          << "): ";
    failed.failure = tried.str() + failed.failure;
    return with_totals(failed);
  }

  template NonlinearResult DieFlowProblem<2>::continue_in_friction(const Vector<double> &, NonlinearResult, CycleSummary &);
  template NonlinearResult DieFlowProblem<3>::continue_in_friction(const Vector<double> &, NonlinearResult, CycleSummary &);
} // namespace dieflow
