// The die-flow problem's refinement cycles: the next mesh from the indicators, and when a target error stops them.
#include <dieflow/flow/pressure_projection.h>
#include <dieflow/mesh/refinement.h>
#include <dieflow/mesh/whole_mesh.h>
#include <dieflow/postprocess/contact_output.h>
#include <dieflow/postprocess/goal_estimate.h>
#include <dieflow/problem/problem.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/numerics/solution_transfer.h>

#include <iomanip>
#include <limits>

namespace dieflow
{
  template <int dim>
  void
  DieFlowProblem<dim>::refine_mesh()
  {
    dealii::TimerOutput::Scope  scope(timer, "refinement");
    const RefinementParameters &refinement = parameters.refinement;
    if (refinement.strategy == RefinementParameters::Strategy::global)
      triangulation.set_all_refine_flags();
    else
      {
        DieFeatures<dim> die;
        die.ids = parameters.contact.die_ids;
        if (!contact.empty())
          die.hot_points = contact_hot_points(contact, contact.results(velocity));
        mark_cells(refinement,
                   refinement.indicator == RefinementParameters::Indicator::dual_weighted ?
                     goal_indicators(dof_handler, velocity, ram_force_dual()) :
                     refinement_indicators(refinement, dof_handler, velocity, die),
                   triangulation);
      }
    // The cell stress q + lambda div v (q = 0 without the augmented
    // Lagrangian) goes along as a piecewise constant: the next mesh's first
    // multiplier, if the iterative method may solve there.
    const bool carry_stress = parameters.linear_solver.method != LinearSolverParameters::Method::direct;
    const dealii::FE_DGQ<dim>                    cell_fe(0);
    DoFHandler<dim>                              cell_dofs(triangulation);
    Vector<double>                               cell_values;
    std::vector<dealii::types::global_dof_index> index(1);
    if (carry_stress)
      {
        cell_dofs.distribute_dofs(cell_fe);
        cell_values.reinit(cell_dofs.n_dofs());
        const Vector<double> pressure = incompressibility.cell_pressures(velocity);
        const unsigned int   n_modes  = PressureProjection<dim>::n_modes_for(fe);
        for (const auto &cell : cell_dofs.active_cell_iterators())
          {
            cell->get_dof_indices(index);
            cell_values[index[0]] = -pressure[cell->active_cell_index() * n_modes];
          }
      }

    dealii::SolutionTransfer<dim, Vector<double>> transfer(dof_handler), cell_transfer(cell_dofs);
    triangulation.prepare_coarsening_and_refinement();
    transfer.prepare_for_coarsening_and_refinement(velocity);
    if (parameters.heat.enabled())
      heat.prepare_refinement();
    if (parameters.steady_strain())
      strain.prepare_refinement();
    if (carry_stress)
      cell_transfer.prepare_for_coarsening_and_refinement(cell_values);
    triangulation.execute_coarsening_and_refinement();
    // (numbered as setup_system() will number them again)
    processes::distribute_dofs(dof_handler, fe);
    Vector<double> transferred(dof_handler.n_dofs());
    transfer.interpolate(velocity, transferred);
    velocity = transferred;
    if (parameters.heat.enabled())
      heat.finish_refinement();
    if (parameters.steady_strain())
      strain.finish_refinement();

    Vector<double> carried;
    if (carry_stress)
      {
        cell_dofs.distribute_dofs(cell_fe);
        Vector<double> new_cell_values(cell_dofs.n_dofs());
        cell_transfer.interpolate(cell_values, new_cell_values);
        carried.reinit(triangulation.n_active_cells());
        for (const auto &cell : cell_dofs.active_cell_iterators())
          {
            cell->get_dof_indices(index);
            carried[cell->active_cell_index()] = new_cell_values[index[0]];
          }
      }
    incompressibility.carry(carried);
  }



  template <int dim>
  Vector<double>
  DieFlowProblem<dim>::ram_force_dual()
  {
    // One more solve with the last Newton step's factorisation (transposed),
    // or with a new one when the cycle needed no linear solve.
    if (!linear_solver.has_factorisation())
      {
        matrix_symmetric =
          system.assemble(velocity, flow_terms(), Linearization::newton, &system_matrix, system_rhs).symmetric;
        linear_solver.factorize(system_matrix, matrix_symmetric);
      }
    // The flow Jacobian's transpose product reads every row: on P > 1 a
    // pattern of all rows for it (the system's holds a process's own).
    dealii::SparsityPattern all_rows;
    if (processes::n() > 1)
      {
        dealii::DynamicSparsityPattern dsp(dof_handler.n_dofs());
        whole_mesh::make_sparsity_pattern(dof_handler, dsp, hanging_node_constraints);
        all_rows.copy_from(dsp);
      }
    return force_dual(dof_handler,
                      hanging_node_constraints,
                      update_constraints,
                      processes::n() > 1 ? all_rows : sparsity_pattern,
                      velocity,
                      assembler,
                      flow_terms(),
                      contact,
                      force_direction(dof_handler, hanging_node_constraints, parameters.goal_part()),
                      [this](Vector<double> &b) {
                        Vector<double> x;
                        linear_solver.solve(b, x, true);
                        b = x;
                      });
  }



  template <int dim>
  bool
  DieFlowProblem<dim>::stop_at_target(RunSummary &summary) const
  {
    const RefinementParameters &refinement = parameters.refinement;
    const CycleSummary &        last       = summary.cycles.back();
    summary.target_quantity                = refinement.target_quantity;
    summary.target_error                   = refinement.target_error;
    summary.target_reached                 = false;
    const double value = named_value(last.quantities, refinement.target_quantity);
    const double estimate =
      named_value(last.estimated_errors, refinement.target_quantity, std::numeric_limits<double>::infinity());
    // The estimate needs three cycles (Extrapolation::estimate).
    if (last.cycle >= 2 && estimate <= refinement.target_error * std::abs(value))
      {
        summary.target_reached = true;
        log << "  target error reached: " << refinement.target_quantity << " = " << std::setprecision(6) << value
            << " +- " << std::setprecision(2) << estimate << std::endl;
        return true;
      }
    // Near Maximum cells the marking refines fewer and fewer cells: stop
    // once a cycle has added less than a tenth.
    const bool at_limit =
      refinement.maximum_cells > 0 &&
      (last.cells >= refinement.maximum_cells ||
       (summary.cycles.size() > 1 && last.cells < 1.1 * summary.cycles[summary.cycles.size() - 2].cells));
    if (at_limit)
      {
        log << "  target error NOT reached: " << refinement.target_quantity << " = " << std::setprecision(6) << value
            << " +- " << std::setprecision(2) << estimate << " with " << triangulation.n_active_cells()
            << " cells, at Refinement/Maximum cells = " << refinement.maximum_cells << std::endl;
        return true;
      }
    if (last.cycle + 1 == refinement.cycles)
      log << "  target error NOT reached in Refinement/Cycles = " << refinement.cycles << " cycles: "
          << refinement.target_quantity << " = " << std::setprecision(6) << value << " +- " << std::setprecision(2)
          << estimate << std::endl;
    return false;
  }

#define DIEFLOW_INSTANTIATE(dim)                                                                                       \
  template void           DieFlowProblem<dim>::refine_mesh();                                                          \
  template Vector<double> DieFlowProblem<dim>::ram_force_dual();                                                       \
  template bool           DieFlowProblem<dim>::stop_at_target(RunSummary &) const;

  DIEFLOW_INSTANTIATE(2)
  DIEFLOW_INSTANTIATE(3)
#undef DIEFLOW_INSTANTIATE
} // namespace dieflow
