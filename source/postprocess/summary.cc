// The run's summary: the result lines on screen and summary.json.
#include <dieflow/base/atomic_file.h>
#include <dieflow/postprocess/summary.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iomanip>
#include <sstream>

namespace dieflow
{
  namespace
  {
    // Keys in the order they are set: summary.json's order is part of its contract.
    using Json = nlohmann::ordered_json;

    /// @p x to the 10 significant digits summary.json has always given; null if not finite.
    /// A whole number below 1e10, which those digits print without a point, stays an integer.
    Json
    number(const double x)
    {
      if (!std::isfinite(x))
        return nullptr;
      std::ostringstream s;
      s << std::setprecision(10) << x;
      const double rounded = std::strtod(s.str().c_str(), nullptr);
      if (std::abs(rounded) < 1e10 && rounded == std::trunc(rounded))
        return static_cast<std::int64_t>(rounded);
      return rounded;
    }

    Json
    optional_number(const std::optional<double> &x)
    {
      return x ? number(*x) : nullptr;
    }

    Json
    numbers(const std::vector<double> &values)
    {
      Json array = Json::array();
      for (const double x : values)
        array.push_back(number(x));
      return array;
    }

    std::string
    key(const std::string &name)
    {
      return name;
    }

    std::string
    key(const BoundaryId id)
    {
      return std::to_string(id);
    }

    /// An object of the (key, value) pairs of @p pairs (a map, or a vector of pairs), in their order.
    template <typename Pairs, typename Format>
    Json
    object(const Pairs &pairs, const Format &format)
    {
      Json result = Json::object();
      for (const auto &[k, value] : pairs)
        result[key(k)] = format(value);
      return result;
    }
  } // namespace



  void
  write_result_summary(const RunSummary &summary, std::ostream &out)
  {
    if (summary.cycles.empty())
      return;
    const CycleSummary &last = summary.cycles.back();
    // A run that did not converge prints its last cycle's values, with
    // no estimate: the study holds the converged cycles only.
    std::map<std::string, QuantityEstimate> estimate;
    if (summary.cycles.size() > 1 && last.converged)
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
    // The temperature and the heat balance (N mm/s = mW: in W).
    if (const auto &h = last.heat)
      {
        out << "  temperature: mean " << std::setprecision(6) << h->T_mean << " K";
        // Steady, where the metal leaves (none found: T_exit_max 0).
        if (!h->transient && h->T_exit_max > 0)
          out << ", where the metal leaves T_exit = " << quantity("T_exit", "K") << " (" << std::setprecision(6)
              << h->T_exit_min << " - " << h->T_exit_max << " K)";
        out << "\n            hottest T_max = " << quantity("T_max", "K") << ", coldest " << std::setprecision(6)
            << h->T_min << " K\n            heat (W" << (whole_body ? "" : " per mm") << "): plastic "
            << std::setprecision(4) << 1e-3 * h->plastic_heat << " + friction " << 1e-3 * h->friction_heat << " = "
            << (h->transient ? "stored " : "carried ") << 1e-3 * (h->transient ? h->stored : h->carried)
            << " + through walls " << 1e-3 * h->transferred << " + at prescribed T " << 0. + 1e-3 * h->prescribed_outflow
            << " (balance " << std::setprecision(2) << h->balance_error << ")\n";
      }
    if (const auto &e = last.strain)
      out << "  equivalent strain: where the metal leaves eps_exit = " << quantity("eps_exit", "") << " ("
          << std::setprecision(4) << e->eps_exit_min << " - " << e->eps_exit_max << "), largest " << e->eps_max
          << "; hardening factor " << e->hardening_min << " - " << e->hardening_max << "\n";
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
    Json json = {{"converged", summary.converged}, {"interrupted", summary.interrupted},
                 {"wall_time", number(summary.wall_time)}, {"velocity_degree", summary.velocity_degree},
                 {"geometry", summary.geometry}, {"problem", summary.problem}};
    if (summary.problem == "incremental")
      {
        const StepTotals t = step_totals(summary);
        Json incremental = {
          {"steps", t.steps}, {"largest_penetration", number(t.largest_penetration)},
          {"volume_change", number(t.volume_change)}, {"smallest_scaled_jacobian", number(t.smallest_scaled_jacobian)},
          {"faces_entered", t.faces_entered}, {"faces_left", t.faces_left}, {"remeshings", t.remeshings},
          {"largest_remesh_volume_change", number(t.largest_remesh_volume_change)}};
        if (!summary.restarted_from.empty())
          incremental["restarted_from"] = {{"file", summary.restarted_from}, {"step", summary.restart_step}};
        if (!summary.checkpoint_file.empty())
          incremental["checkpoint"] = {{"file", summary.checkpoint_file}, {"step", summary.checkpoint_step}};
        json["incremental"] = std::move(incremental);
      }
    json["peak_memory_mb"]  = number(summary.peak_memory_mb);
    json["processes"]       = summary.processes;
    json["threads"]         = summary.threads;
    json["stage_wall_time"] = object(summary.stage_wall_time, number);
    // References into json only while no key is added to it (ordered_json keeps its keys in a vector).
    Json &extrapolated = json["extrapolated"] = Json::object();
    for (const auto &e : summary.extrapolated)
      extrapolated[e.name] = {{"value", number(e.extrapolated)}, {"error", number(e.extrapolation_error)},
                              {"order", number(e.order)},        {"last", number(e.last)},
                              {"estimated_error", number(e.estimate)}};
    if (summary.target_reached)
      {
        json["target_reached"] = *summary.target_reached;
        json["target"] = {{"quantity", summary.target_quantity}, {"relative_error", number(summary.target_error)}};
      }
    if (!summary.failure.empty())
      json["failure"] = summary.failure;
    json["warnings"] = summary.warnings;

    Json &cycles = json["cycles"] = Json::array();
    for (const CycleSummary &s : summary.cycles)
      {
        std::vector<double> residuals, normal_changes, tangential_changes;
        for (const auto &record : s.history)
          {
            residuals.push_back(record.residual);
            normal_changes.push_back(record.state_changes.normal);
            tangential_changes.push_back(record.state_changes.tangential);
          }
        const LinearSolverCounts &l = s.linear_counts;
        Json cycle = {
          {"cycle", s.cycle}, {"cells", s.cells}, {"dofs", s.dofs}, {"converged", s.converged},
          {"nonlinear_iterations", s.nonlinear_iterations}, {"linear_solves", s.linear_solves},
          {"contact_assemblies", s.contact_assemblies}, {"friction_terms", s.friction_terms},
          {"pressure_recoveries", s.pressure_recoveries},
          {"incompressibility", s.incompressibility},
          {"friction_stages", numbers(s.friction_stages)},
          {"rate_sensitivity_stages", numbers(s.rate_sensitivity_stages)},
          {"linear_solver",
           {{"method", s.linear_method}, {"symbolic_analyses", l.symbolic_analyses},
            {"cholesky_factorisations", l.cholesky_factorisations}, {"lu_factorisations", l.lu_factorisations},
            {"iterative_solves", l.iterative_solves}, {"krylov_iterations", l.krylov_iterations},
            {"inner_iterations", l.inner_iterations}, {"residual_decades", number(l.residual_decades)},
            {"direct_fallbacks", l.direct_fallbacks}, {"partial_steps", l.partial_steps},
            {"reused_solves", l.reused_solves}, {"reuse_iterations", l.reuse_iterations},
            {"reuse_refactorised", l.reuse_refactorised}, {"setup_wall_time", number(l.setup_seconds)}}},
          {"boundary_force", object(s.boundary_force, numbers)}, {"flux", object(s.flux, number)},
          {"boundary_area", object(s.boundary_area, number)}, {"die_normal_force", object(s.die_normal_force, number)},
          {"die_friction_force", object(s.die_friction_force, number)},
          {"contact_nodes",
           {{"separated", s.contact_nodes.separated}, {"stick", s.contact_nodes.stick},
            {"slip", s.contact_nodes.slip}}},
          {"contact_length", object(s.contact_length, [](const std::array<double, 3> &length) {
             return Json{{"separated", number(length[0])}, {"stick", number(length[1])}, {"slip", number(length[2])}};
           })},
          {"contact_checks",
           {{"penetration", number(s.contact_penetration)}, {"tension", number(s.contact_tension)},
            {"friction_excess", number(s.friction_excess)},
            {"friction_checked_nodes", s.friction_checked_nodes}, {"stick_slip_rate", number(s.stick_slip_rate)},
            {"separated_reaction", number(s.separated_reaction)}, {"friction_power", number(s.friction_power)},
            {"held_in_contact", s.held_in_contact}, {"regularised_friction", s.regularised_friction}}},
          {"divergence_ratio", number(s.divergence_ratio)},
          {"mass_balance",
           {{"loss", number(s.mass_balance.loss)}, {"volume_change", number(s.mass_balance.volume_change)},
            {"reference_flux", number(s.mass_balance.reference_flux)}, {"status", status_name(s.mass_balance_status)}}},
          {"quantities", object(s.quantities, number)}, {"estimated_errors", object(s.estimated_errors, number)},
          {"error_estimate", number(s.error_estimate)}, {"dual_weighted_error", optional_number(s.dual_weighted_error)},
          {"die_cell_share", number(s.die_cell_share)}, {"start_distance", number(s.start_distance)},
          {"velocity_l2_error", optional_number(s.velocity_l2_error)},
          {"velocity_h1_error", optional_number(s.velocity_h1_error)},
          {"penalty", number(s.penalty)}, {"mean_viscosity", number(s.mean_viscosity)},
          {"residual_history", numbers(residuals)}, {"active_set_changes", numbers(normal_changes)},
          {"stick_slip_changes", numbers(tangential_changes)}, {"wall_time", number(s.wall_time)}};
        if (const auto &step = s.step)
          {
            cycle["step"] = {{"step", step->step}, {"time", number(step->time)}, {"stroke", number(step->stroke)},
                             {"volume", number(step->volume)}, {"volume_change", number(step->volume_change)},
                             {"smallest_scaled_jacobian", number(step->smallest_scaled_jacobian)},
                             {"faces_entered", step->faces_entered}, {"faces_left", step->faces_left},
                             {"penetration", number(step->penetration)},
                             {"mean_equivalent_strain", number(step->mean_strain)},
                             {"max_equivalent_strain", number(step->max_strain)}};
            if (const auto &r = step->remesh)
              cycle["step"]["new_mesh"] = {
                {"cells_before", r->cells_before}, {"cells_after", r->cells_after},
                {"smallest_scaled_jacobian_before", number(r->jacobian_before)},
                {"smallest_scaled_jacobian_after", number(r->jacobian_after)},
                {"volume_change", number(r->volume_change)}, {"split_edges", r->split_edges},
                {"dropped_vertices", r->dropped_vertices}, {"heat_content_change", number(r->heat_content_change)},
                {"mean_temperature_change", number(r->mean_temperature_change)}};
          }
        if (const auto &f = s.free_surface)
          {
            Json lines = Json::array();
            for (const FreeSurfaceLine &line : f->lines)
              {
                Json points = Json::array();
                for (const auto &p : line.points)
                  points.push_back({number(p[0]), number(p[1])});
                const auto &from = line.points.front(), &to = line.points.back();
                lines.push_back({{"leaves", line.leaves}, {"ends", line.ends},
                                 {"from", {number(from[0]), number(from[1])}},
                                 {"to", {number(to[0]), number(to[1])}},
                                 {"swell", number(from[1] != 0 ? to[1] / from[1] : 0.)},
                                 {"points", points}});
              }
            cycle["free_surface"] = {{"moves", f->moves}, {"settled", f->settled},
                                     {"largest_move", number(f->largest_move)}, {"free_faces", f->free_faces},
                                     {"grazing_faces", f->grazing_faces}, {"grazing_flux", number(f->grazing_flux)},
                                     {"lines", lines}};
          }
        // The heat balance in N mm/s (mW; per mm of depth in plane strain).
        if (const auto &h = s.heat)
          cycle["heat"] = {{"solves", h->solves}, {"settled", h->settled}, {"last_change", number(h->last_change)},
                          {"property_passes", h->property_passes},
                           {"plastic_work", number(h->plastic_work)}, {"plastic_heat", number(h->plastic_heat)},
                           {"friction_work", number(h->friction_work)}, {"friction_heat", number(h->friction_heat)},
                           {"carried", number(h->carried)}, {"stored", number(h->stored)},
                           {"transferred", number(h->transferred)},
                           {"prescribed_outflow", number(h->prescribed_outflow)},
                           {"balance_error", number(h->balance_error)}, {"T_min", number(h->T_min)},
                           {"T_max", number(h->T_max)}, {"T_mean", number(h->T_mean)}, {"T_exit", number(h->T_exit)},
                           {"T_exit_min", number(h->T_exit_min)}, {"T_exit_max", number(h->T_exit_max)},
                           {"cell_peclet", number(h->peclet)}};
        if (const auto &h = s.heat)
          for (const auto &[id, out] : h->transferred_by_id)
            cycle["heat"]["transferred_by_id"][std::to_string(id)] = number(out);
        if (const auto &h = s.heat; h && h->T_l2_error)
          cycle["heat"]["T_l2_error"] = number(*h->T_l2_error), cycle["heat"]["T_nodal_error"] = number(*h->T_nodal_error);
        if (const auto &e = s.strain)
          {
            cycle["strain"] = {{"solves", e->solves}, {"settled", e->settled}, {"last_change", number(e->last_change)},
                               {"eps_max", number(e->eps_max)}, {"eps_exit", number(e->eps_exit)},
                               {"eps_exit_min", number(e->eps_exit_min)}, {"eps_exit_max", number(e->eps_exit_max)},
                               {"hardening_min", number(e->hardening_min)}, {"hardening_max", number(e->hardening_max)}};
            if (e->l2_error)
              cycle["strain"]["l2_error"] = number(*e->l2_error), cycle["strain"]["nodal_error"] = number(*e->nodal_error);
          }
        cycles.push_back(std::move(cycle));
      }

    AtomicFile file(file_name);
    // Invalid UTF-8 in a message or a path becomes U+FFFD instead of an exception.
    file.stream() << json.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    file.commit();
  }
} // namespace dieflow
