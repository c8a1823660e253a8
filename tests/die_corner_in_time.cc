// A corner of a die that went into the metal between two of its boundary
// nodes (Problem = incremental, ContactGaps::update): die2d's die face C-D
// and land D-E as a die surface, and one cell whose top edge, a free
// surface, runs from a node on the die face before the exit D to a node
// past D under the land, so that D lies inside the metal (exact checks):
//  1. the node whose move onto D changes the area less (by the triangle its
//     two boundary neighbours span with the move, computed here from the
//     coordinates) goes onto D, exactly; the other stays; the overlap (D's
//     distance under the edge, computed here) is reported as the step's
//     penetration, and the area changes by that triangle;
//  2. a cell so thin under the node of the smaller change that its move
//     would fold the cell over (its corner at D reflex): the other node
//     goes onto D, and the cell stays uninverted;
//  3. the edge passing under D (D outside the metal): nothing moves,
//     penetration 0;
//  4. a straight die (C-D-E on one line, D no corner) with the edge over D:
//     nothing moves.
#include <dieflow/contact/die_surface.h>
#include <dieflow/incremental/contact_gaps.h>
#include <dieflow/incremental/time_stepping.h>

#include "report.h"

#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <iostream>

using namespace dieflow;
using dealii::Point;

namespace
{
  const double   angle = 70. * dealii::numbers::PI / 180.;
  const double   x_d   = 14.25 / std::tan(angle);
  const Point<2> C(0, 19), D(x_d, 4.75), E(x_d + 15, 4.75);

  double
  cross(const Tensor<1, 2> &u, const Tensor<1, 2> &v)
  {
    return u[0] * v[1] - u[1] * v[0];
  }

  /// One cell: bottom left, bottom right, top left (a), top right (b); the
  /// top edge is free (id 6), the others a wall the update leaves (id 5).
  void
  one_cell(dealii::Triangulation<2> &triangulation, const std::array<Point<2>, 4> &x)
  {
    triangulation.clear();
    dealii::CellData<2> cell;
    cell.vertices = {0, 1, 2, 3};
    triangulation.create_triangulation(std::vector<Point<2>>(x.begin(), x.end()), {cell}, dealii::SubCellData());
    // Face 3 joins vertices 2 and 3 (deal.II's numbering).
    for (const unsigned int f : triangulation.begin_active()->face_indices())
      triangulation.begin_active()->face(f)->set_boundary_id(f == 3 ? 6 : 5);
  }

  struct Outcome
  {
    std::vector<Point<2>> vertices;
    double                penetration;
    double                area;
  };

  Outcome
  update(dealii::Triangulation<2> &triangulation, const DieSurface<2> &die)
  {
    ContactGaps<2> gaps;
    gaps.initialize(triangulation, {4}, {{4, die}}, {6});
    const auto             before = triangulation.get_vertices();
    const GapUpdate        update = gaps.update(before, std::vector<bool>(before.size(), false), triangulation,
                                         std::cos(10. * dealii::numbers::PI / 180.));
    const auto &           x      = triangulation.get_vertices();
    const Tensor<1, 2>     d1 = x[3] - x[0], d2 = x[2] - x[1];
    return {x, update.penetration, 0.5 * std::abs(cross(d1, d2))};
  }

  /// D's distance under the edge a-b (positive: inside the metal below it).
  double
  depth_under(const Point<2> &a, const Point<2> &b)
  {
    const Tensor<1, 2> along = (b - a) / (b - a).norm();
    return cross(along, D - a) * -1.;
  }
} // namespace

int
main()
{
  DieSurface<2> die;
  die.set_facets({{{{C, D}}, {}}, {{{D, E}}, {}}});
  const Tensor<1, 2> down_the_face = (D - C) / (D - C).norm();
  dealii::Triangulation<2> triangulation;

  // 1. a on the die face 0.1 before D, b 0.15 past D under the land.
  {
    const Point<2> a = D - 0.1 * down_the_face, b(x_d + 0.15, 4.70);
    const std::array<Point<2>, 4> x{{Point<2>(x_d - 0.3, 3.5), Point<2>(x_d + 0.3, 3.5), a, b}};
    one_cell(triangulation, x);
    const double area_before = 0.5 * std::abs(cross(x[3] - x[0], x[2] - x[1]));
    // Boundary neighbours: a's are the bottom left vertex and b, b's are a and the bottom right.
    const double move_a = 0.5 * std::abs(cross(b - x[0], D - a)), move_b = 0.5 * std::abs(cross(x[1] - a, D - b));
    const double depth  = depth_under(a, b);
    const Outcome out   = update(triangulation, die);
    const unsigned int moved = move_a <= move_b ? 2 : 3, kept = 5 - moved;
    std::cout << "D under the edge by " << depth << " mm; moving a changes the area by " << move_a << ", b by "
              << move_b << std::endl;
    report("the node of the smaller change goes onto D, exactly", out.vertices[moved].distance(D) < 1e-14);
    report("the other stays (to round-off)", out.vertices[kept].distance(x[kept]) < 1e-14);
    report("the overlap is the step's penetration", depth > 0.01 && near(out.penetration, depth));
    report("the area changes by that triangle", near(std::abs(out.area - area_before), std::min(move_a, move_b)));
  }

  // 2. A cell 0.01 thin under a (0.02 before D): a's move would fold it
  //    (its corner at D turns reflex); with b's move the cell stays convex.
  {
    const Point<2> a = D - 0.02 * down_the_face, b(x_d + 0.3, 4.70);
    const std::array<Point<2>, 4> x{{a - Tensor<1, 2>({0., 0.01}), Point<2>(x_d + 0.05, 4.40), a, b}};
    one_cell(triangulation, x);
    const double move_a = 0.5 * std::abs(cross(b - x[0], D - a)), move_b = 0.5 * std::abs(cross(x[1] - a, D - b));
    const Outcome out   = update(triangulation, die);
    report("thin cell: moving a would change the area less", move_a < move_b);
    report("thin cell: a stays (to round-off: it lies on the die face), b goes onto D",
           out.vertices[2].distance(a) < 1e-14 && out.vertices[3].distance(D) < 1e-14);
    report("thin cell: the cell stays uninverted", smallest_scaled_jacobian(triangulation) > 0);
  }

  // 3. The edge under D: D outside the metal.
  {
    const Point<2> a = D - 0.1 * down_the_face - Tensor<1, 2>({0., 0.1}), b(x_d + 0.15, 4.60);
    one_cell(triangulation, {{Point<2>(x_d - 0.3, 3.5), Point<2>(x_d + 0.3, 3.5), a, b}});
    const Outcome out = update(triangulation, die);
    report("edge under D: nothing moves, penetration 0",
           depth_under(a, b) < 0 && out.vertices[2] == a && out.vertices[3] == b && out.penetration == 0);
  }

  // 4. A straight die: D on the line C-E is no corner.
  {
    DieSurface<2>  straight;
    const Point<2> c(x_d - 1, 4.75);
    straight.set_facets({{{{c, D}}, {}}, {{{D, E}}, {}}});
    const Point<2> a(x_d - 0.1, 4.74), b(x_d + 0.1, 4.80);
    one_cell(triangulation, {{Point<2>(x_d - 0.3, 3.5), Point<2>(x_d + 0.3, 3.5), a, b}});
    const Outcome out = update(triangulation, straight);
    report("straight die: a vertex of it over the edge is no corner, nothing moves",
           depth_under(a, b) > 0 && out.vertices[2] == a && out.vertices[3] == b && out.penetration == 0);
  }
  return 0;
}
