#include <dieflow/incremental/checkpoint.h>
#include <dieflow/postprocess/atomic_file.h>
#include <dieflow/problem.h>

#include <boost/archive/binary_iarchive.hpp>
#include <boost/archive/binary_oarchive.hpp>
#include <boost/serialization/map.hpp>
#include <boost/serialization/set.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <filesystem>
#include <fstream>

namespace dieflow
{
  void
  CheckpointParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Checkpoint interval",
                      "10",
                      dealii::Patterns::Integer(0),
                      "Write the state of the run to Output directory/checkpoint.dat "
                      "(replacing the last one) every this many steps, at the last step, "
                      "and when SIGINT or SIGTERM stops the run between steps; 0: only "
                      "at the last step and when stopped. Restart from goes on from it.");
    prm.declare_entry("Restart from",
                      "",
                      dealii::Patterns::Anything(),
                      "A checkpoint.dat of an earlier run of this deck (relative to the "
                      "deck's folder): the run goes on from its step to End time, to the "
                      "same result as a run that was not stopped. The deck must give the "
                      "same Time step (End time may be later). Empty: start at t = 0.");
  }



  void
  CheckpointParameters::parse_parameters(ParameterHandler &prm, const std::string &deck_directory)
  {
    interval     = prm.get_integer("Checkpoint interval");
    restart_from = prm.get("Restart from");
    if (!restart_from.empty() && std::filesystem::path(restart_from).is_relative() && !deck_directory.empty())
      restart_from = (std::filesystem::path(deck_directory) / restart_from).string();
  }



  namespace
  {
    constexpr const char *checkpoint_format = "dieflow incremental checkpoint 2";

    /// Saves or loads a vector: its size, then @p item(x) for each element x.
    template <class Archive, typename T, typename Item>
    void
    serialize_each(Archive &ar, std::vector<T> &items, const Item &item)
    {
      std::size_t n = items.size();
      ar &n;
      items.resize(n);
      for (auto &x : items)
        item(x);
    }

    template <int dim, class Archive>
    void
    serialize_facets(Archive &ar, std::vector<typename DieSurface<dim>::Facet> &facets)
    {
      serialize_each(ar, facets, [&](auto &facet) {
        for (auto &vertex : facet.vertices)
          ar &vertex;
        ar &facet.normal;
      });
    }

    template <int dim, class Archive>
    void
    serialize_dies(Archive &ar, std::map<BoundaryId, std::vector<typename DieSurface<dim>::Facet>> &dies)
    {
      std::size_t n = dies.size();
      ar &n;
      auto it = dies.begin();
      for (std::size_t i = 0; i < n; ++i)
        {
          BoundaryId id = Archive::is_saving::value ? it->first : 0;
          ar &id;
          serialize_facets<dim>(ar, dies[id]);
          if (Archive::is_saving::value)
            ++it;
        }
    }

    template <int dim, class Archive>
    void
    serialize_states(Archive &ar, std::vector<typename ContactSet<dim>::StateRecord> &records)
    {
      serialize_each(ar, records, [&](auto &r) {
        int status = static_cast<int>(r.status);
        ar &r.position &r.id &r.normal &r.weight &r.active &status &r.slip_direction &r.normal_force;
        r.status = static_cast<ContactStatus>(status);
      });
    }

    /// The dies where they are, the faces' ids before a die, the free ids, the tolerance.
    template <int dim, class Archive>
    void
    serialize_gaps(Archive &ar, typename ContactGaps<dim>::State &state)
    {
      serialize_dies<dim>(ar, state.dies);
      ar &state.id_before &state.free_ids &state.tolerance;
    }

    template <class Archive>
    void
    serialize_step(Archive &ar, StepRecord &s)
    {
      ar &s.step &s.time &s.stroke &s.volume &s.volume_change &s.smallest_scaled_jacobian &s.faces_entered
        &s.faces_left &s.penetration &s.mean_strain &s.max_strain;
      bool remeshed = s.remesh.has_value();
      ar &remeshed;
      if (remeshed && !s.remesh)
        s.remesh.emplace();
      if (remeshed)
        ar &s.remesh->step &s.remesh->cells_before &s.remesh->cells_after &s.remesh->jacobian_before
          &s.remesh->jacobian_after &s.remesh->volume_change &s.remesh->split_edges &s.remesh->dropped_vertices;
    }
  } // namespace



  template <int dim>
  void
  DieFlowProblem<dim>::save_checkpoint(const unsigned int n, RunSummary &summary) const
  {
    const std::string file = run_parameters.output_directory + "/checkpoint.dat";
    AtomicFile        out(file);
    {
      boost::archive::binary_oarchive ar(out.stream());
      std::string  format = checkpoint_format;
      unsigned int d = dim, degree = fe.degree, step = n;
      double       time = time_stepping.time(n), dt = time_stepping.time_step;
      ar << format << d << degree << step << time << dt;
      triangulation.save(ar, 0);
      ar << velocity << previous_velocity << equivalent_strain << previous_strain_rate;
      double displacement = ram_displacement();
      ar << mean_viscosity << initial_volume << displacement;
      ar << last_gap_update.entered << last_gap_update.left << last_gap_update.penetration << steps_since_remesh;
      StepRecord last;
      last.remesh = last_remesh;
      serialize_step(ar, last);

      typename ContactGaps<dim>::State gap_state = gaps.state();
      serialize_gaps<dim>(ar, gap_state);
      std::map<BoundaryId, std::vector<typename DieSurface<dim>::Facet>> surfaces;
      for (const auto &[id, surface] : die_surfaces)
        surfaces[id] = surface.all_facets();
      serialize_dies<dim>(ar, surfaces);
      std::vector<typename ContactSet<dim>::StateRecord> states = contact.state_records();
      serialize_states<dim>(ar, states);
      ar << fixed_walls.all_planes();

      ar << pvd_records;
      std::vector<StepRecord> steps = summary.earlier_steps;
      for (const auto &cycle : summary.cycles)
        steps.push_back(*cycle.step);
      serialize_each(ar, steps, [&](StepRecord &step) { serialize_step(ar, step); });
      const std::string rows = earlier_load_stroke + load_stroke_rows(summary);
      ar << rows;
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
    const std::string  entry = "Incremental/Restart from";
    const std::string &file  = checkpoint.restart_from;
    std::ifstream      in(file, std::ios::binary);
    require(in.good(), entry, "cannot read '" + file + "'");
    unsigned int n = 0;
    try
      {
        boost::archive::binary_iarchive ar(in);
        std::string  format;
        unsigned int d = 0, degree = 0;
        double       time = 0, dt = 0;
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
        ar >> velocity >> previous_velocity >> equivalent_strain >> previous_strain_rate;
        double displacement = 0;
        ar >> mean_viscosity >> initial_volume >> displacement;
        ar >> last_gap_update.entered >> last_gap_update.left >> last_gap_update.penetration >> steps_since_remesh;
        StepRecord last;
        serialize_step(ar, last);
        last_remesh = last.remesh;

        typename ContactGaps<dim>::State gap_state;
        serialize_gaps<dim>(ar, gap_state);
        gaps.restore(gap_state);
        std::map<BoundaryId, std::vector<typename DieSurface<dim>::Facet>> surfaces;
        serialize_dies<dim>(ar, surfaces);
        for (const auto &[id, facets] : surfaces)
          die_surfaces[id].set_facets(facets);
        std::vector<typename ContactSet<dim>::StateRecord> states;
        serialize_states<dim>(ar, states);
        contact.restore_states(states);
        typename FixedWalls<dim>::Planes planes;
        ar >> planes;
        fixed_walls.set_planes(planes);

        ar >> pvd_records;
        serialize_each(ar, summary.earlier_steps, [&](StepRecord &step) { serialize_step(ar, step); });
        ar >> earlier_load_stroke;
        ram_offset = displacement;
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
    require(velocity.size() == dof_handler.n_dofs() && equivalent_strain.size() == triangulation.n_active_cells(),
            entry,
            "'" + file + "' does not hold the fields of its mesh");

    record_ram_start();
    update_hardening();
    contact.set_scales(mean_viscosity, material.penalty_factor * mean_viscosity);
    contact_states_valid = true;
    prescribed_speed     = boundary_conditions.largest_prescribed_speed(dof_handler);
    // The contact set of step n, its states restored: the move to step n + 1
    // keeps the nodes in contact on their die (ContactSet::vertex_status()).
    current_step = n;
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
