// The built-in die meshes: the die2d section (plane strain, axisymmetric, extruded), the round bar quarter and the rectangular bar quarter.
#ifndef dieflow_die_meshes_h
#define dieflow_die_meshes_h

#include <dieflow/mesh/geometry.h>

#include <deal.II/grid/tria.h>

namespace dieflow
{
  /// The die2d section of @p g (Die2dGeometry: three structured blocks,
  /// container, converging zone and land, joined as its Layout says, graded
  /// towards the die corners by its Grading exponent).
  void
  make_die2d(const Die2dGeometry &g, Triangulation<2> &triangulation);



  /**
   * The round bar of the die2d profile through its conical die, a quarter
   * (y >= 0, z >= 0) with x the axis: the quarter disc of radius 1 (three
   * cells, refined until at least Cells across cells span the radius,
   * the new vertices on the circle) swept along x through three blocks
   * (container, die face, land) and scaled by the profile's radius: h_i/2
   * in the container, linear along the die face, h_o/2 in the land. The
   * blocks meet as Layout says, as in the die2d section: along the
   * bisectors of the corners C and D (bisected; cones through C and D,
   * 55 and 125 degree cells there for beta = 70), or along the planes
   * through them (blocks: 20 and 160 degrees, the layout whose ram force
   * is far off on coarse meshes). Faces are flat (MappingQ1): the
   * section is a polygon inscribed in the circle.
   * Ids: 1 inlet, 2 outlet, 3 container wall, 4 die face and land, 5 the
   * symmetry planes y = 0 and z = 0.
   */
  void
  make_round_bar_quarter(const Die2dGeometry &g, Triangulation<3> &triangulation);



  /**
   * A rectangular bar through a die that converges at different angles in
   * y and z, a quarter (y >= 0, z >= 0) with x the axis: the half height
   * goes from h_i to h_o (the Die2d profile, semi-angle beta_y) and the
   * half width from w_i to w_o over the same die length x_d (semi-angle
   * beta_z = atan((w_i - w_o)/x_d)). A structured grid of Cells across x
   * Cells in depth cells per section, swept along x through the three
   * blocks of the die2d section: the vertex of section coordinates
   * (xi, eta) in [0, 1]^2 and block fraction t lies at
   *   y = xi h(t),  z = eta w(t),  x = x_C + t (x_D - x_C)  (die block),
   * h and w linear along the die, and the blocks end on surfaces through
   * both die-entry edges (and both die-exit edges): with Layout =
   * bisected, x_C(xi, eta) = max((1 - xi) x_1y, (1 - eta) x_1z), each term
   * the die2d section's bisector in its plane, which is zero on the wall
   * of its own direction; so each wall's corner is a mesh line and, where
   * one wall dominates, its cells have the bisected shape. Without a
   * reduction in z (w_i = w_o) the mesh is the die2d section of the same
   * Cells across extruded in z (tests/rectangular_bar_quarter). The cell
   * counts along x are the larger of the two sections'.
   * Ids: 1 inlet, 2 outlet, 3 container wall y = h_i, 4 die face and land
   * y = h(x), 5 the symmetry planes y = 0 and z = 0, 6 container wall
   * z = w_i, 7 die face and land z = w(x).
   */
  void
  make_rectangular_bar_quarter(const Die2dGeometry &g, Triangulation<3> &triangulation);
} // namespace dieflow

#endif
