// A die given as a surface (Contact/Die surfaces) in time (Problem =
// incremental), where the metal moves over it: die2d's die face C-D and land
// D-E, and wall nodes placed where a step's move leaves them (exact checks):
//  1. the metal's corner node slid 0.05 mm past the die exit D onto the
//     land, with its two directions (the die face's and the land's): in a
//     steady run an input error naming Contact/Die surfaces; in time one
//     direction, the land's facet D-E and normal (0, 1), with the weights
//     and lengths of both (the node is on one wall now);
//  2. a node of a land face 0.05 mm off the land (it separated), with its
//     own face's tilted normal: attach leaves it as it is (no facet within
//     1e-6 of the die's size), and ContactGaps::close_gaps gives it the
//     land's facet and normal and the gap rate of a gap of +0.05 mm (the
//     integrator's gap_rate(g), here g / dt with dt = 0.01: 5 mm/s), so
//     that the active set lets it close the gap, no more;
//  3. a node 0.05 mm inside the land's die: a gap rate of -5 mm/s (it comes
//     back out onto the die by the end of the step);
//  4. a node past the die's end E: no facet under it, so no wall: it is
//     no wall node any more (its own face would be a phantom die);
//  5. the metal's corner that went on past D along the die face's line,
//     0.15 mm under the land, with its die-face direction and a land-side
//     one: the die-face direction faces no facet (the die face ends at D;
//     the land's normal is 70 degrees off) and is dropped, a phantom wall
//     that would hold the metal under the land; the land-side one takes
//     the land and the gap rate of +0.15 mm, 15 mm/s;
//  6. a node 0.02 mm under the die face just above D (off it), whose two
//     faces meet at 10 degrees (a new mesh's node): both its directions
//     take the die face's facet under it, and are one direction (weights
//     0.3 + 0.5, gap rate 2 mm/s): held twice along one normal it would
//     count as held by two walls, at rest, while it slides.
#include <dieflow/contact/die_surface.h>
#include <dieflow/incremental/contact_gaps.h>

#include "report.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <iostream>

using namespace dieflow;
using dealii::Point;

namespace
{
  const double x_d = 14.25 / std::tan(70. * dealii::numbers::PI / 180.);
  const Point<2> C(0, 19), D(x_d, 4.75), E(x_d + 15, 4.75);

  WallDirection<2>
  direction(const Tensor<1, 2> &normal, const double weight)
  {
    WallDirection<2> d;
    d.normal = normal / normal.norm();
    d.id     = 4;
    d.weight = weight;
    d.length = 2 * weight;
    d.facet  = {{Point<2>(), Point<2>(1, 0)}};
    return d;
  }

  WallNode<2>
  node_at(const Point<2> &x, const std::vector<WallDirection<2>> &directions)
  {
    WallNode<2> node;
    node.position   = x;
    node.vertex     = 0;
    node.directions = directions;
    return node;
  }
} // namespace

int
main()
{
  DieSurface<2> die;
  die.set_facets({{{{C, D}}, {}}, {{{D, E}}, {}}});
  const std::map<BoundaryId, DieSurface<2>> surfaces{{4, die}};
  const Tensor<1, 2> cone_normal({std::sin(70. * dealii::numbers::PI / 180.), std::cos(70. * dealii::numbers::PI / 180.)});
  const Tensor<1, 2> land_normal({0., 1.});

  // 1. The corner node past D.
  const Point<2>           past_d(x_d + 0.05, 4.75);
  std::vector<WallNode<2>> corner{node_at(past_d, {direction(cone_normal, 0.3), direction(land_normal, 0.5)})};
  try
    {
      std::vector<WallNode<2>> steady = corner;
      attach_die_surfaces(surfaces, 30., false, steady);
      report("steady: a corner node past the die exit is refused", false);
    }
  catch (const InputError &e)
    {
      report("steady: a corner node past the die exit is refused, naming Contact/Die surfaces",
             std::string(e.what()).find("Contact/Die surfaces") != std::string::npos);
    }
  attach_die_surfaces(surfaces, 30., true, corner);
  const auto &joined = corner[0].directions;
  report("in time: the corner node past D has one direction, the land's facet D-E and normal (0, 1)",
         joined.size() == 1 && joined[0].facet[0].distance(D) < 1e-12 && joined[0].facet[1].distance(E) < 1e-12 &&
           near(joined[0].normal[0], 0) && near(joined[0].normal[1], 1));
  report("in time: its weight and length are both walls' (0.8, 1.6)",
         joined.size() == 1 && near(joined[0].weight, 0.8) && near(joined[0].length, 1.6));

  // 2-4. Nodes off the die.
  const Tensor<1, 2> tilted({0.1, 1.});
  std::vector<WallNode<2>> off{node_at(Point<2>(x_d + 1, 4.70), {direction(tilted, 0.5)}),
                               node_at(Point<2>(x_d + 1, 4.80), {direction(tilted, 0.5)}),
                               node_at(Point<2>(x_d + 16, 4.70), {direction(tilted, 0.5)}),
                               node_at(Point<2>(x_d + 0.15 / std::tan(70. * dealii::numbers::PI / 180.), 4.60),
                                       {direction(cone_normal, 0.3), direction(tilted, 0.5)})};
  const double       turn = 10. * dealii::numbers::PI / 180.;
  const Tensor<1, 2> kinked({std::cos(turn) * cone_normal[0] - std::sin(turn) * cone_normal[1],
                             std::sin(turn) * cone_normal[0] + std::cos(turn) * cone_normal[1]});
  const Point<2>     under_face = C + 0.99 * (D - C) - 0.02 * cone_normal;
  off.push_back(node_at(under_face, {direction(cone_normal, 0.3), direction(kinked, 0.5)}));
  attach_die_surfaces(surfaces, 30., true, off);
  report("in time: nodes off the die keep their own normal and facet after attach",
         off[0].directions[0].normal * tilted > 0.99 * tilted.norm() && off[0].directions[0].facet[1][0] == 1.);

  dealii::Triangulation<2> triangulation;
  dealii::GridGenerator::hyper_cube(triangulation, 0, 1, true);
  ContactGaps<2> gaps;
  gaps.initialize(triangulation, {4}, surfaces, {1});
  const double dt = 0.01;
  gaps.close_gaps(off, {4}, 1., std::cos(30. * dealii::numbers::PI / 180.),
                  [&](const WallNode<2> &, const WallDirection<2> &, const double g) { return g / dt; });
  const auto &separated = off[0].directions[0];
  report("close_gaps: a node 0.05 mm off the land takes the land's facet and normal (0, 1)",
         separated.facet[0].distance(D) < 1e-12 && near(separated.normal[0], 0) && near(separated.normal[1], 1));
  report("close_gaps: and the gap rate of g = +0.05 mm, 5 mm/s", near(separated.gap_rate, 5, 1e-9));
  report("close_gaps: a node 0.05 mm inside the die: gap rate -5 mm/s", near(off[1].directions[0].gap_rate, -5, 1e-9));
  report("close_gaps: a node past the die's end is no wall node any more",
         off.size() == 4 && off[2].position[0] < x_d + 1);
  const auto &corner_under = off[off.size() - 2].directions;
  report("close_gaps: the corner past D under the land keeps only its land-side direction, the land's normal",
         corner_under.size() == 1 && near(corner_under[0].normal[0], 0) && near(corner_under[0].normal[1], 1) &&
           near(corner_under[0].weight, 0.5));
  report("close_gaps: and the gap rate of g = +0.15 mm, 15 mm/s",
         corner_under.size() == 1 && near(corner_under[0].gap_rate, 15, 1e-9));
  const auto &one_wall = off.back().directions;
  report("close_gaps: a node under the die face with a kinked pair of faces has one direction, the die face's normal",
         one_wall.size() == 1 && near(one_wall[0].normal * cone_normal, 1));
  report("close_gaps: with both faces' weight 0.8 and the gap rate of g = +0.02 mm, 2 mm/s",
         one_wall.size() == 1 && near(one_wall[0].weight, 0.8) && near(one_wall[0].gap_rate, 2, 1e-9));
  return 0;
}
