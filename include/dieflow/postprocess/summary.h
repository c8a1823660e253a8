// The run's summary: what each cycle and the whole run report, the result lines on screen and summary.json.
#ifndef dieflow_summary_h
#define dieflow_summary_h

#include <dieflow/contact/contact_results.h>
#include <dieflow/free_surface/free_surface.h>
#include <dieflow/heat/heat_equation.h>
#include <dieflow/strain/strain_field.h>
#include <dieflow/incremental/step_record.h>
#include <dieflow/postprocess/mass_balance.h>
#include <dieflow/solvers/linear_solver.h>
#include <dieflow/solvers/nonlinear_solver.h>
#include <dieflow/base/parameters.h>

#include <array>
#include <map>
#include <optional>
#include <tuple>
#include <string>
#include <vector>

namespace dieflow
{
  /**
   * A quantity of interest over the cycles of a run: its last value, the
   * Richardson extrapolation Q* with its error and order, and the estimated
   * error of the last value (Extrapolation::estimate in study.h).
   */
  struct QuantityEstimate
  {
    std::string name;
    double      last         = 0;
    double      extrapolated = 0;
    double      extrapolation_error = 0;
    double      order        = 0;
    double      estimate     = 0;
  };

  /// What the free surface of a steady cycle did (free_surface.h).
  struct FreeSurfaceRecord
  {
    /// Moves made, each followed by a solve; whether the last look found
    /// no node to move more than the tolerance.
    unsigned int moves   = 0;
    bool         settled = false;
    /// The largest move the last look found (over the free surface's length).
    double       largest_move = 0;
    /// Faces of the free surface after the last move; those lying on a die
    /// (grazing it) and their flux into it (FreeSurfaceMove).
    unsigned int free_faces = 0, grazing_faces = 0;
    double       grazing_flux = 0;
    /// The free stretches as solved last (the polylines of summary.json and free-surface.vtp).
    std::vector<FreeSurfaceLine> lines;
  };

  /// What one refinement cycle reports (interface.md, summary.json).
  struct CycleSummary
  {
    unsigned int cycle                = 0;
    unsigned int cells                = 0;
    unsigned int dofs                 = 0;
    bool         converged            = false;
    unsigned int nonlinear_iterations = 0;
    unsigned int linear_solves        = 0;
    unsigned int contact_assemblies   = 0;
    /// Contact elements whose friction terms were evaluated, summed over
    /// the assemblies (0 when every friction coefficient is 0).
    unsigned int friction_terms       = 0;
    /// Times the pressure field was recovered (only for output files and
    /// for the iterative method's mesh transfer).
    unsigned int pressure_recoveries  = 0;
    /// "direct" or "iterative", and what the linear solvers did.
    std::string        linear_method = "direct";
    /// How incompressibility was held: "penalty", "augmented Lagrangian"
    /// (Uzawa steps; the iterative method of degree 1, or a penalty that
    /// lost too much of the flow) or "mixed".
    std::string        incompressibility = "penalty";
    /// Newton's method failed at the deck's friction and was globalised
    /// (DieFlowProblem::continue_in_friction()): the friction scales of the
    /// stages that converged, in order (1: the deck's; the first at 1 with
    /// Coulomb's bound at its fixed point); empty: not needed.
    std::vector<double> friction_stages;
    /// The rate sensitivities m of the continuation in the law's stages
    /// that converged (the last the deck's); empty: not needed.
    std::vector<double> rate_sensitivity_stages;
    LinearSolverCounts linear_counts;
    /// Integral of the traction sigma n over each boundary part (N/mm in 2D).
    std::map<BoundaryId, std::vector<double>> boundary_force;
    /// Integral of v.n over each boundary part (mm^2/s in 2D).
    std::map<BoundaryId, double> flux;
    /// Each boundary part's area (mm per mm of depth; axisymmetric: mm^2).
    std::map<BoundaryId, double> boundary_area;
    std::map<BoundaryId, double> die_normal_force;
    std::map<BoundaryId, double> die_friction_force;
    ContactCounts                contact_nodes;
    /// Length (mm in 2D; area in 3D) of each die id that is separated,
    /// sticking or slipping: the sum of the nodal boundary weights by state.
    std::map<BoundaryId, std::array<double, 3>> contact_length;
    /// Contact inequalities of the result, dimensionless (0 when exact):
    /// largest v.n > 0 over the largest speed; largest pulling normal force
    /// over the largest normal force; largest |F_t| - bound (at the nodes friction_checked_nodes counts) over the largest
    /// bound; largest |v.t| of a sticking node over the largest speed.
    double contact_penetration = 0;
    double contact_tension     = 0;
    double friction_excess     = 0;
    /// The nodes friction_excess measured: those whose friction is a
    /// reaction, a stick penalty or the 3D semismooth force (a slipping
    /// node's friction is on its bound by construction).
    unsigned int friction_checked_nodes = 0;
    double stick_slip_rate     = 0;
    /// Largest normal reaction at a separated node over the largest normal force.
    double separated_reaction  = 0;
    /// Largest power F_t v.t > 0 of a friction force that drives its slip
    /// instead of opposing it, over (largest |F_t|) x (largest speed).
    double friction_power      = 0;
    /// Directions held in contact, and friction laws regularised, to end
    /// a cycle of the contact states (a held node sits where contact
    /// gives way to separation: its small pull is that transition falling
    /// between two nodes).
    unsigned int held_in_contact      = 0;
    unsigned int regularised_friction = 0;
    /// ||div v||_L2 / ||grad v||_L2, div v at the cell centres.
    double                divergence_ratio = 0;
    /// How much mass the penalty lost, and the guard's verdict on it:
    /// "ok", "warning" or "failed" ("" when the cycle did not converge).
    MassBalance mass_balance;
    MassBalanceStatus mass_balance_status = MassBalanceStatus::unchecked;
    std::optional<double> velocity_l2_error;
    std::optional<double> velocity_h1_error;
    /// The quantities of interest, in a fixed order: the force along x on
    /// each prescribed-velocity part (F_x[1] is die2d's ram force), the die
    /// normal and friction forces per contact id, the velocity at the probe.
    std::vector<std::pair<std::string, double>> quantities;
    /// ||v_start - v|| / ||v|| (dof vectors): how far the cycle's first
    /// iterate (the Newtonian start, or the previous cycle's solution
    /// transferred to this mesh) was from its solution.
    double start_distance = 0;
    /// Kelly's global estimate of the velocity error, sqrt(sum eta_K^2).
    double error_estimate = 0;
    /// The estimated error of each quantity of interest from the cycles up
    /// to this one (empty on the first).
    std::vector<std::pair<std::string, double>> estimated_errors;
    /// With Indicator = dual weighted: the goal-oriented estimate of the
    /// exact minus the computed force of that part (goal_estimate.h).
    std::optional<double> dual_weighted_error;
    /// Share of the cells with a face on a contact id.
    double die_cell_share = 0;
    /// The penalty lambda and the mean viscosity it was made from.
    double penalty           = 0;
    double mean_viscosity    = 0;
    double wall_time         = 0;
    std::vector<IterationRecord> history;
    /// Problem = incremental: the step this solve belongs to.
    std::optional<StepRecord> step;
    /// Steady runs with Free surface/Iterations > 0.
    std::optional<FreeSurfaceRecord> free_surface;
    /// With a temperature field (its vertex values left out).
    std::optional<HeatRecord> heat;
    /// With a steady strain field (its vertex values left out).
    std::optional<StrainRecord> strain;
  };

  /// The value named @p name among (name, value) pairs such as
  /// CycleSummary::quantities, or @p otherwise.
  inline double
  named_value(const std::vector<std::pair<std::string, double>> &named,
              const std::string &                                name,
              const double                                       otherwise = 0)
  {
    for (const auto &[n, v] : named)
      if (n == name)
        return v;
    return otherwise;
  }

  struct RunSummary
  {
    bool                      converged = false;
    double                    wall_time = 0;
    std::string               failure;
    /// One line each: what holds but is doubtful (a mass balance above a
    /// tenth of its tolerance).
    std::vector<std::string>  warnings;
    /// Ended by SIGINT or SIGTERM before it finished (interrupt.h).
    bool                      interrupted = false;
    std::vector<CycleSummary> cycles;
    /// Discretisation/Velocity degree (1: Q1-P0, 2: Q2-P1disc).
    unsigned int              velocity_degree = 1;
    /// Problem: "steady" (cycles are refinement cycles) or "incremental" (time steps).
    std::string               problem = "steady";
    /// Geometry: "plane strain" (forces per mm of depth) or "axisymmetric" (whole body, N).
    std::string               geometry = "plane strain";
    /// Wall time (s) per stage: setup, assembly, linear solve, postprocess, refinement.
    std::map<std::string, double> stage_wall_time;
    /// Peak resident memory of the process (MB); on more than one, the largest process's.
    double peak_memory_mb = 0;
    /// The MPI processes of the run (processes.h).
    unsigned int processes = 1;
    /// The threads the assembly ran on (threads.h; the results do not depend on it).
    unsigned int threads = 1;
    /// Richardson estimates of the quantities (study.h).
    std::vector<QuantityEstimate> extrapolated;
    /// With a Refinement/Target error: whether the estimated relative error
    /// of the target quantity fell below it.
    std::optional<bool> target_reached;
    std::string         target_quantity;
    double              target_error = 0;
    /// Problem = incremental, gone on from a checkpoint: its file and step,
    /// and the step records before it (for the run's totals).
    std::string             restarted_from;
    unsigned int            restart_step = 0;
    std::vector<StepRecord> earlier_steps;
    /// The last checkpoint written (checkpoint.h), and its step.
    std::string  checkpoint_file;
    unsigned int checkpoint_step = 0;
  };

  /**
   * The result a user runs the program for, on @p out: the force on each
   * prescribed-velocity part (the ram), the normal and friction force and the
   * separated / stick / slip lengths of each die id, the probe velocity, each
   * with its Richardson estimate when several cycles ran.
   */
  void
  write_result_summary(const RunSummary &summary, std::ostream &out);

  /// Writes @p summary as JSON (the summary.json contract of interface.md).
  /// A whole incremental run at a glance (summary.json "incremental").
  struct StepTotals
  {
    unsigned int steps = 0;
    /// The deepest any free node went through a die over the run (mm).
    double largest_penetration = 0;
    /// (V - V_0) / V_0 at the last step; the smallest scaled Jacobian of any step.
    double volume_change            = 0;
    double smallest_scaled_jacobian = 1;
    /// Boundary faces that came onto a die and left one, over the run.
    unsigned int faces_entered = 0;
    unsigned int faces_left    = 0;
    /// New meshes of the domain, and the largest |volume change| of one.
    unsigned int remeshings                   = 0;
    double       largest_remesh_volume_change = 0;
  };

  /// The totals of the cycles' step records (none in a steady run).
  StepTotals
  step_totals(const RunSummary &summary);

  void
  write_summary_json(const RunSummary &summary, const std::string &file_name);
} // namespace dieflow

#endif
