// The die-flow problem as Newton's method sees it: the state update, the assembly, the solve and the step of one iteration, and the Newtonian start.
#include <dieflow/base/processes.h>
#include <dieflow/postprocess/mass_balance.h>
#include <dieflow/postprocess/postprocess.h>
#include <dieflow/problem/problem.h>

#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <cmath>
#include <iomanip>

namespace dieflow
{
  namespace
  {
    /// The root mean square over the domain of the equivalent strain rate
    /// sqrt(2/3 D:D) of @p velocity (plane measure, the in-plane rates: a
    /// scale, not a quantity).
    template <int dim>
    double
    process_rate_estimate(const DoFHandler<dim> &dof_handler, const Vector<double> &velocity)
    {
      const dealii::QGauss<dim>                    quadrature(dof_handler.get_fe().degree + 1);
      dealii::FEValues<dim>                        fe_values(dof_handler.get_fe(),
                                      quadrature,
                                      dealii::update_gradients | dealii::update_JxW_values);
      const dealii::FEValuesExtractors::Vector     velocities(0);
      std::vector<dealii::SymmetricTensor<2, dim>> D(quadrature.size());
      double                                       integral = 0, volume = 0;
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          fe_values.reinit(cell);
          fe_values[velocities].get_function_symmetric_gradients(velocity, D);
          for (const unsigned int q : fe_values.quadrature_point_indices())
            {
              integral += 2. / 3. * (D[q] * D[q]) * fe_values.JxW(q);
              volume += fe_values.JxW(q);
            }
        }
      return volume > 0 ? std::sqrt(integral / volume) : 0.;
    }
  } // namespace



  template <int dim>
  StateChanges
  DieFlowProblem<dim>::update_state(Vector<double> &v)
  {
    incompressibility.before_state_update(v);
    const Vector<double> before = v;
    StateChanges         changes;
    // The first iterate of a refined mesh is the previous solution
    // interpolated, not in equilibrium on the new mesh: its reactions say
    // nothing about the contact states, which it keeps from the previous
    // mesh for its first solve.
    if (!contact.empty() && contact_states_valid && !states_from_previous_mesh)
      {
        dealii::TimerOutput::Scope scope(timer, "contact");
        changes = contact.update(v, system.nodal_flow_residual(v, flow_terms(), hanging_node_constraints), log);
        // Contact and exact stick are constraints.
        if (changes.total() > 0)
          make_constraints();
      }
    states_from_previous_mesh = false;
    constraints.distribute(v);
    incompressibility.after_projection(before, v);
    return changes;
  }



  template <int dim>
  double
  DieFlowProblem<dim>::assemble_system(const Vector<double> &v, const Linearization linearization)
  {
    dealii::TimerOutput::Scope scope(timer, "assembly");
    processes::require_same(v, "a Newton iteration's assembly");
    incompressibility.prepare_assembly(v, linearization);
    const FlowTerms<dim> terms = flow_terms();
    matrix_symmetric           = system.assemble(v, terms, linearization, &system_matrix, system_rhs).symmetric;
    last_roundoff_bound        = system.roundoff_bound(system_matrix, v, terms.mixed);
    const double relative      = system.relative_residual(system_rhs);
    // Newton's decisions read it: the same on every process.
    processes::require_same(dealii::Vector<double>{relative, last_roundoff_bound}, "a Newton iteration's residual");
    return relative;
  }



  template <int dim>
  double
  DieFlowProblem<dim>::residual(const Vector<double> &v, Vector<double> &minus_residual)
  {
    dealii::TimerOutput::Scope scope(timer, "assembly");
    system.assemble(v, flow_terms(), Linearization::picard, nullptr, minus_residual);
    const double relative = system.relative_residual(minus_residual);
    processes::require_same(dealii::Vector<double>{relative}, "a line search's residual");
    return relative;
  }



  template <int dim>
  bool
  DieFlowProblem<dim>::reassemble_penalty_form(const Vector<double> &v,
                                               const Linearization   linearization,
                                               const FlowTerms<dim> &terms)
  {
    // The penalty form's terms with what the flow reads besides (hardening, temperature).
    const FlowTerms<dim> state = flow_terms();
    FlowTerms<dim>       full  = terms;
    full.hardening             = state.hardening;
    full.point_hardening       = state.point_hardening;
    full.temperature           = state.temperature;
    matrix_symmetric           = system.assemble(v, full, linearization, &system_matrix, system_rhs).symmetric;
    return matrix_symmetric;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::solve(Vector<double> &update, const double relative_residual)
  {
    dealii::TimerOutput::Scope scope(timer, "linear solve");
    incompressibility.solve(system_matrix,
                            matrix_symmetric,
                            system_rhs,
                            update_constraints,
                            update,
                            relative_residual,
                            residual_floor(),
                            velocity,
                            [this](const Vector<double> &v, const Linearization linearization, const FlowTerms<dim> &terms) {
                              return reassemble_penalty_form(v, linearization, terms);
                            });
    update_constraints.distribute(update);
  }



  template <int dim>
  void
  DieFlowProblem<dim>::set_trial_step(const double step)
  {
    incompressibility.set_trial_step(step);
  }



  template <int dim>
  void
  DieFlowProblem<dim>::accept_step(const Vector<double> &v,
                                   const Vector<double> &update,
                                   const double          step,
                                   const Linearization   linearization)
  {
    contact_states_valid = true;
    incompressibility.accept(step);
    if (linearization == Linearization::newton)
      assembler.update_dual(dof_handler, v, &update, step);
    else
      {
        Vector<double> next = v;
        next.add(step, update);
        assembler.update_dual(dof_handler, next, nullptr, 0);
      }
  }



  template <int dim>
  bool
  DieFlowProblem<dim>::is_linear() const
  {
    // The augmented Lagrangian iterates on its multiplier; the mixed form's
    // Krylov solves are inexact.
    return parameters.material.is_newtonian() && contact.empty() && incompressibility.is_exact();
  }



  template <int dim>
  double
  DieFlowProblem<dim>::residual_floor() const
  {
    // The cancellation in lambda div v, or the round-off bound of the last
    // assembly where it is larger (SystemAssembler::roundoff_bound()).
    return std::max(incompressibility.cancellation_floor(), last_roundoff_bound);
  }



  template <int dim>
  bool
  DieFlowProblem<dim>::constraints_settled()
  {
    // A penalty that lets more of the flow go than the mass-balance guard
    // allows (div v is of order 1/factor) turns augmented here: Uzawa steps
    // then take P div v to zero (Incompressibility::augment()). The guard
    // stays for the dual-weighted estimate, whose dual problem is the
    // penalty form's.
    const double tolerance = parameters.nonlinear_solver.mass_balance_tolerance;
    if (incompressibility.form() == Incompressibility<dim>::Form::penalty && tolerance > 0 &&
        !parameters.refinement.solves_dual())
      {
        const MassBalance balance =
          mass_balance(parameters.coordinates, dof_handler, velocity,
                       boundary_fluxes(parameters.coordinates, dof_handler, velocity));
        if (balance.worst() > tolerance)
          {
            incompressibility.augment(velocity);
            log << "  the penalty (factor " << parameters.material.penalty_factor << ") lets "
                << std::setprecision(2) << 100. * balance.worst()
                << " % of the flow go: Uzawa steps from here (augmented Lagrangian, r = factor x eta per cell)"
                << std::setprecision(6) << std::endl;
            return false;
          }
      }
    return incompressibility.settled(velocity);
  }



  template <int dim>
  std::vector<std::string>
  DieFlowProblem<dim>::contact_changes() const
  {
    std::vector<std::string> changes = parameters.contact.settling_changes();
    // Coulomb friction that did not settle: the law's changes first, the
    // mesh last (measured, ContactParameters::settling_changes()).
    const bool coulomb_friction =
      parameters.contact.law == FrictionLaw::Kind::coulomb && parameters.contact.has_friction();
    changes.insert(coulomb_friction ? changes.end() : changes.begin(), "refine the mesh at the die");
    // The regularised law from Newton's first step: on die2d (blocks, m =
    // 0.2, mu = 0.3, at 1e-6, 1 and 1e6 mm/s; P1 with mu = 0.3, with and
    // without its free surface) the land's directions kept entering and
    // leaving contact, and two Picard steps first converged every one
    // (doc/contact.md).
    if (parameters.contact.law == FrictionLaw::Kind::regularised_coulomb &&
        parameters.nonlinear_solver.method == NonlinearSolver::Method::newton)
      changes.insert(changes.begin(), "set Nonlinear solver/Method = Picard then Newton");
    return changes;
  }



  template <int dim>
  std::vector<std::string>
  DieFlowProblem<dim>::law_changes() const
  {
    return parameters.material.range_changes();
  }



  template <int dim>
  void
  DieFlowProblem<dim>::newtonian_start()
  {
    const Material &material = parameters.material;
    // The velocity of a Newtonian, velocity-driven problem does not depend on
    // the viscosity's value; the law's viscosity at a typical strain rate
    // keeps forces and tractions (body force, Tresca) on the right scale.
    prescribed_speed          = parameters.boundary_conditions.largest_prescribed_speed(dof_handler);
    const double process_rate = prescribed_speed / dealii::GridTools::diameter(triangulation);
    double       reference_rate = material.reference_strain_rate;
    if (reference_rate == 0)
      reference_rate = process_rate == 0 ? 1 : process_rate;
    // The regularisation epsdot_min is an absolute rate: far from below the
    // process's rates it turns the law Newtonian (a die pushed at 1e-6 mm/s
    // with the default 1e-4 1/s), a model the user did not ask for.
    if (!material.is_newtonian() && process_rate > 0 && material.minimum_strain_rate > 1e-2 * process_rate)
      {
        std::ostringstream warning;
        warning << "Material/Minimum strain rate (" << material.minimum_strain_rate
                << " 1/s) is not well below the process's strain rate (largest prescribed speed / size = "
                << std::setprecision(3) << process_rate
                << " 1/s): where the metal deforms slower than it, the law is Newtonian; lower it";
        if (law_warning != warning.str())
          log << "  warning: " << warning.str() << std::endl;
        law_warning = warning.str();
      }
    const double start_viscosity = material.evaluate(reference_rate).eta;
    incompressibility.set_process_rate(reference_rate);
    velocity.reinit(dof_handler.n_dofs());
    constraints.distribute(velocity);
    if (material.is_newtonian())
      {
        // The law is the Newtonian problem: the nonlinear solver's first
        // step solves it.
        incompressibility.set_viscosity_scale(start_viscosity);
        contact.set_scales(start_viscosity, material.penalty_factor * start_viscosity, prescribed_speed);
        log << "  " << incompressibility.name() << " = " << incompressibility.factor() << " x viscosity "
            << start_viscosity << " = " << incompressibility.penalty() << " MPa s" << std::endl;
        incompressibility.uniform_cell_penalty(incompressibility.penalty());
        return;
      }

    Material newtonian = material;
    newtonian.set_newtonian(start_viscosity);
    FlowAssembler<dim> start(newtonian, nullptr);
    start.copy_loads(assembler);
    const double start_penalty = incompressibility.factor() * start_viscosity;
    contact.set_scales(start_viscosity, material.penalty_factor * start_viscosity, prescribed_speed);
    {
      dealii::TimerOutput::Scope scope(timer, "assembly");
      const FlowTerms<dim>       terms = incompressibility.start_terms(start_penalty, velocity);
      matrix_symmetric =
        system.assemble(start, velocity, terms, Linearization::picard, &system_matrix, system_rhs).symmetric;
    }
    Vector<double> update;
    solve(update, 0);
    velocity += update;
    ++start_solves;
    // The process's strain rate for the penalty's bound: the root mean
    // square of the start's rate (where the metal deforms), not below the
    // speed over the domain's size (a long land or container makes that far
    // slower than the die's, and the bound 1e10 x the viscosity there far
    // above the deforming metal's).
    incompressibility.set_process_rate(std::max(process_rate_estimate(dof_handler, velocity), reference_rate));
    const double mean_viscosity = assembler.mean_viscosity(dof_handler, velocity);
    incompressibility.finish_start(start_penalty, mean_viscosity, velocity);
    contact.set_scales(mean_viscosity, material.penalty_factor * mean_viscosity, prescribed_speed);
    contact_states_valid = true;
    log << "  Newtonian start: eta = " << std::setprecision(4) << start_viscosity << " MPa s; "
        << incompressibility.name() << " = " << incompressibility.factor() << " x mean viscosity " << mean_viscosity
        << (incompressibility.penalty_bounded() ? ", at most " + deck_number(Material::largest_penalty_factor) +
                                                    " x the viscosity at the process's strain rate" :
                                                  std::string())
        << " = " << incompressibility.penalty() << " MPa s" << std::endl;
  }

#define DIEFLOW_INSTANTIATE(dim)                                                                                       \
  template StateChanges DieFlowProblem<dim>::update_state(Vector<double> &);                                           \
  template double       DieFlowProblem<dim>::assemble_system(const Vector<double> &, const Linearization);              \
  template double       DieFlowProblem<dim>::residual(const Vector<double> &, Vector<double> &);                       \
  template bool         DieFlowProblem<dim>::reassemble_penalty_form(const Vector<double> &,                          \
                                                             const Linearization,                                      \
                                                             const FlowTerms<dim> &);                                  \
  template void         DieFlowProblem<dim>::solve(Vector<double> &, const double);                                    \
  template void         DieFlowProblem<dim>::set_trial_step(const double);                                             \
  template void         DieFlowProblem<dim>::accept_step(const Vector<double> &,                                       \
                                                 const Vector<double> &,                                               \
                                                 const double,                                                         \
                                                 const Linearization);                                                 \
  template bool         DieFlowProblem<dim>::is_linear() const;                                                        \
  template double       DieFlowProblem<dim>::residual_floor() const;                                                   \
  template bool         DieFlowProblem<dim>::constraints_settled();                                              \
  template std::vector<std::string> DieFlowProblem<dim>::contact_changes() const;                                      \
  template std::vector<std::string> DieFlowProblem<dim>::law_changes() const;                                          \
  template void                     DieFlowProblem<dim>::newtonian_start();

  DIEFLOW_INSTANTIATE(2)
  DIEFLOW_INSTANTIATE(3)
#undef DIEFLOW_INSTANTIATE
} // namespace dieflow
