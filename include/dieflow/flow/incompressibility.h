// The incompressibility forms behind one interface: plain penalty, augmented Lagrangian and the mixed form.
#ifndef dieflow_incompressibility_h
#define dieflow_incompressibility_h

#include <dieflow/flow/flow_assembler.h>
#include <dieflow/flow/material.h>
#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/solvers/linear_solver.h>
#include <dieflow/solvers/linearization.h>
#include <dieflow/solvers/mixed_penalty.h>
#include <dieflow/solvers/saddle_point_solver.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <functional>
#include <limits>
#include <memory>
#include <ostream>
#include <string>

namespace dieflow
{
  /**
   * How the incompressibility of the paper's penalised problem (8) is kept
   * and how the Newton step's linear system is solved. The form follows
   * the linear solver's choice for the mesh (LinearSolver::iterative_for()):
   *
   * - penalty (direct solver): p = -lambda P div v, lambda = (Material/
   *   Penalty factor) x eta_m, eta_m the mean viscosity; J du = -R solved
   *   by CHOLMOD or UMFPACK. Where the iteration has converged but the
   *   penalty let more of the flow go than Nonlinear solver/Mass balance
   *   tolerance allows (a low factor: div v is of order 1/factor), the
   *   form turns augmented (augment()) and stays so for the run: the
   *   augmented Lagrangian below with r = (Penalty factor) x eta per cell,
   *   still solved directly, whose Uzawa steps drive P div v to zero
   *   whatever the factor.
   *
   * - augmented Lagrangian (iterative solver, velocity degree 1; Fortin and
   *   Glowinski, Augmented Lagrangian Methods, 1983): p = -(q + r P div v),
   *   r = (Augmentation factor) x eta per cell, about 1e3 eta instead of
   *   1e7 eta; before each nonlinear iteration the multiplier takes its
   *   Uzawa step q <- q + r P div v (P: the centre value for degree 1).
   *   At the fixed point P div v = 0 in every cell; the iteration stops
   *   when, besides the residual, the divergence ratio is below Divergence
   *   tolerance (settled()).
   *
   * - mixed (iterative solver, velocity degree 2; SaddlePointSolver): the
   *   pressure coefficients p are carried as unknowns of Newton's method
   *   beside v, through the multiplier q = p - lambda P div v of
   *   FlowAssembler (sigma = 2 eta D + (q + lambda P div v) I), so that
   *   neither the residual nor a Krylov method's error is multiplied by
   *   lambda/eta: R_v = A(v) + B^T p - f, R_p = B v - M p / lambda =
   *   -M q / lambda; each Newton step solves the mixed system for
   *   (du, dp) and moves q by dq = dp - lambda M^-1 B du. At the solution
   *   q = 0 and (v, p) is the penalty solution. The step's q moves with
   *   the line search's trial v (set_trial_step()). A solve that fails
   *   goes to the direct solver on the penalty form (the fallback), which
   *   gives the same step exactly.
   *
   * Per Newton iteration: before_state_update(), after_projection() (the
   * contact's new constraints move v), prepare_assembly(), terms() for
   * the assembly, solve(), then set_trial_step() in the line search and
   * accept(). Per mesh: reinit(), from the cell stress carried from the
   * previous mesh (carry()).
   */
  template <int dim>
  class Incompressibility
  {
  public:
    enum class Form
    {
      penalty,
      augmented_lagrangian,
      mixed
    };

    /// The assembly of the penalty form at an iterate into the system the
    /// last solve had (the direct fallback of the mixed form); returns
    /// whether that Jacobian is symmetric.
    using Reassembly = std::function<bool(const Vector<double> &v, const Linearization, const FlowTerms<dim> &)>;

    Incompressibility(const Material &             material,
                      const CoordinateSystem<dim> &coordinates,
                      const DoFHandler<dim> &      dof_handler,
                      LinearSolver &               linear_solver,
                      std::ostream &               log);

    /**
     * A new mesh (the dofs distributed, @p matrix sized to its pattern):
     * forgets the linear solver's analysis, takes the form the linear
     * solver chooses for its size (with Method = auto, the iterative one
     * also where a direct factorisation would not fit in the memory free,
     * LinearSolver::direct_fits()), and starts the multiplier from the
     * carried cell stress (carry(); zero without one) at @p velocity (the
     * iterate the mesh starts from).
     */
    void
    reinit(const AffineConstraints<double> &hanging_node_constraints,
           const Vector<double> &           velocity,
           const SparseMatrix<double> &     matrix);

    Form
    form() const
    {
      return current_form;
    }
    /// Whether the form's linear systems are solved by a Krylov method.
    bool
    iterative() const
    {
      return krylov;
    }
    /// "penalty", "augmented Lagrangian" or "mixed" (summary.json).
    std::string
    form_name() const;
    /**
     * From the penalty form to the augmented Lagrangian, solved directly,
     * at the converged iterate @p v: q = (lambda - r) P div v, so that the
     * pressure -(q + r P div v) = -lambda P div v and the residual do not
     * change; the Uzawa steps before each iteration then take P div v to
     * zero. Later meshes start augmented (their loss would be the same).
     */
    void
    augment(const Vector<double> &v);
    /// The augmented Lagrangian's multiplier as augment() sets it at
    /// @p v (the penalty's pressure there), the Uzawa steps' forgotten: a
    /// solve again from an earlier iterate (continuation) starts with the
    /// pressure of that iterate, not of the one that failed.
    void
    restart_multiplier(const Vector<double> &v);
    /// The multiplier iteration's state at a converged iterate (form,
    /// multipliers, r per cell, Uzawa progress): a continuation stage that
    /// fails returns to it with the velocity and contact states of the last
    /// converged stage, whose pressure it is (a failed stage's Uzawa steps
    /// leave a pressure of no solution).
    struct Iterate
    {
      Form           form = Form::penalty;
      bool           augmented_direct = false;
      Vector<double> multiplier, accepted_multiplier, cell_penalty;
      double         eta_m                 = 0;
      double         last_divergence_ratio = 0;
      unsigned int   stalled_steps         = 0;
    };
    Iterate
    iterate() const
    {
      return {current_form, augmented_direct, multiplier, accepted_multiplier, cell_penalty, eta_m,
              last_divergence_ratio, stalled_steps};
    }
    void
    restore(const Iterate &state)
    {
      current_form          = state.form;
      augmented_direct      = state.augmented_direct;
      multiplier            = state.multiplier;
      accepted_multiplier   = state.accepted_multiplier;
      cell_penalty          = state.cell_penalty;
      set_viscosity_scale(state.eta_m, stage_law);
      last_divergence_ratio = state.last_divergence_ratio;
      stalled_steps         = state.stalled_steps;
    }
    /// Checkpoints: eta_m, and whether augment() was called (a restarted
    /// run goes on augmented where the uninterrupted one did).
    template <class Archive>
    void
    save(Archive &ar) const
    {
      ar << eta_m << process_rate << augmented_direct;
    }
    template <class Archive>
    void
    load(Archive &ar)
    {
      double eta = 0;
      ar >> eta >> process_rate >> augmented_direct;
      set_viscosity_scale(eta);
    }
    /// lambda/eta (penalty, mixed) or r/eta (augmented Lagrangian).
    double
    factor() const;
    /// "penalty lambda" or "augmented-Lagrangian penalty r" (for the log).
    std::string
    name() const;
    /// lambda (or the uniform r): factor() x the viscosity scale.
    double
    penalty() const
    {
      return lambda;
    }
    /// eta_m, the mean viscosity lambda is made from (0 until set).
    double
    viscosity_scale() const
    {
      return eta_m;
    }
    /// eta_m, and lambda = factor() x eta_m, at most (Material::
    /// largest_penalty_factor) x the viscosity of @p law (the deck's if
    /// null; a continuation stage's) at the process's strain rate
    /// (set_process_rate()): the mean viscosity of a strongly
    /// shear-thinning law's first iterate is its dead zones', up to a
    /// thousand times the viscosity where the metal deforms, and lambda over
    /// that viscosity is what round-off multiplies (doc/stress.md). The
    /// augmented Lagrangian's r per cell follows @p law too, until the
    /// next call (the stage's law lives as long as its stage).
    void
    set_viscosity_scale(const double eta, const Material *law = nullptr);
    /// The strain rate of the process that bounds lambda (the root mean
    /// square of the Newtonian start's, at least the largest prescribed
    /// speed over the domain's size or Material/Reference strain rate).
    void
    set_process_rate(const double rate)
    {
      process_rate = rate;
    }
    /// Whether lambda is the bound rather than factor() x eta_m.
    bool
    penalty_bounded() const
    {
      return lambda < factor() * eta_m;
    }
    /// The augmented Lagrangian's r = @p r in every cell.
    void
    uniform_cell_penalty(const double r);

    /// What the flow assembly reads of the form's state (FlowTerms).
    FlowTerms<dim>
    terms();

    /// Before the contact states are revised from @p v: the augmented
    /// Lagrangian's Uzawa step q <- q + r P div v.
    void
    before_state_update(const Vector<double> &v);
    /// After the new constraints moved @p before to @p v: the mixed form's
    /// pressure p = q + lambda P div v stays (else it jumps by lambda P div
    /// of that move).
    void
    after_projection(const Vector<double> &before, const Vector<double> &v);
    /// Before the assembly of the Newton system at @p v.
    void
    prepare_assembly(const Vector<double> &v, const Linearization linearization);

    /**
     * Solves J du = -R for the Newton step @p update (the last assembled
     * @p matrix, symmetric or not, and @p rhs) in the form's way; the mixed
     * form to a tolerance from Newton's @p relative_residual (forcing
     * term) and the round-off @p residual_floor, at the iterate
     * @p velocity; its direct fallback calls @p reassemble into @p matrix
     * and @p rhs.
     */
    void
    solve(SparseMatrix<double> &          matrix,
          const bool                      symmetric,
          Vector<double> &                rhs,
          const AffineConstraints<double> &update_constraints,
          Vector<double> &                update,
          const double                    relative_residual,
          const double                    residual_floor,
          const Vector<double> &          velocity,
          const Reassembly &              reassemble);

    /// The mixed form's pressure moves with the line search's trial step.
    void
    set_trial_step(const double step);
    /// The step of the last solve taken with length @p step.
    void
    accept(const double step);

    /// Whether the constraint that holds only in the limit holds to its
    /// tolerance: the augmented Lagrangian's divergence ratio, the mixed
    /// form's pressure equation (||q / lambda|| / ||grad v|| at @p velocity).
    bool
    settled(const Vector<double> &velocity) const;
    /**
     * The relative residual that the cancellation in lambda div v leaves
     * (lambda = factor x eta): about 1e-16 x factor per nodal force,
     * measured on die2d from 666 to 150,000 dofs as 1.5e-17 to 3e-17 x
     * factor x sqrt(dofs); twice that.
     */
    double
    cancellation_floor() const;
    /// The Uzawa steps of a penalty turned augmented (augment()) stopped
    /// reducing the divergence ratio: settled() gives up on them and the
    /// mass-balance guard judges (the elements lock).
    bool
    uzawa_stalled() const
    {
      return stalled_steps >= 3;
    }
    /// Whether Newton's method meets a linear problem here (no multiplier
    /// iteration, exact solves).
    bool
    is_exact() const
    {
      return current_form == Form::penalty;
    }

    /// p = -(q + r div v) or -lambda div v at each cell's coefficients, of @p velocity.
    Vector<double>
    cell_pressures(const Vector<double> &velocity) const;
    /// The cell stress q + lambda div v of the previous mesh on this one
    /// (one value per active cell; empty: none), for the next reinit().
    void
    carry(const Vector<double> &cell_stress)
    {
      carried_stress = cell_stress;
    }

    /// The Newtonian start's solve (with its own penalty @p start_penalty):
    /// the terms it assembles with, the mixed form's pressure at zero.
    FlowTerms<dim>
    start_terms(const double start_penalty, const Vector<double> &velocity);
    /// After the Newtonian start solved for @p velocity: the form's state
    /// for the law's first iteration, lambda from the mean viscosity @p eta
    /// (the mixed form's pressure scaled as the penalty form's would be).
    void
    finish_start(const double start_penalty, const double eta, const Vector<double> &velocity);

  private:
    /// q = p - lambda M^-1 B v for the cell coefficients @p p.
    Vector<double>
    multiplier_for(const Vector<double> &p, const Vector<double> &v) const;
    /// ||q / lambda|| / ||grad v|| (L2 norms; 0 without q).
    double
    pressure_residual_ratio(const Vector<double> &velocity) const;
    /**
     * The mixed solve's tolerance: Newton's forcing term (LinearSolver::
     * forcing_tolerance(), no looser in absolute terms than the last
     * solve's on this mesh where the residual grew), tightened once
     * Newton's residual is down to its round-off floor (or stalled while
     * the velocity stopped moving) while pressure_residual_ratio() is still
     * above its bound. A solve leaves q = -lambda M^-1 r_p, r_p its
     * pressure rows' residual, so the ratio after a solve scales with the
     * tolerance it was given: the next one gets last tolerance x 0.1 x
     * bound / ratio, but no less than 1e-2 of the forcing term or 1e-10.
     */
    double
    mixed_solve_tolerance(const double relative_residual, const double residual_floor, const Vector<double> &velocity);
    void
    solve_mixed(SparseMatrix<double> &           matrix,
                const bool                       symmetric,
                Vector<double> &                 rhs,
                const AffineConstraints<double> &update_constraints,
                Vector<double> &                 update,
                const double                     tolerance,
                const Reassembly &               reassemble);
    /// r = 'Augmentation factor' x the viscosity of @p v at each cell centre.
    void
    update_cell_penalty(const Vector<double> &v);

    const Material &             material;
    const CoordinateSystem<dim> &coordinates;
    const DoFHandler<dim> &      dof_handler;
    LinearSolver &               linear_solver;
    std::ostream &               log;

    Form   current_form = Form::penalty;
    /// Solved by a Krylov method (else directly); augment() was called.
    bool   krylov = false, augmented_direct = false;
    double eta_m        = 0;
    double lambda       = 0;
    /// set_viscosity_scale()'s law (null: the deck's), whose viscosity r per cell follows.
    const Material *stage_law = nullptr;
    /// set_process_rate()'s (0: lambda unbounded), and the bound on lambda it gives.
    double process_rate = 0, largest_lambda = std::numeric_limits<double>::infinity();
    /// q per pressure coefficient (augmented, mixed); r per cell (augmented).
    Vector<double> multiplier, cell_penalty;
    /// The mixed form's q of the accepted iterate, and the last step's dq.
    Vector<double> accepted_multiplier, multiplier_update;
    /// The pressure is to start at zero at the next assembly (no previous mesh's).
    bool pressure_unset = false;
    /// The iterate and linearisation of the last assembly (for the direct fallback).
    Vector<double> assembled_iterate;
    Linearization  assembled_linearization = Linearization::picard;
    /// The last mixed solve's tolerance on this mesh (0: none yet), Newton's
    /// relative residual it was asked at, and ||du|| / ||v|| of its step.
    double last_mixed_tolerance = 0, last_mixed_residual = 0, last_mixed_update = 1;
    double last_divergence_ratio = 0;
    /// Consecutive Uzawa steps (solved directly) that kept more than half
    /// the divergence ratio.
    unsigned int stalled_steps = 0;
    Vector<double>                          carried_stress;
    MixedPenalty<dim>                       blocks;
    std::unique_ptr<SaddlePointSolver<dim>> saddle_point_solver;
  };
} // namespace dieflow

#endif
