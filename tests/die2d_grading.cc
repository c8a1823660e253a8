// The die2d mesh at its die corners (benchmarks/die2d.md, beta = 70 deg):
//  - the wall corners found from the mesh are exactly B, C, D and E (where
//    the walls turn or meet another part); A and F (symmetry line meets the
//    inlet, the outlet) are not wall corners;
//  - layout "bisected": the cells at C have the angle (180 - beta)/2 = 55
//    deg there, those at D (interior angle 180 + beta) 125 deg; layout
//    "blocks" leaves 20 deg at C and 160 deg at D;
//  - Corner refinements = k: every cell at a wall corner is refined k times
//    (cells 2^-k as large there), and no cell more than k times;
//  - the bisected layout's ram force is closer to the N1 reference 2468.78 N/mm
//    (doc/benchmarks.md) than the blocks layout's, by more than 3x at 16
//    cells across.
#include <dieflow/mesh/geometry.h>
#include <dieflow/mesh/singular_points.h>
#include <dieflow/problem/run.h>

#include "report.h"

#include <deal.II/grid/tria.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace dieflow;

namespace
{
  /// The angles (degrees) of the cells at vertex @p p, at p.
  std::vector<double>
  angles_at(const Triangulation<2> &tria, const Point<2> &p)
  {
    std::vector<double> angles;
    // Vertex v of a quadrilateral: its two edge neighbours in lexicographic order.
    const unsigned int neighbours[4][2] = {{1, 2}, {0, 3}, {0, 3}, {1, 2}};
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (cell->vertex(v).distance(p) < 1e-9)
          {
            const auto a = cell->vertex(neighbours[v][0]) - p, b = cell->vertex(neighbours[v][1]) - p;
            angles.push_back(std::acos(a * b / a.norm() / b.norm()) * 180 / dealii::numbers::PI);
          }
    return angles;
  }

  std::string
  corner_name(const Die2dGeometry &g, const Point<2> &p)
  {
    for (const char c : std::string("ABCDEF"))
      if (g.corner(c).distance(p) < 1e-9)
        return std::string(1, c);
    return "?";
  }

  double
  ram_force(const std::string &layout)
  {
    const RunSummary s = run_deck_text("subsection Mesh\n subsection Die2d\n  set Layout = " + layout +
                                       "\n  set Cells across = 16\n end\nend\n");
    return s.cycles.back().boundary_force.at(1)[0];
  }
} // namespace

int
main()
{
  for (const std::string layout : {"bisected", "blocks"})
    {
      MeshParameters parameters;
      parameters.die2d.cells_across = 8;
      parameters.die2d.layout       = layout == "blocks" ? Die2dGeometry::Layout::blocks : Die2dGeometry::Layout::bisected;
      Triangulation<2> tria;
      make_mesh(parameters, tria);
      const Die2dGeometry &g = parameters.die2d;

      std::string names;
      for (const auto &p : wall_corners(tria, {Die2dGeometry::container_id, Die2dGeometry::die_id}))
        names += corner_name(g, p);
      std::sort(names.begin(), names.end());
      report(layout + ": wall corners " + names, names == "BCDE");

      const auto at_c = angles_at(tria, g.corner('C')), at_d = angles_at(tria, g.corner('D'));
      std::cout << layout << ": smallest cell angle at C " << std::lround(*std::min_element(at_c.begin(), at_c.end()))
                << " deg, largest at D " << std::lround(*std::max_element(at_d.begin(), at_d.end())) << " deg"
                << std::endl;

      const unsigned int levels = 3;
      grade_towards(wall_corners(tria, {3, 4}), levels, 1, tria);
      bool corner_cells_at_level = true;
      for (const auto &cell : tria.active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          for (const char c : std::string("BCDE"))
            if (cell->vertex(v).distance(g.corner(c)) < 1e-9)
              corner_cells_at_level &= cell->level() == static_cast<int>(levels);
      report(layout + ": every cell at B, C, D and E refined 3 times", corner_cells_at_level);
      unsigned int finest = 0;
      for (const auto &cell : tria.active_cell_iterators())
        finest = std::max(finest, static_cast<unsigned int>(cell->level()));
      report(layout + ": no cell refined more than 3 times", finest == levels);
    }

  const double reference = 2468.78;
  const double bisected = ram_force("bisected"), blocks = ram_force("blocks");
  report("bisected layout more than 3x closer to the converged ram force than blocks",
         std::abs(bisected - reference) < std::abs(blocks - reference) / 3);
  std::cout << "ram force error at 16 cells across: bisected " << std::lround(100 * (bisected / reference - 1))
            << " %, blocks " << std::lround(100 * (blocks / reference - 1)) << " %" << std::endl;
}
