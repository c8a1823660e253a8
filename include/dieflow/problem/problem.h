// The die-flow problem: the table of contents of the algorithm, its pieces, and which file implements each phase.
#ifndef dieflow_problem_h
#define dieflow_problem_h

#include <dieflow/contact/contact_set.h>
#include <dieflow/contact/die_surface.h>
#include <dieflow/flow/flow_assembler.h>
#include <dieflow/flow/incompressibility.h>
#include <dieflow/free_surface/free_surface.h>
#include <dieflow/heat/heat_equation.h>
#include <dieflow/incremental/incremental_state.h>
#include <dieflow/mesh/wall_nodes.h>
#include <dieflow/postprocess/cycle_report.h>
#include <dieflow/postprocess/study.h>
#include <dieflow/postprocess/summary.h>
#include <dieflow/problem/problem_parameters.h>
#include <dieflow/solvers/linear_solver.h>
#include <dieflow/solvers/nonlinear_solver.h>
#include <dieflow/strain/strain_field.h>
#include <dieflow/system/system_assembler.h>

#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace dieflow
{
  /**
   * The die-flow problem (deal.II step-42's shape, ASPECT's rooms). A run:
   *
   *   for each cycle (a refinement cycle, or a time step)    (cycles.cc):
   *     the mesh: refined (refinement.cc), or moved with the metal and meshed anew where cells degrade (time_steps.cc);
   *     dofs, constraints, the incompressibility form's state  (setup.cc);
   *     Newton's method (NonlinearSolver) on this system: per iteration
   *       update_state -> assemble_system -> solve -> line search ->
   *       accept_step                                       (newton.cc);
   *       where it fails, at Coulomb's fixed point, then in stages of
   *       friction from frictionless, then of m       (continuation.cc);
   *     a steady free surface moved onto the streamlines till it settles (free_surface.cc);
   *     the temperature, the strain and the flow in turn until they settle (heat.cc);
   *     the report (CycleReport), its guards, the study, summary.json;
   *     a checkpoint in time                            (checkpoint.cc).
   *
   * Data flows one way: the deck (ProblemParameters) -> the mesh -> dofs
   * and constraints -> the solution -> the report (a const view). Each
   * piece owns its state (doc/design.md).
   */
  template <int dim>
  class DieFlowProblem : public NonlinearSystem
  {
  public:
    /// The deck's entries (ProblemParameters).                    (setup.cc)
    static void
    declare_parameters(ParameterHandler &prm, const DeckLayout &layout);

    /// Reads the deck, makes and checks the mesh.                     (setup.cc)
    DieFlowProblem(ParameterHandler &prm, const std::string &deck_directory, std::ostream &log);

    /// Runs every cycle; writes summary.json (also when it fails to converge). (cycles.cc)
    RunSummary
    run();

    /// The nonlinear system of one mesh (NonlinearSystem).            (newton.cc)
    StateChanges
    update_state(Vector<double> &v) override;
    double
    assemble_system(const Vector<double> &v, const Linearization linearization) override;
    double
    residual(const Vector<double> &v, Vector<double> &minus_residual) override;
    const Vector<double> &
    minus_residual() const override { return system_rhs; }
    void
    solve(Vector<double> &update, const double relative_residual) override;
    void
    set_trial_step(const double step) override;
    void
    accept_step(const Vector<double> &v, const Vector<double> &update, const double step, const Linearization) override;
    bool
    is_linear() const override;
    double
    residual_floor() const override;
    bool
    constraints_settled() override;
    double
    velocity_scale() const override { return prescribed_speed; }
    bool
    jacobian_is_symmetric() const override { return matrix_symmetric; }
    std::string
    state_note() const override { return contact.cycling_note(); }
    std::vector<std::string>
    contact_changes() const override;
    std::vector<std::string>
    law_changes() const override;

  private:
    // Set-up of a mesh                                                (setup.cc)
    void
    setup_system();
    /// Boundary conditions and active contact (and their homogeneous twins for the updates).
    void
    make_constraints();
    /// Refuses a die that moves across its own surface in a steady run.
    void
    check_steady_die_motion() const;
    /// What the flow assembly reads: the incompressibility form's terms and the hardening.
    FlowTerms<dim>
    flow_terms();
    /// The solution as the report reads it.
    SolutionView<dim>
    solution_view();

    // A cycle                                                        (cycles.cc)
    /// Refinement cycles, or the steps and the solve at t = 0.
    unsigned int
    n_cycles() const;
    /// The summary's header and the state before the first cycle (a checkpoint's, or t = 0's); returns the first cycle.
    unsigned int
    start_run(RunSummary &summary);
    /// Ctrl-C or SIGTERM before @p cycle: the last converged step's checkpoint, the summary says so.
    void
    stop_between_cycles(const unsigned int cycle, const unsigned int first, RunSummary &summary);
    /// The mesh of @p cycle: refined, or moved (and meshed anew) by a step.
    void
    next_mesh(const unsigned int cycle);
    /// Newton's method (after the Newtonian start on the first cycle) and the free surface.
    NonlinearResult
    solve_cycle(const unsigned int cycle, CycleSummary &cycle_summary);
    /// A failed Newton iteration again from @p start: Coulomb's fixed point, the friction, then m in stages. (continuation.cc)
    NonlinearResult
    continue_in_friction(const Vector<double> &start, NonlinearResult failed, CycleSummary &cycle);
    /// The report and its guards; a guard's failure into @p result.
    void
    report_cycle(CycleSummary &cycle_summary, NonlinearResult &result, RunSummary &summary);
    /// The cycle into the study, the summary, the log, a checkpoint; whether the run goes on.
    bool
    record_cycle(CycleSummary &cycle_summary, const NonlinearResult &result, RunSummary &summary, const double wall_time);
    /// The study, the totals and the final summary.json and screen lines.
    void
    finish_run(RunSummary &summary, const double wall_time);

    /// The first iterate: a Newtonian solve at a typical viscosity.   (newton.cc)
    void
    newtonian_start();
    /// The penalty form's J and -R at @p v into the system (the mixed form's direct fallback).
    bool
    reassemble_penalty_form(const Vector<double> &v, const Linearization linearization, const FlowTerms<dim> &terms);

    // Refinement cycles                                          (refinement.cc)
    void
    refine_mesh();
    /// The dual solution of the goal part's force, for the dual-weighted indicator.
    Vector<double>
    ram_force_dual();
    /// With a Target error, after a converged cycle: whether to stop (reached, or at Maximum cells).
    bool
    stop_at_target(RunSummary &summary) const;

    // Steps in time                                              (time_steps.cc)
    /// Moves the mesh from t_n to t_{n+1} with the integrator of TimeStepping.
    void
    advance_configuration(const unsigned int n);
    /// Meshes the domain anew before step @p n's solve and carries the run's fields over.
    void
    remesh(const unsigned int n, const double jacobian_before);
    /// The free-surface nodes that may reach a die within the current step.
    std::vector<WallNode<dim>>
    approaching_nodes() const;
    /// How far a node may travel in the current step and the gap rate that closes a gap by its end.
    std::pair<double, typename ContactGaps<dim>::GapRate>
    gap_closing() const;
    /// The ram's travel at @p time: its vertices' mean x displacement, or a driving die's |V| t.
    double
    ram_stroke(const double time) const;
    /// load-stroke.txt: a row per step (rewritten each step), after those of an earlier run.
    void
    write_load_stroke(const RunSummary &summary) const;
    std::string
    load_stroke_rows(const RunSummary &summary) const;

    /// Moves a steady free surface until it settles.              (free_surface.cc)
    NonlinearResult
    settle_free_surface(NonlinearResult result, CycleSummary &cycle);

    /// Heat and strain, then the flow at the new T and hardening, in turn until they settle (steady; in time the trapezoid's heat step). (heat.cc)
    NonlinearResult
    couple_fields(NonlinearResult result, CycleSummary &cycle);
    /// T from t_n to t_{n+1} with the flow of t_n (Heat/Model = transient), before the mesh moves.
    void
    step_heat(const unsigned int n);

    // Checkpoints: each piece saves and loads itself            (checkpoint.cc)
    void
    save_checkpoint(const unsigned int n, RunSummary &summary) const;
    unsigned int
    load_checkpoint(RunSummary &summary);

    // The deck and the pieces made from it.
    const ProblemParameters<dim>           parameters;
    std::ostream &                         log;
    /// Wall time per stage: setup, assembly, linear solve, postprocess, refinement, ...
    dealii::TimerOutput                    timer;
    std::map<BoundaryId, DieSurface<dim>>  die_surfaces;
    ContactSet<dim>                        contact;
    FlowAssembler<dim>                     assembler;
    LinearSolver                           linear_solver;

    // The discretisation of the current mesh.
    std::unique_ptr<dealii::Triangulation<dim>> mesh; ///< parallel::shared on P > 1, else plain (processes::new_triangulation())
    dealii::Triangulation<dim> &                triangulation;
    const dealii::FESystem<dim>  fe;
    dealii::DoFHandler<dim>      dof_handler;
    AffineConstraints<double>    hanging_node_constraints, constraints, update_constraints, prescribed_constraints;
    std::vector<WallNode<dim>>   wall_nodes;
    dealii::SparsityPattern      sparsity_pattern;
    processes::RowSums           row_sums; ///< on P > 1 the matrix stored and summed by rows
    dealii::SparseMatrix<double> system_matrix;
    Vector<double>               system_rhs;
    Vector<double>               velocity;

    // The state the cycles carry.
    Incompressibility<dim> incompressibility;
    SystemAssembler<dim>   system;
    IncrementalState<dim>  incremental;
    FreeSurface            free_surface;
    HeatEquation<dim>      heat;
    StrainField<dim>       strain;
    CycleReport<dim>       report;
    StudyTable             study;
    /// The contact states come from a solve (not before a run's first); a new mesh's first iterate keeps the last's.
    bool         contact_states_valid      = false;
    bool         states_from_previous_mesh = false;
    bool         matrix_symmetric          = true;
    double       last_roundoff_bound = 0; ///< roundoff_bound() of the last assembled Jacobian
    double       prescribed_speed    = 0; ///< the largest prescribed speed
    unsigned int start_solves        = 0;
    std::string  law_warning; ///< newtonian_start()'s word on the law's regularisation, for summary.json
  };
} // namespace dieflow

#endif
