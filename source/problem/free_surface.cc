// The die-flow problem's steady free surface: moved onto the streamlines of the solution and solved again until it settles.
#include <dieflow/mesh/mesh_motion.h>
#include <dieflow/problem/problem.h>

#include <iomanip>

namespace dieflow
{
  template <int dim>
  NonlinearResult
  DieFlowProblem<dim>::settle_free_surface(NonlinearResult result, CycleSummary &cycle)
  {
    if constexpr (dim == 2)
      {
        FreeSurfaceRecord record;
        free_surface.new_mesh();
        while (result.converged)
          {
            const bool      last = record.moves == parameters.free_surface.iterations;
            FreeSurfaceMove move;
            {
              dealii::TimerOutput::Scope scope(timer, "mesh motion");
              move = free_surface.move(triangulation, dof_handler, velocity, contact.results(velocity), !last);
            }
            record.largest_move  = move.largest;
            record.free_faces    = move.free_faces;
            record.grazing_faces = move.grazing_faces;
            record.grazing_flux  = move.grazing_flux;
            record.lines         = move.lines;
            log << "  free surface: largest move " << std::setprecision(3) << move.largest << " of its length"
                << (move.relaxation != 1 ? " (relaxed x " + deck_number(move.relaxation) + ")" : std::string())
                << (move.step > 0 && move.step < 1 ? " (a part " + deck_number(move.step) + " of it made)" : std::string())
                << ", " << move.free_faces << " free faces (" << move.let_go << " let go by the dies, "
                << move.reattached << " back on them";
            if (move.grazing_faces > 0)
              log << "; " << move.grazing_faces << " lie on a die, their flux into it " << move.grazing_flux;
            log << ")" << std::setprecision(6) << std::endl;
            record.settled = !move.changes(parameters.free_surface.tolerance);
            if (record.settled)
              break;
            if (last)
              {
                result.converged = false;
                result.failure   = "the free surface did not settle in " + std::to_string(record.moves) +
                                 " moves (the last would move a node " + deck_number(move.largest) +
                                 " of the free surface's length): raise Free surface/Iterations or Tolerance";
                break;
              }
            ++record.moves;
            require(smallest_scaled_jacobian(triangulation) > 0,
                    "Free surface/Iterations",
                    "the free surface's move tangled the mesh (a cell turned inside out): refine the mesh where the metal "
                    "leaves the die, or use Problem = incremental");
            states_from_previous_mesh = true;
            setup_system();
            NonlinearResult next = parameters.nonlinear_solver.solve(*this, velocity, log);
            next.iterations += result.iterations;
            next.linear_solves += result.linear_solves;
            result = next;
          }
        for (const FreeSurfaceLine &line : record.lines)
          log << "  free stretch: leaves id " << line.leaves << " at (" << line.points.front()[0] << ", "
              << line.points.front()[1] << "), ends on id " << line.ends << " at (" << line.points.back()[0] << ", "
              << line.points.back()[1] << ")" << std::endl;
        cycle.free_surface = record;
      }
    return result;
  }

  template NonlinearResult
  DieFlowProblem<2>::settle_free_surface(NonlinearResult, CycleSummary &);
  template NonlinearResult
  DieFlowProblem<3>::settle_free_surface(NonlinearResult, CycleSummary &);
} // namespace dieflow
