// Contact/Friction and Material/Rate sensitivity continuation: where Newton's method fails at a die's friction, or its converged state pulls on the die, Coulomb's fixed point, continuation in the friction and in m converge to a state that keeps Coulomb's law at every node.
//
// Two decks of the extreme corpus (fuzz_extreme.h; seed 3 deck 38 and
// seed 2 deck 30), coarse (2 cells across and 1), nearly rigid-plastic:
// A (Norton-Hoff m = 0.024) with mu 2.5 on the die and land, B (m = 0.02,
// a flat-faced 85.5-degree die at 1e6 mm/s, penalty factor 1.3e4) with mu
// 0.32 there (seed 3 deck 30, B until 2026-12-05, now converges at the
// fixed-point stage: the frozen bounds are coupled again once the states
// settle, doc/contact.md):
// - without the continuations both exit 2 (the contact does not settle);
// - deck A converges at its first stage, the deck's friction with the
//   bound frozen at each iteration's normal force (friction_stages = [1]),
//   to the ram force of the same deck run with Contact/Coulomb coupling =
//   fixed point (the advice the stage replaces) within 1e-6;
// - deck B fails at that stage and converges by continuation: frictionless,
//   at stages below the deck's friction and at the deck's (friction_stages
//   ends with 1 after a stage strictly between 0 and 1), to the ram force
//   that Coulomb coupling = fixed point set in the deck reaches from the
//   start by another path, within 1e-6 (measured 4e-8: the Uzawa steps'
//   divergence tolerance);
// - both converged states keep the contact laws: the run's own contact
//   checks within the guard's bounds, and the die profiles the runs write
//   (read here, independently of the run's checks) keep Coulomb's law with
//   the deck's mu at every node within 1e-6 of the largest pressure or
//   speed (the profiles print 8 digits).
// Two more (seed 3 deck 39, seed 1 deck 37), both nearly rigid-plastic:
// - deck C (m = 0.07, mu 5 on die and land, 7 cells across) exits 2 with
//   Material/Rate sensitivity continuation = false (the friction's paths
//   fail); with it, it converges by continuation in m: stages from m = 0.5
//   through one strictly between to the deck's m (rate_sensitivity_stages);
// - deck D (m = 0.066, mu 4.5 on the container, 1 cell across) converges
//   at first to a state whose directions held in contact pull on the die
//   (exit 2 with Contact/Friction continuation = false, the guard's
//   verdict); with it, that refused state is solved again and the friction
//   path converges (friction_stages ending with 1);
// - both keep the contact laws as A and B do (1e-6).
// Decks E and F take the path in m alone (Friction continuation = false:
// with it both converge at its first stage, Coulomb's fixed point with
// eight times Newton's iterations).
// Deck E (seed 3 deck 23, m = 0.02, augmented): the continuation in m's
// first stage converges as the same deck at m = 0.5 does by itself (the
// stage's Uzawa steps with the stage's law).
// Deck F (seed 3 deck 22: m = 0.062, mu 2.6 on a 200 mm container and
// 3.8 on the die, augmented): exit 2 without the continuations; with the one in m
// its path in m fails at stages and goes on from the last converged one
// (velocity, contact states and the augmented Lagrangian's multiplier: a
// failed stage's Uzawa steps leave a pressure of no solution, and from it
// the path fails at every later stage) to the deck's m, where the state
// keeps the contact laws as A and B do (1e-6).
#include "fuzz_extreme.h"

namespace
{
  /// Exit status, F_x[1] and the friction stages of a run of @p deck with @p extra appended.
  struct Run
  {
    int                 status;
    double              force;
    std::vector<double> stages, law_stages;
    double              breach;
  };

  Run
  run(const fuzz::ExtremeDeck &deck, const std::string &extra)
  {
    std::filesystem::remove_all("fuzz-extreme");
    const fuzz::Outcome outcome = fuzz::run("continuation.prm", deck.text() + extra);
    const auto          tree    = fuzz::summary("fuzz-extreme");
    const auto &        last    = tree.get_child("cycles").back().second;
    Run                 r{outcome.status, fuzz::number(last, "quantities|F_x[1]"), {}, {}, 1};
    for (const auto &stage : last.get_child("friction_stages"))
      r.stages.push_back(stage.second.get_value<double>());
    for (const auto &stage : last.get_child("rate_sensitivity_stages"))
      r.law_stages.push_back(stage.second.get_value<double>());
    if (outcome.status == 0)
      {
        std::string row;
        r.breach = fuzz::judge(deck, outcome, row).empty() ?
                     std::max(fuzz::coulomb_breach("fuzz-extreme/die-profile-3.dat", deck.mu_container),
                              fuzz::coulomb_breach("fuzz-extreme/die-profile-4.dat", deck.mu_die)) :
                     1;
      }
    return r;
  }

  const std::string without = "subsection Contact\n  set Friction continuation = false\nend\n"
                              "subsection Material\n  set Rate sensitivity continuation = false\nend\n";
  const std::string fixed_point =
    "subsection Contact\n  set Friction continuation = false\n  set Coulomb coupling = fixed point\nend\n";
} // namespace

int
main()
{
  const auto yes = [](const bool b) { return b ? "yes" : "NO"; };
  // die angle, outlet half height, container, land, cells across, degree,
  // mu container, mu die, speed, penalty factor, m, Newtonian
  const fuzz::ExtremeDeck a{37.1805, 0.95, 0.240217, 13.8931, 2, 1, 0, 2.54331, 1e-6, 1.35964e8, 0.0235295, false};
  const fuzz::ExtremeDeck b{85.514, 18.0619, 1.69301, 0.1, 1, 1, 0, 0.319626, 1e6, 13227.4, 0.02, false};

  std::cout << "deck A without the continuation: exit 2: " << yes(run(a, without).status == 2) << std::endl;
  const Run a_fixed = run(a, fixed_point);
  const Run a_on    = run(a, "");
  std::cout << "deck A: converges at the fixed-point stage, to the ram force of Coulomb coupling = fixed point "
               "within 1e-6: "
            << yes(a_fixed.status == 0 && a_on.status == 0 && a_on.stages == std::vector<double>{1} &&
                   std::abs(a_on.force / a_fixed.force - 1) < 1e-6)
            << std::endl;
  std::cout << "deck A: contact checks and Coulomb's law in the die profiles within 1e-6: " << yes(a_on.breach < 1e-6)
            << std::endl;

  std::cout << "deck B without the continuation: exit 2: " << yes(run(b, without).status == 2) << std::endl;
  const Run  b_fixed = run(b, fixed_point);
  const Run  b_on    = run(b, "");
  const bool between =
    std::any_of(b_on.stages.begin(), b_on.stages.end(), [](const double s) { return s > 0 && s < 1; });
  std::cout << "deck B: converges through a stage below the deck's friction, to the ram force of Coulomb coupling "
               "= fixed point within 1e-6: "
            << yes(b_on.status == 0 && between && !b_on.stages.empty() && b_on.stages.back() == 1 &&
                   b_fixed.status == 0 && std::abs(b_on.force / b_fixed.force - 1) < 1e-6)
            << std::endl;
  std::cout << "deck B: contact checks and Coulomb's law in the die profiles within 1e-6: " << yes(b_on.breach < 1e-6)
            << std::endl;

  const fuzz::ExtremeDeck c{71.9227, 0.95, 1.44652, 11.3169, 7, 1, 5, 5, 0.261293, 1.28135e8, 0.0699426, false};
  const fuzz::ExtremeDeck d{48.4083, 10.8371, 0.1, 1.367, 1, 1, 4.51616, 0, 16.2724, 9.80453e8, 0.0663514, false};
  std::cout << "deck C without the continuation in m: exit 2: "
            << yes(run(c, "subsection Material\n  set Rate sensitivity continuation = false\nend\n").status == 2)
            << std::endl;
  const Run c_on = run(c, "");
  const auto &m  = c_on.law_stages;
  std::cout << "deck C: converges through stages from m = 0.5 to the deck's m, one between: "
            << yes(c_on.status == 0 && m.size() >= 3 && m.front() == 0.5 && m.back() == c.rate_sensitivity &&
                   std::any_of(m.begin(), m.end(), [&](const double x) { return x < 0.5 && x > c.rate_sensitivity; }))
            << std::endl;
  std::cout << "deck C: contact checks and Coulomb's law in the die profiles within 1e-6: " << yes(c_on.breach < 1e-6)
            << std::endl;
  std::cout << "deck D without the continuation: exit 2: " << yes(run(d, without).status == 2) << std::endl;
  const Run d_on = run(d, "");
  std::cout << "deck D: its refused state solved again, converges at the deck's friction: "
            << yes(d_on.status == 0 && !d_on.stages.empty() && d_on.stages.back() == 1) << std::endl;
  std::cout << "deck D: contact checks and Coulomb's law in the die profiles within 1e-6: " << yes(d_on.breach < 1e-6)
            << std::endl;

  // Deck E (seed 3 deck 23: m = 0.02, mu 3.5 and 5, 1e6 mm/s, penalty
  // factor 1e3, so that the penalty turns augmented): the first stage of
  // its continuation in m, the deck at m = 0.5, converges
  // as that deck does by itself: the Uzawa steps' r per cell follows the
  // stage's law (with the deck's m = 0.02 it did not: 50 iterations).
  const fuzz::ExtremeDeck e{1, 16.9707, 3.32219, 1.76052, 12, 1, 3.51439, 5, 1e6, 1000, 0.02, false};
  fuzz::ExtremeDeck       e_half = e;
  e_half.rate_sensitivity        = 0.5;
  const std::string law_path_only = "subsection Contact\n  set Friction continuation = false\nend\n";
  const Run         e_on          = run(e, law_path_only);
  std::cout << "deck E: its continuation in m converges at its first stage, m = 0.5, as the deck at m = 0.5 does: "
            << yes(e_on.law_stages.size() >= 1 && e_on.law_stages.front() == 0.5 && run(e_half, "").status == 0)
            << std::endl;

  const fuzz::ExtremeDeck f{1, 18.1467, 200, 12.5408, 10, 1, 2.61742, 3.77765, 0.0455712, 16584.6, 0.0617007, false};
  std::cout << "deck F without the continuation: exit 2: " << yes(run(f, without).status == 2) << std::endl;
  const Run f_on = run(f, law_path_only);
  std::cout << "deck F: converges through stages in m to the deck's m: "
            << yes(f_on.status == 0 && f_on.law_stages.size() >= 3 && f_on.law_stages.back() == f.rate_sensitivity)
            << std::endl;
  std::cout << "deck F: contact checks and Coulomb's law in the die profiles within 1e-6: " << yes(f_on.breach < 1e-6)
            << std::endl;
}
