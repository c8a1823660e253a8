// A new mesh of a domain whose boundary nodes crowd (remesh_domain()):
// nodes that flow into a corner where the metal stands, or that the dies
// put back onto one corner, come to lie a millionth of a millimetre apart;
// a new mesh that kept them all had cells of that size and corners of no
// angle (the extrusion start with friction stopped so: a new mesh's
// smallest scaled Jacobian fell 0.5 -> 0.004 -> 7e-6 -> -3e-10 over 20
// new meshes). Exact checks, on a 8 x 4 mesh of [0,2] x [0,1] (edges 0.25):
//  1. as it is: nothing dropped, every boundary vertex kept, the volume to
//     round-off;
//  2. the top's vertex at x = 1 moved to 1e-6 from its neighbour at
//     x = 0.75 (on the wall), the right side's vertex at y = 0.75 moved to
//     1e-6 under the corner (2, 1): both dropped (a vertex on a straight
//     wall, not the corner: the polygon is the same, the volume to
//     round-off), every other boundary vertex kept, no cell smaller than a
//     tenth of the edges (the crowded node gave cells of 1e-6 before) and
//     a smallest scaled Jacobian of at least 0.3;
//  3. an L (the upper right quarter of [-1,1]^2 cut out; 4 x 4 cells), the
//     top side's vertex next to the reflex corner (0, 0)... moved to 1e-6
//     from it along its edge: the reflex corner stays (a chord past it would
//     leave the domain: the new mesh would reach into a die), its
//     neighbour goes, the volume to round-off;
//  4. the 8 x 4 box with its top split in two ids at x = 1.75, and the
//     top's vertex at x = 1.5 moved to (1.749, 1 + h), so that the edge from
//     it to the ids' junction (1.75, 1) crowds its neighbour (0.02-0.05
//     against 0.5): the junction may not go (two ids), the vertex only if it
//     stands no higher over its neighbours' chord than a twentieth of it.
//     h = 0.02 (a twenty-fifth): dropped, the volume changes by the
//     triangle, 0.5 * 0.5 * 0.02 = 0.005; h = 0.05 (a tenth: the corner of a
//     fold): nothing dropped, the volume to round-off.
#include <dieflow/incremental/remeshing.h>
#include <dieflow/incremental/time_stepping.h>

#include "report.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <iostream>
#include <set>

using namespace dieflow;
using dealii::Point;

namespace
{
  std::vector<Point<2>>
  boundary_vertices(const dealii::Triangulation<2> &mesh)
  {
    std::set<unsigned int> on;
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          for (const unsigned int v : face->vertex_indices())
            on.insert(face->vertex_index(v));
    std::vector<Point<2>> points;
    for (const unsigned int v : on)
      points.push_back(mesh.get_vertices()[v]);
    return points;
  }

  /// How many of @p points are no vertex of @p mesh.
  unsigned int
  missing(const std::vector<Point<2>> &points, const dealii::Triangulation<2> &mesh)
  {
    unsigned int n = 0;
    for (const Point<2> &p : points)
      {
        bool found = false;
        for (const Point<2> &q : mesh.get_vertices())
          found |= p.distance(q) < 1e-12;
        n += !found;
      }
    return n;
  }

  double
  smallest_cell(const dealii::Triangulation<2> &mesh)
  {
    double smallest = 1e300;
    for (const auto &cell : mesh.active_cell_iterators())
      for (unsigned int l = 0; l < 4; ++l)
        smallest = std::min(smallest, cell->line(l)->diameter());
    return smallest;
  }

  /// Moves the vertex at @p from to @p to.
  void
  move_vertex(dealii::Triangulation<2> &mesh, const Point<2> &from, const Point<2> &to)
  {
    for (const auto &cell : mesh.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (cell->vertex(v).distance(from) < 1e-12)
          cell->vertex(v) = to;
  }

  NewMesh
  remesh(const dealii::Triangulation<2> &old, dealii::Triangulation<2> &fresh)
  {
    return remesh_domain<2>(
      old, fresh, 0, [](const Point<2> &, const Point<2> &, const BoundaryId) { return true; }, "test");
  }
} // namespace

int
main()
{
  const CoordinateSystem<2> plane;
  {
    dealii::Triangulation<2> box, fresh;
    dealii::GridGenerator::subdivided_hyper_rectangle(box, {8, 4}, Point<2>(0, 0), Point<2>(2, 1));
    const NewMesh made = remesh(box, fresh);
    report("as it is: nothing dropped", made.dropped_vertices == 0);
    report("as it is: every boundary vertex kept", missing(boundary_vertices(box), fresh) == 0);
    report("as it is: volume to round-off",
           std::abs(domain_volume(plane, fresh) - domain_volume(plane, box)) < 1e-12);
  }
  {
    dealii::Triangulation<2> box, fresh;
    dealii::GridGenerator::subdivided_hyper_rectangle(box, {8, 4}, Point<2>(0, 0), Point<2>(2, 1));
    move_vertex(box, Point<2>(1, 1), Point<2>(0.75 + 1e-6, 1));
    move_vertex(box, Point<2>(2, 0.75), Point<2>(2, 1 - 1e-6));
    const NewMesh made = remesh(box, fresh);
    std::vector<Point<2>> kept;
    for (const Point<2> &p : boundary_vertices(box))
      if (p.distance(Point<2>(0.75 + 1e-6, 1)) > 1e-12 && p.distance(Point<2>(2, 1 - 1e-6)) > 1e-12)
        kept.push_back(p);
    report("crowded: the two crowding vertices dropped", made.dropped_vertices == 2 &&
                                                             missing({Point<2>(0.75 + 1e-6, 1)}, fresh) == 1 &&
                                                             missing({Point<2>(2, 1 - 1e-6)}, fresh) == 1);
    report("crowded: every other boundary vertex kept, the corner too", missing(kept, fresh) == 0);
    report("crowded: volume to round-off", std::abs(domain_volume(plane, fresh) - 2) < 1e-12);
    report("crowded: no cell edge under a tenth of the boundary's (0.025)", smallest_cell(fresh) > 0.025);
    report("crowded: smallest scaled Jacobian at least 0.3", smallest_scaled_jacobian(fresh) >= 0.3);
  }
  {
    dealii::Triangulation<2> l_shape, fresh;
    dealii::GridGenerator::hyper_L(l_shape, -1, 1);
    l_shape.refine_global(1);
    // The top side of the cut-out's lower edge: from (1, 0) to the reflex
    // corner (0, 0); its vertex at (0.5, 0) moves to 1e-6 from the corner.
    move_vertex(l_shape, Point<2>(0.5, 0), Point<2>(1e-6, 0));
    const double  before = domain_volume(plane, l_shape);
    const NewMesh made   = remesh(l_shape, fresh);
    report("L: one vertex dropped, the one by the reflex corner, not the corner",
           made.dropped_vertices == 1 && missing({Point<2>(1e-6, 0)}, fresh) == 1 &&
             missing({Point<2>(0, 0)}, fresh) == 0);
    report("L: volume to round-off", std::abs(domain_volume(plane, fresh) - before) < 1e-12 && std::abs(before - 3) < 1e-12);
    report("L: smallest scaled Jacobian positive", smallest_scaled_jacobian(fresh) > 0);
  }
  for (const double h : {0.02, 0.05})
    {
      dealii::Triangulation<2> box, fresh;
      dealii::GridGenerator::subdivided_hyper_rectangle(box, {8, 4}, Point<2>(0, 0), Point<2>(2, 1));
      for (const auto &cell : box.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->center()[1] > 1 - 1e-12 && face->center()[0] > 1.75)
            face->set_boundary_id(7);
      move_vertex(box, Point<2>(1.5, 1), Point<2>(1.749, 1 + h));
      const double  before = domain_volume(plane, box);
      const NewMesh made   = remesh(box, fresh);
      const double  change = domain_volume(plane, fresh) - before;
      if (h < 0.03)
        report("a corner a twenty-fifth over its chord: dropped, the volume changes by its triangle (0.005)",
               made.dropped_vertices == 1 && missing({Point<2>(1.749, 1 + h)}, fresh) == 1 &&
                 std::abs(change + 0.005) < 1e-12);
      else
        report("a corner a tenth over its chord (a fold's): kept, nothing dropped, volume to round-off",
               made.dropped_vertices == 0 && missing(boundary_vertices(box), fresh) == 0 && std::abs(change) < 1e-12);
    }
}
