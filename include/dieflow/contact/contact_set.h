// The contact set: the die's contact nodes, their active set and stick/slip states, and their element terms.
#ifndef dieflow_contact_set_h
#define dieflow_contact_set_h

#include <dieflow/base/archive.h>
#include <dieflow/base/parameters.h>
#include <dieflow/contact/contact_element.h>
#include <dieflow/contact/contact_parameters.h>
#include <dieflow/contact/contact_results.h>
#include <dieflow/mesh/wall_nodes.h>
#include <dieflow/solvers/linearization.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <ostream>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace dieflow
{
  /// What the contact adds to one node's equations in an assembly.
  template <int dim>
  struct ContactContribution
  {
    std::array<GlobalDof, dim> dofs;
    /// Row transformation T = I + b m^T of the node's flow rows: the
    /// dependence of the friction force on the normal reaction m.R_flow
    /// (m = n but for a node with several normals, dual_normal()).
    dealii::FullMatrix<double> row_transform;
    bool                       has_row_transform = false;
    /// Residual and tangent of the contact element (the slave's block).
    dealii::Vector<double>     residual;
    dealii::FullMatrix<double> tangent;
  };



  /**
   * Unilateral contact with friction on the die ids, in velocity form on a
   * rigid die whose surface is the mesh boundary (eq. (6)):
   *   v.n <= 0, F_n <= 0, F_n v.n = 0;  |F_t| <= mu |F_n|, stick or slip.
   *
   * Normal direction, "active set" (deal.II step-41/42, a primal-dual active
   * set / semismooth Newton method): each wall direction k of a contact node
   * (two at a corner) is active when p_k + c (v.n_k) > 0, with the contact
   * pressure p_k = -F_n,k / w_k from the flow residual R at the node (the
   * reaction, decomposed on the active normals) over the lumped boundary
   * weight, and c = (active set constant) x eta_m / h; active directions
   * are the constraints v.n_k = 0 of AffineConstraints. Converged when no
   * direction changes and the residual is small. "penalty": the paper's
   * perturbed Lagrangian with F_n = -omega_n max(v.n, 0), eq. (20).
   *
   * Corners: a node where two wall directions meet (the die entry C, the
   * die exit D) carries one unilateral condition per direction; with both
   * active the 2D node is at rest (counted as stick), with one active it
   * slides along that wall and may leave the other. A node on a
   * prescribed-velocity part is not a contact node: the prescribed velocity
   * wins and its reaction counts for that part.
   *
   * Tangential direction: one ContactElement per active direction,
   * slave = the node, master = a die facet with that normal. Coulomb slip
   * makes the friction force depend on the normal reaction n.R_flow(v); the
   * assembler applies the node's row transformation T = I + b n^T
   * (b = dR_c/dF_n) to the node's flow rows, which is the exact
   * non-symmetric linearisation of that dependence.
   *
   * States are decided in update() and frozen while an iteration assembles
   * and searches its line. A state signature that repeats (cycling) holds
   * the directions that keep entering and leaving contact in contact, and
   * gives those that keep switching between stick and slip the regularised
   * Coulomb law; the log says so.
   */
  template <int dim>
  class ContactSet
  {
  public:
    /// The deck's contact parameters (kept by reference: the problem's one copy).
    void
    initialize(const ContactParameters &parameters);

    bool
    empty() const
    {
      return parameters == nullptr || parameters->die_ids.empty();
    }
    bool
    uses_penalty() const
    {
      return parameters->uses_penalty();
    }

    /**
     * The contact nodes of the current mesh: wall nodes on the die ids
     * without components constrained in @p prescribed (the prescribed
     * velocities). Every
     * direction starts active and slipping (the frictionless slip-wall
     * problem), unless @p keep_state maps it (and its contact pressure,
     * about which Coulomb slip linearises) from the previous mesh by
     * position.
     *
     * @p approaching (Problem = incremental, ContactGaps::approaching()):
     * nodes of the free surface near a die, each direction with its gap
     * rate (g / dt for a forward Euler move). They start separated and
     * never inherit a state; their condition is (v - V).n <= the gap rate
     * with the same active set, so an active one is v.n = V.n + the gap
     * rate: it reaches the die at the end of the step.
     */
    void
    setup(const std::vector<WallNode<dim>> &die_nodes,
          const AffineConstraints<double> & prescribed,
          const bool                        keep_state,
          const std::vector<WallNode<dim>> &approaching = {});

    /**
     * The contact set with the states of this one frozen, on another
     * discretisation of the same mesh (@p die_nodes, @p prescribed: the
     * goal estimate's richer space): each node takes the state of the
     * nearest node with the same wall direction, as on a refined mesh.
     */
    ContactSet
    frozen_on(const std::vector<WallNode<dim>> &die_nodes, const AffineConstraints<double> &prescribed) const;

    /// What setup() maps from the previous mesh to a node's direction: its
    /// state, found by position, die id and normal.
    struct StateRecord
    {
      dealii::Point<dim>  position;
      BoundaryId          id = 0;
      Tensor<1, dim>      normal;
      double              weight = 0;
      bool                active = false;
      ContactStatus       status = ContactStatus::separated;
      std::vector<double> slip_direction;
      double              normal_force = 0;
      /// Direction::bound_frozen: a direction whose Coulomb coupling cycled
      /// keeps the fixed point on the moved or refined mesh.
      bool                bound_frozen = false;
    };
    /// The states of the current nodes (a checkpoint's; the free surface's
    /// approaching directions, which nothing inherits, left out).
    std::vector<StateRecord>
    state_records() const;
    /// The states of the current nodes into a checkpoint; load() reads
    /// them back as the states the next setup() with keep_state maps from
    /// (a restart), instead of the current nodes'.
    void
    save(OutputArchive &ar) const;
    void
    load(InputArchive &ar);


    /// eta_m, the viscosity scale of c; lambda, the incompressibility
    /// penalty that omega_n and omega_t are multiples of; the largest
    /// prescribed speed, which with the dies' speeds sets the speed scale
    /// of the regularised Coulomb law's default v0.
    void
    set_scales(const double eta, const double lambda, const double prescribed_speed)
    {
      viscosity_scale = eta;
      penalty_scale   = lambda;
      speed_scale     = prescribed_speed;
      for (const auto &[id, velocity] : die_velocity)
        speed_scale = std::max(speed_scale, velocity.norm());
      if (!(speed_scale > 0))
        speed_scale = 1;
    }

    /**
     * Revises the states from the velocity @p v and the flow residual
     * @p flow_residual (unconstrained, hanging nodes condensed: the
     * reactions at the contact nodes). Returns how many directions changed
     * their normal and their tangential state.
     */
    StateChanges
    update(const dealii::Vector<double> &v, const dealii::Vector<double> &flow_residual, std::ostream &log);

    /// v.n_k = V.n_k for every active direction, and v.t = V.t where a
    /// node sticks exactly (active set only; V the die's velocity, zero
    /// with @p homogeneous: the constraints of a Newton update).
    void
    add_constraints(AffineConstraints<double> &constraints, const bool homogeneous) const;

    /// The contributions of the contact elements at @p v in the frozen states.
    std::vector<ContactContribution<dim>>
    contributions(const dealii::Vector<double> &v) const;

    /// Node-wise forces and states of the converged @p v (call update() first).
    std::vector<ContactNodeResult<dim>>
    results(const dealii::Vector<double> &v) const;

    /// Status per vertex of @p dof_handler's triangulation (0 separated,
    /// 1 stick, 2 slip; -1 elsewhere) for the VTU.
    dealii::Vector<double>
    vertex_status(const DoFHandler<dim> &dof_handler) const;

    /// "" or what the cycling guard did in this cycle.
    std::string
    cycling_note() const;

    /// Every friction bound (mu, the Tresca bound) times @p scale: 0 the
    /// frictionless problem, 1 the deck's (a continuation's stages,
    /// DieFlowProblem::continue_in_friction()).
    void
    set_friction_scale(const double scale)
    {
      friction_scale = scale;
    }
    /// Every direction back in contact and slipping, as setup() starts it
    /// (the free surface's approaching ones separated), with no force.
    void
    restart_states();
    /// The cycling guard's holds (held in contact, regularised, bound
    /// frozen) and the slip reversals forgotten, the states kept: a new
    /// continuation stage is a new problem.
    void
    release_holds();
    /// From the next release_holds() on, every direction's Coulomb bound
    /// frozen at each update's normal force (Contact/Coulomb coupling =
    /// fixed point) if @p frozen; else only where the states cycle.
    void
    freeze_bounds(const bool frozen)
    {
      bounds_frozen_everywhere = frozen;
    }

    /// What the cycling guard did: directions held in contact, and friction
    /// laws regularised.
    std::pair<unsigned int, unsigned int>
    cycle_breaks() const;

    /// True where the deck's friction law of die id @p id transmits no
    /// tangential force (mu = 0, or a zero Tresca bound).
    bool
    frictionless(const BoundaryId id) const
    {
      return parameters->frictionless(id);
    }

    /// The translation velocity of die id @p id (zero for a die at rest).
    Tensor<1, dim>
    velocity_of(const BoundaryId id) const;

    /// Whether any die moves.
    bool
    dies_move() const
    {
      return !die_velocity.empty();
    }

    const ContactParameters &
    get_parameters() const
    {
      return *parameters;
    }

    /// The positions of the nodes where walls meet (more than one wall
    /// direction: the die's corners, where it meets a symmetry line).
    std::vector<dealii::Point<dim>>
    corner_points() const;

    /// A node is separated when no wall holds it, stick when held at rest
    /// (two walls, or a sticking one), slip otherwise.
    ContactCounts
    node_counts() const;

  private:
    using Slip = typename ContactElement<dim>::Slip;
    struct Direction
    {
      WallDirection<dim>  wall;
      ContactElement<dim> element;
      bool                active;
      ContactStatus       status;
      /// The slip direction of the state, in the tangent basis (2D: the sign).
      Slip                slip_direction;
      double              normal_force;
      /// t_i.R_flow of a node held at rest by the exact stick constraint.
      Slip                stick_force;
      /// n.R_flow at a separated direction: zero at equilibrium.
      double              free_reaction;
      /// 3D slip: the friction force lambda carried by the semismooth Newton
      /// method (ContactElement::friction()), and the slip rate and bound it
      /// is linearised at; zero: none yet (until the node's first state
      /// update on this mesh: its slip direction is then g / |g|).
      Slip                multiplier;
      Slip                multiplier_rate;
      double              multiplier_bound;
      /// How often the slip direction reversed in this cycle.
      unsigned int        reversals;
      /// Cycling: the direction stays in contact from now on...
      bool                held_in_contact;
      /// ... or its friction law becomes the regularised one.
      bool                regularised;
      /// Cycling under Contact/Coulomb coupling = auto, first: the Coulomb
      /// bound frozen at each update's normal force (Coulomb at the fixed
      /// point, so no break of the law).
      bool                bound_frozen;
      /// A free-surface node approaching the die (its gap rate in wall).
      bool                approaching;
    };
    struct Node
    {
      std::array<GlobalDof, dim> dofs;
      dealii::Point<dim>         position;
      unsigned int               vertex;
      std::vector<Direction>     directions;
      /// Normals of the node's slip walls and symmetry lines: always held.
      std::vector<Tensor<1, dim>> fixed_normals;
      unsigned int               n_active() const;
      /// Active contact directions and fixed walls: dim or more is at rest.
      unsigned int
      n_held() const
      {
        return n_active() + fixed_normals.size();
      }
    };

    FrictionLaw
    law_of(const Direction &direction) const;
    /// c of the semismooth rules (force per velocity): (active set
    /// constant) x eta_m x w / h.
    double
    contact_constant(const Direction &direction) const;
    /// omega per node: factor x lambda x w / h, h = (the node's wall length)^(1/(dim-1)).
    double
    penalty_of(const double factor, const WallDirection<dim> &wall) const;
    /// (v - V).n - g / dt: positive where the node would go through the die
    /// (g / dt = 0 for a node on it).
    double
    normal_rate(const Node &node, const Direction &direction, const dealii::Vector<double> &v) const;
    /// (v_s, V, .., V): the node's velocity and the die's at its master nodes.
    typename ContactElement<dim>::Vector
    element_velocity(const Node &node, const Direction &direction, const dealii::Vector<double> &v) const;
    /// True for a direction that sticks exactly to its wall, on a node that
    /// its walls do not hold at rest already (one wall, or two in 3D).
    bool
    sticks_exactly(const Node &node, const Direction &direction) const;
    /// m with F_n = m.R_flow for @p direction at @p node: its row of the
    /// least-squares split of a reaction on the node's normals.
    Tensor<1, dim>
    dual_normal(const Node &node, const Direction &direction) const;
    /// The node's reaction on its active normals (into @p forces) and, where
    /// it sticks exactly, on the tangents (into @p stick_forces): what the
    /// slipping walls' friction at @p v leaves, shared by the sticking walls
    /// in proportion to their bounds.
    void
    decompose_reaction(const Node &                  node,
                       const dealii::Vector<double> &flow_residual,
                       const dealii::Vector<double> &v,
                       std::vector<double> &         forces,
                       std::vector<Slip> &           stick_forces) const;

    const ContactParameters *  parameters = nullptr;
    std::map<BoundaryId, Tensor<1, dim>> die_velocity;
    std::vector<Node>          nodes;
    /// load()'s, for the next setup().
    std::vector<StateRecord>   restored_states;
    double                     viscosity_scale = 1;
    double                     penalty_scale   = 1;
    /// The largest prescribed or die speed (1 if nothing moves).
    double                     speed_scale     = 1;
    /// v0 of the friction laws regularised because their states cycled.
    double                     cycling_velocity = 1;
    /// set_friction_scale()'s.
    double                     friction_scale   = 1;
    bool                       bounds_frozen_everywhere = false;
    /// The largest speed of the last update (the 3D slip floor's scale).
    double                     largest_speed = 1;
    std::vector<std::size_t>   recent_signatures;
    /// The (node, direction) pairs each of recent_signatures' updates changed:
    /// a cycle's members are those changed since its state was last seen.
    std::vector<std::vector<std::pair<unsigned int, unsigned int>>> recent_changes;
    /// Updates in a row without a change of state, and the frozen bounds
    /// thawed since the last setup() or release_holds() (see update()).
    unsigned int               quiet_updates = 0, thaws = 0;
    /// The velocity of the last update, to tell when Newton has stopped
    /// moving the solution (3D ties on the cone, see update()).
    dealii::Vector<double>     previous_velocity;
  };

} // namespace dieflow

#endif
