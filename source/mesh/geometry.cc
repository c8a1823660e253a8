#include <dieflow/mesh/geometry.h>

#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace dieflow
{
  double
  Die2dGeometry::die_exit_x() const
  {
    const double beta = die_angle_degrees * dealii::numbers::PI / 180.;
    // cos(90 deg) is not exactly zero in floating point.
    return (die_angle_degrees == 90.) ?
             0. :
             (inlet_half_height - outlet_half_height) / std::tan(beta);
  }

  Point<2>
  Die2dGeometry::corner(const char name) const
  {
    const double x_d = die_exit_x();
    const double x_e = x_d + land_length;
    switch (name)
      {
        case 'A':
          return {-container_length, 0};
        case 'B':
          return {-container_length, inlet_half_height};
        case 'C':
          return {0, inlet_half_height};
        case 'D':
          return {x_d, outlet_half_height};
        case 'E':
          return {x_e, outlet_half_height};
        case 'F':
          return {x_e, 0};
        default:
          Assert(false, dealii::ExcInternalError());
          return {};
      }
  }



  void
  MeshParameters::declare_parameters(ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Mesh");
    {
      prm.declare_entry("Source",
                        "die2d",
                        Selection("die2d|round bar quarter|rectangular bar quarter|box|gmsh"),
                        "Where the coarse mesh comes from: the built-in die2d "
                        "scene (subsection Die2d; with Dimension = 3 extruded in "
                        "z, see Depth), the die2d profile as a round bar through "
                        "a conical die, a quarter of it (Dimension = 3; the "
                        "Die2d heights are radii; ids as die2d, 5 the two "
                        "symmetry planes y = 0 and z = 0), a rectangular bar through "
                        "a die converging at different angles in y (the Die2d "
                        "profile) and z (Inlet/Outlet half width), a quarter of it "
                        "(Dimension = 3; ids 1-5 as the round bar, 6 the container "
                        "wall and 7 the die face and land in z), an axis-parallel box "
                        "(subsection Box), or a Gmsh file whose physical groups "
                        "are the boundary ids.");
      prm.declare_entry("Gmsh file",
                        "",
                        Anything(),
                        "Gmsh .msh file (format 2 or 4) of quadrilaterals "
                        "(hexahedra in 3D) for Source = gmsh; the physical group "
                        "number of each boundary line (surface) is its boundary id. "
                        "A relative path is relative to the deck's directory.");
      prm.declare_entry("Global refinements",
                        "0",
                        Integer(0, 12),
                        "Number of uniform refinements of the coarse mesh before "
                        "the first cycle.");
      prm.declare_entry("Corner refinements",
                        "0",
                        Integer(0, 30),
                        "Levels of geometric grading towards the corners of the "
                        "walls (die and slip-wall ids) before the first cycle, after "
                        "the global refinements: where a wall turns (die2d: the die "
                        "entry C and the re-entrant die exit D, whose singularity "
                        "dominates the error) or meets another boundary part (B, "
                        "E). Each level halves the cells around every corner, so "
                        "the smallest cells there are 2^-levels of the mesh size. "
                        "Works on every mesh source, a Gmsh mesh included.");
      prm.declare_entry("Corner grading width",
                        "1",
                        Double(0, 8),
                        "Width of each graded layer in cell diameters: a level "
                        "refines the cells whose centres lie within (1/2 + width) "
                        "diameters of a corner. 0 refines only the cells at the "
                        "corner; larger values grade more gently.");

      prm.enter_subsection("Die2d");
      {
        prm.declare_entry("Inlet half height",
                          "19",
                          Double(),
                          "h_i/2 (mm): half height of the container (inlet).");
        prm.declare_entry("Outlet half height",
                          "4.75",
                          Double(),
                          "h_o/2 (mm): half height of the land (outlet).");
        prm.declare_entry("Die angle",
                          "70",
                          Double(),
                          "Semi-angle beta (degrees) between the die face and the "
                          "axis, in (0, 90]; 90 is a flat (square) die.");
        prm.declare_entry("Container length",
                          "20",
                          Double(),
                          "Length (mm) of the container from the inlet to the die "
                          "entry C.");
        prm.declare_entry("Land length",
                          "15",
                          Double(),
                          "Length (mm) of the land from the die exit D to the "
                          "outlet.");
        prm.declare_entry("Layout",
                          "bisected",
                          Selection("blocks|bisected"),
                          "How the three blocks meet: blocks: along the verticals "
                          "through the die entry C and exit D; bisected: along the "
                          "bisectors of the corners C and D, so that no cell at a die "
                          "corner is flattened (for a flat die both are the same; "
                          "where the two bisectors would cross before the axis, a "
                          "small reduction through a short steep die, blocks).");
        prm.declare_entry("Grading exponent",
                          "1",
                          Double(1, 4),
                          "Power grading q of the structured die2d-like meshes "
                          "(die2d, round bar quarter, rectangular bar quarter; "
                          "not a flat die) towards the die corners C and D and "
                          "the walls: a block coordinate t in [0, 1] becomes t^q "
                          "at a graded end, so the cell at a die corner is "
                          "(1/n)^q of the block instead of 1/n for n cells, and "
                          "refining (Cells across) keeps the grading. Along the "
                          "axis the container is graded towards C, the die face "
                          "towards C and D, the land towards D; across, every "
                          "block towards its wall. 1: uniform cells; 2 to 3 "
                          "resolve the singular die exit D (doc/three-dimensional.md).");
        prm.declare_entry("Cells across",
                          "4",
                          Integer(1, 4096),
                          "Number of cells across the channel in every block; the "
                          "number along each block follows for cells of aspect "
                          "ratio near one.");
        prm.declare_entry("Depth",
                          "1",
                          Double(),
                          "Dimension = 3: the scene extruded in z over this depth "
                          "(mm), a slab between the planes z = 0 (boundary id 6) "
                          "and z = Depth (id 7); make them Symmetry ids for the "
                          "plane-strain slab between frictionless side planes.");
        prm.declare_entry("Cells in depth",
                          "1",
                          Integer(1, 4096),
                          "Dimension = 3: the number of cell layers in z (the "
                          "rectangular bar quarter: cells across its half width).");
        prm.declare_entry("Inlet half width",
                          "10",
                          Double(),
                          "Source = rectangular bar quarter: the half width in z "
                          "(mm) of the container; the die narrows it linearly to "
                          "Outlet half width over the die length of the y profile "
                          "(semi-angle atan((w_i - w_o)/x_d) in z).");
        prm.declare_entry("Outlet half width",
                          "6",
                          Double(),
                          "Source = rectangular bar quarter: the half width in z "
                          "(mm) of the land, at most Inlet half width (equal: the "
                          "die converges in y only, and with ids 6, 7 as symmetry "
                          "planes the bar is the plane-strain slab).");
      }
      prm.leave_subsection();

      prm.enter_subsection("Box");
      {
        prm.declare_entry("Lower corner",
                          "0, 0",
                          List(Double(), 2, 3),
                          "Lower corner of the box (one coordinate per dimension).");
        prm.declare_entry("Upper corner",
                          "1, 1",
                          List(Double(), 2, 3),
                          "Upper corner of the box.");
        prm.declare_entry("Subdivisions",
                          "4, 4",
                          List(Integer(1, 100000), 2, 3),
                          "Number of cells along each axis.");
        prm.declare_entry("Rotation",
                          "0",
                          Double(-360, 360),
                          "Rotation of the box (degrees, counter-clockwise about "
                          "the origin; 2D only), for inclined walls.");
        prm.declare_entry("Distortion",
                          "0",
                          Double(0, 0.45),
                          "Shift of every interior vertex by up to this fraction of "
                          "the cell size in each direction (deterministic), to "
                          "test distorted meshes.");
      }
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }



  namespace
  {
    std::vector<double>
    get_double_list(ParameterHandler &prm, const std::string &entry)
    {
      std::vector<double> values;
      for (const auto &item : dealii::Utilities::split_string_list(prm.get(entry)))
        values.push_back(dealii::Utilities::string_to_double(item));
      return values;
    }
  } // namespace



  void
  MeshParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    source             = prm.get("Source");
    gmsh_file          = prm.get("Gmsh file");
    global_refinements = prm.get_integer("Global refinements");
    corner_refinements = prm.get_integer("Corner refinements");
    corner_width       = prm.get_double("Corner grading width");
    if (source == "gmsh")
      require(!gmsh_file.empty(), "Mesh/Gmsh file", "is empty but Source = gmsh");

    prm.enter_subsection("Die2d");
    {
      const auto positive = [&](const std::string &entry) { return get_positive(prm, "Mesh/Die2d/", entry); };
      die2d.inlet_half_height  = positive("Inlet half height");
      die2d.outlet_half_height = positive("Outlet half height");
      die2d.die_angle_degrees  = positive("Die angle");
      // The round bar quarter may leave out the container or the land (a
      // plain cone, for the sink flow); the die2d section needs both.
      const auto length = [&](const std::string &entry) {
        const double value = prm.get_double(entry);
        require(value > 0 || (value == 0 && source == "round bar quarter"),
                "Mesh/Die2d/" + entry,
                "must be positive" + std::string(source == "round bar quarter" ? " or zero" : "") + ", got " +
                  prm.get(entry));
        return value;
      };
      die2d.container_length   = length("Container length");
      die2d.land_length        = length("Land length");
      die2d.cells_across       = prm.get_integer("Cells across");
      die2d.layout             = prm.get("Layout");
      die2d.grading_exponent   = prm.get_double("Grading exponent");
      die2d.depth              = positive("Depth");
      die2d.cells_in_depth     = prm.get_integer("Cells in depth");
      die2d.inlet_half_width   = positive("Inlet half width");
      die2d.outlet_half_width  = positive("Outlet half width");
      if (source == "rectangular bar quarter")
        require(die2d.outlet_half_width <= die2d.inlet_half_width,
                "Mesh/Die2d/Outlet half width",
                "must not exceed Inlet half width (a die does not widen the bar), got " +
                  prm.get("Outlet half width") + " > " + prm.get("Inlet half width"));
      require(die2d.outlet_half_height < die2d.inlet_half_height,
              "Mesh/Die2d/Outlet half height",
              "must be smaller than Inlet half height (a die reduces the section)");
      require(die2d.die_angle_degrees <= 90,
              "Mesh/Die2d/Die angle",
              "must lie in (0, 90] degrees, got " + prm.get("Die angle"));
      require(die2d.grading_exponent == 1 || die2d.die_angle_degrees < 90,
              "Mesh/Die2d/Grading exponent",
              "needs a converging die (Die angle below 90 degrees), got " + prm.get("Grading exponent") +
                " with a flat die");
    }
    prm.leave_subsection();

    prm.enter_subsection("Box");
    {
      box.lower = get_double_list(prm, "Lower corner");
      box.upper = get_double_list(prm, "Upper corner");
      box.subdivisions.clear();
      for (const double s : get_double_list(prm, "Subdivisions"))
        box.subdivisions.push_back(static_cast<unsigned int>(s));
      box.distortion = prm.get_double("Distortion");
      box.rotation   = prm.get_double("Rotation");
      require(box.lower.size() == box.upper.size() &&
                box.lower.size() == box.subdivisions.size(),
              "Mesh/Box",
              "Lower corner, Upper corner and Subdivisions need the same number "
              "of entries");
      for (unsigned int d = 0; d < box.lower.size(); ++d)
        require(box.upper[d] > box.lower[d],
                "Mesh/Box/Upper corner",
                "must exceed Lower corner in every coordinate");
    }
    prm.leave_subsection();
    prm.leave_subsection();
  }



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
     * counts the grading gained little (q = 2, 8 across: 3.3 % against
     * 7.9 % uniform), with these 1.3 % on fewer cells; twice more die cells
     * gained nothing more.
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
      if (g.layout != "bisected" || !bisectors_apart)
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

    /// Deterministic offsets in [-1, 1] from a vertex index.
    double
    hashed_unit(const unsigned int index, const unsigned int component)
    {
      std::uint64_t h = 0x9E3779B97F4A7C15ull * (index + 1) + 0xBF58476D1CE4E5B9ull * (component + 7);
      h ^= h >> 31;
      h *= 0x94D049BB133111EBull;
      h ^= h >> 29;
      return 2. * static_cast<double>(h % 1000003) / 1000002. - 1.;
    }

    template <int dim>
    void
    make_box(const BoxGeometry &box, Triangulation<dim> &triangulation)
    {
      require(box.lower.size() == dim,
              "Mesh/Box/Lower corner",
              "needs " + std::to_string(dim) + " coordinates for Dimension = " +
                std::to_string(dim));
      Point<dim>                lower, upper;
      std::vector<unsigned int> repetitions(dim);
      for (unsigned int d = 0; d < dim; ++d)
        {
          lower[d]       = box.lower[d];
          upper[d]       = box.upper[d];
          repetitions[d] = box.subdivisions[d];
        }
      dealii::GridGenerator::subdivided_hyper_rectangle(
        triangulation, repetitions, lower, upper, /*colorize=*/true);
      // colorize numbers the faces 0..2dim-1; the deck's ids start at 1.
      for (const auto &face : triangulation.active_face_iterators())
        if (face->at_boundary())
          face->set_boundary_id(face->boundary_id() + 1);

      if (box.distortion > 0)
        {
          std::vector<bool> at_boundary(triangulation.n_vertices(), false);
          for (const auto &face : triangulation.active_face_iterators())
            if (face->at_boundary())
              for (const unsigned int v : face->vertex_indices())
                at_boundary[face->vertex_index(v)] = true;
          auto &vertices = const_cast<std::vector<Point<dim>> &>(triangulation.get_vertices());
          for (unsigned int i = 0; i < vertices.size(); ++i)
            if (!at_boundary[i])
              for (unsigned int d = 0; d < dim; ++d)
                vertices[i][d] += box.distortion * (upper[d] - lower[d]) /
                                  repetitions[d] * hashed_unit(i, d);
        }
      if (box.rotation != 0)
        {
          if constexpr (dim == 2)
            dealii::GridTools::rotate(box.rotation * dealii::numbers::PI / 180., triangulation);
          else
            throw InputError("Mesh/Box/Rotation: only available in 2D");
        }
    }

    template <int dim>
    void
    read_gmsh(const std::string &file_name, const std::string &base_directory, Triangulation<dim> &triangulation)
    {
      read_msh_file(file_name, base_directory, "Mesh/Gmsh file", "a Gmsh mesh", triangulation);
      require(triangulation.n_active_cells() > 0,
              "Mesh/Gmsh file",
              "'" + file_name + "' contains no cells of dimension " +
                std::to_string(dim));
      require(triangulation.all_reference_cells_are_hyper_cube(),
              "Mesh/Gmsh file",
              "'" + file_name + "' contains triangles or tetrahedra; dieflow "
              "needs quadrilaterals/hexahedra (Gmsh: Recombine)");
    }
  } // namespace



  namespace
  {
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
      const bool   bisected = g.layout == "bisected" && g.container_length + lean * R_i > 0;
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
  } // namespace



  template <int dim, int spacedim>
  void
  read_msh_file(const std::string &                   file_name,
                const std::string &                   base_directory,
                const std::string &                   entry,
                const std::string &                   what,
                dealii::Triangulation<dim, spacedim> &triangulation)
  {
    std::filesystem::path path(file_name);
    if (path.is_relative() && !base_directory.empty())
      path = std::filesystem::path(base_directory) / path;
    std::ifstream in(path);
    require(static_cast<bool>(in), entry, "cannot open '" + file_name + "' (missing or unreadable)");
    in.peek();
    require(!in.eof(), entry, "'" + file_name + "' is empty");
    dealii::GridIn<dim, spacedim> grid_in;
    grid_in.attach_triangulation(triangulation);
    try
      {
        grid_in.read_msh(in);
      }
    catch (const std::exception &exc)
      {
        throw InputError(entry + ": cannot read '" + file_name + "' as " + what + ": " + one_line_message(exc));
      }
  }



  template <int dim>
  void
  make_mesh(const MeshParameters &parameters, Triangulation<dim> &triangulation)
  {
    if (parameters.source == "die2d")
      {
        if constexpr (dim == 2)
          make_die2d(parameters.die2d, triangulation);
        else
          {
            // The section extruded in z: the lateral faces keep the section's
            // ids 1..5, z = 0 and z = depth get the next free ones, 6 and 7.
            Triangulation<2> section;
            make_die2d(parameters.die2d, section);
            dealii::GridGenerator::extrude_triangulation(
              section, parameters.die2d.cells_in_depth + 1, parameters.die2d.depth, triangulation);
          }
      }
    else if (parameters.source == "round bar quarter")
      {
        if constexpr (dim == 3)
          make_round_bar_quarter(parameters.die2d, triangulation);
        else
          throw InputError("Mesh/Source: 'round bar quarter' is a 3D mesh; set Dimension = 3 (in 2D the "
                           "round bar is the die2d scene with Geometry = axisymmetric)");
      }
    else if (parameters.source == "rectangular bar quarter")
      {
        if constexpr (dim == 3)
          make_rectangular_bar_quarter(parameters.die2d, triangulation);
        else
          throw InputError("Mesh/Source: 'rectangular bar quarter' is a 3D mesh; set Dimension = 3 (in 2D "
                           "the die2d scene is its section)");
      }
    else if (parameters.source == "box")
      make_box(parameters.box, triangulation);
    else
      read_gmsh(parameters.gmsh_file, parameters.base_directory, triangulation);

    triangulation.refine_global(parameters.global_refinements);
  }



  template <int dim>
  void
  check_boundary_ids(const Triangulation<dim> &               triangulation,
                     const std::map<BoundaryId, std::string> &assigned)
  {
    std::set<BoundaryId> mesh_ids;
    for (const auto id : triangulation.get_boundary_ids())
      mesh_ids.insert(id);

    for (const auto &[id, entry] : assigned)
      if (mesh_ids.count(id) == 0)
        {
          std::string present;
          for (const auto m : mesh_ids)
            present += (present.empty() ? "" : ", ") + std::to_string(m);
          throw InputError(entry + ": boundary id " + std::to_string(id) +
                           " is not in the mesh (its ids are " + present + ")");
        }
    for (const auto id : mesh_ids)
      require(assigned.count(id) == 1,
              "Boundary conditions",
              "boundary id " + std::to_string(id) +
                " of the mesh has no condition; list it under Prescribed "
                "velocity ids, Symmetry ids, Slip wall ids, Traction free ids "
                "or Contact/Die ids");
  }

  template <int dim>
  void
  check_axisymmetric_mesh(const Triangulation<dim> &triangulation, const std::set<BoundaryId> &symmetry_ids)
  {
    // Vertices of generated and Gmsh meshes on the axis have y = 0 up to round-off of the mesh size.
    const double tolerance = 1e-10 * dealii::GridTools::diameter(triangulation);
    for (const auto &vertex : triangulation.get_vertices())
      if (vertex[1] < -tolerance)
        {
          std::ostringstream where;
          for (unsigned int d = 0; d < dim; ++d)
            where << (d > 0 ? ", " : "") << vertex[d];
          throw InputError("Geometry: axisymmetric needs y >= 0 (y is the radius, x the axis), but the mesh has "
                           "a vertex at (" + where.str() + "); move the mesh to the upper half-plane");
        }
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        {
          const auto face = cell->face(f);
          if (!face->at_boundary() || symmetry_ids.count(face->boundary_id()))
            continue;
          bool on_axis = true;
          for (const unsigned int v : face->vertex_indices())
            on_axis &= std::abs(face->vertex(v)[1]) <= tolerance;
          require(!on_axis,
                  "Geometry",
                  "axisymmetric: boundary id " + std::to_string(face->boundary_id()) +
                    " lies on the axis y = 0; list it under Boundary conditions/Symmetry ids "
                    "(v_y = 0 on the axis)");
        }
  }

  template void
  check_axisymmetric_mesh<2>(const Triangulation<2> &, const std::set<BoundaryId> &);
  template void
  make_mesh<2>(const MeshParameters &, Triangulation<2> &);
  template void
  make_mesh<3>(const MeshParameters &, Triangulation<3> &);
  template void
  check_boundary_ids<2>(const Triangulation<2> &, const std::map<BoundaryId, std::string> &);
  template void
  check_boundary_ids<3>(const Triangulation<3> &, const std::map<BoundaryId, std::string> &);
  template void
  check_axisymmetric_mesh<3>(const Triangulation<3> &, const std::set<BoundaryId> &);
  template void
  read_msh_file<2, 2>(const std::string &, const std::string &, const std::string &, const std::string &,
                      dealii::Triangulation<2, 2> &);
  template void
  read_msh_file<3, 3>(const std::string &, const std::string &, const std::string &, const std::string &,
                      dealii::Triangulation<3, 3> &);
  template void
  read_msh_file<1, 2>(const std::string &, const std::string &, const std::string &, const std::string &,
                      dealii::Triangulation<1, 2> &);
  template void
  read_msh_file<2, 3>(const std::string &, const std::string &, const std::string &, const std::string &,
                      dealii::Triangulation<2, 3> &);
} // namespace dieflow
