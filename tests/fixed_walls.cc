// The fixed walls of a moving mesh (FixedWalls, Problem = incremental): the
// planes of the symmetry planes and slip walls stay the planes they were at
// t = 0, also over new meshes (exact checks, 2 x 4 and 3 x 5 cells on
// [0, 2] x [0, 1], walls y = 0 (id 5) and x = 2 (id 7)):
//  1. at t = 0, keep() moves no vertex (bitwise);
//  2. after a move of every vertex, keep() puts the wall vertices back onto
//     their planes exactly (y = 0, x = 2; the corner (2, 0) onto both) and
//     leaves the others;
//  3. a new mesh whose wall vertices are off the planes by round-off (a
//     zigzag of 1e-9 mm, as positions after many steps are): its faces take
//     the t = 0 planes, so keep() puts them back exactly. Planes taken from
//     the new faces would keep the zigzag, and the nodes moving along them
//     went further off at each new mesh (the extrusion start with dt 0.1 ms);
//  4. a wall face on no known plane (the bottom 0.01 up): its own plane, so
//     keep() leaves its vertices.
#include <dieflow/incremental/time_stepping.h>

#include "report.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <iostream>

using namespace dieflow;
using dealii::Point;

namespace
{
  void
  rectangle(dealii::Triangulation<2> &triangulation, const unsigned int nx, const unsigned int ny)
  {
    triangulation.clear();
    dealii::GridGenerator::subdivided_hyper_rectangle(triangulation, {nx, ny}, Point<2>(0, 0), Point<2>(2, 1));
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          face->set_boundary_id(face->center()[1] == 0 ? 5 : face->center()[0] == 2 ? 7 : 1);
  }

  /// Whether every vertex on y = 0 (x = 2) before, @p before, is exactly there now.
  bool
  on_walls(const dealii::Triangulation<2> &triangulation, const std::vector<Point<2>> &before)
  {
    bool holds = true;
    for (unsigned int v = 0; v < before.size(); ++v)
      {
        if (std::abs(before[v][1]) < 1e-3)
          holds = holds && triangulation.get_vertices()[v][1] == 0;
        if (std::abs(before[v][0] - 2) < 1e-3)
          holds = holds && triangulation.get_vertices()[v][0] == 2;
      }
    return holds;
  }
} // namespace

int
main()
{
  const std::set<BoundaryId> walls = {5, 7};
  dealii::Triangulation<2>   mesh;
  rectangle(mesh, 4, 2);
  FixedWalls<2> fixed;
  fixed.initialize(mesh, walls);
  const std::vector<Point<2>> start = mesh.get_vertices();
  fixed.keep(mesh);
  report("1. at t = 0 no vertex moves", mesh.get_vertices() == start);

  for (auto &cell : mesh.active_cell_iterators())
    for (const unsigned int v : cell->vertex_indices())
      cell->vertex(v) = start[cell->vertex_index(v)] + dealii::Tensor<1, 2>({0.01 + 0.003 * start[cell->vertex_index(v)][1],
                                                                              0.002 * std::sin(3. * start[cell->vertex_index(v)][0])});
  std::vector<Point<2>> moved = mesh.get_vertices();
  fixed.keep(mesh);
  bool others_stay = true;
  for (unsigned int v = 0; v < start.size(); ++v)
    if (start[v][1] != 0 && start[v][0] != 2)
      others_stay = others_stay && mesh.get_vertices()[v] == moved[v];
  report("2. after a move the wall vertices are back on y = 0 and x = 2 exactly", on_walls(mesh, start));
  report("   the corner (2, 0) on both", mesh.get_vertices()[4][0] == 2 && mesh.get_vertices()[4][1] == 0);
  report("   the others where the move put them", others_stay);

  dealii::Triangulation<2> fresh;
  rectangle(fresh, 5, 3);
  unsigned int zig = 0;
  for (auto &cell : fresh.active_cell_iterators())
    for (const unsigned int v : cell->vertex_indices())
      {
        Point<2> &x = cell->vertex(v);
        if (x[1] == 0 && x[0] > 0 && x[0] < 2)
          x[1] = (zig++ % 2 == 0 ? 1e-9 : -1e-9);
      }
  const std::vector<Point<2>> fresh_start = fresh.get_vertices();
  std::vector<Point<2>>       exact       = fresh_start;
  for (Point<2> &x : exact)
    if (std::abs(x[1]) <= 1e-9)
      x[1] = 0;
  fixed.initialize(fresh, walls);
  fixed.keep(fresh);
  report("3. a new mesh off the planes by 1e-9: its wall vertices back on them exactly",
         zig > 0 && on_walls(fresh, exact));

  dealii::Triangulation<2> lifted;
  rectangle(lifted, 5, 3);
  for (auto &cell : lifted.active_cell_iterators())
    for (const unsigned int v : cell->vertex_indices())
      if (cell->vertex(v)[1] == 0)
        cell->vertex(v)[1] = 0.01;
  const std::vector<Point<2>> lifted_start = lifted.get_vertices();
  fixed.initialize(lifted, walls);
  fixed.keep(lifted);
  bool bottom_stays = true;
  for (unsigned int v = 0; v < lifted_start.size(); ++v)
    if (lifted_start[v][1] == 0.01)
      bottom_stays = bottom_stays && lifted.get_vertices()[v][1] == 0.01;
  report("4. a wall face on no known plane keeps its own: the bottom stays at y = 0.01", bottom_stays);
}
