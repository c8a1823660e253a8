#ifndef dieflow_problem_h
#define dieflow_problem_h

#include <dieflow/boundary_conditions.h>
#include <dieflow/contact/contact.h>
#include <dieflow/flow/flow_assembler.h>
#include <dieflow/mesh/free_surface.h>
#include <dieflow/mesh/geometry.h>
#include <dieflow/solvers/linear_solver.h>
#include <dieflow/solvers/saddle_point_solver.h>
#include <dieflow/flow/mixed_penalty.h>
#include <dieflow/flow/material.h>
#include <dieflow/solvers/nonlinear_solver.h>
#include <dieflow/parameters.h>
#include <dieflow/mesh/refinement.h>
#include <dieflow/postprocess/postprocess.h>
#include <dieflow/postprocess/study.h>
#include <dieflow/postprocess/summary.h>
#include <dieflow/mesh/wall_nodes.h>
#include <dieflow/contact/die_surface.h>
#include <dieflow/incremental/contact_gaps.h>
#include <dieflow/incremental/checkpoint.h>
#include <dieflow/incremental/remeshing.h>
#include <dieflow/incremental/time_stepping.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <optional>
#include <ostream>

namespace dieflow
{
  /// What the second reading of a deck declares beyond the fixed entries.
  struct DeckLayout
  {
    unsigned int         dimension = 2;
    std::set<BoundaryId> velocity_ids{1};
  };

  /**
   * The die-flow problem: owns the mesh, the dofs and the pieces of the
   * deck. Problem = steady runs the refinement cycles:
   *   mesh -> dofs and constraints -> [assemble -> solve -> update state]
   *   until converged -> postprocess -> refine -> next cycle;
   * Problem = incremental runs the time steps the same way, with the mesh
   * moved by the step's velocity (TimeStepping) in place of the refinement.
   */
  template <int dim>
  class DieFlowProblem : public NonlinearSystem
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm, const DeckLayout &layout);

    DieFlowProblem(ParameterHandler &prm, const std::string &deck_directory, std::ostream &log);

    /// Runs every cycle; writes summary.json (also when it fails to converge).
    RunSummary
    run();

    /**
     * With a Refinement/Target error, after a converged cycle: true when the
     * estimated relative error of the target quantity is below the target
     * (summary.target_reached), or when Maximum cells is reached (then not).
     */
    bool
    stop_at_target(RunSummary &summary) const;

    StateChanges
    update_state(Vector<double> &v) override;
    double
    assemble_system(const Vector<double> &v, const Linearization linearization) override;
    double
    residual(const Vector<double> &v, Vector<double> &minus_residual) override;
    const Vector<double> &
    minus_residual() const override
    {
      return system_rhs;
    }
    void
    solve(Vector<double> &update, const double relative_residual) override;
    bool
    is_linear() const override;
    double
    residual_floor() const override;
    double
    velocity_scale() const override
    {
      return prescribed_speed;
    }
    std::vector<std::string>
    contact_changes() const override;
    std::vector<std::string>
    law_changes() const override;
    std::string
    state_note() const override
    {
      return contact.cycling_note();
    }
    bool
    jacobian_is_symmetric() const override
    {
      return matrix_symmetric;
    }
    bool
    constraints_settled() const override;
    void
    accept_step(const Vector<double> &v,
                const Vector<double> &update,
                const double          step,
                const Linearization   linearization) override;

    void
    set_trial_step(const double step) override;

  private:
    /**
     * The mixed form of the stable pair's penalty (iterative linear solver,
     * velocity degree 2; MixedPenalty, SaddlePointSolver). The pressure
     * coefficients p are carried as unknowns of Newton's method beside v,
     * through the multiplier q = p - lambda P div v of FlowAssembler (the
     * stress is 2 eta D + (q + lambda P div v) I = 2 eta D + p I), so that
     * neither the residual nor a Krylov method's error is multiplied by
     * lambda/eta: the momentum residual is R_v = A(v) + B^T p - f, the
     * pressure's R_p = B v - M p / lambda = -M q / lambda, and each
     * Newton step solves the mixed system for (du, dp) and moves q by
     * dq = dp - lambda M^-1 B du. At the solution q = 0 and (v, p) is the
     * penalty solution. The step's q moves with the line search's trial v
     * (set_trial_step()).
     */
    void
    solve_mixed(Vector<double> &update, const double tolerance);
    /**
     * The mixed solve's tolerance: Newton's forcing term (LinearSolver::
     * forcing_tolerance(), no looser in absolute terms than the last
     * solve's on this mesh where the residual grew), tightened once
     * Newton's residual is down to its round-off floor (residual_floor())
     * while pressure_residual_ratio() is still above its bound. A solve leaves q
     * = -lambda M^-1 r_p, r_p its pressure rows' residual, so the ratio
     * after a solve scales with the tolerance it was given: the next one
     * gets last tolerance x 0.1 x bound / ratio, but no less than 1e-2 of
     * the forcing term (q also carries what earlier steps left) or 1e-10.
     */
    double
    mixed_solve_tolerance(const double relative_residual);
    /// q = p - lambda M^-1 B v for the cell coefficients @p p (lambda: the assembler's).
    Vector<double>
    multiplier_for(const Vector<double> &p, const Vector<double> &v) const;
    /// ||q / lambda|| / ||grad v|| (L2 norms; 0 without q).
    double
    pressure_residual_ratio() const;

    /**
     * The augmented-Lagrangian (iterated penalty) form of the incompressible
     * limit, used with the iterative linear solver (Fortin and Glowinski,
     * Augmented Lagrangian Methods, 1983): the penalty pressure -lambda div v
     * of the paper's (8) becomes -(q + r div v), r = 'Augmentation factor'
     * x eta (per cell) about 1e3 eta instead of lambda = 1e7 eta, and before each
     * nonlinear iteration the cell multiplier takes its Uzawa step
     *   q <- q + r P div v   (P: the centre value for degree 1, the P1disc
     *                         projection for degree 2, PressureProjection).
     * At the fixed point P div v = 0 in every cell: the incompressible
     * solution, which the penalty method approaches to O(eta/lambda). The
     * iteration stops when, besides the residual, the divergence ratio is
     * below 'Divergence tolerance'.
     */
    void
    update_multiplier(const Vector<double> &v);
    void
    uniform_cell_penalty(const double r);
    /// r = 'Augmentation factor' x the viscosity of @p v at each cell centre.
    void
    update_cell_penalty(const Vector<double> &v);
    /// The viscosity at each cell centre.
    Vector<double>
    cell_viscosity(const Vector<double> &v) const;
    /// p = -(q + r div v) or -lambda div v at each cell centre, of the solution.
    Vector<double>
    cell_pressures() const;
    /// r/eta (augmented Lagrangian) or lambda/eta (penalty).
    double
    penalty_factor() const
    {
      return augmented ? linear_solver.augmentation : material.penalty_factor;
    }
    std::string
    penalty_name() const
    {
      return augmented ? "augmented-Lagrangian penalty r" : "penalty lambda";
    }
    /// The mass-balance guard on a converged cycle (mass_balance.h): a
    /// failure makes the cycle not converged, a warning goes to the log and
    /// to @p summary.
    void
    guard_mass_balance(CycleSummary &cycle, NonlinearResult &result, RunSummary &summary) const;
    /// A converged cycle whose state breaks the contact conditions
    /// (contact_checks beyond their bounds: penetration or pull 1e-6, or
    /// 1e-4 where directions were held in contact to end a cycle of the
    /// states; friction 1e-12; sticking speed 1e-8) is not converged.
    void
    guard_contact(CycleSummary &cycle, NonlinearResult &result) const;
    /// Steady runs with a free surface: moves it onto the streamlines of
    /// the solution @p result and solves again, until it settles (the
    /// moves into @p cycle; the last solve's result, iterations summed).
    NonlinearResult
    settle_free_surface(NonlinearResult result, CycleSummary &cycle);
    void
    setup_system();
    void
    newtonian_start();
    void
    postprocess(CycleSummary &summary);
    void
    refine_mesh();
    /// Moves the mesh from t_n to t_{n+1} with the integrator of TimeStepping.
    void
    advance_configuration(const unsigned int n);
    /// eps += a epsdot_n + b epsdot_{n-1} per cell (the integrator's weights,
    /// as the positions'), and the hardening factors that follow.
    void
    advance_strain(const double a, const double b);
    /// The hardening factor (eps_0 + eps)^n of every active cell from its
    /// equivalent strain, for the assembler (when the material hardens).
    void
    update_hardening();
    /// Time, stroke, volume and cell shape of the current configuration (step @p n).
    StepRecord
    step_record(const unsigned int n) const;
    /// Mean displacement along x of the vertices of goal_part() since t = 0
    /// (or, driven by a moving die alone, its travel |V| t).
    double
    ram_stroke(const double time) const;
    /// The signed mean x displacement of goal_part()'s vertices since t = 0.
    double
    ram_displacement() const;
    /// ram_start: goal_part()'s vertices where they are now.
    void
    record_ram_start();
    /// The weights (a, b) of the move x += a v_n + b v_{n-1} of step @p n:
    /// TimeStepping's, forward Euler after a change of contact (or without v_{n-1}).
    std::pair<double, double>
    move_weights(const unsigned int n) const;
    /**
     * Meshes the domain anew before step @p n's solve (remesh_domain(): the
     * same boundary, Gmsh's quadrilaterals inside) and carries over what the
     * run holds on the mesh: the velocities v_n (the first iterate of the
     * solve) and v_{n-1} (Adams-Bashforth 2's), interpolated at the new
     * nodes: both are fields on the moved mesh, so the value at a new node
     * is that of the material point there, as the Lagrangian move needs;
     * the equivalent strain and its previous rate, the old cell's at each
     * new cell's centre; the ram's stroke, the fixed walls and the faces'
     * ids before they came onto a die. The contact states follow the nodes
     * (ContactSet::setup(): the boundary nodes are the same).
     * @p jacobian_before: the moved mesh's smallest scaled Jacobian, which
     * decided the new mesh (for the record).
     */
    void
    remesh(const unsigned int n, const double jacobian_before);
    /// The free-surface nodes that may reach a die within the current step
    /// (ContactGaps::approaching(); empty in a steady run and at the last step).
    std::vector<WallNode<dim>>
    approaching_nodes() const;
    /// How far a node may travel in the current step (twice the largest
    /// speed times dt) and the gap rate at which it closes a gap g by the
    /// end of it (the integrator's move; for ContactGaps); a reach of -1
    /// where there is none (a steady run, the last step, no dies in time).
    std::pair<double, typename ContactGaps<dim>::GapRate>
    gap_closing() const;
    /// Refuses a die that moves across its own surface in a steady run.
    void
    check_steady_die_motion() const;
    /// load-stroke.txt: a row per step of @p summary (rewritten each step),
    /// after those of the run a checkpoint came from.
    void
    write_load_stroke(const RunSummary &summary) const;
    /// The rows of load-stroke.txt for the steps of @p summary.
    std::string
    load_stroke_rows(const RunSummary &summary) const;
    /**
     * Writes the state at the end of step @p n's solve to Output
     * directory/checkpoint.dat (atomically), and names it in @p summary:
     * the mesh (deal.II's serialisation of the triangulation: the moved
     * vertices, the boundary ids), v_n and v_{n-1}, the strain and its
     * previous rate, the dies where they are now, the contact states per
     * node, the faces' ids before they came onto a die, the viscosity scale
     * of the penalty, the volume at t = 0, the stroke, the last move's
     * contact events and new mesh, and the outputs' records so far.
     */
    void
    save_checkpoint(const unsigned int n, RunSummary &summary) const;
    /// Reads the checkpoint of Incremental/Restart from into the run; returns its step.
    unsigned int
    load_checkpoint(RunSummary &summary);
    double
    relative_residual(const Vector<double> &minus_residual) const;
    /// eps || |J| |v| || over the free rows, relative to the reactions: the
    /// round-off floor of the relative residual at the last assembly.
    double
    roundoff_bound(const Vector<double> &v) const;
    /// Constraints of the state: boundary conditions and active contact.
    void
    make_constraints();
    /// Flow and contact terms at v: J (if @p matrix) and -R condensed.
    void
    assemble(const FlowAssembler<dim> &flow,
             const Vector<double> &    v,
             const Linearization       linearization,
             dealii::SparseMatrix<double> *matrix,
             Vector<double> &          minus_residual);
    /**
     * The prescribed-velocity part whose force F_x the dual-weighted
     * indicator aims at: the Target quantity's, if it is such a force, else
     * the first part.
     */
    BoundaryId
    goal_part() const;
    /// The dual solution of goal_part()'s force in the solution's own
    /// space (force_dual(), goal_estimate.h), for the dual-weighted
    /// indicator; computed only when a refinement follows.
    Vector<double>
    ram_force_dual();
    /// Symmetry lines, slip walls and the dies without friction.
    std::set<BoundaryId>
    frictionless_walls() const;
    /// The dies' shares of the nodes they share with prescribed-velocity
    /// parts, into the die normal and friction forces of @p summary.
    void
    add_die_shares(const std::vector<WallShare<dim>> &shares,
                   const std::set<BoundaryId> &       frictionless,
                   CycleSummary &                     summary) const;
    /// Volume per unit time through the parts other than the dies: the larger of inflow and outflow.
    double
    boundary_conditions_throughput(const std::map<BoundaryId, double> &flux) const;
    /// The flow residual at the nodes (reactions), hanging nodes condensed.
    Vector<double>
    nodal_flow_residual(const Vector<double> &v);

    RunParameters                              run_parameters;
    CoordinateSystem<dim>                      coordinates;
    MeshParameters                             mesh_parameters;
    Material                                   material;
    BoundaryConditions<dim>                    boundary_conditions;
    NonlinearSolver                            nonlinear_solver;
    LinearSolver                               linear_solver;
    RefinementParameters                       refinement;
    TimeStepping                               time_stepping;
    ContactParameters                          contact_parameters;
    ContactSet<dim>                            contact;
    /// Dies given on their own (Contact/Die surfaces), by boundary id.
    std::map<BoundaryId, DieSurface<dim>>      die_surfaces;
    /// False until the first solve of a run: the contact states are then
    /// judged from a velocity that solves something.
    bool                                       contact_states_valid = false;
    /// True for the first iterate of a refined mesh (see update_state()).
    bool                                       states_from_previous_mesh = false;
    unsigned int                               contact_assemblies   = 0;
    unsigned int                               friction_terms       = 0;
    mutable unsigned int                       pressure_recoveries  = 0;
    std::unique_ptr<dealii::FunctionParser<dim>> exact_velocity;

    std::ostream &log;
    /// Wall time per stage: setup, assembly, linear solve, postprocess, refinement.
    dealii::TimerOutput timer;

    dealii::Triangulation<dim> triangulation;
    dealii::FESystem<dim>      fe;
    dealii::DoFHandler<dim>    dof_handler;

    AffineConstraints<double>  hanging_node_constraints;
    AffineConstraints<double>  constraints;
    AffineConstraints<double>  update_constraints;
    AffineConstraints<double>  prescribed_constraints;
    std::vector<WallNode<dim>> wall_nodes;

    dealii::SparsityPattern      sparsity_pattern;
    dealii::SparseMatrix<double> system_matrix;
    /// The augmented-Lagrangian form is in use (iterative linear solver, degree 1).
    bool                         augmented = false;
    /// The mixed form is in use (iterative linear solver, degree 2).
    bool                         mixed_form = false;
    /// The last mixed solve's tolerance on this mesh (0: none yet), and
    /// Newton's relative residual it was asked at.
    double                       last_mixed_tolerance = 0;
    double                       last_mixed_residual  = 0;
    /// ||du|| / ||v|| of the last mixed-form step.
    double                       last_mixed_update    = 1;
    MixedPenalty<dim>            mixed;
    std::unique_ptr<SaddlePointSolver<dim>> saddle_point_solver;
    /// The mixed form's q of the accepted iterate, and the last step's dq.
    Vector<double>               accepted_multiplier, multiplier_update;
    /// The pressure is to start at zero at the next assembly (no previous mesh's).
    bool                         pressure_unset = false;
    /// The iterate and linearisation of the last assembly (for the direct fallback).
    Vector<double>               assembled_iterate;
    Linearization                assembled_linearization = Linearization::picard;
    /// Its multiplier q per active cell (see update_multiplier()).
    Vector<double>               multiplier;
    /// Its penalty r per cell: 'Augmentation factor' x the cell's viscosity.
    Vector<double>               cell_penalty;
    /// The cell stress q + lambda div v of the previous mesh, on this one.
    Vector<double>               transferred_cell_stress;
    double                       last_divergence_ratio = 0;
    Vector<double>               velocity;
    /// v_{n-1} at the same nodes, for Adams-Bashforth 2 (empty before the first step).
    Vector<double>               previous_velocity;
    /// The volume at t = 0, and the ram part's vertices with their start positions.
    double                                   initial_volume = 0;
    std::map<unsigned int, dealii::Point<dim>> ram_start;
    /// The dies' surfaces for the free surface's gaps, and the last step's update.
    ContactGaps<dim>                         gaps;
    FixedWalls<dim>                          fixed_walls;
    /// The step being solved (Problem = incremental).
    unsigned int                             current_step = 0;
    /// Per active cell: the equivalent strain, its rate at the previous
    /// step (Adams-Bashforth 2), and the hardening factor (eps_0 + eps)^n.
    Vector<double>                           equivalent_strain, previous_strain_rate, cell_hardening;
    GapUpdate                                last_gap_update;
    RemeshingParameters                      remeshing;
    FreeSurfaceParameters                    free_surface_parameters;
    /// The free surface of a steady run (2D; the dies of the first mesh).
    FreeSurface                              free_surface;
    unsigned int                             steps_since_remesh = 0;
    std::optional<RemeshRecord>              last_remesh;
    /// The ram's mean displacement before the last new mesh (ram_start's base).
    double                                   ram_offset = 0;
    CheckpointParameters                     checkpoint;
    /// load-stroke.txt's rows of the run a checkpoint came from.
    std::string                              earlier_load_stroke;
    Vector<double>               system_rhs;
    Vector<double>               raw_residual;

    FlowAssembler<dim> assembler;
    /// Whether the last assembled Jacobian is symmetric (CHOLMOD applies).
    bool               matrix_symmetric = true;
    double             mean_viscosity = 0;
    unsigned int       start_solves   = 0;
    double             prescribed_speed = 0;
    /// roundoff_bound() of the last assembled Jacobian.
    double             last_roundoff_bound = 0;

    std::vector<std::pair<double, std::string>> pvd_records;
    StudyTable                                  study;
    /// Where the velocity is reported as a quantity of interest (if any).
    std::optional<dealii::Point<dim>>           probe;
    /// The contact results of the last cycle, for the die criterion.
    std::vector<ContactNodeResult<dim>>         contact_results;
  };
} // namespace dieflow

#endif
