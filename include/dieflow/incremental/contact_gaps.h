// Contact in a run in time by the gap in positions: nodes put back onto the dies, faces that come onto and leave them, gaps closed within a step.
#ifndef dieflow_incremental_contact_gaps_h
#define dieflow_incremental_contact_gaps_h

#include <dieflow/base/archive.h>
#include <dieflow/contact/die_surface.h>
#include <dieflow/mesh/wall_nodes.h>
#include <dieflow/base/parameters.h>

#include <deal.II/grid/tria.h>

#include <functional>
#include <map>
#include <set>
#include <vector>

namespace dieflow
{
  /// What ContactGaps::update() did in one step.
  struct GapUpdate
  {
    /// Boundary faces that came onto a die (free -> die id) and left it.
    unsigned int entered = 0;
    unsigned int left    = 0;
    /// The deepest a free node went through a die within the step, before
    /// it was put back on the die's surface, or a die's corner went into
    /// the metal between two of its boundary nodes, before one of them was
    /// put on the corner (mm; 0 when none did).
    double penetration = 0;
  };

  /**
   * Contact by the gap in positions (Problem = incremental): the seed
   * paper's g_n = (x_s - x_1).n, for the nodes of the free surface. The
   * velocity problem of a step keeps the nodes of the die faces on the die
   * (their gap rate g_n' = v.n <= 0, the active set), and after the move
   * the nodes that every die direction held are put back on it (the drift
   * of a curved die, or of Adams-Bashforth 2's previous velocity, never adds
   * up; a corner node that one wall of a die corner let go is not pulled
   * onto the other). The nodes no die held (the free surface's, and die
   * faces' separated ones) are not in that active set, so a node that the
   * step moves through a die (its distance to a facet's plane changes sign
   * and it ends over that facet) is put back onto the facet's plane along
   * the normal, and the depth it went through is reported. In 2D a corner
   * of a die (two of its facets meeting at more than the wall corner angle)
   * that went into the metal between two nodes of its boundary (the
   * node-to-facet contact holds nodes, not the edges between them: past
   * the die exit D the edge from the last node on the die face to the
   * first one past D cut over D, and the metal flowed through an opening
   * that much wider, the ram force low; doc/benchmarks.md) puts one
   * of the two nodes on the corner: the metal's boundary passes through it
   * again, as a steady run's mesh has a node there. Then a free face whose vertices all
   * lie on one die (within 1e-6 of the die's size) becomes a face of that
   * die (its boundary id), so that the next step's active set takes its
   * nodes (they enter in contact and may separate at the next state
   * update); a die face with no vertex left on the die goes back to the
   * free surface (its id before, or the first traction-free id). A face
   * with some vertices on the die keeps its id: the nodes off it are the
   * active set's separated nodes, and a face that entered and left on
   * alternate steps would rebuild the contact set every step.
   *
   * The dies are the Contact/Die surfaces where given, else the metal's die
   * faces at t = 0, whose end segments (2D) go on straight by the mesh's
   * diameter (the metal slides past the edge of its first contact on a
   * platen). A die with a velocity (Contact/Die velocities) is translated
   * before each update, so that the nodes in contact go back onto where it
   * is now and a node crosses it where it moved to.
   */
  template <int dim>
  class ContactGaps
  {
  public:
    /// The gap rate (v - V).n at which a node's direction closes the gap g
    /// by the end of the step: gap_rate(node, direction, g).
    using GapRate = std::function<double(const WallNode<dim> &, const WallDirection<dim> &, double)>;

    void
    initialize(const dealii::Triangulation<dim> &           triangulation,
               const std::set<BoundaryId> &                  die_ids,
               const std::map<BoundaryId, DieSurface<dim>> & given_surfaces,
               const std::set<BoundaryId> &                  free_ids);

    /**
     * After the mesh moved from @p old_vertices to its vertices now: the
     * vertices of die faces that were @p in_contact (by vertex index: held
     * by every die direction in the step's solution) go back onto their
     * die, the other vertices of the free surface and of die faces that
     * went through a die too, a node goes onto a die corner that went into
     * the metal (2D; a corner: facets meeting at an angle whose cosine is
     * below @p cos_corner, Boundary conditions/Wall corner angle), and faces
     * come onto and leave the dies.
     */
    GapUpdate
    update(const std::vector<dealii::Point<dim>> &old_vertices,
           const std::vector<bool> &              in_contact,
           dealii::Triangulation<dim> &           triangulation,
           const double                           cos_corner);

    /**
     * The nodes of the free surface (@p free_nodes, from collect_wall_nodes()
     * on the traction-free ids) that lie over a die within @p reach of its
     * plane, each with one direction per such die: the normal towards the
     * die, the die's id and facet (the master of its contact element), the
     * node's free-surface weight and length, and the gap rate
     * @p gap_rate(node, direction, g) at which it reaches the die at the end
     * of the step (the paper's g_n + dt (v_s - v_die).n <= 0 in rates; the
     * integrator's, DieFlowProblem::approaching_nodes()). The step's solve
     * holds them to (v - V).n <= that rate, so that a node that would go
     * through a die within the step lands on it instead
     * (ContactSet::setup()).
     */
    std::vector<WallNode<dim>>
    approaching(const std::vector<WallNode<dim>> &free_nodes, const double reach, const GapRate &gap_rate) const;

    /**
     * The nodes of die faces that are off their die (of @p ids: the dies
     * given as Contact/Die surfaces): a node that separated, or a corner of
     * the metal that slid past a corner of the die, stands at a gap g from
     * the facet under it (within @p reach, its normal within the corner
     * angle, @p cos_corner, of the wall's), not on it. Its direction takes
     * that facet and normal and the gap rate at which it closes the gap by
     * the end of the step, as approaching() does for the free surface: the
     * active set then holds it to arrive on the die, not to stay at the gap
     * (or, for a node that went into it, to come back out onto it). A
     * direction with no such facet (past the die's edge, or facing away
     * from the die under it) is dropped: its own face would hold the node
     * as if the die went on (a phantom wall), and a node left with no
     * direction is no wall node.
     */
    void
    close_gaps(std::vector<WallNode<dim>> &wall_nodes,
               const std::set<BoundaryId> &ids,
               const double                reach,
               const double                cos_corner,
               const GapRate &             gap_rate) const;

    /// After the domain was meshed anew (remesh_domain()): the faces that
    /// came onto a die remember their id before under their new index.
    void
    renumber_faces(const std::map<unsigned int, unsigned int> &new_face_of_old);

    /// Into a checkpoint, and back: the dies where they are, the faces' ids
    /// before they came onto a die, the free ids and the tolerance.
    void
    save(OutputArchive &ar) const;
    void
    load(InputArchive &ar);

    /// Moves die @p id by @p shift (Contact/Die velocities: V dt), before update().
    void
    translate(const BoundaryId id, const dealii::Tensor<1, dim> &shift);

    bool
    empty() const
    {
      return dies.empty();
    }

  private:
    /**
     * 2D: for each corner of a die, the boundary edge of the metal (of a
     * free or die id) that passes deepest on the metal's side of it, within
     * one edge length and over the edge's interior: the end whose move
     * onto the corner changes the enclosed area least (the overlap, and
     * what the move adds or cuts off beside it), of those whose cells stay
     * uninverted, goes onto the corner (none if neither). Returns the
     * deepest overlap closed.
     */
    double
    put_nodes_on_die_corners(dealii::Triangulation<dim> &triangulation, const double cos_corner) const;

    /// How many vertices of @p face lie on the surface of @p die.
    template <typename FaceIterator>
    unsigned int
    vertices_on(const FaceIterator &face, const BoundaryId die) const;

    std::map<BoundaryId, DieSurface<dim>> dies;
    /// How far each die moved since the last update().
    std::map<BoundaryId, dealii::Tensor<1, dim>> shifts;
    std::set<BoundaryId>                  free_ids;
    /// The id a face had before it came onto a die (by face index).
    std::map<unsigned int, BoundaryId> id_before;
    double                             tolerance = 0;
  };
} // namespace dieflow

#endif
