// The die-flow problem's run: the cycles (refinement cycles, or steps in time), each solved, reported and judged.
#include <dieflow/base/processes.h>
#include <dieflow/base/atomic_file.h>
#include <dieflow/base/interrupt.h>
#include <dieflow/base/threads.h>
#include <dieflow/postprocess/cycle_guards.h>
#include <dieflow/problem/problem.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <iomanip>
#include <limits>
#include <sstream>

namespace dieflow
{
  namespace
  {
    /// ", N partial steps" where there were any (the log stays as it was otherwise).
    std::string
    partial_steps_text(const unsigned int n)
    {
      return n == 0 ? "" : ", " + std::to_string(n) + " partial steps";
    }
  } // namespace



  template <int dim>
  RunSummary
  DieFlowProblem<dim>::run()
  {
    dealii::Timer      run_timer;
    RunSummary         summary;
    const unsigned int first = start_run(summary);
    for (unsigned int cycle = first; cycle < n_cycles(); ++cycle)
      {
        dealii::Timer cycle_timer;
        if (cycle > 0 && interrupt::requested())
          {
            stop_between_cycles(cycle, first, summary);
            break;
          }
        incremental.current_step = cycle;
        if (cycle > 0)
          next_mesh(cycle);
        setup_system();
        CycleSummary cycle_summary;
        cycle_summary.cycle    = cycle;
        NonlinearResult result = solve_cycle(cycle, cycle_summary);
        report_cycle(cycle_summary, result, summary);
        cycle_summary.wall_time = cycle_timer.wall_time();
        if (!record_cycle(cycle_summary, result, summary, run_timer.wall_time()))
          break;
      }
    finish_run(summary, run_timer.wall_time());
    return summary;
  }



  template <int dim>
  unsigned int
  DieFlowProblem<dim>::n_cycles() const
  {
    // Steady: the refinement cycles. Incremental: a solve at t_0, ..., t_N.
    return parameters.time_stepping.incremental ? parameters.time_stepping.n_steps() + 1 : parameters.refinement.cycles;
  }



  template <int dim>
  unsigned int
  DieFlowProblem<dim>::start_run(RunSummary &summary)
  {
    summary.velocity_degree = fe.degree;
    summary.geometry        = dim == 3 ? "3d" : geometry_name(parameters.coordinates.kind());
    const bool in_time      = parameters.time_stepping.incremental;
    summary.problem         = in_time ? "incremental" : "steady";
    unsigned int first      = 0;
    if (in_time && !parameters.checkpoint.restart_from.empty())
      first = load_checkpoint(summary) + 1;
    else if (in_time)
      incremental.initialize(triangulation,
                             parameters.goal_part(),
                             parameters.boundary_conditions.wall_ids(),
                             parameters.contact.die_ids,
                             die_surfaces,
                             parameters.boundary_conditions.traction_free_ids);
    // The deck's warnings: on the log and in summary.json.
    const auto warn = [&](const std::string &warning) {
      log << "  warning: " << warning << std::endl;
      summary.warnings.push_back(warning);
    };
    if (parameters.material.deck_penalty_factor > parameters.material.penalty_factor)
      warn("Material/Penalty factor = " + deck_number(parameters.material.deck_penalty_factor) +
           " is beyond double precision (round-off of about 1e-16 x factor in the reactions, "
           "more than the 1/factor it changes): solved at " +
           deck_number(parameters.material.penalty_factor));
    if (const std::string warning = parameters.contact.unused_friction_warning(); !warning.empty())
      warn(warning);
    if constexpr (dim == 2)
      if (parameters.free_surface.enabled())
        free_surface.initialize(triangulation, parameters.contact.die_ids, parameters.free_surface,
                                parameters.coordinates);
    return first;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::stop_between_cycles(const unsigned int cycle, const unsigned int first, RunSummary &summary)
  {
    const bool        in_time = parameters.time_stepping.incremental;
    const std::string unit    = in_time ? "step " : "cycle ";
    // Between two steps the state is a converged step's: the place to go on from.
    if (in_time && cycle > first && (summary.checkpoint_file.empty() || summary.checkpoint_step + 1 != cycle))
      save_checkpoint(cycle - 1, summary);
    summary.interrupted = true;
    summary.failure     = "stopped by " + interrupt::signal_name() + " before " + unit + std::to_string(cycle);
    log << "  INTERRUPTED before " << unit << cycle << std::endl;
  }



  template <int dim>
  bool
  DieFlowProblem<dim>::record_cycle(CycleSummary &         cycle_summary,
                                    const NonlinearResult &result,
                                    RunSummary &           summary,
                                    const double           wall_time)
  {
    const bool         in_time = parameters.time_stepping.incremental;
    const unsigned int cycle   = cycle_summary.cycle;
    // A cycle that did not converge is no member of the mesh study: its
    // values would enter the extrapolation of the cycles before it.
    if (!in_time && result.converged)
      {
        study.add(cycle_summary);
        if (cycle > 0)
          for (const auto &[name, e] : study.extrapolations())
            cycle_summary.estimated_errors.emplace_back(name, e.estimate);
      }
    summary.cycles.push_back(cycle_summary);
    if (in_time)
      write_load_stroke(summary);

    if (!result.converged)
      {
        summary.interrupted = result.interrupted;
        summary.failure     = (in_time ? "step " : "cycle ") + std::to_string(cycle) + ": " + result.failure;
        log << "  NOT CONVERGED: " << result.failure << std::endl;
        return false;
      }
    log << "  converged: " << result.iterations << " iterations, " << cycle_summary.linear_solves
        << " linear solves, divergence ratio " << std::scientific << std::setprecision(2)
        << cycle_summary.divergence_ratio << std::defaultfloat << std::endl;
    if (incompressibility.iterative())
      log << "  iterative linear solver: " << linear_solver.counts.iterative_solves << " solves, "
          << linear_solver.counts.krylov_iterations << " Krylov iterations, " << linear_solver.counts.direct_fallbacks
          << " direct fallbacks" << partial_steps_text(linear_solver.counts.partial_steps) << std::endl;
    if (in_time && parameters.checkpoint.due(cycle, parameters.time_stepping.n_steps()))
      save_checkpoint(cycle, summary);
    summary.wall_time = wall_time;
    write_summary_json(summary, parameters.run.output_directory + "/summary.json");
    return !(parameters.refinement.target_error > 0 && stop_at_target(summary));
  }



  template <int dim>
  void
  DieFlowProblem<dim>::next_mesh(const unsigned int cycle)
  {
    if (!parameters.time_stepping.incremental)
      refine_mesh();
    else
      {
        advance_configuration(cycle - 1);
        const double jacobian = smallest_scaled_jacobian(triangulation);
        const auto & remeshing = parameters.remeshing;
        if (remeshing.enabled() &&
            remeshing.due(jacobian,
                          ++incremental.steps_since_remesh,
                          incremental.last_remesh ? incremental.last_remesh->jacobian_after : 1.))
          remesh(cycle, jacobian);
        // Without new meshes the run would go on with cells turned inside
        // out, and forces of no meaning
        // (doc/benchmarks.md, "Figures behind the code's rules"). A corner a
        // little past straight (a cell squeezed to a triangle where a side
        // folds onto a platen, a fold's round-off) leaves every quadrature
        // point's Jacobian positive: the run goes on.
        if (!remeshing.enabled() && !(jacobian > -0.1))
          {
            std::ostringstream where;
            where << std::setprecision(3) << "the move to step " << cycle
                  << " turned cells inside out (smallest scaled Jacobian " << jacobian << ", the cell at "
                  << worst_cell_centre(triangulation)
                  << "); set it (about 0.2-0.3) for new meshes when cells degrade (2D), or lower "
                     "Incremental/Time step";
            throw InputError("Incremental/Remesh below Jacobian: " + where.str());
          }
      }
    states_from_previous_mesh = true;
  }



  template <int dim>
  NonlinearResult
  DieFlowProblem<dim>::solve_cycle(const unsigned int cycle, CycleSummary &cycle_summary)
  {
    const bool in_time = parameters.time_stepping.incremental;
    log << (in_time ? "step " : "cycle ") << cycle << ": ";
    if (in_time)
      log << "t = " << parameters.time_stepping.time(cycle) << " s, ";
    log << triangulation.n_active_cells() << " cells, " << dof_handler.n_dofs() << " dofs" << std::endl;
    start_solves = 0;
    system.reset_counts();
    linear_solver.counts = LinearSolverCounts();
    NonlinearResult result;
    Vector<double>  start;
    try
      {
        if (cycle == 0)
          newtonian_start();
        // A hardening law's first flow: at the strain of the Newtonian start's (not of the metal entering).
        // (A Newtonian law has no start: the velocity is zero inside.)
        if (cycle == 0 && parameters.steady_strain() && parameters.material.hardens() && !parameters.material.is_newtonian())
          {
            strain.solve(dof_handler, velocity);
            strain.update_flow_hardening();
          }
        assembler.update_dual(dof_handler, velocity, nullptr, 0);
        start = velocity;
        constraints.distribute(start);
        result = continue_in_friction(start, parameters.nonlinear_solver.solve(*this, velocity, log), cycle_summary);
        if (parameters.free_surface.enabled() && result.converged)
          result = settle_free_surface(result, cycle_summary);
        if ((parameters.heat.model == HeatParameters::Model::steady || parameters.steady_strain() ||
             (in_time && parameters.heat.step_coupling == HeatParameters::StepCoupling::trapezoid)) &&
            result.converged)
          result = couple_fields(result, cycle_summary);
      }
    catch (const SolverFailure &failure)
      {
        result.failure = std::string(failure.what()) + " for the Newtonian start";
      }
    cycle_summary.converged            = result.converged;
    cycle_summary.nonlinear_iterations = result.iterations;
    cycle_summary.linear_solves        = result.linear_solves + start_solves;
    cycle_summary.linear_method        = incompressibility.iterative() ? "iterative" : "direct";
    cycle_summary.incompressibility    = incompressibility.form_name();
    cycle_summary.linear_counts        = linear_solver.counts;
    cycle_summary.history              = result.history;
    if (start.size() == velocity.size() && velocity.l2_norm() > 0)
      {
        start -= velocity;
        cycle_summary.start_distance = start.l2_norm() / velocity.l2_norm();
      }
    return result;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::report_cycle(CycleSummary &cycle_summary, NonlinearResult &result, RunSummary &summary)
  {
    const bool in_time = parameters.time_stepping.incremental;
    if (in_time)
      cycle_summary.step = incremental.step_record(cycle_summary.cycle,
                                                   ram_stroke(parameters.time_stepping.time(cycle_summary.cycle)),
                                                   triangulation);
    cycle_summary.contact_assemblies = system.counts().contact_assemblies;
    cycle_summary.friction_terms     = system.counts().friction_terms;
    {
      dealii::TimerOutput::Scope scope(timer, "postprocess");
      const bool                 write_fields = (parameters.run.write_vtu || parameters.run.write_gnuplot) &&
                                (!in_time || parameters.time_stepping.writes_output(cycle_summary.cycle));
      report.report(solution_view(),
                    write_fields,
                    in_time ? parameters.time_stepping.time(cycle_summary.cycle) : cycle_summary.cycle,
                    cycle_summary);
    }
    if (!law_warning.empty() &&
        std::find(summary.warnings.begin(), summary.warnings.end(), law_warning) == summary.warnings.end())
      summary.warnings.push_back(law_warning);
    const auto fail = [&](const GuardVerdict &verdict) {
      if (!verdict.warning.empty())
        {
          summary.warnings.push_back("cycle " + std::to_string(cycle_summary.cycle) + ": " + verdict.warning);
          log << "  warning: " << verdict.warning << std::endl;
        }
      if (verdict.failure.empty())
        return;
      cycle_summary.converged = false;
      result.converged        = false;
      result.failure          = verdict.failure;
    };
    const bool     augmented = incompressibility.form() == Incompressibility<dim>::Form::augmented_lagrangian;
    const MassHold hold      = !augmented                         ? MassHold::penalty :
                               incompressibility.uzawa_stalled() ? MassHold::uzawa_stalled :
                                                                   MassHold::uzawa;
    if (result.converged)
      fail(guard_mass_balance(cycle_summary,
                              parameters.nonlinear_solver.mass_balance_tolerance,
                              incompressibility.factor(),
                              hold,
                              parameters.linear_solver.divergence_tolerance));
    if (result.converged)
      fail(guard_contact(cycle_summary, dim, parameters.contact, contact_changes()));
  }



  template <int dim>
  void
  DieFlowProblem<dim>::finish_run(RunSummary &summary, const double wall_time)
  {
    summary.converged = summary.failure.empty();
    summary.wall_time = wall_time;
    for (const auto &[name, e] : study.extrapolations())
      {
        QuantityEstimate q;
        q.name                = name;
        q.extrapolated        = e.value;
        q.extrapolation_error = e.error;
        q.order               = e.order;
        q.estimate            = e.estimate;
        q.last                = named_value(std::find_if(summary.cycles.rbegin(), summary.cycles.rend(),
                                           [](const CycleSummary &c) { return c.converged; })->quantities,
                                              name);
        summary.extrapolated.push_back(q);
      }
    if (!parameters.time_stepping.incremental)
      {
        AtomicFile table(parameters.run.output_directory + "/study.txt");
        study.write(table.stream());
        table.commit();
        if (parameters.refinement.cycles > 1)
          study.write(log);
      }
    summary.stage_wall_time = timer.get_summary_data(dealii::TimerOutput::total_wall_time);
    dealii::Utilities::System::MemoryStats memory;
    dealii::Utilities::System::get_memory_stats(memory);
    summary.peak_memory_mb = memory.VmHWM / 1024.;
    if (processes::n() > 1)
      summary.peak_memory_mb = dealii::Utilities::MPI::max(summary.peak_memory_mb, processes::communicator());
    summary.processes      = processes::n();
    summary.threads        = threads::running();
    write_summary_json(summary, parameters.run.output_directory + "/summary.json");

    write_result_summary(summary, log);
    log << "wall time " << std::fixed << std::setprecision(3) << summary.wall_time << " s:";
    for (const auto &[stage, seconds] : summary.stage_wall_time)
      log << ' ' << stage << ' ' << seconds;
    log << "; peak memory " << std::setprecision(1) << summary.peak_memory_mb << " MB"
        << (summary.processes > 1 ? " (the largest process's); " + std::to_string(summary.processes) + " processes of " : "; ")
        << summary.threads << (summary.threads == 1 ? " thread" : " threads") << std::defaultfloat << std::setprecision(6)
        << std::endl;
  }

#define DIEFLOW_INSTANTIATE(dim)                                                                                       \
  template RunSummary      DieFlowProblem<dim>::run();                                                                 \
  template unsigned int    DieFlowProblem<dim>::n_cycles() const;                                                      \
  template unsigned int    DieFlowProblem<dim>::start_run(RunSummary &);                                               \
  template void            DieFlowProblem<dim>::stop_between_cycles(const unsigned int, const unsigned int, RunSummary &); \
  template bool DieFlowProblem<dim>::record_cycle(CycleSummary &, const NonlinearResult &, RunSummary &, const double); \
  template void            DieFlowProblem<dim>::next_mesh(const unsigned int);                                         \
  template NonlinearResult DieFlowProblem<dim>::solve_cycle(const unsigned int, CycleSummary &);                       \
  template void            DieFlowProblem<dim>::report_cycle(CycleSummary &, NonlinearResult &, RunSummary &);         \
  template void            DieFlowProblem<dim>::finish_run(RunSummary &, const double);

  DIEFLOW_INSTANTIATE(2)
  DIEFLOW_INSTANTIATE(3)
#undef DIEFLOW_INSTANTIATE
} // namespace dieflow
