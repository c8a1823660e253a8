// A scene does only the work it needs, as the counters of summary.json show:
//  - a Newtonian deck without contact (slip walls) is linear: one linear
//    solve, no contact assembly, no friction term, no pressure recovery;
//    with every output switch off, the output directory holds summary.json
//    and study.txt only;
//  - the same deck with VTU output recovers the pressure once and writes it;
//  - contact with mu = 0 everywhere assembles contact but no friction term;
//    with the paper's friction (N1) there are friction terms (the counter
//    counts);
//  - a nonlinear contact solve (N1, P1) costs at most 2 linear solves per
//    Newton iteration (one per iteration, plus the Newtonian start and any
//    Picard fallback of the line search);
//  - the direct solver orders and factorises symbolically once per mesh and
//    kind (Cholesky, LU) and reuses that for every nonlinear iteration; the
//    symmetric Newtonian system goes to CHOLMOD, a slipping friction's
//    non-symmetric one to UMFPACK.
#include "report.h"

#include <filesystem>
#include <set>

using namespace dieflow;

namespace
{
  const std::string coarse = "subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = 8\n end\nend\n";
  const std::string no_contact =
    "subsection Boundary conditions\n set Slip wall ids = 3, 4\nend\nsubsection Contact\n set Die ids =\nend\n";
  const std::string outputs_off = "set Write gnuplot = false\nset Write mesh SVG = false\n";

  std::set<std::string>
  files_in(const std::string &directory)
  {
    std::set<std::string> names;
    for (const auto &entry : std::filesystem::directory_iterator(directory))
      names.insert(entry.path().filename().string());
    return names;
  }

  /// One factorisation per linear solve, and one ordering per kind used.
  bool
  symbolic_factorisation_reused(const CycleSummary &c)
  {
    const LinearSolverCounts &n     = c.linear_counts;
    const unsigned int        kinds = (n.cholesky_factorisations > 0 ? 1 : 0) + (n.lu_factorisations > 0 ? 1 : 0);
    return n.cholesky_factorisations + n.lu_factorisations == c.linear_solves && n.symbolic_analyses == kinds &&
           c.linear_solves > 2;
  }

  bool
  at_most_two_solves_per_iteration(const CycleSummary &c)
  {
    return c.converged && c.linear_solves <= 2 * c.nonlinear_iterations;
  }
} // namespace

int
main()
{
  std::filesystem::remove_all("results");
  const CycleSummary linear = run_deck_text(outputs_off + coarse + no_contact).cycles.back();
  report("Newtonian without contact: one linear solve", linear.converged && linear.linear_solves == 1);
  report("... no contact assembly, no friction term",
         linear.contact_assemblies == 0 && linear.friction_terms == 0);
  report("... no pressure recovered", linear.pressure_recoveries == 0);
  report("... one Cholesky factorisation (CHOLMOD: the system is symmetric)",
         linear.linear_counts.cholesky_factorisations == 1 && linear.linear_counts.lu_factorisations == 0);
  report("... only summary.json and study.txt written",
         files_in("results") == std::set<std::string>{"summary.json", "study.txt"});

  std::filesystem::remove_all("results");
  const CycleSummary with_vtu =
    run_deck_text(outputs_off + "set Write VTU = true\n" + coarse + no_contact).cycles.back();
  report("with VTU output: the pressure recovered once and written",
         with_vtu.pressure_recoveries == 1 && files_in("results").count("solution-00.vtu") == 1);

  const CycleSummary frictionless =
    run_deck_text(outputs_off + coarse + "subsection Contact\n set Friction coefficients = 3: 0, 4: 0\nend\n")
      .cycles.back();
  report("mu = 0: contact assembled, no friction term",
         frictionless.converged && frictionless.contact_assemblies > 0 && frictionless.friction_terms == 0);

  const CycleSummary n1 = run_deck_text(outputs_off + coarse).cycles.back();
  report("N1 (mu = 0.1 on the die): friction terms assembled", n1.converged && n1.friction_terms > 0);
  report("N1: at most 2 linear solves per Newton iteration", at_most_two_solves_per_iteration(n1));
  report("N1: slipping friction factorised by LU", n1.linear_counts.lu_factorisations > 0);
  report("N1: one symbolic factorisation per kind, reused", symbolic_factorisation_reused(n1));

  const CycleSummary p1 = run_deck_text(outputs_off + coarse +
                                        "subsection Material\n set Law = Norton-Hoff\n set Consistency K = 0.834\n"
                                        " set Rate sensitivity m = 0.2\n set Minimum strain rate = 1e-4\nend\n")
                            .cycles.back();
  report("P1: at most 2 linear solves per Newton iteration", at_most_two_solves_per_iteration(p1));
  report("P1: one symbolic factorisation per kind, reused", symbolic_factorisation_reused(p1));
}
