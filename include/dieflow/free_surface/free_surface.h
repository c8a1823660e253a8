// The free surface of a steady flow and the deck's Free surface subsection: moves onto the streamlines of a solution, the dies keeping it out.
#ifndef dieflow_free_surface_h
#define dieflow_free_surface_h

#include <dieflow/base/parameters.h>

#include <dieflow/contact/contact_results.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace dieflow
{
  /// The free surface of a steady run (subsection Free surface).
  struct FreeSurfaceParameters
  {
    /// The most moves of the free surface per cycle (0: the domain is kept).
    unsigned int            iterations = 0;
    /// Settled when no node would move more than this part of its edges' length.
    double                  tolerance = 1e-3;
    /// Traction-free ids whose faces are free surfaces; the first also
    /// takes the faces a die lets go.
    std::vector<BoundaryId> ids;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
    bool
    enabled() const
    {
      return iterations > 0;
    }
  };

  /// What one move of the free surface did.
  struct FreeSurfaceMove
  {
    /// The largest move of a node over the shorter of its two boundary edges.
    double       largest = 0;
    /// Faces of the free surface after the move; die faces it took from the
    /// dies (the metal left them) and gave back (it came onto them again).
    unsigned int free_faces = 0, let_go = 0, reattached = 0;
  };

  /**
   * The free surface of a steady flow (2D: plane strain and axisymmetric):
   * the part of the boundary where the metal is not held, on which a steady
   * flow has v.n = 0 (the surface is a streamline). A steady run on the
   * domain as meshed lets the metal leave a die only in velocity: past the
   * sharp exit D of die2d the land's nodes separate with v.n > 0, a share
   * of the throughput coming in through the land (the mass-balance
   * warning; doc/benchmarks.md). move() makes the free surface a streamline
   * of the last solution, and the run solves again, until the surface
   * settles (the streamline method of free-surface flows, e.g. die swell).
   *
   * The free surface is made of stretches of boundary edges: the faces of
   * the Free surface ids, and die faces neither of whose nodes a die
   * direction of that face's normal holds (the contact results). Each
   * stretch is marched from its upstream end (where the flow enters it;
   * that node stays): each edge becomes its projection onto the mean
   * velocity of its two nodes (nodes move across the flow, not along it: a
   * stretch along the land keeps its nodes' x, and its end stays on the
   * outlet; v.n then integrates to zero over each straight Q1 edge). A node
   * the march puts into a die goes onto the die surface (the dies of the
   * first mesh, kept), and an edge with both nodes on a die is that die's
   * again, unless the dies let it go before on this mesh: then it stays
   * free, lying on the die (the surface grazes the die with no pressure;
   * given back, such faces pull away from the die at the next solve and
   * the march puts them back, a cycle of two). The march goes on over the
   * die faces downstream of the stretch (the metal may leave them too) to
   * the next other part; the straight
   * boundary there (the outlet) is stretched to the march's end. Each move
   * is damped to a quarter of an edge (a damped fixed point: the first
   * streamlines of a domain the metal does not fill can be far off). The
   * interior follows by deal.II's Laplace transform (GridTools), hanging
   * vertices onto their parents.
   */
  class FreeSurface
  {
  public:
    /// Keeps the dies' surfaces: the faces of @p die_ids of the first mesh.
    void
    initialize(const dealii::Triangulation<2> &mesh, const std::set<BoundaryId> &die_ids,
               const FreeSurfaceParameters &parameters);

    /**
     * Moves the free surface of @p mesh onto the streamlines of @p velocity
     * (a vector field of @p dof_handler), the dies holding the nodes that
     * @p results (of the same velocity) hold, and sets the faces' ids;
     * nothing moves if no node would move more than the tolerance, or if
     * not @p apply (then it only measures).
     */
    FreeSurfaceMove
    move(dealii::Triangulation<2> &mesh, const dealii::DoFHandler<2> &dof_handler, const dealii::Vector<double> &velocity,
         const std::vector<ContactNodeResult<2>> &results, const bool apply);

    /// Forgets the faces the dies let go (a new mesh: its faces are others).
    void
    new_mesh()
    {
      let_go.clear();
    }

  private:
    struct Segment
    {
      dealii::Point<2>  a, b;
      /// Out of the metal, into the die.
      Tensor<1, 2>      normal;
      BoundaryId        id;
    };
    struct Nearest
    {
      /// Positive inside a die.
      double           depth;
      dealii::Point<2> point;
      BoundaryId       id;
    };
    /// The nearest point of the dies to @p x (at a die corner the sign
    /// of the depth from the sum of the two walls' normals).
    Nearest
    nearest_die(const dealii::Point<2> &x) const;

    std::vector<Segment>  dies;
    /// The faces (by index) the dies let go since the last new mesh.
    std::set<unsigned int> let_go;
    double                on_die = 0;
    FreeSurfaceParameters parameters;
  };
} // namespace dieflow

#endif
