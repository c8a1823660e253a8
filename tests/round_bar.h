// The round bar's Mesh subsection as the 3D tests write it (parameters/roundbar.prm's die: 38 to 9.5 mm, a 70-degree cone, graded).
#ifndef dieflow_tests_round_bar_h
#define dieflow_tests_round_bar_h

#include <string>

/// The Mesh subsection: Source = @p source ("round bar quarter", or
/// "die2d" for the axisymmetric section), @p cells across, Grading
/// exponent 2.5, no corner refinements.
inline std::string
round_bar_mesh(const std::string &source, const unsigned int cells = 4)
{
  return "subsection Mesh\n"
         "  set Source = " +
         source +
         "\n  set Corner refinements = 0\n"
         "  subsection Die2d\n"
         "    set Inlet half height = 19\n    set Outlet half height = 4.75\n    set Die angle = 70\n"
         "    set Container length = 20\n    set Land length = 15\n"
         "    set Cells across = " +
         std::to_string(cells) +
         "\n    set Grading exponent = 2.5\n"
         "  end\n"
         "end\n";
}

#endif
