// A restart in 3D at velocity degree 2 from a periodic checkpoint loses
// nothing: the run that goes on from the checkpoint an uninterrupted run
// wrote at step 4 (Checkpoint interval = 4, the run going on to step 10)
// ends with that run's result, to the last bit. The scene carries every
// state a 3D step hands to the next: a quarter block upset by a moving
// platen with Coulomb friction (mu = 0.3: stick near the centre, slip
// outside, two tangent directions per node), strain hardening (the carried
// strain), Adams-Bashforth 2 (v_{n-1}) and a temperature field in time (the
// heat of deformation and friction, the platen chilling the block).
// Compared: load-stroke.txt byte for byte (every step's time, stroke,
// forces, volume, cell shape, contact events, strain, temperatures, to 8
// digits), the platen force and the mean, lowest and highest temperature at
// the end to 1e-12. restart.cc covers the 2D cases (a new mesh, SIGINT, the
// refusals). Checked by breaking: the contact states' normal forces read
// from a 3D checkpoint scaled by 1.5 fail the last three checks.
#include <dieflow/postprocess/summary.h>

#include "report.h"

#include <filesystem>

using namespace dieflow;

namespace
{
  std::string
  deck(const std::string &output, const std::string &restart_from)
  {
    std::ostringstream text;
    text << "set Dimension = 3\n"
         << "set Output directory = " << output << "\n"
         << "set Write VTU = false\n"
         << "set Problem = incremental\n"
         << "subsection Incremental\n"
         << "  set Time step = 0.04\n"
         << "  set End time = 0.4\n"
         << "  set Integrator = Adams-Bashforth 2\n"
         << "  set Checkpoint interval = 4\n"
         << "  set Restart from = " << restart_from << "\n"
         << "end\n"
         << "subsection Mesh\n"
         << "  set Source = box\n"
         << "  subsection Box\n"
         << "    set Lower corner = 0, 0, 0\n"
         << "    set Upper corner = 2, 2, 1\n"
         << "    set Subdivisions = 2, 2, 2\n"
         << "  end\n"
         << "end\n"
         << "subsection Discretisation\n"
         << "  set Velocity degree = 2\n"
         << "end\n"
         << "subsection Material\n"
         << "  set Law = Norton-Hoff\n"
         << "  set Consistency K = 100\n"
         << "  set Rate sensitivity m = 0.2\n"
         << "  set Minimum strain rate = 1e-4\n"
         << "  set Hardening exponent n = 0.2\n"
         << "  set Hardening strain eps0 = 0.05\n"
         << "  set Temperature = 700\n"
         << "end\n"
         << "subsection Boundary conditions\n"
         << "  set Prescribed velocity ids =\n"
         << "  set Symmetry ids = 1, 3, 5\n"
         << "  set Slip wall ids =\n"
         << "  set Traction free ids = 2, 4\n"
         << "end\n"
         << "subsection Contact\n"
         << "  set Die ids = 6\n"
         << "  set Friction law = Coulomb\n"
         << "  set Friction coefficients = 6: 0.3\n"
         << "  set Die velocities = 6: 0 0 -1\n"
         << "end\n"
         << "subsection Heat\n"
         << "  set Model = transient\n"
         << "  set Density = 7800\n"
         << "  set Specific heat = 500\n"
         << "  set Conductivity = 30\n"
         << "  set Prescribed temperature ids =\n"
         << "  set Heat transfer coefficients = 6: 10000\n"
         << "  set Ambient temperatures = 6: 400\n"
         << "end\n"
         << "subsection Refinement\n"
         << "  set Probe point =\n"
         << "end\n";
    return text.str();
  }

  /// A log that keeps a copy of @p from when the run's step @p step ends
  /// (its "  converged:" line): the checkpoint on disk between two steps.
  class CopyAtStepEnd : public std::streambuf
  {
  public:
    CopyAtStepEnd(const unsigned int step, const std::string &from, const std::string &to)
      : step(step)
      , from(from)
      , to(to)
    {}

  protected:
    int
    overflow(const int c) override
    {
      text += static_cast<char>(c);
      if (text.size() >= 12 && text.compare(text.size() - 12, 12, "  converged:") == 0 && steps_ended++ == step)
        std::filesystem::copy_file(from, to, std::filesystem::copy_options::overwrite_existing);
      return c;
    }

  private:
    const unsigned int step;
    const std::string  from, to;
    std::string        text;
    unsigned int       steps_ended = 0;
  };

  RunSummary
  run(const std::string &text, std::ostream &log)
  {
    std::ofstream("deck.prm") << text;
    ParameterHandler prm;
    read_deck("deck.prm", prm);
    return run_deck(prm, ".", log);
  }
} // namespace

int
main()
{
  // At the end of step 5 the file holds step 4's periodic checkpoint.
  CopyAtStepEnd copy(5, "whole/checkpoint.dat", "step4.dat");
  std::ostream  copy_log(&copy);
  const RunSummary whole = run(deck("whole", ""), copy_log);
  std::ostringstream swallowed;
  const RunSummary   rest = run(deck("rest", "step4.dat"), swallowed);

  const ContactCounts nodes = whole.cycles[4].contact_nodes;
  report("the uninterrupted run converged, 10 steps, sticking and slipping on the platen at step 4",
         whole.converged && whole.cycles.size() == 11 && nodes.stick > 0 && nodes.slip > 0);
  report("the copy is a periodic checkpoint: the restarted run solved steps 5 to 10 only",
         rest.converged && rest.restart_step == 4 && rest.cycles.size() == 6 && rest.cycles.front().cycle == 5);
  report("load-stroke.txt of the restarted run is the uninterrupted run's, byte for byte",
         file_contents("rest/load-stroke.txt") == file_contents("whole/load-stroke.txt"));
  const double F_whole = named_value(whole.cycles.back().quantities, "F_n[6]");
  const double F_rest  = named_value(rest.cycles.back().quantities, "F_n[6]");
  report("platen force at the end the same to 1e-12 (and not zero)",
         F_whole != 0 && std::abs(F_rest / F_whole - 1) < 1e-12);
  const HeatRecord &a = *whole.cycles.back().heat, &b = *rest.cycles.back().heat;
  report("mean, lowest and highest temperature at the end the same to 1e-12 (the platen chilled the block, unevenly)",
         std::abs(a.T_mean - b.T_mean) < 1e-12 * a.T_mean && std::abs(a.T_min - b.T_min) < 1e-12 * a.T_min &&
           std::abs(a.T_max - b.T_max) < 1e-12 * a.T_max && a.T_mean < 700 && a.T_max - a.T_min > 1);
}
