// The built-in die meshes: the die2d section (plane strain, axisymmetric, extruded), the round bar quarter and the rectangular bar quarter.
#include <dieflow/mesh/die_meshes.h>

#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

#include <array>
#include <cmath>
#include <vector>

namespace dieflow
{
  namespace
  {
    /**
     * Power grading of a block coordinate t in [0, 1] towards the ends it
     * names: t^q towards 0, 1 - (1 - t)^q towards 1, each half mapped so
     * towards both. With n uniform cells the cell at a graded end is
     * (1/n)^q long (2^(q-1) (1/n)^q for both ends): an algebraic
     * ("radical") mesh, the classical grading for corner singularities,
     * which stays graded as n grows, so a study by Cells across keeps a
     * fixed mesh family.
     */
    struct Grading
    {
      double q             = 1;
      bool   towards_start = false, towards_end = false;

      double
      operator()(const double t) const
      {
        if (q == 1)
          return t;
        if (towards_start && towards_end)
          return t < 0.5 ? 0.5 * std::pow(2 * t, q) : 1 - 0.5 * std::pow(2 * (1 - t), q);
        if (towards_start)
          return std::pow(t, q);
        if (towards_end)
          return 1 - std::pow(1 - t, q);
        return t;
      }
    };

    /// The three blocks of a die2d-like channel, along the axis.
    enum class Block
    {
      container,
      die,
      land
    };

    /// The grading along a block: the container towards the die entry C,
    /// the die face towards C and the die exit D, the land towards D.
    Grading
    along(const Block block, const double q)
    {
      return {q, block != Block::container, block != Block::land};
    }

    /// Where slice @p s (0 .. n_c + n_d + n_l) of a sweep through the three
    /// blocks lies: its block and its graded fraction along it (a block of
    /// no slices, a plain cone's container, is skipped).
    std::pair<Block, double>
    swept_position(const double s, const double n_c, const double n_d, const double n_l, const double q)
    {
      if (n_c > 0 && s <= n_c)
        return {Block::container, along(Block::container, q)(s / n_c)};
      if (s <= n_c + n_d)
        return {Block::die, along(Block::die, q)((s - n_c) / n_d)};
      return {Block::land, along(Block::land, q)((s - n_c - n_d) / n_l)};
    }

    /// A block of nx x ny cells filling the quadrilateral p00-p10-p01-p11
    /// (bilinear map of the unit square, its coordinates graded).
    void
    make_block(const Point<2> &     p00,
               const Point<2> &     p10,
               const Point<2> &     p01,
               const Point<2> &     p11,
               const unsigned int   nx,
               const unsigned int   ny,
               Triangulation<2> &   block,
               const Grading &      along  = {},
               const Grading &      across = {})
    {
      dealii::GridGenerator::subdivided_hyper_rectangle(
        block, {nx, ny}, Point<2>(0, 0), Point<2>(1, 1));
      dealii::GridTools::transform(
        [&](const Point<2> &p) {
          const double s = along(p[0]), t = across(p[1]);
          return Point<2>((1 - s) * (1 - t) * p00 + s * (1 - t) * p10 +
                          (1 - s) * t * p01 + s * t * p11);
        },
        block);
    }

    unsigned int
    cells_along(const double length, const double cell_size)
    {
      // At least one cell, also for a degenerate length.
      const long n = std::lround(length / cell_size);
      return n >= 1 ? static_cast<unsigned int>(n) : 1u;
    }

    /**
     * Where the three blocks of a die2d-like channel meet along the axis and
     * how many cells each block has along it: the container from the inlet
     * to x_1 (on the axis), the converging zone to x_2, the land to the
     * outlet, each with cells of aspect ratio near one for @p across cells
     * across. For the layout "bisected" x_1 and x_2 are where the bisectors
     * of the die entry C and the die exit D (both of direction
     * (-sin beta/2, -cos beta/2) for the semi-angle beta) meet the axis; for
     * "blocks" they are 0 and x_d, the verticals through C and D.
     */
    /**
     * How graded blocks change the cell counts along the axis: the die
     * face, graded towards both corners, gets 2^(q-1) times the cells of
     * the uniform mesh, so that its middle cells (2^(q-1)/n of the block)
     * keep the uniform size where the metal shears; the container and the
     * land, graded towards one corner, 1/q times, their far cells (q/n)
     * growing where the metal moves almost rigidly. Measured on the
     * axisymmetric round bar (doc/three-dimensional.md): with the uniform
     * counts the grading gained little, with these much more on fewer
     * cells; more die cells gained nothing more (doc/benchmarks.md,
     * "Figures behind the code's rules").
     */
    struct AxialCounts
    {
      double die = 1, container_and_land = 1;
    };

    AxialCounts
    graded_counts(const double q)
    {
      return {std::pow(2., q - 1), 1 / q};
    }

    struct AxialLayout
    {
      double       x_1, x_2;
      unsigned int container_cells, die_cells, land_cells;
    };

    AxialLayout
    axial_layout(const Die2dGeometry &g,
                 const double         inlet_half_height,
                 const double         outlet_half_height,
                 const double         half_beta,
                 const unsigned int   across)
    {
      const double h_i = inlet_half_height, h_o = outlet_half_height, x_d = g.die_exit_x();
      const Point<2> A(-g.container_length, 0), C(0, h_i), D(x_d, h_o), F(x_d + g.land_length, 0);
      // The bisectors of C and D meet the axis at x_1 and x_2; for a small
      // reduction through a short steep die they cross before the axis
      // (x_2 < x_1), and the bisected layout would turn the converging
      // block inside out: it then falls back to the vertical blocks.
      double       x_1             = std::max(-h_i * std::tan(half_beta), A[0] + 0.25 * g.container_length);
      double       x_2             = x_d - h_o * std::tan(half_beta);
      const bool   bisectors_apart = x_2 > x_1 + 0.25 * C.distance(D);
      if (g.layout != Die2dGeometry::Layout::bisected || !bisectors_apart)
        {
          x_1 = 0;
          x_2 = x_d;
        }
      // Along the converging zone: the mean of its length on the axis and
      // along the die face, so that the die face is resolved like the walls
      // next to it.
      const double across_c = 0.5 * (h_i + C.distance(Point<2>(x_1, 0))) / across;
      const double across_z = 0.5 * (C.distance(Point<2>(x_1, 0)) + D.distance(Point<2>(x_2, 0))) / across;
      const AxialCounts n = graded_counts(g.grading_exponent);
      return {x_1,
              x_2,
              cells_along(n.container_and_land * 0.5 * (g.container_length + x_1 - A[0]), across_c),
              cells_along(n.die * 0.5 * (x_2 - x_1 + C.distance(D)), across_z),
              cells_along(n.container_and_land * 0.5 * (F[0] - x_2 + g.land_length), h_o / across)};
    }
  } // namespace



  void
  make_die2d(const Die2dGeometry &g, Triangulation<2> &triangulation)
  {
    const unsigned int ny  = g.cells_across;
    const double       h_i = g.inlet_half_height, h_o = g.outlet_half_height;
    const double       x_d = g.die_exit_x();
    const Point<2>     A = g.corner('A'), B = g.corner('B'), C = g.corner('C'),
                   D = g.corner('D'), E = g.corner('E'), F = g.corner('F');

    std::vector<Triangulation<2>> blocks(3);
    if (x_d > 1e-9 * h_i)
      {
        // Bisected: the container and the converging zone meet on the
        // bisector of the die entry C, the converging zone and the land on
        // that of the die exit D: every cell at C and D then has the
        // corner's half angle ((180 - beta)/2 at C, 90 + beta/2 at D), where
        // the blocks that meet at the vertical through D leave a cell angle
        // of 180 - beta at C and 90 + beta at D (160 degrees for the
        // 70-degree die), which a bilinear cell resolves badly exactly where
        // the solution is singular.
        const AxialLayout l =
          axial_layout(g, h_i, h_o, 0.5 * g.die_angle_degrees * dealii::numbers::PI / 180., ny);
        const double  q = g.grading_exponent;
        const Grading to_wall{q, false, true};
        make_block(A, Point<2>(l.x_1, 0), B, C, l.container_cells, ny, blocks[0], along(Block::container, q), to_wall);
        make_block(Point<2>(l.x_1, 0), Point<2>(l.x_2, 0), C, D, l.die_cells, ny, blocks[1], along(Block::die, q),
                   to_wall);
        make_block(Point<2>(l.x_2, 0), F, D, E, l.land_cells, ny, blocks[2], along(Block::land, q), to_wall);
      }
    else
      {
        // Flat die: the container's right side is the land's inlet below
        // h_o and the die face above it.
        const unsigned int nx    = cells_along(g.container_length, h_i / ny);
        const unsigned int upper = cells_along(h_i - h_o, h_i / ny);
        make_block(A, Point<2>(0, 0), Point<2>(A[0], h_o), D, nx, ny, blocks[0]);
        make_block(Point<2>(A[0], h_o), D, B, C, nx, upper, blocks[1]);
        make_block(Point<2>(0, 0), F, D, E, cells_along(g.land_length, h_o / ny), ny, blocks[2]);
      }
    dealii::GridGenerator::merge_triangulations({&blocks[0], &blocks[1], &blocks[2]},
                                                triangulation,
                                                1e-10 * h_i);

    const double tol = 1e-8 * h_i;
    for (const auto &face : triangulation.active_face_iterators())
      if (face->at_boundary())
        {
          const Point<2> c = face->center();
          BoundaryId     id;
          if (std::abs(c[0] - A[0]) < tol)
            id = Die2dGeometry::inlet_id;
          else if (std::abs(c[0] - F[0]) < tol)
            id = Die2dGeometry::outlet_id;
          else if (std::abs(c[1]) < tol)
            id = Die2dGeometry::symmetry_id;
          else if (std::abs(c[1] - h_i) < tol && c[0] < 0)
            id = Die2dGeometry::container_id;
          else
            id = Die2dGeometry::die_id;
          face->set_boundary_id(id);
        }
  }



  void
  make_round_bar_quarter(const Die2dGeometry &g, Triangulation<3> &triangulation)
  {
    Triangulation<2> disc, section;
    dealii::GridGenerator::quarter_hyper_ball(disc);
    unsigned int across = 2;
    while (across < g.cells_across)
      {
        disc.refine_global(1);
        across *= 2;
      }
    dealii::GridGenerator::flatten_triangulation(disc, section);

    const double R_i = g.inlet_half_height, R_o = g.outlet_half_height, x_d = g.die_exit_x();
    require(x_d > 1e-9 * R_i,
            "Mesh/Die2d/Die angle",
            "must be below 90 degrees for Source = round bar quarter (a flat die has no converging zone "
            "for the section to shrink along)");

    // The blocks' ends at radius fraction rho: vertical through C and D
    // (blocks), or along the bisectors of the corners C and D as in the
    // die2d section (bisected; both bisectors have the direction
    // (cos beta - 1, -sin beta)), unless the container is too short for C's.
    const double beta     = g.die_angle_degrees * dealii::numbers::PI / 180.;
    const double lean     = (std::cos(beta) - 1) / std::sin(beta); // dx/dr along a bisector, < 0
    const bool   bisected = g.layout == Die2dGeometry::Layout::bisected && g.container_length + lean * R_i > 0;
    const auto   x_C      = [&](const double rho) { return bisected ? lean * R_i * (1 - rho) : 0.; };
    const auto   x_D      = [&](const double rho) { return bisected ? x_d + lean * R_o * (1 - rho) : x_d; };
    const double x_end    = x_d + g.land_length;

    // Slices of about the cell size of each block at mid-radius.
    const auto count = [&](const double length, const double cell_size) {
      return length > 0 ? std::max(1, static_cast<int>(std::round(length / cell_size))) : 0;
    };
    const AxialCounts graded = graded_counts(g.grading_exponent);
    const int         n_c    = count(graded.container_and_land * (g.container_length + x_C(0.5)), R_i / across);
    const int         n_d    = count(graded.die * (x_D(0.5) - x_C(0.5)), 0.5 * (R_i + R_o) / across);
    const int         n_l    = count(graded.container_and_land * (x_end - x_D(0.5)), R_o / across);
    std::vector<double> slices;
    for (int k = 0; k <= n_c + n_d + n_l; ++k)
      slices.push_back(k);
    dealii::GridGenerator::extrude_triangulation(section, slices, triangulation);

    // Section (p0, p1) of radius fraction rho, slice s: block and the
    // fraction t along it, x between the block's ends at rho, the radius
    // R(t) rho with R the profile's (linear along the die face).
    // Grading: the section radially towards the wall (rho -> the graded
    // rho, a monotone radial map that keeps the circle), each block along
    // the axis towards the die corners, as in the die2d section.
    const double  q = g.grading_exponent;
    const Grading to_wall{q, false, true};
    dealii::GridTools::transform(
      [&](const Point<3> &p) {
        const double r   = std::hypot(p[0], p[1]);
        const double rho = std::min(1., to_wall(std::min(1., r)));
        const double y = r > 0 ? p[0] * rho / r : 0., z = r > 0 ? p[1] * rho / r : 0.;
        const auto [block, t] = swept_position(p[2], n_c, n_d, n_l, q);
        double x, R;
        if (block == Block::container)
          {
            x = -g.container_length + t * (x_C(rho) + g.container_length);
            R = R_i;
          }
        else if (block == Block::die)
          {
            x = x_C(rho) + t * (x_D(rho) - x_C(rho));
            R = R_i + t * (R_o - R_i);
          }
        else
          {
            x = x_D(rho) + t * (x_end - x_D(rho));
            R = R_o;
          }
        return Point<3>(x, R * y, R * z);
      },
      triangulation);

    const double tolerance = 1e-9 * (g.container_length + x_d + g.land_length);
    for (const auto &face : triangulation.active_face_iterators())
      if (face->at_boundary())
        {
          const Point<3> c = face->center();
          if (std::abs(c[0] + g.container_length) < tolerance)
            face->set_boundary_id(Die2dGeometry::inlet_id);
          else if (std::abs(c[0] - x_d - g.land_length) < tolerance)
            face->set_boundary_id(Die2dGeometry::outlet_id);
          else if (face->boundary_id() == 1) // the section's cut lines
            face->set_boundary_id(Die2dGeometry::symmetry_id);
          else
            face->set_boundary_id(c[0] < 0 ? Die2dGeometry::container_id : Die2dGeometry::die_id);
        }
  }



  void
  make_rectangular_bar_quarter(const Die2dGeometry &g, Triangulation<3> &triangulation)
  {
    const double x_d = g.die_exit_x();
    require(x_d > 1e-9 * g.inlet_half_height,
            "Mesh/Die2d/Die angle",
            "must be below 90 degrees for Source = rectangular bar quarter (a flat die has no converging "
            "zone for the section to shrink along)");
    const double h_i = g.inlet_half_height, h_o = g.outlet_half_height;
    const double w_i = g.inlet_half_width, w_o = g.outlet_half_width;
    const bool   converges_in_z = w_o < w_i;

    const AxialLayout in_y =
      axial_layout(g, h_i, h_o, 0.5 * g.die_angle_degrees * dealii::numbers::PI / 180., g.cells_across);
    const AxialLayout in_z =
      converges_in_z ? axial_layout(g, w_i, w_o, 0.5 * std::atan2(w_i - w_o, x_d), g.cells_in_depth) : in_y;
    const unsigned int n_c = std::max(in_y.container_cells, in_z.container_cells);
    const unsigned int n_d = std::max(in_y.die_cells, in_z.die_cells);
    const unsigned int n_l = std::max(in_y.land_cells, in_z.land_cells);

    // A wall without a corner (no reduction in z) does not bind the
    // blocks' ends.
    const auto block_end = [&](const double xi, const double eta, const double y_end, const double z_end,
                               const double corner) {
      const double along_y = corner + (1 - xi) * (y_end - corner);
      return converges_in_z ? std::max(along_y, corner + (1 - eta) * (z_end - corner)) : along_y;
    };

    dealii::GridGenerator::subdivided_hyper_rectangle(triangulation,
                                                      {n_c + n_d + n_l, g.cells_across, g.cells_in_depth},
                                                      Point<3>(0, 0, 0),
                                                      Point<3>(n_c + n_d + n_l, 1, 1),
                                                      /*colorize=*/true);
    const double  x_end = x_d + g.land_length;
    const double  q     = g.grading_exponent;
    const Grading to_wall{q, false, true};
    dealii::GridTools::transform(
      [&](const Point<3> &p) {
        const auto [block, f] = swept_position(p[0], n_c, n_d, n_l, q);
        const double xi = to_wall(p[1]), eta = to_wall(p[2]);
        const double x_C = block_end(xi, eta, in_y.x_1, in_z.x_1, 0.);
        const double x_D = block_end(xi, eta, in_y.x_2, in_z.x_2, x_d);
        // x, and t the fraction of the die's reduction.
        double x, t;
        if (block == Block::container)
          {
            x = -g.container_length + f * (x_C + g.container_length);
            t = 0;
          }
        else if (block == Block::die)
          {
            x = x_C + f * (x_D - x_C);
            t = f;
          }
        else
          {
            x = x_D + f * (x_end - x_D);
            t = 1;
          }
        return Point<3>(x, xi * (h_i + t * (h_o - h_i)), eta * (w_i + t * (w_o - w_i)));
      },
      triangulation);

    // colorize numbered the faces 0..5 for x-, x+, y-, y+, z-, z+.
    for (const auto &face : triangulation.active_face_iterators())
      if (face->at_boundary())
        {
          const bool in_container = face->center()[0] < 0;
          switch (face->boundary_id())
            {
              case 0:
                face->set_boundary_id(Die2dGeometry::inlet_id);
                break;
              case 1:
                face->set_boundary_id(Die2dGeometry::outlet_id);
                break;
              case 3:
                face->set_boundary_id(in_container ? Die2dGeometry::container_id : Die2dGeometry::die_id);
                break;
              case 5:
                face->set_boundary_id(in_container ? Die2dGeometry::front_id : Die2dGeometry::back_id);
                break;
              default:
                face->set_boundary_id(Die2dGeometry::symmetry_id);
            }
        }
  }
} // namespace dieflow
