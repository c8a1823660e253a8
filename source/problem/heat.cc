// The die-flow problem's temperature: the heat equation and the flow solved in turn until the temperature settles.
#include <dieflow/problem/problem.h>

#include <algorithm>
#include <iomanip>

namespace dieflow
{
  template <int dim>
  NonlinearResult
  DieFlowProblem<dim>::couple_heat(NonlinearResult result, CycleSummary &cycle)
  {
    const HeatParameters &heat_parameters = parameters.heat;
    unsigned int          solves          = 0;
    bool                  settled         = false;
    while (result.converged)
      {
        // The friction work of each contact node, -F_t.v_slip (the metal's
        // friction force against its slip on the die).
        std::vector<std::pair<dealii::Point<dim>, double>> friction;
        if (!contact.empty())
          for (const auto &node : contact.results(velocity))
            if (node.status != ContactStatus::separated)
              friction.emplace_back(node.position, std::max(-(node.friction_force * node.slip_velocity), 0.));
        double change;
        {
          dealii::TimerOutput::Scope scope(timer, "heat");
          change = heat.solve(dof_handler, velocity, friction);
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

  template NonlinearResult DieFlowProblem<2>::couple_heat(NonlinearResult, CycleSummary &);
  template NonlinearResult DieFlowProblem<3>::couple_heat(NonlinearResult, CycleSummary &);
} // namespace dieflow
