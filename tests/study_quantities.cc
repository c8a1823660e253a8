// The mesh study with a quantity that some cycles lack (h_extrudate, while the free surface is more than one stretch): each quantity is extrapolated over the trailing cycles that have it, and the table writes.
//
// Values Q = Q* + C N^-1 on four cycles, exactly: with all three last cycles
// the extrapolation recovers Q* to round-off. A second quantity exists on
// cycles 1 and 2 only, a third on cycles 2 and 3 only (it appeared late):
// the third's sequence is its own two values (the estimate from its one
// change: |Q3 - Q2| / ((N3/N2)^1/2 - 1)), never a value of another
// quantity, and the table of the study writes, with '-' where a cycle
// lacks a quantity. (Before 2026-12-02 the quantities were taken by their
// index in the last cycle: the third would have been extrapolated over the
// second's values, and the table's columns of unequal length failed to
// write: 'cannot write study.txt'.)
#include <dieflow/postprocess/study.h>

#include "report.h"

#include <cmath>
#include <sstream>

using namespace dieflow;

int
main()
{
  StudyTable         study;
  const double       N[4] = {1000, 2000, 4000, 8000};
  const auto         exact = [](const double n) { return 5 + 300 / n; };
  for (unsigned int k = 0; k < 4; ++k)
    {
      CycleSummary c;
      c.cycle = k;
      c.dofs  = N[k];
      c.quantities.emplace_back("F", exact(N[k]));
      if (k == 1 || k == 2)
        c.quantities.emplace_back("gone", 100. + k);
      if (k >= 2)
        c.quantities.emplace_back("late", k == 2 ? 7. : 7.5);
      study.add(c);
    }
  const auto extrapolations = study.extrapolations();
  report("the last cycle's quantities are extrapolated, no others", extrapolations.size() == 2);
  for (const auto &[name, e] : extrapolations)
    {
      if (name == "F")
        report("F: Richardson recovers the limit 5 of 5 + 300/N", e.valid && std::abs(e.value - 5) < 1e-9 &&
                                                                     std::abs(e.order - 1) < 1e-6);
      if (name == "late")
        report("late: over its own two cycles (last value 7.5, estimate 0.5 / (sqrt 2 - 1))",
               !e.valid && e.value == 7.5 && std::abs(e.estimate - 0.5 / (std::sqrt(2.) - 1)) < 1e-12);
    }
  std::ostringstream out;
  study.write(out);
  const std::string text = out.str();
  report("the table writes, with '-' where a cycle lacks a quantity",
         bool(out) && text.find(" - ") != std::string::npos && text.find("late") != std::string::npos &&
           text.find("gone") != std::string::npos);
}
