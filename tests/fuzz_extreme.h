// Fuzz corpus, part 2: valid but extreme die2d decks drawn from a fixed
// seed over the ranges a new user tried (die angle 1-90 degrees, reduction
// 1-95 %, 1-16 cells across, container and land 0.1-200 mm, mu 0-5 on each
// wall, ram speed 1e-6 to 1e6 mm/s, penalty factor 1e3 to 1e11, Newtonian
// or Norton-Hoff with m from 1 down to 0.02, velocity degree 1 or 2), each
// value at an end of its range one time in four. Decks whose meshes would
// exceed 4,000 cells (1,000 for degree 2) are drawn again: the corpus must
// run in a ctest's minute; the issue's two 100k-cell decks ran past two
// minutes, not hangs.
//
// Every deck must end with exit status 0 or 2 (never 1, 3, a crash or a
// hang), with a summary.json that parses. Every converged one must pass
// the physical checks: the mass balance within the guard (1e-3 of the
// flow), a positive and finite ram force, and the contact inequalities of
// contact_checks within the bounds of the stress suite (penetration and
// pull 1e-6, friction beyond the cone and friction power 1e-12, sticking
// speed 1e-8, all relative; a pull up to 1e-4 where a direction was held in
// contact to end a cycle of the states, see judge()). Every exit-2 one must say why in "failure".
#ifndef dieflow_tests_fuzz_extreme_h
#define dieflow_tests_fuzz_extreme_h

#include "fuzz.h"

#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <regex>

namespace fuzz
{
  struct ExtremeDeck
  {
    double       die_angle, outlet_half_height, container_length, land_length;
    unsigned int cells_across, velocity_degree;
    double       mu_container, mu_die, speed, penalty_factor, rate_sensitivity;
    bool         newtonian;

    /// Cells of the die2d generator (cells of aspect about 1, n across).
    double
    estimated_cells() const
    {
      const double h_i = 19, h_o = outlet_half_height, pi = 3.14159265358979;
      const double die_length = (h_i - h_o) / std::tan(die_angle * pi / 180);
      return cells_across * cells_across *
             (container_length / h_i + die_length / (0.5 * (h_i + h_o)) + land_length / h_o + 3);
    }

    std::string
    text() const
    {
      std::ostringstream d;
      d << std::setprecision(6) << "set Output directory = fuzz-extreme\nset Write VTU = false\n"
        << "subsection Mesh\n  subsection Die2d\n    set Outlet half height = " << outlet_half_height
        << "\n    set Die angle = " << die_angle << "\n    set Container length = " << container_length
        << "\n    set Land length = " << land_length << "\n    set Cells across = " << cells_across
        << "\n  end\nend\nsubsection Discretisation\n  set Velocity degree = " << velocity_degree << "\nend\n"
        << "subsection Material\n  set Law = " << (newtonian ? "Newtonian" : "Norton-Hoff")
        << "\n  set Rate sensitivity m = " << rate_sensitivity << "\n  set Penalty factor = " << penalty_factor
        << "\nend\nsubsection Boundary conditions\n  set Symmetry ids = 5\n  set Prescribed velocity ids = 1\n"
        << "  set Traction free ids = 2\n  subsection Prescribed velocity 1\n    set Velocity = " << speed
        << "; 0\n  end\nend\nsubsection Contact\n  set Die ids = 3, 4\n  set Friction coefficients = 3: "
        << mu_container << ", 4: " << mu_die << "\nend\n";
      return d.str();
    }
  };

  /// A value of [a, b] (log scale if @p log): an end one time in four.
  inline double
  extreme(Draw &draw, const double a, const double b, const bool log)
  {
    if (draw.chance(0.25))
      return draw.chance(0.5) ? a : b;
    return log ? draw.log_uniform(a, b) : draw.uniform(a, b);
  }

  inline ExtremeDeck
  draw_deck(Draw &draw)
  {
    for (;;)
      {
        ExtremeDeck d;
        d.die_angle          = extreme(draw, 1, 90, false);
        d.outlet_half_height = 19 * (1 - extreme(draw, 0.01, 0.95, false));
        d.container_length   = extreme(draw, 0.1, 200, true);
        d.land_length        = extreme(draw, 0.1, 200, true);
        d.cells_across       = draw.chance(0.25) ? (draw.chance(0.5) ? 1 : 16) : draw.integer(1, 16);
        d.velocity_degree    = draw.integer(1, 2);
        d.mu_container       = draw.chance(0.25) ? 0 : extreme(draw, 0, 5, false);
        d.mu_die             = draw.chance(0.25) ? 0 : extreme(draw, 0, 5, false);
        d.speed              = extreme(draw, 1e-6, 1e6, true);
        d.penalty_factor     = extreme(draw, 1e3, 1e11, true);
        d.newtonian          = draw.chance(0.3);
        d.rate_sensitivity   = extreme(draw, 0.02, 1, true);
        if (d.estimated_cells() * d.velocity_degree * d.velocity_degree <= 4000)
          return d;
      }
  }

  /// "" if the run of @p deck ended as it must; else what went wrong.
  inline std::string
  judge(const ExtremeDeck &, const Outcome &outcome, std::string &row)
  {
    if (outcome.status != 0 && outcome.status != 2)
      return "exit status " + std::to_string(outcome.status) + ": " + outcome.error;
    boost::property_tree::ptree tree;
    try
      {
        tree = summary("fuzz-extreme");
      }
    catch (const std::exception &)
      {
        return "summary.json does not parse";
      }
    const auto &last = tree.get_child("cycles").back().second;
    std::ostringstream r;
    r << std::setprecision(3) << number(last, "mass_balance|loss") << " | " << number(last, "quantities|F_x[1]");
    row = r.str();
    if (outcome.status == 2)
      return tree.get<std::string>("failure", "").empty() ? "exit status 2 without a failure" : "";

    std::string wrong;
    const auto  check = [&](const bool holds, const std::string &what) {
      if (!holds)
        wrong += (wrong.empty() ? "" : "; ") + what;
    };
    const double balance = std::max(number(last, "mass_balance|loss"), number(last, "mass_balance|volume_change"));
    check(balance <= 1e-3 && last.get<std::string>("mass_balance.status") != "failed", "mass balance beyond the guard");
    const double force = number(last, "quantities|F_x[1]");
    check(std::isfinite(force) && force > 0, "ram force not positive and finite");
    // A direction held in contact to end a cycle of the states sits where
    // contact gives way to separation, whose exact pressure is zero: its
    // pull is the transition falling between two nodes, allowed up to 1e-4.
    const double tension_bound = number(last, "contact_checks|held_in_contact") > 0 ? 1e-4 : 1e-6;
    const std::vector<std::pair<std::string, double>> bounds = {{"penetration", 1e-6},     {"tension", tension_bound},
                                                                {"friction_excess", 1e-12}, {"friction_power", 1e-12},
                                                                {"stick_slip_rate", 1e-8}};
    for (const auto &[name, bound] : bounds)
      {
        const double value = number(last, "contact_checks|" + name);
        check(std::isfinite(value) && value <= bound, "contact check " + name + " above " + std::to_string(bound));
      }
    return wrong;
  }

  /// The first words of an exit-2 run's "failure" (for the table).
  inline std::string
  why(const Outcome &outcome)
  {
    if (outcome.status != 2)
      return "";
    try
      {
        std::string failure = summary("fuzz-extreme").get<std::string>("failure", "");
        for (char &c : failure)
          c = (c == '|' || c == '\n') ? ' ' : c;
        // The first solve's reason first, then how far the continuation got.
        const std::string tried = " continuation): ";
        if (const auto at = failure.find(tried); at != std::string::npos)
          {
            const auto reached = failure.find("reached ");
            failure            = "cycle 0: " + failure.substr(at + tried.size(), 130) + " [continuation " +
                      (reached != std::string::npos && reached < at ? failure.substr(reached, 14) : "failed") + "]";
            return failure;
          }
        return failure.substr(0, 160);
      }
    catch (const std::exception &)
      {
        return "";
      }
  }

  /**
   * The first change the exit-2 line @p failure advises that can be made
   * to a deck without judgement, applied to @p deck (empty if none):
   * "raise S/E (it is x) to y" sets y; "set S/E = a" sets a ("a or b":
   * b, the regularised Coulomb law of the contact advice, which keeps the
   * deck's mu); "lower S/E (it is x)" sets x / 100, "raise S/E (it is
   * x)" 4 x. "refine the mesh at the die" and "lower Contact/Friction
   * coefficients" ask for a judgement and are not applied.
   */
  inline std::string
  apply_advice(const std::string &failure, std::string deck)
  {
    static const std::regex advice(
      R"((raise|lower|set) ([A-Z][A-Za-z ]*)/([A-Z][A-Za-z ]*?)(?: \(it is ([-0-9.e+]+)\))?(?: to ([-0-9.e+]+)| = ([^,;]+))?(?=[,;]|$))");
    for (auto m = std::sregex_iterator(failure.begin(), failure.end(), advice); m != std::sregex_iterator(); ++m)
      {
        const std::string verb = (*m)[1], section = (*m)[2], entry = (*m)[3], now = (*m)[4];
        std::string       value;
        if ((*m)[5].matched)
          value = (*m)[5];
        else if ((*m)[6].matched)
          {
            value = (*m)[6];
            if (const auto o = value.rfind(" or "); o != std::string::npos)
              value = value.substr(o + 4);
          }
        else if (!now.empty())
          {
            std::ostringstream v;
            v << std::stod(now) * (verb == "lower" ? 0.01 : 4);
            value = v.str();
          }
        if (value.empty() || (verb == "set" && !(*m)[6].matched))
          continue;
        const std::regex line("\n *set " + entry + " = [^\n]*");
        if (std::smatch found; std::regex_search(deck, found, line))
          return found.prefix().str() + "\n  set " + entry + " = " + value + found.suffix().str();
        return deck + "subsection " + section + "\n  set " + entry + " = " + value + "\nend\n";
      }
    return "";
  }

  /**
   * Runs @p count decks from @p seed and prints the verdicts, and whether
   * at least @p least_converged of them converged; then applies the
   * advice of each one that exits 2 (apply_advice()) and runs it again:
   * at least @p least_advised of those must converge. Decks before @p
   * first are drawn but not run (a corpus split over two tests).
   * FUZZ_DECKS=dir writes each deck to dir/SEED-INDEX.prm (to rerun one by
   * hand). With FUZZ_TABLE=file, also a Markdown row per deck (for
   * doc/stress.md; the statuses are not printed here: which extreme deck
   * converges may change with the round-off of another BLAS, the verdicts
   * must not).
   */
  inline void
  run_extreme_corpus(unsigned int seed, unsigned int count, const unsigned int least_converged,
                     const unsigned int least_advised, const unsigned int first = 0)
  {
    // FUZZ_SEED / FUZZ_COUNT draw another corpus, to explore by hand.
    if (const char *s = std::getenv("FUZZ_SEED"))
      seed = std::stoul(s);
    if (const char *c = std::getenv("FUZZ_COUNT"))
      count = std::stoul(c);
    Draw                     draw(seed);
    std::vector<std::string> failures;
    unsigned int             converged = 0, given_up = 0, advised = 0, advice_converged = 0;
    std::ofstream            table;
    if (const char *file = std::getenv("FUZZ_TABLE"))
      table.open(file, std::ios::app);
    for (unsigned int i = 0; i < count; ++i)
      {
        const ExtremeDeck deck    = draw_deck(draw);
        if (i < first)
          continue; // drawn, run by another part
        std::filesystem::remove_all("fuzz-extreme");
        // FUZZ_DECKS=dir writes each deck there, to rerun one by hand.
        if (const char *dir = std::getenv("FUZZ_DECKS"))
          std::ofstream(std::string(dir) + "/" + std::to_string(seed) + "-" + std::to_string(i) + ".prm") << deck.text();
        const Outcome     outcome = run("extreme.prm", deck.text());
        std::string       row;
        const std::string wrong   = judge(deck, outcome, row);
        converged += outcome.status == 0 && wrong.empty();
        if (!wrong.empty())
          failures.push_back("deck " + std::to_string(i) + ": " + wrong + "\n" + deck.text());
        const std::string reason = why(outcome);
        // The advice of a deck that gave up, followed.
        std::string after_advice;
        if (outcome.status == 2)
          {
            ++given_up;
            const std::string changed =
              apply_advice(summary("fuzz-extreme").get<std::string>("failure", ""), deck.text());
            if (!changed.empty())
              {
                ++advised;
                std::filesystem::remove_all("fuzz-extreme");
                const Outcome again = run("extreme.prm", changed);
                std::string   ignored;
                const bool    good = again.status == 0 && judge(deck, again, ignored).empty();
                advice_converged += good;
                after_advice = good ? "0" : std::to_string(again.status);
              }
          }
        if (table.is_open())
          table << "| " << seed << "/" << i << " | " << std::setprecision(3) << deck.die_angle << " | "
                << 100 * (1 - deck.outlet_half_height / 19) << " | " << deck.container_length << " | "
                << deck.land_length << " | " << deck.cells_across << " | " << deck.velocity_degree << " | "
                << deck.mu_container << ", " << deck.mu_die << " | " << deck.speed << " | " << deck.penalty_factor
                << " | " << (deck.newtonian ? std::string("Newtonian") : "m = " + std::to_string(deck.rate_sensitivity).substr(0, 5))
                << " | " << outcome.status << " | " << row << " | " << (wrong.empty() ? "yes" : "NO") << " | " << reason << " | " << after_advice << " |\n";
      }
    std::cout << count - first << " extreme decks (seed " << seed << (first > 0 ? ", from deck " + std::to_string(first) : std::string())
              << "): every one exits 0 or 2 with a readable summary.json, every converged one passes the physical "
                 "checks, every other says why: "
              << (failures.empty() ? "yes" : "NO") << std::endl;
    // Without a bound below, a corpus in which every deck exits 2 would
    // pass: the verdicts above hold for any deck that gives up.
    std::cout << "at least " << least_converged << " of the " << count - first
              << " converge (and pass the checks): " << (converged >= least_converged ? "yes" : "NO") << std::endl;
    // Advice that, followed, does not converge is no advice.
    std::cout << "of those that do not converge, those whose advice can be followed without judgement converge "
                 "when it is, at least "
              << least_advised << ": " << (advice_converged >= least_advised ? "yes" : "NO") << std::endl;
    if (std::getenv("FUZZ_COUNTS"))
      std::cout << "counts: converged " << converged << ", exit 2 " << given_up << ", advice followed " << advised
                << ", then converged " << advice_converged << std::endl;
    for (const auto &failure : failures)
      std::cout << failure << std::endl;
  }
} // namespace fuzz

#endif
