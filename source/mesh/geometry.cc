// The mesh of a deck: the Mesh subsection, the box, Gmsh files, the checks of boundary ids and of the axis.
#include <dieflow/mesh/die_meshes.h>
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



  MeshParameters::Source
  MeshParameters::source_named(const std::string &name)
  {
    return name == "round bar quarter"       ? Source::round_bar_quarter :
           name == "rectangular bar quarter" ? Source::rectangular_bar_quarter :
           name == "box"                     ? Source::box :
           name == "gmsh"                    ? Source::gmsh :
                                               Source::die2d;
  }



  void
  MeshParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    source             = source_named(prm.get("Source"));
    gmsh_file          = prm.get("Gmsh file");
    global_refinements = prm.get_integer("Global refinements");
    corner_refinements = prm.get_integer("Corner refinements");
    corner_width       = prm.get_double("Corner grading width");
    if (source == Source::gmsh)
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
        require(value > 0 || (value == 0 && source == Source::round_bar_quarter),
                "Mesh/Die2d/" + entry,
                "must be positive" + std::string(source == Source::round_bar_quarter ? " or zero" : "") + ", got " +
                  prm.get(entry));
        return value;
      };
      die2d.container_length   = length("Container length");
      die2d.land_length        = length("Land length");
      die2d.cells_across       = prm.get_integer("Cells across");
      die2d.layout             = prm.get("Layout") == "blocks" ? Die2dGeometry::Layout::blocks : Die2dGeometry::Layout::bisected;
      die2d.grading_exponent   = prm.get_double("Grading exponent");
      die2d.depth              = positive("Depth");
      die2d.cells_in_depth     = prm.get_integer("Cells in depth");
      die2d.inlet_half_width   = positive("Inlet half width");
      die2d.outlet_half_width  = positive("Outlet half width");
      if (source == Source::rectangular_bar_quarter)
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
    if (parameters.source == MeshParameters::Source::die2d)
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
    else if (parameters.source == MeshParameters::Source::round_bar_quarter)
      {
        if constexpr (dim == 3)
          make_round_bar_quarter(parameters.die2d, triangulation);
        else
          throw InputError("Mesh/Source: 'round bar quarter' is a 3D mesh; set Dimension = 3 (in 2D the "
                           "round bar is the die2d scene with Geometry = axisymmetric)");
      }
    else if (parameters.source == MeshParameters::Source::rectangular_bar_quarter)
      {
        if constexpr (dim == 3)
          make_rectangular_bar_quarter(parameters.die2d, triangulation);
        else
          throw InputError("Mesh/Source: 'rectangular bar quarter' is a 3D mesh; set Dimension = 3 (in 2D "
                           "the die2d scene is its section)");
      }
    else if (parameters.source == MeshParameters::Source::box)
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
