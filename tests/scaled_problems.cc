// Scaled problems are the same problem: die2d run at a ram speed s times the deck's (and, for Norton-Hoff, the minimum strain rate s times too) gives s^m times its forces, m = 1 for Newtonian.
//
// The velocity-driven viscoplastic problem with Coulomb friction is
// homogeneous: if v solves it at the ram speed V, s v solves it at s V,
// with the stresses (2 eta(s D) s D) s^m times as large (eta ~ |D|^(m-1))
// and the Coulomb tractions, mu times the normal ones, too. Any absolute
// speed inside the program breaks that: the friction laws regularised to
// end a cycle of the contact states had v0 = max(1 mm/s, 0.01 |v|), and
// the regularised Coulomb law's default v0 was 1 mm/s, so that at 1e-6
// mm/s the die had almost no friction (issue 48's "a Newtonian problem at
// 1e-6 mm/s is the 190 mm/s problem scaled"). The two runs take the same
// iterates up to round-off and stop at the same one, so the forces agree
// to far below the 1e-6 asked here (measured: 1e-9 and less).
#include "fuzz.h"
#include "fuzz_extreme.h"

#include <cmath>
#include <iomanip>

namespace
{
  std::string
  deck(const std::string &law, const double m, const std::string &friction, const double speed,
       const double minimum_rate, const std::string &extra)
  {
    std::ostringstream d;
    d << std::setprecision(17) << "set Output directory = scaled\nset Write VTU = false\n"
      << "subsection Mesh\n  subsection Die2d\n    set Layout = blocks\n    set Cells across = 8\n  end\nend\n"
      << "subsection Material\n  set Law = " << law << "\n  set Rate sensitivity m = " << m
      << "\n  set Minimum strain rate = " << minimum_rate << "\nend\n"
      << "subsection Boundary conditions\n  subsection Prescribed velocity 1\n    set Velocity = " << speed
      << "; 0\n  end\nend\nsubsection Contact\n" << friction << "end\n" << extra;
    return d.str();
  }

  /// Force F_x[1] of the run, NaN if it did not converge.
  double
  force(const std::string &text)
  {
    const fuzz::Outcome outcome = fuzz::run("scaled.prm", text);
    if (outcome.status != 0)
      return std::nan("");
    return fuzz::number(fuzz::summary("scaled").get_child("cycles").back().second, "quantities|F_x[1]");
  }
} // namespace

int
main()
{
  const std::string coulomb     = "  set Friction coefficients = 3: 0.3, 4: 0.3\n";
  const std::string regularised = "  set Friction law = regularised Coulomb\n" + coulomb;
  struct Case
  {
    std::string name, law, friction;
    double      m;
    std::string extra = "";
  };
  // The regularised law has no stick (since 2026-12-04; it held the nodes
  // slower than v0 at rest before): from the Newtonian start, Newton's
  // first step on, this deck does not converge (exit 2), and the first
  // advice of its message (Picard steps first) must: the runs below use
  // the deck with that advice followed. (Its Newton iteration ends in a
  // state that pulls on the die; the fallbacks, off here, solve it again
  // and converge: Contact/Friction continuation, stages 0, 0.5, 1.)
  std::string picard_first;
  {
    const std::string as_is = deck("Norton-Hoff", 0.2, regularised + "  set Friction continuation = false\n", 1, 1e-4,
                                   "subsection Material\n  set Rate sensitivity continuation = false\nend\n");
    const fuzz::Outcome outcome = fuzz::run("scaled.prm", as_is);
    const std::string   failure = outcome.status == 2 ? fuzz::summary("scaled").get<std::string>("failure", "") : "";
    const std::string   advised = fuzz::apply_advice(failure, as_is);
    picard_first = advised.size() > as_is.size() ? advised.substr(as_is.size()) : "";
    std::cout << "Norton-Hoff m = 0.2, regularised Coulomb mu = 0.3, Newton from the first step: exit 2, and its "
                 "first advice is Picard steps first: "
              << (outcome.status == 2 && picard_first.find("set Method = Picard then Newton") != std::string::npos ?
                    "yes" :
                    "NO")
              << std::endl;
    std::cout << "  that advice followed, it converges: " << (!advised.empty() && std::isfinite(force(advised)) ? "yes" : "NO")
              << std::endl;
  }
  const std::vector<Case> cases = {
    {"Newtonian, Coulomb mu = 0.3 (stick and slip)", "Newtonian", coulomb, 1},
    {"Norton-Hoff m = 0.2, Coulomb mu = 0.3", "Norton-Hoff", coulomb, 0.2},
    {"Norton-Hoff m = 0.2, regularised Coulomb mu = 0.3 (the default v0)", "Norton-Hoff", regularised, 0.2, picard_first}};
  const double speed = 1, minimum_rate = 1e-4; // the deck's defaults
  for (const auto &c : cases)
    {
      const double reference = force(deck(c.law, c.m, c.friction, speed, minimum_rate, c.extra));
      for (const double s : {1e-6, 1e6})
        {
          const double scaled   = force(deck(c.law, c.m, c.friction, s * speed, s * minimum_rate, c.extra));
          const double relative = std::abs(scaled / (std::pow(s, c.m) * reference) - 1);
          std::cout << c.name << ", speed x " << s << ": both converge, F_x[1] = s^m times the deck's within 1e-6: "
                    << (std::isfinite(relative) && relative < 1e-6 ? "yes" : "NO") << std::endl;
          if (!(relative < 1e-6))
            std::cout << "  F_x[1] = " << std::setprecision(10) << scaled << " against " << std::pow(s, c.m) * reference
                      << std::endl;
        }
    }
}
