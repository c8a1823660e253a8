// Helpers of the unit tests: a verdict line, and a run of a deck given as text.
#ifndef dieflow_tests_report_h
#define dieflow_tests_report_h

#include <dieflow/problem/run.h>

#include <cmath>
#include <csignal>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>

/// One verdict line: the claim, then yes or NO.
inline void
report(const std::string &claim, const bool holds)
{
  std::cout << claim << ": " << (holds ? "yes" : "NO") << std::endl;
}

/// Whether @p a and @p b agree to @p tolerance (absolute).
inline bool
near(const double a, const double b, const double tolerance = 1e-12)
{
  return std::abs(a - b) <= tolerance;
}

/// The relative gap of @p a from @p b; equal values have none (zeros too:
/// the friction forces of frictionless dies).
inline double
relative_gap(const double a, const double b)
{
  return a == b ? 0. : std::abs(a / b - 1);
}

/// Whether two cycles report the same quantities (the ram force, each die's
/// normal and friction force, the probe's velocity) within @p tolerance of
/// each other, relative.
inline bool
quantities_agree(const dieflow::CycleSummary &a, const dieflow::CycleSummary &b, const double tolerance)
{
  bool same = !a.quantities.empty() && a.quantities.size() == b.quantities.size();
  for (unsigned int k = 0; same && k < a.quantities.size(); ++k)
    same = a.quantities[k].first == b.quantities[k].first &&
           relative_gap(a.quantities[k].second, b.quantities[k].second) < tolerance;
  return same;
}

/// The whole text of @p file ("" if there is none).
inline std::string
file_contents(const std::string &file)
{
  std::ifstream     in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The deck tests/@p name without its Output directory and its Test subsection (the check driver's).
inline std::string
test_deck(const std::string &name)
{
  const std::string text = file_contents(std::string(SOURCE_DIR) + "/" + name);
  return std::regex_replace(std::regex_replace(text, std::regex("set Output directory[^\\n]*"), ""),
                            std::regex("subsection Test[\\s\\S]*"), "");
}

/// Runs the deck @p text (written to deck.prm; results in results/, no VTU
/// unless @p text sets Write VTU: an entry may be set only once).
inline dieflow::RunSummary
run_deck_text(const std::string &text)
{
  const bool sets_vtu = text.find("set Write VTU") != std::string::npos;
  std::ofstream("deck.prm") << "set Output directory = results\n"
                            << (sets_vtu ? "" : "set Write VTU = false\n") << text;
  dieflow::ParameterHandler prm;
  dieflow::read_deck("deck.prm", prm);
  std::ostringstream log;
  return dieflow::run_deck(prm, ".", log);
}

/// A log that raises SIGINT when it reads "  converged:" (the end of a
/// cycle or step): a signal at a fixed point of a run.
class SignalAtCycleEnd : public std::streambuf
{
protected:
  int
  overflow(const int c) override
  {
    text += static_cast<char>(c);
    if (!raised && text.size() >= 12 && text.compare(text.size() - 12, 12, "  converged:") == 0)
      {
        raised = true;
        std::cout << std::flush;
        std::raise(SIGINT);
      }
    return c;
  }

private:
  std::string text;
  bool        raised = false;
};

#endif
