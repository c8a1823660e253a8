// The steady free surface in the run's ParaView index: solution.pvd lists, at each cycle, the fields' VTU
// (part 0) and the cycle's free-surface polyline (part 1), and that polyline is the exact settled surface.
//
// The plug flow of tests/free_surface_plug_flow.prm (metal in at v = (1, 0)
// under a wavy free surface, id 6) over two cycles of global refinement,
// with VTU output. Its only steady flow is the plug flow under the flat
// surface y = 1 from x = 0 to 4: each cycle's free-surface-NN.vtp must hold
// the nodes of that line (x rising from the fixed corners 0 to 4, to 1e-9;
// y = 1 to 1e-6: the settled tolerance, 1e-7 of the length 4, lets a node
// lie 4e-7 off it, measured 3e-9), as many as the cycle's free surface in
// summary.json, at its points (the .vtp's 10 digits: 1e-9). Breaking it: with deal.II's write_pvd_record (every file part 0)
// the part check fails; without the cycle's file in the index, the listing
// check fails.
#include "report.h"

#include <filesystem>
#include <regex>

using namespace dieflow;

namespace
{
  /// The points of a free-surface .vtp file (x, y per point).
  std::vector<std::array<double, 2>>
  polyline_points(const std::string &file)
  {
    const std::string text  = file_contents(file);
    const auto        begin = text.find("<Points>");
    const auto        start = text.find('>', text.find("<DataArray", begin)) + 1;
    const auto        end   = text.find("</DataArray>", start);
    std::istringstream in(begin == std::string::npos ? std::string() : text.substr(start, end - start));
    std::vector<std::array<double, 2>> points;
    double                             x, y, z;
    while (in >> x >> y >> z)
      points.push_back({{x, y}});
    return points;
  }
} // namespace

int
main()
{
  std::filesystem::remove_all("results");
  // The deck without its Test block (read by the check driver only), its
  // mesh from the source tree, two cycles, and its fields written.
  std::stringstream deck;
  deck << std::regex_replace(std::regex_replace(test_deck("free_surface_plug_flow.prm"),
                                                std::regex("set Write VTU[^\\n]*"), ""),
                             std::regex("meshes/"), std::string(SOURCE_DIR) + "/meshes/");
  deck << "set Write VTU = true\nsubsection Refinement\n  set Cycles = 2\n  set Strategy = global\nend\n";
  const RunSummary summary = run_deck_text(deck.str());

  report("the run converges over two cycles", summary.converged && summary.cycles.size() == 2);
  const std::string pvd = file_contents("results/solution.pvd");
  bool listed = true, parts = true, exact = true, as_summary = true;
  for (unsigned int c = 0; c < summary.cycles.size(); ++c)
    {
      const std::string n   = c < 10 ? "0" + std::to_string(c) : std::to_string(c);
      const std::string vtu = "timestep=\"" + std::to_string(c) + "\" group=\"\" part=\"0\" file=\"solution-" + n + ".vtu\"";
      const std::string vtp =
        "timestep=\"" + std::to_string(c) + "\" group=\"\" part=\"1\" file=\"free-surface-" + n + ".vtp\"";
      listed = listed && pvd.find("file=\"free-surface-" + n + ".vtp\"") != std::string::npos &&
               std::filesystem::exists("results/free-surface-" + n + ".vtp");
      parts = parts && pvd.find(vtu) != std::string::npos && pvd.find(vtp) != std::string::npos;

      const auto points = polyline_points("results/free-surface-" + n + ".vtp");
      exact             = exact && points.size() > 2 && std::abs(points.front()[0]) < 1e-9 &&
              std::abs(points.back()[0] - 4) < 1e-9;
      for (unsigned int i = 0; i < points.size(); ++i)
        exact = exact && std::abs(points[i][1] - 1) < 1e-6 && (i == 0 || points[i][0] > points[i - 1][0]);

      std::vector<std::array<double, 2>> expected;
      const auto &                       record = summary.cycles[c].free_surface;
      if (record)
        for (const auto &stretch : record->lines)
          for (const auto &p : stretch.points)
            expected.push_back({{p[0], p[1]}});
      as_summary = as_summary && expected.size() == points.size();
      for (unsigned int i = 0; as_summary && i < points.size(); ++i)
        as_summary = std::abs(points[i][0] - expected[i][0]) < 1e-9 && std::abs(points[i][1] - expected[i][1]) < 1e-9;
    }
  report("solution.pvd lists each cycle's free-surface polyline, and the file is there", listed);
  report("each cycle's VTU is its part 0 and the polyline its part 1 (one block each in ParaView)", parts);
  report("each cycle's polyline is the settled surface y = 1 (1e-6) from x = 0 to 4 (1e-9)", exact);
  report("each cycle's polyline has summary.json's free-surface points (1e-9)", as_summary);
}
