// The die-flow problem's temperature and strain: steady, the heat and strain equations and the flow solved in turn until they settle; in time, a heat step per time step.
#include <dieflow/problem/problem.h>

#include <algorithm>
#include <iomanip>

namespace dieflow
{
  namespace
  {
    /// Each contact node's position and friction work -F_t.v_slip (the
    /// metal's friction force against its slip on the die): the heat
    /// sources at the dies.
    template <int dim>
    std::vector<FrictionWork<dim>>
    friction_work(const ContactSet<dim> &contact, const Vector<double> &velocity)
    {
      std::vector<FrictionWork<dim>> friction;
      if (!contact.empty())
        for (const auto &node : contact.results(velocity))
          if (node.status != ContactStatus::separated)
            friction.push_back({node.position, std::max(-(node.friction_force * node.slip_velocity), 0.), node.id});
      return friction;
    }
  } // namespace



  template <int dim>
  NonlinearResult
  DieFlowProblem<dim>::couple_fields(NonlinearResult result, CycleSummary &cycle)
  {
    const HeatParameters &  heat_parameters   = parameters.heat;
    const StrainParameters &strain_parameters = parameters.strain;
    // In time (Step coupling = trapezoid): the step from t_n made again
    // with the flow of t_n+1, that flow solved again at its T, in turn.
    const bool in_time = heat_parameters.model == HeatParameters::Model::transient;
    const bool with_heat =
      heat_parameters.model == HeatParameters::Model::steady ||
      (in_time && heat_parameters.step_coupling == HeatParameters::StepCoupling::trapezoid && heat.can_correct());
    const double dt =
      in_time && cycle.cycle > 0 ? parameters.time_stepping.time(cycle.cycle) - parameters.time_stepping.time(cycle.cycle - 1) : 0.;
    const bool              with_strain       = parameters.steady_strain();
    // Without hardening the strain is read from the flow and changes nothing in it.
    const bool   hardening    = with_strain && parameters.material.hardens();
    unsigned int heat_solves = 0, strain_solves = 0;
    bool         heat_settled = !with_heat, strain_settled = !with_strain;
    while (result.converged)
      {
        double heat_change = 0, heat_bound = 0, strain_change = 0, strain_bound = 0;
        if (with_heat)
          {
            {
              dealii::TimerOutput::Scope scope(timer, "heat");
              heat_change = in_time ? heat.correct_step(dof_handler, velocity, friction_work(contact, velocity), dt,
                                                        incremental.hardening()) :
                                      heat.solve(dof_handler, velocity, friction_work(contact, velocity), 0, nullptr,
                                                 hardening ? strain.flow_hardening() : nullptr);
            }
            ++heat_solves;
            const HeatRecord &record = heat.record();
            // Against the temperature's range over the metal (or 1e-6 K where it is uniform).
            heat_bound   = std::max(heat_parameters.coupling_tolerance * heat.range(), 1e-6);
            heat_settled = heat_change <= heat_bound;
            log << "  heat " << (in_time ? "step again " : "") << heat_solves << ": T " << std::fixed << std::setprecision(2)
                << record.T_min << " - " << record.T_max << " K";
            if (!in_time)
              log << ", leaving at " << record.T_exit << " K";
            log << "; change " << std::scientific
                << std::setprecision(2) << heat_change << " K (settled below " << heat_bound << "), heat balance "
                << record.balance_error << std::defaultfloat << std::setprecision(6) << std::endl;
          }
        if (with_strain)
          {
            {
              dealii::TimerOutput::Scope scope(timer, "strain");
              strain_change = strain.solve(dof_handler, velocity, hardening);
            }
            ++strain_solves;
            const StrainRecord &record = strain.record();
            // Against eps's own root mean square (its range is a dead zone's
            // strain, which grows without bound in a steady flow).
            strain_bound   = std::max(strain_parameters.coupling_tolerance * strain.root_mean_square(), 1e-9);
            strain_settled = !hardening || strain_change <= strain_bound;
            log << "  strain " << strain_solves << ": eps leaving " << std::setprecision(5) << record.eps_exit
                << " (" << record.eps_exit_min << " - " << record.eps_exit_max << "), largest " << record.eps_max
                << "; change " << std::scientific << std::setprecision(2) << strain_change << " (settled below "
                << strain_bound << ")" << std::defaultfloat << std::setprecision(6) << std::endl;
          }
        if (heat_settled && strain_settled)
          break;
        if (!heat_settled && heat_solves == heat_parameters.coupling_iterations)
          {
            result.converged = false;
            result.failure   = "the temperature and the flow did not settle in " + std::to_string(heat_solves) +
                             " heat solves (the last changed T by " + deck_number(heat_change) + " K, more than " +
                             deck_number(heat_bound) + " K): raise Heat/Coupling iterations (it is " +
                             std::to_string(heat_parameters.coupling_iterations) + ") or Heat/Coupling tolerance";
            break;
          }
        if (!strain_settled && strain_solves == strain_parameters.coupling_iterations)
          {
            result.converged = false;
            result.failure   = "the strain hardening and the flow did not settle in " + std::to_string(strain_solves) +
                             " strain solves (the last changed eps by " + deck_number(strain_change) +
                             ", more than " + deck_number(strain_bound) +
                             "): raise Equivalent strain/Coupling iterations (it is " +
                             std::to_string(strain_parameters.coupling_iterations) +
                             ") or Equivalent strain/Coupling tolerance";
            break;
          }
        // The flow at the new temperature and hardening, from the last velocity.
        if (with_heat)
          heat.update_flow_temperatures();
        if (hardening)
          strain.update_flow_hardening();
        NonlinearResult next = parameters.nonlinear_solver.solve(*this, velocity, log);
        next.iterations += result.iterations;
        next.linear_solves += result.linear_solves;
        result = next;
        if (parameters.free_surface.enabled() && result.converged)
          result = settle_free_surface(result, cycle);
      }
    if (with_heat)
      heat.record().solves = heat_solves + (in_time ? 1 : 0), heat.record().settled = heat_settled;
    if (with_strain)
      strain.record().solves = strain_solves, strain.record().settled = strain_settled;
    return result;
  }

  template <int dim>
  void
  DieFlowProblem<dim>::step_heat(const unsigned int n)
  {
    // From t_n to t_{n+1} with the flow of t_n, on the mesh of t_n: the
    // mesh then moves, carrying T's nodal values with the metal, and the
    // flow of t_{n+1} takes T_{n+1} (a step behind in the sources, as the
    // mesh's move is with the velocity of t_n: first order in dt).
    const double dt = parameters.time_stepping.time(n + 1) - parameters.time_stepping.time(n);
    {
      dealii::TimerOutput::Scope scope(timer, "heat");
      heat.solve(dof_handler, velocity, friction_work(contact, velocity), dt, incremental.hardening());
      heat.update_flow_temperatures();
    }
    heat.record().solves  = 1;
    heat.record().settled = true;
    const HeatRecord &record = heat.record();
    log << "  heat to t = " << parameters.time_stepping.time(n + 1) << " s: T " << std::fixed << std::setprecision(2)
        << record.T_min << " - " << record.T_max << " K, mean " << record.T_mean << " K; heat balance "
        << std::scientific << std::setprecision(2) << record.balance_error << std::defaultfloat << std::setprecision(6)
        << std::endl;
  }



  template NonlinearResult DieFlowProblem<2>::couple_fields(NonlinearResult, CycleSummary &);
  template NonlinearResult DieFlowProblem<3>::couple_fields(NonlinearResult, CycleSummary &);
  template void DieFlowProblem<2>::step_heat(const unsigned int);
  template void DieFlowProblem<3>::step_heat(const unsigned int);
} // namespace dieflow
