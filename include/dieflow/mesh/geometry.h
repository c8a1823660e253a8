// The mesh of a deck: the Mesh subsection, the die2d scene, the box, Gmsh files, the checks of boundary ids and of the axis.
#ifndef dieflow_geometry_h
#define dieflow_geometry_h

#include <dieflow/base/parameters.h>

#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include <map>
#include <set>
#include <string>

namespace dieflow
{
  using dealii::Point;
  using dealii::Triangulation;

  /**
   * The die2d scene of benchmarks/die2d.md (upper half, x axis = symmetry):
   *   A = (-L_c, 0), B = (-L_c, h_i), C = (0, h_i), D = (x_d, h_o),
   *   E = (x_d + L_l, h_o), F = (x_d + L_l, 0),  x_d = (h_i - h_o)/tan(beta),
   * with boundary ids 1 inlet A-B, 2 outlet E-F, 3 container wall B-C,
   * 4 die face C-D and land D-E, 5 symmetry F-A.
   *
   * The mesh has three structured blocks (container, converging zone, land)
   * with the same number of cells across; each block has cells of aspect
   * ratio near one, so the cells shrink with the channel towards the exit.
   * Layout "bisected" (the default) joins the blocks along the bisectors of
   * the die corners C and D, so that the cells there have the corner's half
   * angle: 55 and 125 degrees for beta = 70. Layout "blocks" joins them along
   * the verticals through C and D, which leaves cells of 20 degrees at C and
   * 160 degrees at D: its ram force is far off on coarse meshes
   * (doc/benchmarks.md).
   * A flat die (beta = 90) has no converging zone: the container's right
   * side is split at h_o into the land's inlet and the die face.
   */
  struct Die2dGeometry
  {
    double       inlet_half_height  = 19;
    double       outlet_half_height = 4.75;
    double       die_angle_degrees  = 70;
    double       container_length   = 20;
    double       land_length        = 15;
    unsigned int cells_across       = 4;
    /// How the blocks of the die section are cut (doc/benchmarks.md): along
    /// the verticals through C and D, or along the bisectors of their angles.
    enum class Layout
    {
      blocks,
      bisected
    };
    Layout       layout             = Layout::bisected;
    /// Power grading towards the die corners and the walls (1: uniform).
    double       grading_exponent   = 1;
    /// Dimension = 3: the scene extruded over z in [0, depth] (ids 6, 7).
    double       depth              = 1;
    unsigned int cells_in_depth     = 1;
    /// Source = rectangular bar quarter: the half widths in z.
    double       inlet_half_width   = 10;
    double       outlet_half_width  = 6;

    double
    die_exit_x() const;
    /// The corner points A..F of the scene.
    Point<2>
    corner(const char name) const;

    static constexpr BoundaryId inlet_id     = 1;
    static constexpr BoundaryId outlet_id    = 2;
    static constexpr BoundaryId container_id = 3;
    static constexpr BoundaryId die_id       = 4;
    static constexpr BoundaryId symmetry_id  = 5;
    static constexpr BoundaryId front_id     = 6;
    static constexpr BoundaryId back_id      = 7;
  };

  /**
   * An axis-parallel box [lower, upper] with ids 1 (x = x_min), 2 (x = x_max),
   * 3 (y = y_min), 4 (y = y_max), 5 (z = z_min), 6 (z = z_max); used by the
   * exact-solution tests (channels, compression, Couette layers).
   */
  struct BoxGeometry
  {
    std::vector<double>       lower{0, 0, 0};
    std::vector<double>       upper{1, 1, 1};
    std::vector<unsigned int> subdivisions{4, 4, 4};
    /// Shift of interior vertices, as a fraction of the cell size, to test
    /// distorted meshes (0: none). Deterministic pseudo-random.
    double distortion = 0;
    /// Rotation (degrees, counter-clockwise about the origin; 2D), to test
    /// inclined walls.
    double rotation = 0;
  };

  /**
   * The deck's "Mesh" subsection: where the mesh comes from and how often it
   * is refined before the first cycle.
   */
  struct MeshParameters
  {
    /// Where the mesh comes from (Mesh/Source).
    enum class Source
    {
      die2d,
      round_bar_quarter,
      rectangular_bar_quarter,
      box,
      gmsh
    };
    /// The deck's names: "die2d", "round bar quarter", "rectangular bar quarter", "box", "gmsh".
    static Source
    source_named(const std::string &name);

    Source        source = Source::die2d;
    Die2dGeometry die2d;
    BoxGeometry   box;
    /// As written in the deck (error messages name it so).
    std::string   gmsh_file;
    /// Directory that a relative Gmsh file name is relative to: the deck's.
    std::string   base_directory;
    unsigned int  global_refinements = 0;
    /// Levels of geometric grading towards the wall corners (see
    /// grade_towards()), and the width of each layer in cell diameters.
    unsigned int  corner_refinements = 0;
    double        corner_width       = 1;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /**
   * Reads the Gmsh file @p file_name (format 2 or 4; a relative path is
   * relative to @p base_directory) into @p triangulation: a missing, empty
   * or unreadable file is an InputError of the deck entry @p entry, which
   * calls the file @p what ("a Gmsh mesh"). Meshes and die surfaces
   * (dim = spacedim - 1) alike.
   */
  template <int dim, int spacedim>
  void
  read_msh_file(const std::string &                   file_name,
                const std::string &                   base_directory,
                const std::string &                   entry,
                const std::string &                   what,
                dealii::Triangulation<dim, spacedim> &triangulation);

  /// Builds the coarse mesh the deck asks for and refines it globally.
  template <int dim>
  void
  make_mesh(const MeshParameters &parameters, Triangulation<dim> &triangulation);

  /**
   * Checks that the boundary ids the deck assigns and those of the mesh
   * agree: every id the deck names exists in the mesh, and every id of the
   * mesh has a condition. @p assigned maps an id to the deck entry naming it.
   */
  template <int dim>
  void
  check_boundary_ids(const Triangulation<dim> &                   triangulation,
                     const std::map<BoundaryId, std::string> &assigned);

  /**
   * The axisymmetric geometry's conditions on the mesh: y (the radius) is
   * nowhere negative, and every boundary face on the axis y = 0 belongs to
   * one of @p symmetry_ids (v_r = 0 there, without which the hoop rate
   * v_r / r and the weak form are unbounded). An InputError naming
   * Geometry otherwise.
   */
  template <int dim>
  void
  check_axisymmetric_mesh(const Triangulation<dim> &triangulation, const std::set<BoundaryId> &symmetry_ids);
} // namespace dieflow

#endif
