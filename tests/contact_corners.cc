// The rules at the corners of the die, on die2d N1 (8 cells across), read
// from the die-wall profiles the program writes:
//  - B, where the container wall meets the inlet: the prescribed velocity
//    wins; B is no contact node;
//  - C, the die entry, a convex corner of the metal: one unilateral
//    condition per wall, both active, so the node is at rest (stick);
//  - D, the die exit, re-entrant: one condition per wall; the die face holds
//    and the land lets go, so D slides along the die face and leaves the
//    land: its velocity is its slip along the face, whose normal component
//    on the land is negative, and the land carries no pressure there;
//  - E, where the land meets the free outlet, is a contact node.
#include <dieflow/problem/run.h>

#include "report.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

using namespace dieflow;

namespace
{
  struct Row
  {
    double s, x, y, pressure, friction, normal_velocity, slip_velocity;
    int    status;
  };

  std::vector<Row>
  profile(const std::string &file)
  {
    std::ifstream    in(file);
    std::vector<Row> rows;
    std::string      line;
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#')
        {
          std::istringstream l(line);
          Row                r;
          l >> r.s >> r.x >> r.y >> r.pressure >> r.friction >> r.normal_velocity >> r.slip_velocity >> r.status;
          rows.push_back(r);
        }
    return rows;
  }

  std::vector<Row>
  at(const std::vector<Row> &rows, const double x, const double y)
  {
    std::vector<Row> found;
    for (const auto &r : rows)
      if (std::abs(r.x - x) < 1e-6 && std::abs(r.y - y) < 1e-6)
        found.push_back(r);
    return found;
  }
} // namespace

int
main()
{
  report("die2d N1 converges",
         run_deck_text("subsection Mesh\n subsection Die2d\n  set Layout = blocks\n  set Cells across = 8\n end\nend\n").converged);

  const auto   container = profile("results/die-profile-3.dat");
  const auto   die       = profile("results/die-profile-4.dat");
  const double x_d       = 14.25 / std::tan(70 * M_PI / 180);

  report("B (inlet corner) is no contact node", at(container, -20, 19).empty());

  const auto c3 = at(container, 0, 19), c4 = at(die, 0, 19);
  report("C is on both walls, at rest, sticking",
         c3.size() == 1 && c4.size() == 1 && c3[0].status == 1 && c4[0].status == 1 &&
           c3[0].slip_velocity == 0 && c3[0].normal_velocity == 0 && c4[0].slip_velocity == 0 &&
           c3[0].pressure > 0 && c4[0].pressure > 0);

  const auto d = at(die, x_d, 4.75);
  bool       d_ok = d.size() == 2;
  if (d_ok)
    {
      // The die face's row comes first along the wall (C-D-E).
      const Row &face = d[0], &land = d[1];
      const double sin_beta = std::sin(70 * M_PI / 180);
      d_ok = face.status == 2 && std::abs(face.normal_velocity) < 1e-9 * std::abs(face.slip_velocity) &&
             face.pressure > 0 && land.status == 0 &&
             land.pressure == 0 && land.normal_velocity < 0 &&
             std::abs(land.normal_velocity - face.slip_velocity * sin_beta) < 1e-6 * std::abs(land.normal_velocity); // 8 digits in the file
    }
  report("D slides along the die face and leaves the land", d_ok);

  report("E (land and free outlet) is a contact node", at(die, x_d + 15, 4.75).size() == 1);
}
