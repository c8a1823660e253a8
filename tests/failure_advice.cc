// A failure message advises only changes the deck has not made already
// (issue: "use Newton tangent = primal-dual" was printed to runs that used
// it). Each way the nonlinear iteration can fail is driven by a scripted
// system, for every Method x Newton tangent, and the message must (a) name
// no setting in use, (b) offer at least one change (or, where every setting
// that could help is in use, point at the boundary conditions), (c) say why
// it stopped.
// The contact, viscosity-law and mass-balance advice are checked for each
// friction law, each law kind, and each penalty regime; a frictionless deck
// is not told to change its friction law, and a Tresca deck with Coulomb's
// coefficients but no bound is warned that it runs frictionless.
#include <dieflow/contact/contact_parameters.h>
#include <dieflow/flow/material.h>
#include <dieflow/postprocess/mass_balance.h>
#include <dieflow/solvers/linear_solver.h>
#include <dieflow/solvers/nonlinear_solver.h>

#include "report.h"
#include "scripted_system.h"

#include <algorithm>
#include <cmath>
#include <limits>

using namespace dieflow;

namespace
{
  enum class Failure
  {
    not_a_number,
    iteration_limit,
    contact_cycling,
    singular_matrix,
    divergence
  };

  const char *
  name(const Failure f)
  {
    switch (f)
      {
        case Failure::not_a_number:
          return "residual not a number";
        case Failure::iteration_limit:
          return "iteration limit";
        case Failure::contact_cycling:
          return "contact cycling";
        case Failure::singular_matrix:
          return "singular linear system";
        default:
          return "divergence";
      }
  }

  /// A one-unknown system scripted to fail in one way.
  class ScriptedSystem : public OneUnknownSystem
  {
  public:
    explicit ScriptedSystem(const Failure failure)
      : failure(failure)
    {}

    StateChanges
    update_state(dealii::Vector<double> &) override
    {
      return failure == Failure::contact_cycling ? StateChanges{2, 1} : StateChanges{};
    }
    double
    assemble_system(const dealii::Vector<double> &, const Linearization) override
    {
      r[0] = 1;
      return failure == Failure::not_a_number ? std::numeric_limits<double>::quiet_NaN() : 1.;
    }
    double
    residual(const dealii::Vector<double> &, dealii::Vector<double> &minus_residual) override
    {
      minus_residual = r;
      return 1;
    }
    double
    velocity_scale() const override
    {
      return 1;
    }
    void
    solve(dealii::Vector<double> &update, const double) override
    {
      if (failure == Failure::singular_matrix)
        throw SolverFailure("the linear solver failed (singular matrix)");
      // Divergence: a step far beyond the speeds (the trust bound shortens
      // it to 100 x the largest speed, which grows each iteration); else a
      // step along the residual that never reduces it.
      update.reinit(1);
      update[0] = failure == Failure::divergence ? 1e12 : 1e-3;
    }
    std::vector<std::string>
    contact_changes() const override
    {
      return {"refine the mesh at the die", "set Contact/Friction law = regularised Coulomb"};
    }
    std::vector<std::string>
    law_changes() const override
    {
      return {"raise Material/Minimum strain rate (it is 1e-4)"};
    }

  private:
    const Failure failure;
  };

  std::string
  message(const Failure failure, const std::string &method, const std::string &tangent)
  {
    NonlinearSolver solver;
    solver.method             = NonlinearSolver::method_named(method);
    solver.newton_tangent     = NonlinearSolver::tangent_named(tangent);
    solver.maximum_iterations = 6;
    solver.residual_tolerance = 1e-8;
    solver.update_tolerance   = 0;
    ScriptedSystem         system(failure);
    dealii::Vector<double> v(1);
    v[0] = 1;
    std::ostringstream    log;
    const NonlinearResult result = solver.solve(system, v, log);
    return result.converged ? "" : result.failure;
  }

  /// Every value that @p text sets @p key to ("Method = " -> "Picard then
  /// Newton"): up to the next comma, semicolon, parenthesis or the end.
  std::vector<std::string>
  advised_values(const std::string &text, const std::string &key)
  {
    std::vector<std::string> values;
    for (auto at = text.find(key); at != std::string::npos; at = text.find(key, at + 1))
      {
        const auto start = at + key.size();
        const auto end   = text.find_first_of(",;)", start);
        values.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
      }
    return values;
  }

  bool
  contains(const std::string &text, const std::string &part)
  {
    return text.find(part) != std::string::npos;
  }
} // namespace



int
main()
{
  const std::vector<std::string> methods  = {"Newton", "Picard", "Picard then Newton"};
  const std::vector<std::string> tangents = {"primal-dual", "standard"};
  const std::map<Failure, std::string> why = {{Failure::not_a_number, "not a number"},
                                              {Failure::iteration_limit, "no convergence in 6 iterations"},
                                              {Failure::contact_cycling, "the contact did not settle"},
                                              {Failure::singular_matrix, "singular"},
                                              {Failure::divergence, "the iteration diverges"}};
  for (const auto &[failure, reason] : why)
    {
      bool never_in_use = true, some_change = true, says_why = true;
      for (const auto &method : methods)
        for (const auto &tangent : tangents)
          {
            const std::string text = message(failure, method, tangent);
            const auto methods_advised  = advised_values(text, "Method = ");
            const auto tangents_advised = advised_values(text, "Newton tangent = ");
            never_in_use &= std::find(methods_advised.begin(), methods_advised.end(), method) == methods_advised.end() &&
                            std::find(tangents_advised.begin(), tangents_advised.end(), tangent) == tangents_advised.end();
            some_change &= contains(text, "set ") || contains(text, "raise ") || contains(text, "refine ") ||
                           contains(text, "check ") || contains(text, "Boundary conditions in doc/user-guide.md");
            says_why &= contains(text, reason);
          }
      report(std::string(name(failure)) + ": the advice never names a setting in use (6 settings)", never_in_use);
      report(std::string(name(failure)) + ": a change is always offered, and why it stopped", some_change && says_why);
      std::cout << "  Newton, standard tangent: " << message(failure, "Newton", "standard") << '\n'
                << "  Picard then Newton, primal-dual: " << message(failure, "Picard then Newton", "primal-dual")
                << std::endl;
    }

  // The contact advice for each friction law: never the law in use.
  ContactParameters contact;
  contact.friction_coefficient[3] = 0.2;
  contact.tresca_factor[3]        = 0.5;
  for (const auto &[law, deck_name] : std::vector<std::pair<FrictionLaw::Kind, std::string>>{
         {FrictionLaw::Kind::coulomb, "Coulomb"},
         {FrictionLaw::Kind::tresca, "Tresca"},
         {FrictionLaw::Kind::regularised_coulomb, "regularised Coulomb"}})
    {
      contact.law     = law;
      bool suggests_own_law = false;
      std::string joined;
      for (const auto &change : contact.settling_changes())
        {
          suggests_own_law |= contains(change, "Friction law = " + deck_name + " ") ||
                              change == "set Contact/Friction law = " + deck_name;
          joined += (joined.empty() ? "" : "; ") + change;
        }
      report("friction law " + deck_name + ": the contact advice does not suggest it", !suggests_own_law);
      std::cout << "  " << joined << std::endl;
    }
  contact.law = FrictionLaw::Kind::coulomb;
  contact.friction_coefficient[3] = 0;
  bool lowers_zero = false;
  for (const auto &change : contact.settling_changes())
    lowers_zero |= contains(change, "lower Contact/Friction coefficients");
  report("mu = 0: no advice to lower the friction coefficient", !lowers_zero);
  bool changes_law_zero = false;
  for (const auto &change : contact.settling_changes())
    changes_law_zero |= contains(change, "Friction law");
  report("mu = 0: no advice to change a friction law that transmits nothing", !changes_law_zero);

  // A Tresca deck with Coulomb's coefficients and no bound runs frictionless:
  // it is told so; with a bound (factors and k), or under Coulomb, it is not.
  contact.die_ids                 = {3};
  contact.friction_coefficient[3] = 0.5;
  contact.tresca_factor.clear();
  contact.shear_flow_stress = 0;
  contact.law               = FrictionLaw::Kind::tresca;
  const std::string unused  = contact.unused_friction_warning();
  report("Tresca law, Coulomb coefficients, no bound: warned, the entries named",
         contains(unused, "Contact/Tresca friction factors") && contains(unused, "frictionless"));
  contact.tresca_factor[3]  = 0.5;
  report("Tresca law, factors but k = 0: still warned", !contact.unused_friction_warning().empty());
  contact.shear_flow_stress = 100;
  report("Tresca law with a bound: no warning", contact.unused_friction_warning().empty());
  contact.law = FrictionLaw::Kind::coulomb;
  report("Coulomb law: no warning", contact.unused_friction_warning().empty());

  // The viscosity-law advice: a minimum strain rate only where the law has one.
  ParameterHandler prm;
  Material::declare_parameters(prm);
  Material material;
  material.parse_parameters(prm);
  report("Newtonian law: no minimum-strain-rate advice", material.range_changes().empty());
  prm.enter_subsection("Material");
  prm.set("Law", "Norton-Hoff");
  prm.leave_subsection();
  material.parse_parameters(prm);
  report("Norton-Hoff: raise the minimum strain rate, its value named",
         material.range_changes().size() == 1 && contains(material.range_changes()[0], "(it is 1e-4)"));

  // The mass-balance advice: the penalty factor to set (the loss scales as
  // 1/factor: 7.4e-2 at 1e3 -> 7.4e-6 at 1e7, a hundredth of 1e-3), the
  // limit of double precision, and the augmented Lagrangian's tolerance.
  MassBalance balance;
  balance.loss = balance.volume_change = 7.4e-2;
  const std::string low = mass_balance_advice(balance, 1e-3, 1e3, MassHold::penalty, 1e-7);
  std::cout << "  " << low << std::endl;
  report("penalty 1e3 losing 7.4e-2: raise the factor to 1e7", contains(low, "(it is 1e3) to 1e7"));
  const std::string high = mass_balance_advice(balance, 1e-3, 1e10, MassHold::penalty, 1e-7);
  report("penalty 1e10: not raised further, the iterative method instead",
         !contains(high, "raise") && contains(high, "Linear solver/Method = iterative"));
  const std::string capped = mass_balance_advice(balance, 1e-3, 1e7, MassHold::penalty, 1e-7);
  report("a factor beyond 1e10 needed: 1e10 advised, as the limit", contains(capped, "to 1e10, the limit"));
  const std::string augmented = mass_balance_advice(balance, 1e-3, 1e3, MassHold::uzawa, 1e-7);
  report("augmented Lagrangian: its divergence tolerance, not the penalty factor",
         contains(augmented, "Divergence tolerance (it is 1e-7)") && !contains(augmented, "Penalty factor"));
  const std::string stalled = mass_balance_advice(balance, 1e-3, 1e3, MassHold::uzawa_stalled, 1e-7);
  report("Uzawa steps stalled (locking): a finer mesh or degree 2, not a tolerance or the factor",
         contains(stalled, "Velocity degree = 2") && !contains(stalled, "tolerance") && !contains(stalled, "Penalty factor"));
  report("status: failed above the tolerance, warning above a tenth, else ok",
         mass_balance_status(balance, 1e-3) == MassBalanceStatus::failed &&
           mass_balance_status(balance, 0.5) == MassBalanceStatus::warning &&
           mass_balance_status(balance, 1) == MassBalanceStatus::ok);
}
