#ifndef dieflow_contact_h
#define dieflow_contact_h

#include <dieflow/contact/contact_element.h>
#include <dieflow/flow/flow_assembler.h>
#include <dieflow/solvers/nonlinear_solver.h>
#include <dieflow/parameters.h>
#include <dieflow/postprocess/summary.h>
#include <dieflow/mesh/wall_nodes.h>

#include <deal.II/base/symmetric_tensor.h>
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
  /// The deck's "Contact" subsection.
  struct ContactParameters
  {
    std::set<BoundaryId>         die_ids;
    std::string                  normal_enforcement = "active set";
    /// "exact": v.t = 0 as a constraint where a node sticks (active set
    /// only); "penalty": the paper's F_t = -omega_t v_t.
    std::string                  stick_enforcement = "exact";
    FrictionLaw::Kind            law                = FrictionLaw::Kind::coulomb;
    std::map<BoundaryId, double> friction_coefficient;
    std::map<BoundaryId, double> tresca_factor;
    double                       shear_flow_stress         = 0;
    double                       normal_penalty_factor     = 1;
    double                       tangential_penalty_factor = 100;
    double                       regularisation_velocity   = 1;
    double                       active_set_constant       = 1;
    /// Die ids whose die is a surface mesh of its own (Gmsh file names).
    std::map<BoundaryId, std::string> die_surface_files;
    /// Die ids that move: their rigid translation velocity (components as
    /// written; the problem checks there are dim of them).
    std::map<BoundaryId, std::vector<double>> die_velocities;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    /// Deck changes that may let contact states that keep changing settle,
    /// none of them in use already (for the failure message).
    std::vector<std::string>
    settling_changes() const;
  };

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

  /// Node-wise results for the die-wall profiles and the checks.
  template <int dim>
  struct ContactNodeResult
  {
    dealii::Point<dim> position;
    /// The triangulation's vertex (invalid at a degree-2 edge midpoint).
    unsigned int       vertex;
    BoundaryId         id;
    Tensor<1, dim>     normal;
    /// t (2D: the direction of the signed profile values; 3D: t_1).
    Tensor<1, dim>     tangent;
    /// The node's boundary weight (int phi dA) and its share of the wall's arc length (int phi ds).
    double             weight, length;
    ContactStatus      status;
    /// F_n (<= 0 pressing), a nodal force, and v.n.
    double normal_force, normal_rate;
    /// The friction force (nodal, in the tangent plane) and the slip velocity.
    Tensor<1, dim> friction_force, slip_velocity;
    /// The normal reaction where separated (must vanish at equilibrium).
    double free_reaction;
    double friction_bound;
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
    void
    initialize(const ContactParameters &parameters);

    bool
    empty() const
    {
      return parameters.die_ids.empty();
    }
    bool
    uses_penalty() const
    {
      return parameters.normal_enforcement == "penalty";
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
    };
    /// The states of the current nodes (a checkpoint's; the free surface's
    /// approaching directions, which nothing inherits, left out).
    std::vector<StateRecord>
    state_records() const;
    /// The states the next setup() with keep_state maps from, instead of
    /// the current nodes' (a restart from a checkpoint).
    void
    restore_states(const std::vector<StateRecord> &records)
    {
      restored_states = records;
    }


    /// eta_m, the viscosity scale of c, and lambda, the incompressibility
    /// penalty that omega_n and omega_t are multiples of.
    void
    set_scales(const double eta, const double lambda)
    {
      viscosity_scale  = eta;
      penalty_scale    = lambda;
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

    /// Forces per id, node counts and the inequality checks (velocities
    /// relative to @p speed_scale), into @p summary.
    void
    summarise(const std::vector<ContactNodeResult<dim>> &results,
              const double                               speed_scale,
              CycleSummary &                             summary) const;

    /**
     * One gnuplot-ready profile per die id: arc length, x, y, contact
     * pressure and friction stress (the nodal forces over their boundary
     * weights), normal and slip velocity, status, and a recovered pressure
     * and shear. With @p vertex_stress (degree 1, vertex_stresses()): the
     * pressure recovered along the wall (pressures_along() in the source),
     * the shear t.sigma n of the stress at the node; without (degree 2,
     * whose nodal values do not zigzag): the raw values again.
     */
    void
    write_profiles(const std::vector<ContactNodeResult<dim>> &                 results,
                   const std::vector<dealii::SymmetricTensor<2, dim>> *vertex_stress,
                   const std::string &                          directory) const;

    /**
     * 3D: one table per die id of the contact nodes (die-surface-ID.dat):
     * position, contact pressure, friction stress vector, normal and slip
     * velocity, status; a die-surface field to plot or to map.
     */
    void
    write_surface_fields(const std::vector<ContactNodeResult<dim>> &results, const std::string &directory) const;

    /**
     * Where the die needs a fine mesh: the corners (nodes with more than one
     * wall direction) and the nodes whose state differs from the next
     * node's along the wall (stick turning to slip, contact opening).
     */
    std::vector<dealii::Point<dim>>
    hot_points(const std::vector<ContactNodeResult<dim>> &results) const;

    /// Status per vertex of @p dof_handler's triangulation (0 separated,
    /// 1 stick, 2 slip; -1 elsewhere) for the VTU.
    dealii::Vector<double>
    vertex_status(const DoFHandler<dim> &dof_handler) const;

    /// "" or what the cycling guard did in this cycle.
    std::string
    cycling_note() const;

    /// What the cycling guard did: directions held in contact, and friction
    /// laws regularised.
    std::pair<unsigned int, unsigned int>
    cycle_breaks() const;

    /// True where the deck's friction law of die id @p id transmits no
    /// tangential force (mu = 0, or a zero Tresca bound).
    bool
    frictionless(const BoundaryId id) const;

    /// The translation velocity of die id @p id (zero for a die at rest).
    Tensor<1, dim>
    velocity_of(const BoundaryId id) const;

    /// Whether any die moves.
    bool
    dies_move() const
    {
      return !die_velocity.empty();
    }

    /// Friction coefficient of a die id (0 if none given).
    double
    friction_coefficient(const BoundaryId id) const;

    const ContactParameters &
    get_parameters() const
    {
      return parameters;
    }

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
    /// The deck's law of die id @p id for a node of boundary weight
    /// @p weight (the Tresca bound scales with it), without the cycling
    /// guard's regularisation and the stick penalty.
    FrictionLaw
    law_of(const BoundaryId id, const double weight) const;
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

    ContactParameters          parameters;
    std::map<BoundaryId, Tensor<1, dim>> die_velocity;
    std::vector<Node>          nodes;
    /// restore_states()'s, for the next setup().
    std::vector<StateRecord>   restored_states;
    double                     viscosity_scale = 1;
    double                     penalty_scale   = 1;
    /// v0 of the friction laws regularised because their states cycled.
    double                     cycling_velocity = 1;
    /// The largest speed of the last update (the 3D slip floor's scale).
    double                     largest_speed = 1;
    std::vector<std::size_t>   recent_signatures;
    /// The velocity of the last update, to tell when Newton has stopped
    /// moving the solution (3D ties on the cone, see update()).
    dealii::Vector<double>     previous_velocity;
  };

  /**
   * The linearised system of flow and contact at @p v: the flow terms with
   * the row transformations of the slipping contact nodes, then the contact
   * elements' own residuals and tangents (the slave's block: the die is
   * rigid), condensed with @p update_constraints. Without @p matrix, the
   * residual only; with @p mixed, the penalty's blocks apart (see
   * FlowAssembler::assemble_system()).
   */
  struct AssemblyInfo
  {
    /// Contact terms were assembled.
    bool contact = false;
    /// The Jacobian is symmetric (no slipping friction's row transformation
    /// or non-symmetric element tangent).
    bool symmetric = true;
    /// Contact elements whose friction (tangential) terms were evaluated.
    unsigned int friction_terms = 0;
  };

  template <int dim>
  AssemblyInfo
  assemble_with_contact(const FlowAssembler<dim> &        flow,
                        const ContactSet<dim> &           contact,
                        const DoFHandler<dim> &           dof_handler,
                        const dealii::Vector<double> &    v,
                        const AffineConstraints<double> & update_constraints,
                        const Linearization               linearization,
                        dealii::SparseMatrix<double> *    matrix,
                        dealii::Vector<double> &          minus_residual,
                        dealii::Vector<double> &          raw_residual,
                        MixedPenalty<dim> *               mixed = nullptr);
} // namespace dieflow

#endif
