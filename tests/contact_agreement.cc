// The paper's penalty normal enforcement (F_n = -omega_n max(v.n, 0)) and the
// active set (v.n = 0 exactly where pressed) solve the same contact problem
// as omega_n grows: on die2d N1 (8 cells across), the ram force, the die
// normal force and the flux through the separated land of the penalty runs
// approach the active-set values, the gap falling about in proportion to
// 1/omega_n (factor 10 per decade: at least 5 here, before round-off), and
// the penalty's penetration rate max v.n falls likewise. (The split of a
// corner node's reaction into normal and friction forces differs between
// the two, by a corner node's share, so the die's force is compared as the
// vector integral of sigma n, not as the sum of |F_n|.)
#include <dieflow/problem/run.h>

#include "report.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

using namespace dieflow;

namespace
{
  CycleSummary
  run(const std::string &contact_section)
  {
    return run_deck_text("subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = 8\n end\nend\n"
                         "subsection Contact\n" +
                         contact_section + "end\n")
      .cycles.back();
  }
} // namespace

int
main()
{
  const CycleSummary exact = run(" set Normal enforcement = active set\n");
  std::vector<double> ram_gap, normal_gap, penetration;
  bool                converged = true;
  for (const double factor : {1e-3, 1e-2, 1e-1})
    {
      std::ostringstream section;
      section << " set Normal enforcement = penalty\n set Normal penalty factor = " << factor << "\n";
      const CycleSummary p = run(section.str());
      converged &= p.converged;
      ram_gap.push_back(std::abs(p.boundary_force.at(1)[0] / exact.boundary_force.at(1)[0] - 1));
      normal_gap.push_back(std::abs(p.boundary_force.at(4)[1] / exact.boundary_force.at(4)[1] - 1) +
                           std::abs(p.flux.at(4) / exact.flux.at(4) - 1));
      penetration.push_back(p.contact_penetration);
    }
  report("all runs converge", converged && exact.converged);
  bool falls = true;
  for (unsigned int i = 1; i < ram_gap.size(); ++i)
    falls &= ram_gap[i] < ram_gap[i - 1] / 5 && normal_gap[i] < normal_gap[i - 1] / 5 &&
             penetration[i] < penetration[i - 1] / 5;
  report("ram force, die force, land flux and penetration approach the active set as 1/omega_n", falls);
  report("omega_n = 0.1 lambda: ram force within 1e-3 of the active set", ram_gap.back() < 1e-3);
}
