// The die-flow problem's checkpoints: each piece of a run in time saves and loads itself, in one file.
#include <dieflow/base/atomic_file.h>
#include <dieflow/base/serialization.h>
#include <dieflow/problem/problem.h>

#include <fstream>

namespace dieflow
{
  namespace
  {
    constexpr const char *checkpoint_format = "dieflow incremental checkpoint 6";
  } // namespace



  template <int dim>
  void
  DieFlowProblem<dim>::save_checkpoint(const unsigned int n, RunSummary &summary) const
  {
    const std::string file = parameters.run.output_directory + "/checkpoint.dat";
    AtomicFile        out(file);
    {
      boost::archive::binary_oarchive ar(out.stream());
      std::string                     format = checkpoint_format;
      unsigned int                    d = dim, degree = fe.degree, step = n;
      double time = parameters.time_stepping.time(n), dt = parameters.time_stepping.time_step;
      ar << format << d << degree << step << time << dt;
      // The mesh (deal.II's serialisation: the moved vertices, the
      // boundary ids) and the solution on it; then each piece's state.
      triangulation.save(ar, 0);
      ar << velocity;
      incompressibility.save(ar);
      incremental.save(ar, triangulation);
      save_dies(ar, die_surfaces);
      contact.save(ar);
      report.save(ar);
      heat.save(ar);
      // The outputs' records so far: the steps, and load-stroke.txt's rows.
      std::vector<StepRecord> steps = summary.earlier_steps;
      for (const auto &cycle : summary.cycles)
        steps.push_back(*cycle.step);
      const std::string rows = incremental.earlier_load_stroke + load_stroke_rows(summary);
      ar << steps << rows;
    }
    out.commit();
    summary.checkpoint_file = file;
    summary.checkpoint_step = n;
    log << "  checkpoint of step " << n << ": " << file << std::endl;
  }



  template <int dim>
  unsigned int
  DieFlowProblem<dim>::load_checkpoint(RunSummary &summary)
  {
    const std::string   entry         = "Incremental/Restart from";
    const std::string & file          = parameters.checkpoint.restart_from;
    const TimeStepping &time_stepping = parameters.time_stepping;
    std::ifstream       in(file, std::ios::binary);
    require(in.good(), entry, "cannot read '" + file + "'");
    unsigned int n = 0;
    try
      {
        boost::archive::binary_iarchive ar(in);
        std::string                     format;
        unsigned int                    d = 0, degree = 0;
        double                          time = 0, dt = 0;
        ar >> format;
        require(format == checkpoint_format, entry, "'" + file + "' is no dieflow checkpoint");
        ar >> d >> degree >> n >> time >> dt;
        require(d == dim && degree == fe.degree,
                entry,
                "'" + file + "' is a checkpoint of a run with Dimension = " + std::to_string(d) +
                  " and Velocity degree = " + std::to_string(degree) + "; this deck has " + std::to_string(dim) +
                  " and " + std::to_string(fe.degree));
        require(std::abs(dt / time_stepping.time_step - 1) < 1e-12,
                "Incremental/Time step",
                "is " + deck_number(time_stepping.time_step) + " but the checkpoint's run (" + file + ") had " +
                  deck_number(dt) + ": a restart goes on with the same step");
        require(n < time_stepping.n_steps(),
                entry,
                "the checkpoint is of step " + std::to_string(n) + ", t = " + deck_number(time) +
                  " s; End time = " + deck_number(time_stepping.end_time) + " leaves no step after it");

        triangulation.load(ar, 0);
        dof_handler.reinit(triangulation);
        dof_handler.distribute_dofs(fe);
        ar >> velocity;
        incompressibility.load(ar);
        incremental.load(ar);
        load_dies(ar, die_surfaces);
        contact.load(ar);
        report.load(ar);
        heat.load(ar);
        ar >> summary.earlier_steps >> incremental.earlier_load_stroke;
      }
    catch (const InputError &)
      {
        throw;
      }
    catch (const std::exception &)
      {
        // A foreign or cut file: boost's archive or the string it reads fails.
        throw InputError(entry + ": '" + file + "' is no complete dieflow checkpoint");
      }
    require(velocity.size() == dof_handler.n_dofs() &&
              incremental.equivalent_strain.size() == triangulation.n_active_cells(),
            entry,
            "'" + file + "' does not hold the fields of its mesh");
    const bool heat_in_time = parameters.heat.model == HeatParameters::Model::transient;
    require(heat_in_time == heat.has_temperature(),
            "Heat/Model",
            heat_in_time ? "is transient but the checkpoint's run (" + file + ") had no temperature: a restart goes on with the same model" :
                           "is off but the checkpoint's run (" + file + ") had a temperature: set transient to go on with it");
    require(!heat_in_time || heat.temperature_fits(),
            "Heat/Degree",
            "differs from the checkpoint's run (" + file + "): its temperature is of another element");

    incremental.record_ram_start(triangulation, parameters.goal_part());
    const double eta = incompressibility.viscosity_scale();
    prescribed_speed     = parameters.boundary_conditions.largest_prescribed_speed(dof_handler);
    contact.set_scales(eta, parameters.material.penalty_factor * eta, prescribed_speed);
    contact_states_valid = true;
    // The contact set of step n, its states restored: the move to step n + 1
    // keeps the nodes in contact on their die (ContactSet::vertex_status()).
    incremental.current_step = n;
    setup_system();
    summary.restarted_from = file;
    summary.restart_step   = n;
    log << "restart from " << file << ": step " << n << ", t = " << time_stepping.time(n) << " s" << std::endl;
    return n;
  }

  template void
  DieFlowProblem<2>::save_checkpoint(const unsigned int, RunSummary &) const;
  template void
  DieFlowProblem<3>::save_checkpoint(const unsigned int, RunSummary &) const;
  template unsigned int
  DieFlowProblem<2>::load_checkpoint(RunSummary &);
  template unsigned int
  DieFlowProblem<3>::load_checkpoint(RunSummary &);
} // namespace dieflow
