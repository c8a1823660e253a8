// Meshing a run's domain anew: when (the deck's remeshing entries), and how (Gmsh's quadrilaterals inside the same boundary).
#ifndef dieflow_incremental_remeshing_h
#define dieflow_incremental_remeshing_h

#include <dieflow/base/parameters.h>

#include <deal.II/grid/tria.h>

#include <algorithm>
#include <functional>
#include <map>
#include <string>

namespace dieflow
{
  /**
   * When an incremental run meshes its domain anew (subsection Incremental):
   * when the smallest scaled Jacobian of the moved mesh falls below a
   * threshold (smallest_scaled_jacobian(): the sine of the worst corner
   * angle), and, if asked, every so many steps.
   */
  struct RemeshingParameters
  {
    /// Remesh when the smallest scaled Jacobian is below this (0: never).
    double       jacobian_threshold = 0;
    /// Remesh every this many steps as well (0: only by the Jacobian).
    unsigned int interval = 0;
    /// The longest boundary edge of a new mesh (mm; 0: the boundary's edges
    /// as they are). The extrudate's edges stretch with the reduction.
    double       boundary_edge_length = 0;

    /// Declares the entries in the current subsection (Incremental).
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    bool
    enabled() const
    {
      return jacobian_threshold > 0 || interval > 0;
    }
    /**
     * Whether a configuration whose smallest scaled Jacobian is @p jacobian,
     * @p steps_since the last new mesh, is meshed anew. A new mesh cannot
     * have better corners than the boundary's own (a fold's sharp corner):
     * when the last one, of smallest scaled Jacobian @p last_new_mesh, was
     * below the threshold, the next one comes when the cells are a tenth
     * worse than it, not at every step.
     */
    bool
    due(const double jacobian, const unsigned int steps_since, const double last_new_mesh) const
    {
      const double threshold = std::min(jacobian_threshold, 0.9 * last_new_mesh);
      return jacobian < threshold || (interval > 0 && steps_since >= interval);
    }
  };

  /// Whether the boundary edge from a to b of boundary id id may be cut
  /// into pieces on itself (remesh_domain()'s longest edge).
  template <int dim>
  using EdgeFilter = std::function<bool(const dealii::Point<dim> &, const dealii::Point<dim> &, BoundaryId)>;

  /// What remesh_domain() made of the old mesh.
  struct NewMesh
  {
    /// Old boundary face index -> the new mesh's face on the same edge (an
    /// edge split in two to make a loop's edge count even has none).
    std::map<unsigned int, unsigned int> boundary_face_of_old;
    /// Boundary edges cut into pieces (edges without a partner, at their
    /// midpoints, and edges longer than the limit; see remesh_domain()).
    unsigned int split_edges = 0;
    /// Boundary vertices that crowded their neighbours, dropped (see
    /// remesh_domain()).
    unsigned int dropped_vertices = 0;
    /// How Gmsh made it, if not at the first attempt (remesh_domain()).
    std::string  attempt;
  };

  /**
   * Meshes the domain of @p old anew with quadrilaterals, into @p fresh
   * (2D; the seed paper's "remeshing of the domain"). The boundary stays
   * what it is: every boundary vertex of @p old is a vertex of the new mesh
   * and every boundary edge is one edge of it (or two halves, below), with
   * its boundary id, so that the domain is the same polygon (the volume is
   * kept to round-off, also in the axisymmetric form: the cells are
   * straight-sided), the nodes in contact stay where the dies hold them and
   * the boundary faces keep their ids. Except where boundary vertices
   * crowd: while an edge is shorter than a quarter of the longer of its
   * neighbours, or than a tenth of @p longest_edge (if not 0), one of its
   * ends is dropped (NewMesh::dropped_vertices), the one whose triangle
   * with its neighbours is the smaller, never a reflex corner (the new
   * polygon stays inside the old one) nor a vertex higher over its
   * neighbours' chord than a twentieth of it (a corner of the metal's
   * shape, such as a fold's, not a crowding), and its two edges of one id become
   * one: the volume changes by those triangles (nothing for a vertex on a
   * straight wall). Nodes that flow into a corner where the metal stands,
   * or that the dies put back onto one corner, come to lie a millionth of
   * a millimetre apart: a new mesh that kept them had cells of that size.
   *
   * How: Gmsh (its C++ API, which the Debian deal.II links) triangulates
   * with Frontal-Delaunay, recombines the triangles into quadrilaterals
   * with the Blossom algorithm and splits every cell (a quadrilateral into
   * 4, a triangle into 3), which leaves no triangle whatever Blossom left
   * but halves every boundary line. So the boundary goes to Gmsh at half
   * its resolution: consecutive edges a-m-b of one id whose middle vertex
   * lies within a tenth of the chord from its midpoint are one line a-b,
   * whose midpoint node is then put back at m; an edge that has no such
   * partner is a line of its own, and is split at its midpoint (on the
   * edge: the domain is the same; NewMesh::split_edges). An edge longer
   * than @p longest_edge (if not 0) and that @p may_cut is never paired and
   * is cut into equal pieces no longer than it, on itself (the material's
   * boundary stretches
   * where it flows out of a die: an extrudate's edges grow with the
   * reduction). The cell size at each point is the mean length of its two
   * lines, which Gmsh interpolates inside. Cells take the material id of
   * @p old's first cell. If Gmsh's cells come out tangled (a cell gone
   * round the other way, or a corner of no angle), or Gmsh fails, the
   * domain is meshed again with Gmsh's Delaunay, then its Frontal-Delaunay
   * for quadrilaterals, and last with every edge a line of its own
   * (NewMesh::attempt says which).
   *
   * Throws InputError naming @p entry if every attempt fails (Gmsh's
   * error, or tangled cells), or Gmsh's mesh is not the old boundary's.
   */
  template <int dim>
  NewMesh
  remesh_domain(const dealii::Triangulation<dim> &old,
                dealii::Triangulation<dim> &      fresh,
                const double                      longest_edge,
                const EdgeFilter<dim> &           may_cut,
                const std::string &               entry);
} // namespace dieflow

#endif
