// The verdicts on a converged cycle: the mass the penalty lost, and the contact conditions its state must keep.
#include <dieflow/base/parameters.h>
#include <dieflow/postprocess/cycle_guards.h>
#include <dieflow/postprocess/mass_balance.h>

#include <iomanip>
#include <sstream>
#include <tuple>

namespace dieflow
{
  GuardVerdict
  guard_mass_balance(CycleSummary &cycle,
                     const double  tolerance,
                     const double  penalty_factor,
                     const MassHold hold,
                     const double  divergence_tolerance)
  {
    GuardVerdict verdict;
    if (tolerance == 0)
      {
        cycle.mass_balance_status = MassBalanceStatus::off;
        return verdict;
      }
    const MassBalance &balance = cycle.mass_balance;
    cycle.mass_balance_status  = mass_balance_status(balance, tolerance);
    if (cycle.mass_balance_status == MassBalanceStatus::ok)
      return verdict;
    std::ostringstream what;
    what << "the penalty lost " << std::setprecision(2) << 100 * balance.worst()
         << " % of the flow (mass balance " << std::scientific << balance.loss << ", cells' volume change "
         << balance.volume_change << std::defaultfloat << ", against Nonlinear solver/Mass balance tolerance = "
         << tolerance << "): the forces are off by about as much; "
         << mass_balance_advice(balance, tolerance, penalty_factor, hold, divergence_tolerance);
    if (cycle.mass_balance_status == MassBalanceStatus::failed)
      verdict.failure = what.str();
    else
      verdict.warning = what.str();
    return verdict;
  }



  GuardVerdict
  guard_contact(const CycleSummary &            cycle,
                const unsigned int              dim,
                const ContactParameters &       contact,
                const std::vector<std::string> &changes)
  {
    GuardVerdict verdict;
    if (contact.die_ids.empty())
      return verdict;
    // The 3D bound on friction: the semismooth Newton method reaches the
    // cone only as it converges, and a converged run ends a little beyond
    // it (tests/rectangular_bar_quarter; doc/benchmarks.md).
    const bool exact_normal = contact.normal_enforcement == ContactParameters::NormalEnforcement::active_set;
    const bool exact_stick  = exact_normal && contact.stick_enforcement == ContactParameters::StickEnforcement::exact;
    const std::vector<std::tuple<std::string, double, double, bool>> checks = {
      {"penetration", cycle.contact_penetration, 1e-6, exact_normal},
      {"pull of the die", cycle.contact_tension, cycle.held_in_contact > 0 ? 1e-4 : 1e-6, exact_normal},
      {"friction beyond its bound", cycle.friction_excess, dim == 3 ? 1e-8 : 1e-12, true},
      {"friction driving the slip", cycle.friction_power, 1e-12, true},
      {"sliding of sticking nodes", cycle.stick_slip_rate, 1e-8, exact_stick}};
    std::ostringstream broken;
    for (const auto &[name, value, bound, applies] : checks)
      if (applies && !(value <= bound))
        broken << (broken.tellp() > 0 ? ", " : "") << name << ' ' << std::setprecision(1) << value << " (above "
               << bound << ")";
    if (broken.tellp() == 0)
      return verdict;
    std::ostringstream what;
    what << "the converged state breaks the contact conditions: " << broken.str() << " of the largest force or speed";
    if (cycle.held_in_contact > 0)
      what << ", with " << cycle.held_in_contact << " direction(s) held in contact to end a cycle of the states";
    what << "; " << one_of_changes(changes, "");
    verdict.failure = what.str();
    return verdict;
  }
} // namespace dieflow
