// The direct fallback of a failed iterative solve is refused, with the
// sizes, where it would not fit in the machine's free memory (a 3D
// fallback of 316,179 unknowns was killed by the kernel at 23 GB without a
// word), and allowed where it does:
//  - the estimate reproduces the measurements it rests on (2D: 2.3 GB at
//    458,000 unknowns; 3D: 1.9 GB at 42,315) and grows as stated (3D:
//    N^(4/3), 2^(4/3) = 2.52 per doubling);
//  - 3D with 10 million unknowns (some 2.8 TB by the estimate, beyond any
//    machine this runs on) throws ResourceFailure naming the remedy;
//  - 2D with 1,000 unknowns (5 MB) passes;
//  - direct_fallback_fits(), which decides whether a mixed-form solve that
//    stopped short is taken as a partial step, answers as the guard does.
#include <dieflow/solvers/linear_solver.h>

#include "report.h"

#include <cmath>
#include <string>

using namespace dieflow;

int
main()
{
  const auto estimate = [](const unsigned int dim, const std::size_t n) {
    return LinearSolver::direct_memory_estimate(dim, n);
  };
  report("2D estimate at 458,000 unknowns: 2.3 GB", std::abs(estimate(2, 458000) - 2.3e9) < 1e6);
  report("3D estimate at 42,315 unknowns: 1.9 GB", std::abs(estimate(3, 42315) - 1.9e9) < 1e6);
  report("3D estimate grows by 2^(4/3) per doubling",
         std::abs(estimate(3, 200000) / estimate(3, 100000) - std::pow(2., 4. / 3.)) < 1e-12);
  try
    {
      LinearSolver::require_direct_fallback_fits(3, 10000000);
      report("3D, 10 million unknowns: the fallback is refused", false);
    }
  catch (const ResourceFailure &failure)
    {
      const std::string what = failure.what();
      report("3D, 10 million unknowns: the fallback is refused, with the sizes and a remedy",
             what.find("10000000 unknowns") != std::string::npos && what.find("GB free") != std::string::npos &&
               what.find("Refinement/Cycles") != std::string::npos);
    }
  bool small_fits = true;
  try
    {
      LinearSolver::require_direct_fallback_fits(2, 1000);
    }
  catch (const ResourceFailure &)
    {
      small_fits = false;
    }
  report("2D, 1,000 unknowns: the fallback is allowed", small_fits);
  report("direct_fallback_fits() answers as the guard: no for 10 million in 3D, yes for 1,000 in 2D",
         !LinearSolver::direct_fallback_fits(3, 10000000) && LinearSolver::direct_fallback_fits(2, 1000));
}
