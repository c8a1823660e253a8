// The report of a converged cycle: forces, fluxes, checks, errors, quantities of interest and the output files, from a read-only view of the solution.
#include <dieflow/base/atomic_file.h>
#include <dieflow/base/processes.h>
#include <dieflow/base/parameters.h>
#include <dieflow/base/serialization.h>
#include <dieflow/flow/pressure_projection.h>
#include <dieflow/mesh/refinement.h>
#include <dieflow/mesh/whole_mesh.h>
#include <dieflow/postprocess/contact_output.h>
#include <dieflow/postprocess/cycle_report.h>
#include <dieflow/postprocess/free_surface_output.h>
#include <dieflow/postprocess/goal_estimate.h>
#include <dieflow/postprocess/mass_balance.h>
#include <dieflow/postprocess/postprocess.h>
#include <dieflow/postprocess/vertex_stress.h>

#include <deal.II/grid/grid_out.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>

namespace dieflow
{
  namespace
  {
    /// Symmetry lines, slip walls and the dies without friction.
    template <int dim>
    std::set<BoundaryId>
    frictionless_walls(const SolutionView<dim> &view)
    {
      std::set<BoundaryId> ids = view.boundary_conditions.wall_ids();
      for (const BoundaryId id : view.contact.get_parameters().die_ids)
        if (view.contact.frictionless(id))
          ids.insert(id);
      return ids;
    }

    /// The dies' shares of the nodes they share with prescribed-velocity
    /// parts, into the die normal and friction forces of @p summary.
    template <int dim>
    void
    add_die_shares(const std::set<BoundaryId> &       die_ids,
                   const std::vector<WallShare<dim>> &shares,
                   const std::set<BoundaryId> &       frictionless,
                   CycleSummary &                     summary)
    {
      // The node belongs to the prescribed part, not to the contact set, but
      // the die carries its share of it: |f.n| and |f - (f.n) n|, as the
      // contact nodes' forces are counted.
      for (const auto &share : shares)
        if (die_ids.count(share.id) && share.normal.norm_square() > 0)
          {
            const double normal = share.force * share.normal;
            summary.die_normal_force[share.id] += std::abs(normal);
            if (!frictionless.count(share.id))
              summary.die_friction_force[share.id] += (share.force - normal * share.normal).norm();
          }
    }

    /// Volume per unit time through the parts other than the dies: the larger of inflow and outflow.
    double
    throughput(const std::set<BoundaryId> &die_ids, const std::map<BoundaryId, double> &flux)
    {
      // A ram pushes the metal in, a drawing pull takes it out through a
      // prescribed outlet while the inlet is free.
      double inflow = 0, outflow = 0;
      for (const auto &[id, q] : flux)
        if (!die_ids.count(id))
          (q < 0 ? inflow : outflow) += std::abs(q);
      return std::max(inflow, outflow);
    }
  } // namespace



  template <int dim>
  CycleReport<dim>::CycleReport(const ReportSettings<dim> &settings, std::ostream &log)
    : settings(settings)
    , log(log)
  {}



  template <int dim>
  void
  CycleReport<dim>::report(const SolutionView<dim> &view,
                           const bool               write_fields_now,
                           const double             record_time,
                           CycleSummary &           summary)
  {
    const auto &                dof_handler   = view.dof_handler;
    const auto &                triangulation = dof_handler.get_triangulation();
    const auto &                coordinates   = view.coordinates;
    const auto &                velocity      = view.velocity;
    const auto &                contact       = view.contact;
    const std::set<BoundaryId> &die_ids       = contact.get_parameters().die_ids;
    summary.cells         = triangulation.n_active_cells();
    summary.dofs          = dof_handler.n_dofs();
    summary.flux          = boundary_fluxes(coordinates, dof_handler, velocity);
    summary.boundary_area = boundary_areas(coordinates, dof_handler);

    // Reactions of the converged state, with hanging nodes' shares moved to
    // the vertices they hang from.
    Vector<double> unused, reactions;
    view.flow.assemble_residual(dof_handler, velocity, view.terms, view.update_constraints, unused, reactions);
    view.hanging_node_constraints.condense(reactions);
    std::vector<WallShare<dim>> wall_shares;
    const auto                  frictionless = frictionless_walls(view);
    summary.boundary_force                   = boundary_forces(
      coordinates, dof_handler, reactions, view.boundary_conditions, view.wall_nodes, frictionless, &wall_shares);
    summary.divergence_ratio = divergence_ratio(coordinates, dof_handler, velocity);
    summary.mass_balance     = mass_balance(coordinates, dof_handler, velocity, summary.flux);
    summary.penalty          = view.incompressibility.penalty();
    summary.mean_viscosity   = view.incompressibility.viscosity_scale();
    summary.error_estimate   = kelly_estimate(dof_handler, velocity);
    if (settings.dual_weighted_estimate)
      {
        // The flow's T and hardening, from their fields at the dual's points.
        const PointFields fields = [&view](const unsigned int points) {
          std::vector<double> temperature, hardening;
          if (view.temperature != nullptr)
            temperature = view.temperature->values_at(points);
          if (view.strain_field != nullptr && view.material.hardens())
            hardening = view.strain_field->hardening_at(points, &temperature);
          return std::make_pair(temperature, hardening);
        };
        const auto goal = dual_weighted_force_error(dof_handler, view.hanging_node_constraints, velocity, view.flow,
                                                    view.terms, view.material, contact, view.boundary_conditions,
                                                    die_ids, settings.goal_part, fields);
        summary.dual_weighted_error = goal.error;
        log << "  dual-weighted estimate: F_x[" << settings.goal_part << "] exact - computed = " << std::setprecision(3)
            << goal.error << " (velocity part " << goal.velocity_part << ", pressure part " << goal.pressure_part
            << "; dual problem " << goal.dual_dofs << " dofs)" << std::endl;
      }
    summary.die_cell_share = share_of_cells_at(triangulation, die_ids);
    if (settings.exact_velocity != nullptr)
      {
        const auto errors         = velocity_errors(dof_handler, velocity, *settings.exact_velocity);
        summary.velocity_l2_error = errors.first;
        summary.velocity_h1_error = errors.second;
      }

    std::map<std::string, Vector<double>> nodal_fields, cell_fields;
    if (view.equivalent_strain != nullptr)
      cell_fields["equivalent_strain"] = *view.equivalent_strain;
    // The hardening factor per cell for the stresses and fields written: a
    // run in time's own; a steady one's the mean of the factors the flow
    // read at the cell's quadrature points.
    Vector<double> hardening;
    if (view.terms.hardening != nullptr)
      hardening = *view.terms.hardening;
    else if (view.terms.point_hardening != nullptr && triangulation.n_active_cells() > 0)
      {
        const std::vector<double> &points   = *view.terms.point_hardening;
        const std::size_t          n_points = points.size() / triangulation.n_active_cells();
        hardening.reinit(triangulation.n_active_cells());
        for (std::size_t c = 0; c < hardening.size() && n_points > 0; ++c)
          for (std::size_t q = 0; q < n_points; ++q)
            hardening[c] += points[c * n_points + q] / n_points;
      }
    if (hardening.size() > 0)
      cell_fields["hardening_factor"] = hardening;
    if (view.strain != nullptr)
      {
        const auto &eps                   = view.strain->vertex_strain;
        nodal_fields["equivalent_strain"] = Vector<double>(eps.begin(), eps.end());
        summary.strain                    = *view.strain;
        summary.strain->vertex_strain.clear();
      }
    if (view.heat != nullptr)
      {
        const auto &T           = view.heat->vertex_temperature;
        nodal_fields["temperature"] = Vector<double>(T.begin(), T.end());
        summary.heat            = *view.heat;
        summary.heat->vertex_temperature.clear();
      }
    // The pressure is recovered once, for the degree-1 die profiles and the
    // fields.
    const bool     recover_profiles = !contact.empty() && dof_handler.get_fe().degree == 1;
    Vector<double> pressure;
    if (recover_profiles || write_fields_now)
      {
        pressure = view.incompressibility.cell_pressures(velocity);
        ++summary.pressure_recoveries;
      }
    if (!contact.empty())
      {
        const auto results = contact.results(velocity);
        summarise_contact(contact, results, velocity.linfty_norm(), summary);
        add_die_shares(die_ids, wall_shares, frictionless, summary);
        const auto stress = recover_profiles ?
                              vertex_stresses(coordinates, dof_handler, velocity, view.material, pressure,
                                                view.heat ? &view.heat->vertex_temperature : nullptr,
                                                hardening.size() > 0 ? &hardening : nullptr) :
                              std::vector<dealii::SymmetricTensor<2, dim>>();
        write_die_profiles(die_ids, results, recover_profiles ? &stress : nullptr, view.temperature, settings.output_directory);
        nodal_fields["contact_status"] = contact.vertex_status(dof_handler);
        const double flow_through     = throughput(die_ids, summary.flux);
        for (const BoundaryId id : die_ids)
          if (std::abs(summary.flux[id]) > 1e-6 * flow_through)
            log << "  flux through die id " << id << ": " << std::setprecision(4) << summary.flux[id] << " ("
                << 100. * std::abs(summary.flux[id]) / flow_through << "% of the throughput): "
                << (summary.flux[id] < 0 ? "the metal leaves the wall there (separated), see doc/contact.md" :
                                           "penetration")
                << std::endl;
      }
    for (const BoundaryId id : view.boundary_conditions.velocity_ids)
      summary.quantities.emplace_back("F_x[" + std::to_string(id) + "]", summary.boundary_force.at(id)[0]);
    for (const BoundaryId id : die_ids)
      {
        summary.quantities.emplace_back("F_n[" + std::to_string(id) + "]", summary.die_normal_force[id]);
        summary.quantities.emplace_back("F_t[" + std::to_string(id) + "]", summary.die_friction_force[id]);
      }
    // The temperature where the metal leaves (its flux-weighted mean; in time: the metal's mean) and the hottest point.
    if (summary.heat)
      {
        summary.quantities.emplace_back(summary.heat->transient ? "T_mean" : "T_exit",
                                        summary.heat->transient ? summary.heat->T_mean : summary.heat->T_exit);
        summary.quantities.emplace_back("T_max", summary.heat->T_max);
      }
    // The strain the metal leaves with (flux-weighted mean).
    if (summary.strain)
      summary.quantities.emplace_back("eps_exit", summary.strain->eps_exit);
    if (settings.probe)
      {
        dealii::Vector<double> value(dim);
        try
          {
            whole_mesh::point_value(dof_handler, velocity, *settings.probe, value);
          }
        catch (const std::exception &)
          {
            throw InputError("Refinement/Probe point: the point is not in the mesh");
          }
        summary.quantities.emplace_back("v_x(probe)", value[0]);
      }
    // The cycle's own polyline, listed with its VTU in solution.pvd.
    const std::string free_surface_file =
      write_fields_now && settings.write_vtu && summary.free_surface && !summary.free_surface->lines.empty() ?
        "free-surface-" + dealii::Utilities::int_to_string(summary.cycle, 2) + ".vtp" :
        std::string();
    // The metal's half thickness (radius: y is the distance from the
    // symmetry line) where the free surface ends on a part that is no die
    // (the outlet: the extrudate as it leaves, with its swell), and the
    // least over the free surface (the jet's contraction, where the metal
    // comes onto the land again too).
    if (summary.free_surface && !summary.free_surface->lines.empty())
      {
        double least = std::numeric_limits<double>::infinity(), leaving = least;
        for (const auto &line : summary.free_surface->lines)
          {
            for (const auto &p : line.points)
              least = std::min(least, p[1]);
            if (!die_ids.count(line.ends))
              leaving = std::min(leaving, line.points.back()[1]);
          }
        if (std::isfinite(leaving))
          summary.quantities.emplace_back("h_extrudate", leaving);
        summary.quantities.emplace_back("h_jet", least);
        write_free_surface(*summary.free_surface, settings.output_directory, free_surface_file);
      }

    if (write_fields_now)
      write_fields(coordinates,
                   dof_handler,
                   velocity,
                   view.material,
                   pressure,
                   nodal_fields,
                   cell_fields,
                   settings.output_directory,
                   summary.cycle,
                   record_time,
                   settings.write_vtu,
                   settings.write_gnuplot,
                   pvd_records);
    if (write_fields_now && settings.write_vtu)
      {
        if (!free_surface_file.empty())
          pvd_records.emplace_back(record_time, free_surface_file);
        write_pvd(pvd_records, settings.output_directory);
      }
    if (settings.write_mesh_svg && processes::writes_output())
      {
        std::ofstream svg =
          output_stream(settings.output_directory + "/mesh-" + dealii::Utilities::int_to_string(summary.cycle, 2) + ".svg");
        dealii::GridOut().write_svg(triangulation, svg);
      }
  }



  template <int dim>
  void
  CycleReport<dim>::save(OutputArchive &ar) const
  {
    ar << pvd_records;
  }



  template <int dim>
  void
  CycleReport<dim>::load(InputArchive &ar)
  {
    ar >> pvd_records;
  }

  template class CycleReport<2>;
  template class CycleReport<3>;
} // namespace dieflow
