// The free surface of a steady flow and the deck's Free surface subsection: moves onto the streamlines of a solution, the dies keeping it out.
#ifndef dieflow_free_surface_h
#define dieflow_free_surface_h

#include <dieflow/base/parameters.h>

#include <dieflow/contact/contact_results.h>
#include <dieflow/mesh/coordinate_system.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <set>
#include <vector>

namespace dieflow
{
  /// The free surface of a steady run (subsection Free surface).
  struct FreeSurfaceParameters
  {
    /// The most moves of the free surface per cycle (0: the domain is kept).
    unsigned int            iterations = 0;
    /// Settled when no node would move more than this part of the free surface's length (and no face changes hands).
    double                  tolerance = 1e-5;
    /// How each move follows from the march's (Free surface/Relaxation).
    enum class Relaxation
    {
      aitken,
      none
    };
    Relaxation relaxation = Relaxation::aitken;
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

  /// A stretch of the free surface: its nodes from where the metal leaves the part before it.
  struct FreeSurfaceLine
  {
    /// The boundary ids of the parts before and after it: the die the metal
    /// leaves at the first point, and where it ends (the outlet, or a die
    /// the metal comes onto again).
    BoundaryId                    leaves = 0, ends = 0;
    std::vector<dealii::Point<2>> points;
  };

  /// What one move of the free surface did.
  struct FreeSurfaceMove
  {
    /// The largest move of a node over the free surface's length.
    double       largest = 0;
    /// The part of the move made (halved while it would spoil the cells; 0: none).
    double       step = 0;
    /// The march's move times this is the move made (Aitken's relaxation).
    double       relaxation = 1;
    /// Faces of the free surface after the move; die faces it took from the
    /// dies (the metal left them) and gave back (it came onto them again).
    unsigned int free_faces = 0, let_go = 0, reattached = 0;
    /// Free faces lying on a die (let go before on this mesh: the metal
    /// grazes the die), and their flux into it (v.n, out of the metal).
    unsigned int grazing_faces = 0;
    double       grazing_flux  = 0;
    /// The free stretches before the move.
    std::vector<FreeSurfaceLine> lines;

    /// Whether the surface moves or changes hands: a node would move more
    /// than @p tolerance of its length, or a face goes to or from a die.
    bool
    changes(const double tolerance) const
    {
      return largest > tolerance || let_go > 0 || reattached > 0;
    }
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
   * that node stays): node i + 1 goes along its spine (the outward normal
   * where it first took part in a move on this mesh; the outlet's line for
   * the stretch's end) to where the edge from the moved node i lies along
   * the mean velocity over the edge (r-weighted in axisymmetric runs): the
   * edge's flux int v.n then vanishes for either velocity degree, and no
   * node slides along the surface. A node the march puts into a die goes
   * onto it along its spine. The march goes on over the die faces
   * downstream of the stretch (the metal may leave them too): from where
   * the streamline meets a die, the nodes a die holds stay (the contact
   * decides there). An edge with both nodes on a die is that die's again
   * (given back); one given back and let go again by the next solve stays
   * free on this mesh, lying on the die (grazing: counted, with its flux
   * into the die). The straight boundary after the stretch (the outlet) is
   * stretched to the march's end. The whole move is made, halved while it
   * would spoil the cells; the interior follows by deal.II's Laplace
   * transform (GridTools), hanging vertices onto their parents. Each move
   * is the march's relaxed by Aitken's factor (relax()). Settled when no
   * node would move more than the tolerance times the free surface's
   * length and no face would go to or from a die (doc/incremental.md).
   */
  class FreeSurface
  {
  public:
    /// Keeps the dies' surfaces: the faces of @p die_ids of the first mesh.
    void
    initialize(const dealii::Triangulation<2> &mesh, const std::set<BoundaryId> &die_ids,
               const FreeSurfaceParameters &parameters, const CoordinateSystem<2> &coordinates);

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
      given_back.clear();
      spines.clear();
      last_residual.clear();
      relaxation   = 1;
      restart      = false;
      carry_let_go = true;
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
    /// Where the segment from @p out (outside the dies) to @p in (inside) meets a die.
    dealii::Point<2>
    onto_die(dealii::Point<2> out, dealii::Point<2> in) const;
    /**
     * Aitken's relaxation of the march's move r_k = placed - x (Irons and
     * Tuck; as in partitioned fluid-structure solvers): the move made is
     * omega_k r_k, omega_k = -omega_k-1 r_k-1.(r_k - r_k-1) / |r_k - r_k-1|^2
     * within [0.25, 2], the secant step of a fixed point along the last
     * change. The raw march overshoots on its second move (the first
     * streamlines of a domain the metal does not fill come back onto
     * the land; 0.52 damps it on die2d).
     */
    void
    relax(std::map<unsigned int, dealii::Point<2>> &placed, const std::vector<dealii::Point<2>> &x);

    std::vector<Segment>  dies;
    /// The faces (by index) the march gave back to the dies since the last
    /// new mesh, and those of them the dies let go again.
    std::set<unsigned int> given_back, let_go;
    /// The march's last move (by vertex) and the relaxation it was made with.
    std::map<unsigned int, Tensor<1, 2>> last_residual;
    double                               relaxation = 1;
    /// The last move gave faces back to the dies: the next starts Aitken's sequence anew.
    bool                                 restart = false;
    static constexpr double              smallest_relaxation = 0.25, largest_relaxation = 2;
    /// The direction each node of the free surface moves in (by vertex), since the last new mesh.
    std::map<unsigned int, Tensor<1, 2>> spines;
    /// The measure of ds (1, or 2 pi r): the faces' mean velocities and the grazing flux.
    CoordinateSystem<2>   coordinates;
    /// The first move on a new mesh: its free faces lying on a die were let go on the mesh before.
    bool                  carry_let_go = false;
    double                on_die = 0;
    FreeSurfaceParameters parameters;
  };
} // namespace dieflow

#endif
