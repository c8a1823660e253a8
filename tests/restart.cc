// A long run loses nothing: an incremental run that goes on from its
// checkpoint (Incremental/Restart from) ends with the result of the run that
// was not stopped, to the last bit. The scene holds every kind of state a
// step carries to the next: axisymmetric upsetting by a moving platen with
// Coulomb friction (contact states, stick and slip), the free side folding
// onto the platen (faces entering, the gaps' dies where they moved to),
// strain hardening (the carried strain), Adams-Bashforth 2 (v_{n-1}) and a
// new mesh at 39 % (after the restart at 30 %: the checkpoint's mesh is
// the moved one). Compared: load-stroke.txt byte for byte (every step's
// time, stroke, forces, volume, cell shape, contact events, strain, to 8
// digits) and the platen force at 50 % to 1e-12; the run's totals in
// summary.json. Then the same from the checkpoint a SIGINT leaves between
// steps (raised at the end of step 0: the step-0 state), and six bad
// restarts (another time step, no step left, not a checkpoint, no file,
// another velocity degree, another dimension), each one message naming the
// entry.
#include <dieflow/base/interrupt.h>
#include <dieflow/postprocess/summary.h>

#include "report.h"

#include <filesystem>

using namespace dieflow;

namespace
{
  std::string
  deck(const std::string &output, const double end_time, const std::string &restart_from, const double dt = 0.01)
  {
    std::ostringstream text;
    text << "set Geometry = axisymmetric\n"
         << "set Output directory = " << output << "\n"
         << "set Write VTU = false\n"
         << "set Problem = incremental\n"
         << "subsection Incremental\n"
         << "  set Time step = " << dt << "\n"
         << "  set End time = " << end_time << "\n"
         << "  set Remesh below Jacobian = 0.3\n"
         << "  set Checkpoint interval = 0\n"
         << "  set Restart from = " << restart_from << "\n"
         << "end\n"
         << "subsection Mesh\n"
         << "  set Source = box\n"
         << "  subsection Box\n"
         << "    set Lower corner = 0, 0\n"
         << "    set Upper corner = 5, 10\n"
         << "    set Subdivisions = 8, 16\n"
         << "  end\n"
         << "end\n"
         << "subsection Material\n"
         << "  set Law = Norton-Hoff\n"
         << "  set Consistency K = 1\n"
         << "  set Rate sensitivity m = 0.05\n"
         << "  set Minimum strain rate = 1e-4\n"
         << "  set Hardening exponent n = 0.2\n"
         << "  set Hardening strain eps0 = 0.05\n"
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

  /// Runs the deck @p text; its log goes to @p log (default: nowhere).
  RunSummary
  run(const std::string &text, std::ostream *log = nullptr)
  {
    std::ofstream("deck.prm") << text;
    ParameterHandler prm;
    read_deck("deck.prm", prm);
    std::ostringstream swallowed;
    return run_deck(prm, ".", log != nullptr ? *log : swallowed);
  }

  /// The rows of a load-stroke.txt (its lines that are no comment).
  unsigned int
  rows(const std::string &text)
  {
    std::istringstream in(text);
    unsigned int       n = 0;
    for (std::string line; std::getline(in, line);)
      n += !line.empty() && line[0] != '#';
    return n;
  }

  double
  platen_force(const RunSummary &summary)
  {
    return named_value(summary.cycles.back().quantities, "F_n[2]");
  }

  bool
  same_totals(const RunSummary &a, const RunSummary &b)
  {
    const StepTotals s = step_totals(a), t = step_totals(b);
    return s.steps == t.steps && s.largest_penetration == t.largest_penetration &&
           s.volume_change == t.volume_change && s.smallest_scaled_jacobian == t.smallest_scaled_jacobian &&
           s.faces_entered == t.faces_entered && s.faces_left == t.faces_left && s.remeshings == t.remeshings;
  }

  /// The message of a run that must refuse its deck, the checkpoint's path as FILE.
  void
  refused(const std::string &what, const std::string &text, const std::string &file)
  {
    try
      {
        run(text);
        std::cout << what << ": not refused" << std::endl;
      }
    catch (const InputError &error)
      {
        std::string message = error.what();
        for (std::size_t at; (at = message.find(file)) != std::string::npos;)
          message.replace(at, file.size(), "FILE");
        std::cout << what << ": " << message << std::endl;
      }
  }
} // namespace

int
main()
{
  const RunSummary whole = run(deck("whole", 0.5, ""));
  const RunSummary first = run(deck("first", 0.3, ""));
  const RunSummary rest  = run(deck("rest", 0.5, "first/checkpoint.dat"));

  bool new_mesh_after_30 = false;
  for (unsigned int n = 31; n < whole.cycles.size(); ++n)
    new_mesh_after_30 |= whole.cycles[n].step->remesh.has_value();
  report("the uninterrupted run converged, 50 steps, a new mesh after step 30",
         whole.converged && whole.cycles.size() == 51 && step_totals(whole).remeshings == 1 && new_mesh_after_30);
  report("the first run wrote its checkpoint at its last step, 30",
         first.converged && first.checkpoint_step == 30 && std::filesystem::exists("first/checkpoint.dat"));
  report("the restarted run solved steps 31 to 50 only",
         rest.converged && rest.cycles.size() == 20 && rest.cycles.front().cycle == 31 && rest.restart_step == 30);
  report("load-stroke.txt of the restarted run is the uninterrupted run's (51 rows), byte for byte",
         rows(file_contents("whole/load-stroke.txt")) == 51 &&
           file_contents("rest/load-stroke.txt") == file_contents("whole/load-stroke.txt"));
  report("platen force at 50 % the same to 1e-12",
         std::abs(platen_force(rest) / platen_force(whole) - 1) < 1e-12);
  report("the run's totals in summary.json the same (penetration, volume, shape, faces, new meshes)",
         same_totals(rest, whole));

  // A SIGINT at the end of step 0 stops the run before step 1 and leaves
  // the checkpoint of step 0.
  interrupt::install_handlers();
  SignalAtCycleEnd signal_at_step_end;
  std::ostream     log(&signal_at_step_end);
  const RunSummary stopped = run(deck("stopped", 0.5, ""), &log);
  interrupt::clear();
  report("a run stopped by SIGINT after step 0 left the checkpoint of step 0",
         stopped.interrupted && stopped.cycles.size() == 1 && stopped.checkpoint_step == 0 &&
           std::filesystem::exists("stopped/checkpoint.dat"));
  const RunSummary resumed = run(deck("resumed", 0.5, "stopped/checkpoint.dat"));
  report("going on from it gives the uninterrupted run's load-stroke.txt, byte for byte",
         resumed.converged && file_contents("resumed/load-stroke.txt") == file_contents("whole/load-stroke.txt"));

  refused("another time step", deck("bad", 0.5, "first/checkpoint.dat", 0.02), "first/checkpoint.dat");
  refused("no step after the checkpoint", deck("bad", 0.3, "first/checkpoint.dat"), "first/checkpoint.dat");
  std::ofstream("not-a-checkpoint.dat") << "load-stroke\n";
  refused("not a checkpoint", deck("bad", 0.5, "not-a-checkpoint.dat"), "not-a-checkpoint.dat");
  refused("no such file", deck("bad", 0.5, "missing.dat"), "missing.dat");
  refused("another velocity degree",
          deck("bad", 0.5, "first/checkpoint.dat") + "subsection Discretisation\n  set Velocity degree = 2\nend\n",
          "first/checkpoint.dat");
  // The same scene as a 3D block (plane strain, the third direction free).
  std::string three_d = deck("bad", 0.5, "first/checkpoint.dat");
  for (const auto &[from, to] : std::vector<std::pair<std::string, std::string>>{
         {"set Geometry = axisymmetric\n", "set Dimension = 3\n"},
         {"Lower corner = 0, 0\n", "Lower corner = 0, 0, 0\n"},
         {"Upper corner = 5, 10\n", "Upper corner = 5, 10, 5\n"},
         {"Subdivisions = 8, 16\n", "Subdivisions = 2, 4, 2\n"},
         {"Traction free ids = 4\n", "Traction free ids = 4, 5, 6\n"},
         {"Die velocities = 2: -5 0\n", "Die velocities = 2: -5 0 0\n"},
         {"Remesh below Jacobian = 0.3\n", "Remesh below Jacobian = 0\n"}})
    three_d.replace(three_d.find(from), from.size(), to);
  refused("another dimension", three_d, "first/checkpoint.dat");
}
