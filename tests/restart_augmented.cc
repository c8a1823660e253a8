// A restart goes on augmented where the run did: a run in time whose penalty the mass-balance guard turned augmented (Uzawa steps) gives, from its checkpoint, the uninterrupted run's steps, iterations and forces.
//
// Axisymmetric upsetting by a moving platen with Coulomb friction (the
// scene of restart.cc, 4 x 8 cells, Norton-Hoff m = 0.2, no hardening) with
// Penalty factor 1e3: at step 0 the penalty lets 0.14 % of the flow go,
// more than Mass balance tolerance (1e-3), and the form turns augmented
// for the run (Incompressibility::augment()). 10 steps of 0.01 s; a run to
// t = 0.05 leaves its checkpoint at step 5, a run from it goes to 0.1.
// Checked: every step of both runs augmented; the restarted steps 6-10 take
// the uninterrupted run's Newton iterations, step for step (a checkpoint
// without the form started step 6 with the penalty, converged it in 6
// iterations instead of 10, then turned augmented: tried, this check
// fails and the forces differ in the 10th digit); load-stroke.txt byte for
// byte; each force component at step 10 the same to 1e-13 of the force.
#include <dieflow/postprocess/summary.h>

#include "report.h"

#include <cmath>
#include <filesystem>

using namespace dieflow;

namespace
{
  std::string
  deck(const std::string &output, const double end_time, const std::string &restart_from)
  {
    std::ostringstream text;
    text << "set Geometry = axisymmetric\n"
         << "set Output directory = " << output << "\n"
         << "set Write VTU = false\n"
         << "set Problem = incremental\n"
         << "subsection Incremental\n"
         << "  set Time step = 0.01\n"
         << "  set End time = " << end_time << "\n"
         << "  set Checkpoint interval = 0\n"
         << "  set Restart from = " << restart_from << "\n"
         << "end\n"
         << "subsection Mesh\n"
         << "  set Source = box\n"
         << "  subsection Box\n"
         << "    set Lower corner = 0, 0\n"
         << "    set Upper corner = 5, 10\n"
         << "    set Subdivisions = 4, 8\n"
         << "  end\n"
         << "end\n"
         << "subsection Material\n"
         << "  set Law = Norton-Hoff\n"
         << "  set Consistency K = 1\n"
         << "  set Rate sensitivity m = 0.2\n"
         << "  set Penalty factor = 1000\n"
         << "end\n"
         << "subsection Boundary conditions\n"
         << "  set Prescribed velocity ids =\n"
         << "  set Symmetry ids = 1, 3\n"
         << "  set Slip wall ids =\n"
         << "  set Traction free ids = 4\n"
         << "end\n"
         << "subsection Contact\n"
         << "  set Die ids = 2\n"
         << "  set Friction law = Coulomb\n"
         << "  set Friction coefficients = 2: 0.2\n"
         << "  set Die velocities = 2: -5 0\n"
         << "end\n"
         << "subsection Refinement\n"
         << "  set Probe point =\n"
         << "end\n";
    return text.str();
  }

  RunSummary
  run(const std::string &text)
  {
    std::ofstream("deck.prm") << text;
    ParameterHandler prm;
    read_deck("deck.prm", prm);
    std::ostringstream swallowed;
    return run_deck(prm, ".", swallowed);
  }

  bool
  all_augmented(const RunSummary &summary)
  {
    for (const auto &cycle : summary.cycles)
      if (cycle.incompressibility != "augmented Lagrangian")
        return false;
    return !summary.cycles.empty();
  }
} // namespace

int
main()
{
  const RunSummary whole = run(deck("whole", 0.1, ""));
  const RunSummary first = run(deck("first", 0.05, ""));
  const RunSummary rest  = run(deck("rest", 0.1, "first/checkpoint.dat"));

  report("the uninterrupted run converged, 10 steps, every one augmented",
         whole.converged && whole.cycles.size() == 11 && all_augmented(whole));
  report("the first run wrote its checkpoint at step 5",
         first.converged && first.checkpoint_step == 5 && std::filesystem::exists("first/checkpoint.dat"));
  report("the restarted run solved steps 6 to 10, every one augmented",
         rest.converged && rest.cycles.size() == 5 && rest.cycles.front().cycle == 6 && all_augmented(rest));
  bool same_iterations = rest.cycles.size() == 5 && whole.cycles.size() == 11;
  for (unsigned int i = 0; same_iterations && i < 5; ++i)
    same_iterations = rest.cycles[i].nonlinear_iterations == whole.cycles[6 + i].nonlinear_iterations;
  report("steps 6-10 take the uninterrupted run's Newton iterations, step for step", same_iterations);
  report("load-stroke.txt the uninterrupted run's, byte for byte",
         file_contents("rest/load-stroke.txt") == file_contents("whole/load-stroke.txt"));
  bool same_forces = !whole.cycles.back().boundary_force.empty();
  for (const auto &[id, force] : whole.cycles.back().boundary_force)
    {
      const auto other = rest.cycles.back().boundary_force.find(id);
      const double size = std::hypot(force[0], force[1]);
      same_forces &= other != rest.cycles.back().boundary_force.end() &&
                     std::hypot(force[0] - other->second[0], force[1] - other->second[1]) <= 1e-13 * std::max(size, 1.);
    }
  report("every boundary force at step 10 the same to 1e-13 of it", same_forces);
}
