#include <dieflow/postprocess/atomic_file.h>
#include <dieflow/postprocess/summary.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace dieflow
{
  namespace
  {
    std::string
    number(const double x)
    {
      if (!std::isfinite(x))
        return "null";
      std::ostringstream s;
      s << std::setprecision(10) << x;
      return s.str();
    }

    std::string
    optional_number(const std::optional<double> &x)
    {
      return x ? number(*x) : "null";
    }

    template <typename Map, typename Format>
    std::string
    id_map(const Map &map, const Format &format)
    {
      std::string text = "{";
      for (auto it = map.begin(); it != map.end(); ++it)
        text += (it == map.begin() ? "\"" : ", \"") + std::to_string(it->first) + "\": " +
                format(it->second);
      return text + "}";
    }

    std::string
    vector(const std::vector<double> &values)
    {
      std::string text = "[";
      for (unsigned int i = 0; i < values.size(); ++i)
        text += (i == 0 ? "" : ", ") + number(values[i]);
      return text + "]";
    }

    std::string
    string(const std::string &s)
    {
      std::string escaped = "\"";
      for (const char c : s)
        {
          if (c == '"' || c == '\\')
            escaped += '\\';
          escaped += c;
        }
      return escaped + "\"";
    }
  } // namespace



  void
  write_result_summary(const RunSummary &summary, std::ostream &out)
  {
    if (summary.cycles.empty())
      return;
    const CycleSummary &last = summary.cycles.back();
    std::map<std::string, QuantityEstimate> estimate;
    if (summary.cycles.size() > 1)
      for (const auto &e : summary.extrapolated)
        estimate[e.name] = e;
    const auto quantity = [&](const std::string &name, const std::string &unit) {
      std::ostringstream text;
      const double       value = named_value(last.quantities, name);
      text << std::setprecision(6) << value << ' ' << unit;
      if (const auto e = estimate.find(name); e != estimate.end())
        text << " +- " << std::setprecision(2) << e->second.estimate << " ("
             << (value != 0 ? 100 * e->second.estimate / std::abs(value) : 0.) << " %)";
      return text.str();
    };
    // Plane strain: per mm of depth; axisymmetric: the whole body of revolution; 3D: the body.
    const bool        whole_body = summary.geometry != "plane strain";
    const std::string force_unit = whole_body ? "N" : "N/mm";
    // Problem = incremental: the last step's, at its time.
    if (last.step)
      out << "result (step " << last.cycle << ", t = " << last.step->time << " s, ";
    else
      out << "result (cycle " << last.cycle << ", ";
    out << last.dofs << " dofs, velocity degree " << summary.velocity_degree
        << (summary.geometry == "plane strain" ? "" : ", " + summary.geometry) << "):\n";
    for (const auto &[name, value] : last.quantities)
      if (name.rfind("F_x[", 0) == 0)
        {
          const BoundaryId id = std::stoul(name.substr(4, name.size() - 5));
          out << "  force on prescribed-velocity part " << id << ", " << name << " = " << quantity(name, force_unit)
              << '\n';
          // The ram's extrusion pressure, a drawing pull's drawing stress.
          if (const auto area = last.boundary_area.find(id); area != last.boundary_area.end() && area->second > 0)
            out << "      mean axial stress F_x[" << id << "] / A = " << std::setprecision(6) << value / area->second
                << " MPa over A = " << area->second << (whole_body ? " mm^2" : " mm") << '\n';
        }
    // The extent of the contact zones: a length of wall in 2D, an area in 3D.
    const std::string wall_unit = summary.geometry == "3d" ? " mm^2" : " mm";
    for (const auto &[id, length] : last.contact_length)
      {
        const std::string i = std::to_string(id);
        out << "  die id " << i << ": normal force F_n[" << i << "] = " << quantity("F_n[" + i + "]", force_unit)
            << "\n            friction force F_t[" << i << "] = " << quantity("F_t[" + i + "]", force_unit)
            << "\n            separated " << std::setprecision(4) << length[0] << wall_unit << ", stick " << length[1]
            << wall_unit << ", slip " << length[2] << wall_unit << "\n";
      }
    for (const auto &[name, value] : last.quantities)
      if (name == "v_x(probe)")
        out << "  probe velocity v_x = " << quantity(name, "mm/s") << '\n';
    if (summary.cycles.size() == 1)
      out << "  (one cycle: no error estimate; run several Refinement/Cycles, or set a Refinement/Target error)\n";
    else
      out << "  (+- the estimated error of the last cycle's value, from the last cycles' changes: doc/user-guide.md)\n";
    if (summary.target_reached)
      out << "  target error " << std::setprecision(3) << 100 * summary.target_error << " % on "
          << summary.target_quantity << (*summary.target_reached ? ": reached" : ": NOT reached") << '\n';
    out << std::defaultfloat;
  }



  StepTotals
  step_totals(const RunSummary &summary)
  {
    StepTotals totals;
    const auto add = [&](const StepRecord &step) {
      totals.steps                    = step.step;
      totals.largest_penetration      = std::max(totals.largest_penetration, step.penetration);
      totals.volume_change            = step.volume_change;
      totals.smallest_scaled_jacobian = std::min(totals.smallest_scaled_jacobian, step.smallest_scaled_jacobian);
      totals.faces_entered += step.faces_entered;
      totals.faces_left += step.faces_left;
      if (step.remesh)
        {
          ++totals.remeshings;
          totals.largest_remesh_volume_change =
            std::max(totals.largest_remesh_volume_change, std::abs(step.remesh->volume_change));
        }
    };
    // A restarted run counts the steps before its checkpoint too.
    for (const StepRecord &step : summary.earlier_steps)
      add(step);
    for (const auto &cycle : summary.cycles)
      if (cycle.step)
        add(*cycle.step);
    return totals;
  }



  void
  write_summary_json(const RunSummary &summary, const std::string &file_name)
  {
    AtomicFile    file(file_name);
    std::ostream &out = file.stream();
    out << "{\n"
        << "  \"converged\": " << (summary.converged ? "true" : "false") << ",\n"
        << "  \"interrupted\": " << (summary.interrupted ? "true" : "false") << ",\n"
        << "  \"wall_time\": " << number(summary.wall_time) << ",\n"
        << "  \"velocity_degree\": " << summary.velocity_degree << ",\n"
        << "  \"geometry\": \"" << summary.geometry << "\",\n"
        << "  \"problem\": \"" << summary.problem << "\",\n";
    if (summary.problem == "incremental")
      {
        const StepTotals totals = step_totals(summary);
        out << "  \"incremental\": {\"steps\": " << totals.steps
            << ", \"largest_penetration\": " << number(totals.largest_penetration)
            << ", \"volume_change\": " << number(totals.volume_change)
            << ", \"smallest_scaled_jacobian\": " << number(totals.smallest_scaled_jacobian)
            << ", \"faces_entered\": " << totals.faces_entered << ", \"faces_left\": " << totals.faces_left
            << ", \"remeshings\": " << totals.remeshings
            << ", \"largest_remesh_volume_change\": " << number(totals.largest_remesh_volume_change);
        if (!summary.restarted_from.empty())
          out << ", \"restarted_from\": {\"file\": " << string(summary.restarted_from)
              << ", \"step\": " << summary.restart_step << "}";
        if (!summary.checkpoint_file.empty())
          out << ", \"checkpoint\": {\"file\": " << string(summary.checkpoint_file)
              << ", \"step\": " << summary.checkpoint_step << "}";
        out << "},\n";
      }
    out << "  \"peak_memory_mb\": " << number(summary.peak_memory_mb) << ",\n"
        << "  \"threads\": " << summary.threads << ",\n"
        << "  \"stage_wall_time\": {";
    for (auto it = summary.stage_wall_time.begin(); it != summary.stage_wall_time.end(); ++it)
      out << (it == summary.stage_wall_time.begin() ? "" : ", ") << string(it->first) << ": "
          << number(it->second);
    out << "},\n"
        << "  \"extrapolated\": {";
    for (unsigned int i = 0; i < summary.extrapolated.size(); ++i)
      {
        const auto &e = summary.extrapolated[i];
        out << (i == 0 ? "" : ", ") << string(e.name) << ": {\"value\": " << number(e.extrapolated)
            << ", \"error\": " << number(e.extrapolation_error) << ", \"order\": " << number(e.order)
            << ", \"last\": " << number(e.last) << ", \"estimated_error\": " << number(e.estimate) << "}";
      }
    out << "},\n";
    if (summary.target_reached)
      out << "  \"target_reached\": " << (*summary.target_reached ? "true" : "false") << ",\n"
          << "  \"target\": {\"quantity\": " << string(summary.target_quantity)
          << ", \"relative_error\": " << number(summary.target_error) << "},\n";
    if (!summary.failure.empty())
      out << "  \"failure\": " << string(summary.failure) << ",\n";
    out << "  \"warnings\": [";
    for (unsigned int i = 0; i < summary.warnings.size(); ++i)
      out << (i == 0 ? "" : ", ") << string(summary.warnings[i]);
    out << "],\n";
    out << "  \"cycles\": [";
    for (unsigned int c = 0; c < summary.cycles.size(); ++c)
      {
        const CycleSummary &s = summary.cycles[c];
        std::vector<double> residuals, normal_changes, tangential_changes;
        for (const auto &record : s.history)
          {
            residuals.push_back(record.residual);
            normal_changes.push_back(record.state_changes.normal);
            tangential_changes.push_back(record.state_changes.tangential);
          }
        out << (c == 0 ? "\n" : ",\n") << "    {\n"
            << "      \"cycle\": " << s.cycle << ", \"cells\": " << s.cells << ", \"dofs\": " << s.dofs
            << ",\n"
            << "      \"converged\": " << (s.converged ? "true" : "false")
            << ", \"nonlinear_iterations\": " << s.nonlinear_iterations
            << ", \"linear_solves\": " << s.linear_solves
            << ", \"contact_assemblies\": " << s.contact_assemblies
            << ", \"friction_terms\": " << s.friction_terms
            << ", \"pressure_recoveries\": " << s.pressure_recoveries << ",\n"
            << "      \"linear_solver\": {\"method\": \"" << s.linear_method
            << "\", \"symbolic_analyses\": " << s.linear_counts.symbolic_analyses
            << ", \"cholesky_factorisations\": " << s.linear_counts.cholesky_factorisations
            << ", \"lu_factorisations\": " << s.linear_counts.lu_factorisations
            << ", \"iterative_solves\": " << s.linear_counts.iterative_solves
            << ", \"krylov_iterations\": " << s.linear_counts.krylov_iterations
            << ", \"inner_iterations\": " << s.linear_counts.inner_iterations
            << ", \"residual_decades\": " << number(s.linear_counts.residual_decades)
            << ", \"direct_fallbacks\": " << s.linear_counts.direct_fallbacks
            << ", \"partial_steps\": " << s.linear_counts.partial_steps << "},\n"
            << "      \"boundary_force\": " << id_map(s.boundary_force, vector) << ",\n"
            << "      \"flux\": " << id_map(s.flux, number) << ",\n"
            << "      \"boundary_area\": " << id_map(s.boundary_area, number) << ",\n"
            << "      \"die_normal_force\": " << id_map(s.die_normal_force, number) << ",\n"
            << "      \"die_friction_force\": " << id_map(s.die_friction_force, number) << ",\n"
            << "      \"contact_nodes\": {\"separated\": " << s.contact_nodes.separated
            << ", \"stick\": " << s.contact_nodes.stick << ", \"slip\": " << s.contact_nodes.slip
            << "},\n"
            << "      \"contact_length\": "
            << id_map(s.contact_length,
                      [](const std::array<double, 3> &l) {
                        return "{\"separated\": " + number(l[0]) + ", \"stick\": " + number(l[1]) +
                               ", \"slip\": " + number(l[2]) + "}";
                      })
            << ",\n"
            << "      \"contact_checks\": {\"penetration\": " << number(s.contact_penetration)
            << ", \"tension\": " << number(s.contact_tension) << ", \"friction_excess\": "
            << number(s.friction_excess) << ", \"stick_slip_rate\": " << number(s.stick_slip_rate)
            << ", \"separated_reaction\": " << number(s.separated_reaction)
            << ", \"friction_power\": " << number(s.friction_power)
            << ", \"held_in_contact\": " << s.held_in_contact
            << ", \"regularised_friction\": " << s.regularised_friction << "},\n"
            << "      \"divergence_ratio\": " << number(s.divergence_ratio) << ",\n"
            << "      \"mass_balance\": {\"loss\": " << number(s.mass_balance.loss)
            << ", \"volume_change\": " << number(s.mass_balance.volume_change)
            << ", \"reference_flux\": " << number(s.mass_balance.reference_flux) << ", \"status\": "
            << string(s.mass_balance_status) << "},\n"
            << "      \"quantities\": {";
        for (unsigned int q = 0; q < s.quantities.size(); ++q)
          out << (q == 0 ? "" : ", ") << string(s.quantities[q].first) << ": " << number(s.quantities[q].second);
        out << "},\n"
            << "      \"estimated_errors\": {";
        for (unsigned int q = 0; q < s.estimated_errors.size(); ++q)
          out << (q == 0 ? "" : ", ") << string(s.estimated_errors[q].first) << ": "
              << number(s.estimated_errors[q].second);
        out << "},\n"
            << "      \"error_estimate\": " << number(s.error_estimate)
            << ", \"dual_weighted_error\": " << optional_number(s.dual_weighted_error)
            << ", \"die_cell_share\": " << number(s.die_cell_share)
            << ", \"start_distance\": " << number(s.start_distance) << ",\n"
            << "      \"velocity_l2_error\": " << optional_number(s.velocity_l2_error)
            << ", \"velocity_h1_error\": " << optional_number(s.velocity_h1_error) << ",\n"
            << "      \"penalty\": " << number(s.penalty)
            << ", \"mean_viscosity\": " << number(s.mean_viscosity) << ",\n"
            << "      \"residual_history\": " << vector(residuals) << ",\n"
            << "      \"active_set_changes\": " << vector(normal_changes) << ",\n"
            << "      \"stick_slip_changes\": " << vector(tangential_changes) << ",\n"
            << "      \"wall_time\": " << number(s.wall_time);
        if (s.step)
          {
            out << ",\n      \"step\": {\"step\": " << s.step->step << ", \"time\": " << number(s.step->time)
                << ", \"stroke\": " << number(s.step->stroke) << ", \"volume\": " << number(s.step->volume)
                << ", \"volume_change\": " << number(s.step->volume_change)
                << ", \"smallest_scaled_jacobian\": " << number(s.step->smallest_scaled_jacobian)
                << ", \"faces_entered\": " << s.step->faces_entered << ", \"faces_left\": " << s.step->faces_left
                << ", \"penetration\": " << number(s.step->penetration)
                << ", \"mean_equivalent_strain\": " << number(s.step->mean_strain)
                << ", \"max_equivalent_strain\": " << number(s.step->max_strain);
            if (const auto &r = s.step->remesh)
              out << ", \"new_mesh\": {\"cells_before\": " << r->cells_before << ", \"cells_after\": " << r->cells_after
                  << ", \"smallest_scaled_jacobian_before\": " << number(r->jacobian_before)
                  << ", \"smallest_scaled_jacobian_after\": " << number(r->jacobian_after)
                  << ", \"volume_change\": " << number(r->volume_change) << ", \"split_edges\": " << r->split_edges
                  << ", \"dropped_vertices\": " << r->dropped_vertices
                  << "}";
            out << "}";
          }
        if (const auto &f = s.free_surface)
          out << ",\n      \"free_surface\": {\"moves\": " << f->moves << ", \"settled\": " << (f->settled ? "true" : "false")
              << ", \"largest_move\": " << number(f->largest_move) << ", \"free_faces\": " << f->free_faces << "}";
        out << "\n    }";
      }
    out << "\n  ]\n}\n";
    file.commit();
  }
} // namespace dieflow
