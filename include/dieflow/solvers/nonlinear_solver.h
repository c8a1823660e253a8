// The nonlinear iteration: what it asks of a discrete system, Picard, Newton with a line search, their settings and their log.
#ifndef dieflow_nonlinear_solver_h
#define dieflow_nonlinear_solver_h

#include <dieflow/solvers/linearization.h>
#include <dieflow/base/parameters.h>

#include <deal.II/lac/vector.h>

#include <ostream>
#include <string>
#include <vector>

namespace dieflow
{
  /**
   * What the nonlinear solver needs of a discrete problem. The state (the
   * contact active set, stick and slip) is the system's: update_state()
   * revises it from the current iterate and projects the iterate onto the
   * resulting constraints.
   */
  class NonlinearSystem
  {
  public:
    virtual ~NonlinearSystem() = default;

    /// Revises the state from @p v, projects @p v onto the constraints, and
    /// returns how many contact directions changed state.
    virtual StateChanges
    update_state(dealii::Vector<double> &v) = 0;

    /// Assembles J(v) and -R(v); returns the relative residual (see residual()).
    virtual double
    assemble_system(const dealii::Vector<double> &v, const Linearization linearization) = 0;

    /// The relative residual ||R(v)|| / ||reactions(v)|| of the free dofs;
    /// -R(v) (condensed) into @p minus_residual.
    virtual double
    residual(const dealii::Vector<double> &v, dealii::Vector<double> &minus_residual) = 0;

    /// The relative residual that round-off alone leaves (the solver never
    /// asks for less).
    virtual double
    residual_floor() const
    {
      return 0;
    }

    /// Whether the last assembled Jacobian is symmetric (the problem then
    /// minimises a potential).
    virtual bool
    jacobian_is_symmetric() const
    {
      return true;
    }

    /// What the state did that a failure message should mention (empty: nothing).
    virtual std::string
    state_note() const
    {
      return "";
    }

    /// Changes that may help the contact settle, deck settings not in use
    /// already ("refine the mesh at the die", "set Contact/Friction law =
    /// Tresca", ...), for failure messages.
    virtual std::vector<std::string>
    contact_changes() const
    {
      return {};
    }

    /// Deck changes that keep the viscosity law in its range (a larger
    /// minimum strain rate), for failure messages; empty when none applies.
    virtual std::vector<std::string>
    law_changes() const
    {
      return {};
    }

    /// The largest prescribed speed: updates far above it are not trusted.
    virtual double
    velocity_scale() const
    {
      return 0;
    }

    /// Whether the constraints the iterate satisfies only in the limit
    /// (an augmented Lagrangian's) hold to their tolerance at the last
    /// update_state(); asked only of an iterate that has otherwise
    /// converged, it may change how they are held (then false).
    virtual bool
    constraints_settled()
    {
      return true;
    }

    /// -R (condensed) of the last assemble_system().
    virtual const dealii::Vector<double> &
    minus_residual() const = 0;

    /// True when R is affine in v (Newtonian, no contact): one Newton step solves it.
    virtual bool
    is_linear() const = 0;

    /// Called when the step v -> v + step * update of the given
    /// linearisation is taken (before v changes), for state that follows the
    /// iterate (the primal-dual variable).
    virtual void
    accept_step(const dealii::Vector<double> &v,
                const dealii::Vector<double> &update,
                const double                  step,
                const Linearization           linearization) = 0;

    /// The residual() calls that follow evaluate v + @p step * update of
    /// the last solve (state that moves with v, as a mixed form's
    /// pressure, moves with it); accept_step() and assemble_system() end it.
    virtual void
    set_trial_step(const double step)
    {
      (void)step;
    }

    /// Solves J du = -R with the last assembled system. An iterative solve
    /// may stop early where @p relative_residual (the residual() of the
    /// iterate) is large: the inexact Newton method's forcing term.
    virtual void
    solve(dealii::Vector<double> &update, const double relative_residual) = 0;
  };

  /// One line of the iteration log.
  struct IterationRecord
  {
    unsigned int  iteration;
    Linearization linearization;
    double        residual;
    double        update;
    double        step;
    StateChanges  state_changes;
  };

  struct NonlinearResult
  {
    bool                         converged     = false;
    unsigned int                 iterations    = 0;
    unsigned int                 linear_solves = 0;
    std::vector<IterationRecord> history;
    /// Why it stopped without convergence, and what to change.
    std::string failure;
    /// Stopped by SIGINT or SIGTERM (interrupt.h).
    bool interrupted = false;
  };

  /**
   * Picard (the paper's successive substitution with its relative-update
   * test), Newton with the consistent tangent and a backtracking (Armijo)
   * line search on the residual norm, or Picard then Newton.
   *
   * Converged when no node changed state and either the relative residual
   * ||R|| / ||reactions|| is below the residual tolerance, or the last relative
   * update ||du|| / ||v|| is below the update tolerance. Newton updates
   * smaller than 1e-6 ||v|| are taken whole (the quadratic regime). A Newton step that
   * the line search cannot make reduce the residual is replaced by a Picard
   * step (the Picard matrix is positive definite). No update may change a
   * velocity by more than a hundred times the larger of the largest
   * prescribed speed and the current largest speed (a longer step is
   * shortened, and the log says so), and an iterate faster than ten
   * thousand times the prescribed speed ends the run: it diverges.
   */
  class NonlinearSolver
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    /// Iterates from @p v (overwritten with the result), logging a line per iteration.
    NonlinearResult
    solve(NonlinearSystem &system, dealii::Vector<double> &v, std::ostream &log) const;

    /**
     * The changes of this solver's own settings that may help an iteration
     * that failed, each one not in use already (a failure message never
     * advises what the deck already says): the primal-dual tangent, Picard
     * steps before Newton, or more of them.
     */
    std::vector<std::string>
    method_changes() const;

  private:
    /// The accepted fraction of the Newton step @p update from @p v (0: none).
    double
    line_search_step(NonlinearSystem &             system,
                     const dealii::Vector<double> &v,
                     const dealii::Vector<double> &update,
                     dealii::Vector<double> &      trial,
                     const double                  residual) const;

  public:
    enum class Method
    {
      newton,
      picard,
      picard_then_newton
    };
    /// The Newton tangent's form (FlowAssembler::Tangent).
    enum class NewtonTangent
    {
      primal_dual,
      standard
    };
    /// The deck's names of the methods ("Newton", "Picard", "Picard then
    /// Newton") and tangents ("primal-dual", "standard").
    static Method
    method_named(const std::string &name);
    static NewtonTangent
    tangent_named(const std::string &name);

    Method        method                    = Method::newton;
    NewtonTangent newton_tangent            = NewtonTangent::primal_dual;
    unsigned int maximum_iterations         = 50;
    double       residual_tolerance         = 1e-8;
    double       update_tolerance           = 1e-8;
    unsigned int picard_iterations          = 2;
    /// Largest share of the flow the penalty may lose in a converged
    /// cycle (the check is the problem's: mass_balance.h); 0: off.
    double       mass_balance_tolerance     = 1e-3;
    bool         line_search                = true;
    unsigned int maximum_line_search_steps  = 8;
  };
} // namespace dieflow

#endif
