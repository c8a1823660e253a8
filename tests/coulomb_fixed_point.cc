// Contact/Coulomb coupling: the fixed point on the Coulomb bound gives Newton's answer where Newton converges, and where a die with mu of order 1 makes Newton's states cycle, auto's switch to it converges to a state that keeps Coulomb's law at every node.
//
// With Newton's coupling the bound mu |F_n| is linearised with the normal
// force (ContactSet::contributions()); the fixed point freezes it at each
// iteration's normal force (a Tresca law with that bound), so that at
// convergence the friction is mu |F_n| of the converged F_n: Coulomb's
// law, the same solution. Checked here:
// - a steep die (75 degrees, 11 cells across, Newtonian) with mu 1 on the
//   container and 0.3 on the die and land: Newton, fixed point and auto
//   give the same ram force to 1e-6 (the Newton tolerance's 1e-8 with
//   margin). (The fixed point from the first iteration starts without
//   friction, and on die2d at mu 0.3 it ends with a direction held in
//   contact, pulling: exit 2. auto starts with Newton's.)
// - the same die with mu 1.5 on the die and land, where Newton's coupling does not settle (whole lands
//   flip between pulling and penetrating): auto converges with no
//   direction held or regularised, and the die profiles written by the
//   run (independent of the run's own contact_checks) keep the law: in
//   contact p >= 0 and no penetration, sticking nodes at rest with |tau|
//   <= mu p, slipping nodes with |tau| = mu p against the slip. The
//   profiles print 8 digits: equalities to 1e-6 of the largest value.
#include "fuzz.h"

#include <fstream>
#include <iomanip>

namespace
{
  std::string
  deck(const std::string &geometry, const std::string &friction, const std::string &coupling)
  {
    return "set Output directory = coupling\nset Write VTU = false\nsubsection Mesh\n  subsection Die2d\n" + geometry +
           "  end\nend\nsubsection Material\n  set Law = Newtonian\nend\nsubsection Contact\n  set Friction "
           "coefficients = " +
           friction + "\n  set Coulomb coupling = " + coupling + "\n  set Friction continuation = false\nend\n";
  }

  /// Exit status and F_x[1] of a run.
  std::pair<int, double>
  run(const std::string &text)
  {
    const fuzz::Outcome outcome = fuzz::run("coupling.prm", text);
    const auto          tree    = fuzz::summary("coupling");
    return {outcome.status, fuzz::number(tree.get_child("cycles").back().second, "quantities|F_x[1]")};
  }
} // namespace

int
main()
{
  const auto yes = [](const bool b) { return b ? "yes" : "NO"; };

  const std::string steep = "    set Outlet half height = 6.35928\n    set Die angle = 75.3229\n"
                            "    set Container length = 17.073\n    set Land length = 16.8563\n"
                            "    set Cells across = 11\n";
  const auto        newton    = run(deck(steep, "3: 1, 4: 0.3", "Newton"));
  const auto        fixed     = run(deck(steep, "3: 1, 4: 0.3", "fixed point"));
  const auto        automatic = run(deck(steep, "3: 1, 4: 0.3", "auto"));
  std::cout << "steep die, mu 1 and 0.3: Newton, fixed point and auto converge to the same ram force within 1e-6: "
            << yes(newton.first == 0 && fixed.first == 0 && automatic.first == 0 &&
                   std::abs(fixed.second / newton.second - 1) < 1e-6 &&
                   std::abs(automatic.second / newton.second - 1) < 1e-6)
            << std::endl;

  std::cout << "steep die, mu 1 and 1.5: Newton's coupling alone does not settle (exit 2): "
            << yes(run(deck(steep, "3: 1, 4: 1.5", "Newton")).first == 2) << std::endl;
  const auto switched = run(deck(steep, "3: 1, 4: 1.5", "auto"));
  const auto checks   = fuzz::summary("coupling").get_child("cycles").back().second;
  std::cout << "auto converges, no direction held or regularised: "
            << yes(switched.first == 0 && fuzz::number(checks, "contact_checks|held_in_contact") == 0 &&
                   fuzz::number(checks, "contact_checks|regularised_friction") == 0)
            << std::endl;
  const double breach =
    std::max(fuzz::coulomb_breach("coupling/die-profile-3.dat", 1), fuzz::coulomb_breach("coupling/die-profile-4.dat", 1.5));
  std::cout << "its die profiles keep Coulomb's law at every node within 1e-6: " << yes(breach < 1e-6) << std::endl;
}
