// The die-flow problem's temperature: steady, the heat equation and the flow solved in turn until T settles; in time, a heat step per time step.
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
    std::vector<std::pair<dealii::Point<dim>, double>>
    friction_work(const ContactSet<dim> &contact, const Vector<double> &velocity)
    {
      std::vector<std::pair<dealii::Point<dim>, double>> friction;
      if (!contact.empty())
        for (const auto &node : contact.results(velocity))
          if (node.status != ContactStatus::separated)
            friction.emplace_back(node.position, std::max(-(node.friction_force * node.slip_velocity), 0.));
      return friction;
    }
  } // namespace



  template <int dim>
  NonlinearResult
  DieFlowProblem<dim>::couple_heat(NonlinearResult result, CycleSummary &cycle)
  {
    const HeatParameters &heat_parameters = parameters.heat;
    unsigned int          solves          = 0;
    bool                  settled         = false;
    while (result.converged)
      {
        double change;
        {
          dealii::TimerOutput::Scope scope(timer, "heat");
          change = heat.solve(dof_handler, velocity, friction_work(contact, velocity));
        }
        ++solves;
        const HeatRecord &record = heat.record();
        // Against the temperature's range over the metal (or 1e-6 K where it is uniform).
        const double bound = std::max(heat_parameters.coupling_tolerance * heat.range(), 1e-6);
        settled            = change <= bound;
        log << "  heat " << solves << ": T " << std::fixed << std::setprecision(2) << record.T_min << " - "
            << record.T_max << " K, leaving at " << record.T_exit << " K; change " << std::scientific
            << std::setprecision(2) << change << " K (settled below " << bound << "), heat balance "
            << record.balance_error << std::defaultfloat << std::setprecision(6) << std::endl;
        if (settled)
          break;
        if (solves == heat_parameters.coupling_iterations)
          {
            result.converged = false;
            result.failure   = "the temperature and the flow did not settle in " + std::to_string(solves) +
                             " heat solves (the last changed T by " + deck_number(change) + " K, more than " +
                             deck_number(bound) + " K): raise Heat/Coupling iterations (it is " +
                             std::to_string(heat_parameters.coupling_iterations) + ") or Heat/Coupling tolerance";
            break;
          }
        // The flow at the new temperature, from the last velocity.
        heat.update_flow_temperatures();
        NonlinearResult next = parameters.nonlinear_solver.solve(*this, velocity, log);
        next.iterations += result.iterations;
        next.linear_solves += result.linear_solves;
        result = next;
        if (parameters.free_surface.enabled() && result.converged)
          result = settle_free_surface(result, cycle);
      }
    heat.record().solves  = solves;
    heat.record().settled = settled;
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
      heat.solve(dof_handler, velocity, friction_work(contact, velocity), dt);
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



  template NonlinearResult DieFlowProblem<2>::couple_heat(NonlinearResult, CycleSummary &);
  template NonlinearResult DieFlowProblem<3>::couple_heat(NonlinearResult, CycleSummary &);
  template void DieFlowProblem<2>::step_heat(const unsigned int);
  template void DieFlowProblem<3>::step_heat(const unsigned int);
} // namespace dieflow
