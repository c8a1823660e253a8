// The test driver of the .prm tests: runs the deck with the program's own
// code, sends the iteration log to log.txt, and prints a deterministic
// report: the exit status (and the error message of bad input), a table of
// the quantities the deck's "subsection Test" asks for, and the verdict of
// each of its checks. The checks are the proof; the table guards against
// regressions.
#include <algorithm>
#include <dieflow/base/parameters.h>
#include <dieflow/problem/run.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>

using namespace dieflow;

namespace
{
  void
  declare_test_section(ParameterHandler &prm)
  {
    prm.enter_subsection("Test");
    prm.declare_entry("Columns", "", dealii::Patterns::Anything(), "Quantities printed per cycle.");
    prm.declare_entry("Precision", "3", dealii::Patterns::Integer(1, 8), "Significant digits printed.");
    prm.declare_entry("Round-off",
                      "0",
                      dealii::Patterns::Double(0),
                      "Values smaller in magnitude are round-off (or solver tolerance) for this deck: printed as "
                      "'<' and this bound, so that the table compares what they are not (a value that grows past "
                      "it changes the table). 0: every value printed.");
    prm.declare_entry("Checks", "", dealii::Patterns::Anything(), "label: expression; ... (true = pass)");
    prm.leave_subsection();
  }

  /// Observed convergence order of the error e against the mesh size h ~ dofs^(-1/dim).
  double
  rate(const double e_coarse, const double e_fine, const double dofs_coarse, const double dofs_fine, const int dim)
  {
    return std::log(e_coarse / e_fine) / std::log(std::pow(dofs_fine / dofs_coarse, 1. / dim));
  }

  /// Order p of r_{k+1} ~ r_k^p from the last three Newton residuals above 1e-12.
  double
  newton_order(const CycleSummary &cycle)
  {
    std::vector<double> r;
    for (const auto &record : cycle.history)
      if (record.linearization == Linearization::newton && record.residual > 1e-12)
        r.push_back(record.residual);
    if (r.size() < 3)
      return std::nan("");
    const unsigned int n = r.size();
    return std::log(r[n - 1] / r[n - 2]) / std::log(r[n - 2] / r[n - 3]);
  }

  std::map<std::string, double>
  quantities(const RunSummary &summary, const int exit_status)
  {
    std::map<std::string, double> q;
    q["exit_status"] = exit_status;
    q["n_cycles"]    = summary.cycles.size();
    q["n_warnings"]  = summary.warnings.size();
    const StepTotals totals         = step_totals(summary);
    q["largest_penetration"]        = totals.largest_penetration;
    q["total_faces_entered"]        = totals.faces_entered;
    q["total_faces_left"]           = totals.faces_left;
    q["smallest_jacobian_over_run"] = totals.smallest_scaled_jacobian;
    q["remeshings"]                 = totals.remeshings;
    q["largest_remesh_volume_change"] = totals.largest_remesh_volume_change;
    q["target_reached"] = summary.target_reached ? double(*summary.target_reached) : std::nan("");
    const double nan = std::nan("");
    for (unsigned int c = 0; c < summary.cycles.size(); ++c)
      {
        const CycleSummary &s = summary.cycles[c];
        std::map<std::string, double> cycle;
        cycle["cells"]              = s.cells;
        cycle["dofs"]               = s.dofs;
        cycle["converged"]          = s.converged;
        cycle["iterations"]         = s.nonlinear_iterations;
        cycle["linear_solves"]      = s.linear_solves;
        cycle["contact_assemblies"] = s.contact_assemblies;
        cycle["divergence_ratio"]   = s.divergence_ratio;
        cycle["mass_loss"]          = s.mass_balance.loss;
        cycle["volume_change"]      = s.mass_balance.volume_change;
        cycle["mass_balance_failed"] = s.mass_balance_status == MassBalanceStatus::failed;
        cycle["mass_balance_warning"] = s.mass_balance_status == MassBalanceStatus::warning;
        cycle["penalty"]            = s.penalty;
        cycle["separated"]          = s.contact_nodes.separated;
        cycle["stick"]              = s.contact_nodes.stick;
        cycle["slip"]               = s.contact_nodes.slip;
        cycle["contact_penetration"] = s.contact_penetration;
        cycle["contact_tension"]     = s.contact_tension;
        cycle["friction_excess"]     = s.friction_excess;
        cycle["friction_checked"]    = s.friction_checked_nodes;
        cycle["stick_slip_rate"]     = s.stick_slip_rate;
        cycle["separated_reaction"]  = s.separated_reaction;
        cycle["friction_power"]      = s.friction_power;
        cycle["die_cell_share"]      = s.die_cell_share;
        cycle["error_estimate"]      = s.error_estimate;
        cycle["start_distance"]      = s.start_distance;
        cycle["first_residual"]      = s.history.empty() ? nan : s.history.front().residual;
        cycle["l2_error"]           = s.velocity_l2_error.value_or(nan);
        cycle["h1_error"]           = s.velocity_h1_error.value_or(nan);
        cycle["newton_order"]       = newton_order(s);
        cycle["l2_rate"] = cycle["h1_rate"] = nan;
        // Problem = incremental: the step's time, stroke, volume and shape.
        cycle["time"] = cycle["stroke"] = cycle["volume"] = cycle["step_volume_change"] = cycle["min_scaled_jacobian"] = nan;
        if (s.step)
          {
            cycle["time"]                = s.step->time;
            cycle["stroke"]              = s.step->stroke;
            cycle["volume"]              = s.step->volume;
            cycle["step_volume_change"] = s.step->volume_change;
            cycle["min_scaled_jacobian"] = s.step->smallest_scaled_jacobian;
            cycle["faces_entered"]       = s.step->faces_entered;
            cycle["faces_left"]          = s.step->faces_left;
            cycle["penetration"]         = s.step->penetration;
            cycle["mean_strain"]         = s.step->mean_strain;
            cycle["max_strain"]          = s.step->max_strain;
            cycle["remeshed"]            = s.step->remesh.has_value();
            cycle["remesh_volume_change"] = s.step->remesh ? s.step->remesh->volume_change : 0.;
            cycle["remesh_heat_content_change"] = s.step->remesh ? s.step->remesh->heat_content_change : 0.;
            cycle["jacobian_after_remesh"] = s.step->remesh ? s.step->remesh->jacobian_after : nan;
            cycle["split_edges"]          = s.step->remesh ? s.step->remesh->split_edges : 0.;
          }
        // Steady runs with a free surface (free_surface.h).
        // With a temperature field (heat_equation.h).
        if (const auto &h = s.heat)
          for (const auto &[name, value] : std::vector<std::pair<std::string, double>>{
                 {"heat_solves", h->solves}, {"heat_settled", h->settled}, {"plastic_work", h->plastic_work},
                 {"heat_property_passes", double(h->property_passes)},
                 {"plastic_heat", h->plastic_heat}, {"friction_work", h->friction_work},
                 {"friction_heat", h->friction_heat}, {"heat_carried", h->carried},
                 {"heat_transferred", h->transferred}, {"heat_prescribed_outflow", h->prescribed_outflow},
                 {"heat_stored", h->stored}, {"T_mean", h->T_mean},
                 {"heat_balance", h->balance_error}, {"T_min", h->T_min}, {"T_max", h->T_max},
                 {"T_exit", h->T_exit}, {"T_exit_min", h->T_exit_min}, {"T_exit_max", h->T_exit_max},
                 {"cell_peclet", h->peclet}, {"T_l2_error", h->T_l2_error.value_or(nan)},
                 {"T_nodal_error", h->T_nodal_error.value_or(nan)}})
            cycle[name] = value;
        if (const auto &h = s.heat)
          for (const auto &[id, out] : h->transferred_by_id)
            cycle["heat_transferred_" + std::to_string(id)] = out;
        // With a steady strain field (strain_field.h).
        if (const auto &e = s.strain)
          for (const auto &[name, value] : std::vector<std::pair<std::string, double>>{
                 {"strain_solves", e->solves}, {"strain_settled", e->settled}, {"eps_max", e->eps_max},
                 {"eps_exit", e->eps_exit}, {"eps_exit_min", e->eps_exit_min}, {"eps_exit_max", e->eps_exit_max},
                 {"hardening_min", e->hardening_min}, {"hardening_max", e->hardening_max},
                 {"eps_l2_error", e->l2_error.value_or(nan)}, {"eps_nodal_error", e->nodal_error.value_or(nan)}})
            cycle[name] = value;
        cycle["free_surface_moves"]   = s.free_surface ? s.free_surface->moves : nan;
        cycle["free_surface_settled"] = s.free_surface ? s.free_surface->settled : nan;
        cycle["free_surface_move"]    = s.free_surface ? s.free_surface->largest_move : nan;
        cycle["free_faces"]           = s.free_surface ? s.free_surface->free_faces : nan;
        cycle["grazing_faces"]        = s.free_surface ? s.free_surface->grazing_faces : nan;
        cycle["grazing_flux"]         = s.free_surface ? s.free_surface->grazing_flux : nan;
        cycle["free_lines"]           = s.free_surface ? s.free_surface->lines.size() : nan;
        // The longest free stretch: where it leaves (from) and ends (to), the ids of the parts there.
        if (s.free_surface && !s.free_surface->lines.empty())
          {
            const FreeSurfaceLine &line =
              *std::max_element(s.free_surface->lines.begin(), s.free_surface->lines.end(),
                                [](const auto &a, const auto &b) { return a.points.size() < b.points.size(); });
            cycle["line_from_x"] = line.points.front()[0];
            cycle["line_from_y"] = line.points.front()[1];
            cycle["line_to_x"]   = line.points.back()[0];
            cycle["line_to_y"]   = line.points.back()[1];
            cycle["line_leaves"] = line.leaves;
            cycle["line_ends"]   = line.ends;
          }
        if (c > 0 && s.velocity_l2_error)
          {
            const CycleSummary &p = summary.cycles[c - 1];
            const int dim    = summary.geometry == "3d" ? 3 : 2;
            cycle["l2_rate"] = rate(*p.velocity_l2_error, *s.velocity_l2_error, p.dofs, s.dofs, dim);
            cycle["h1_rate"] = rate(*p.velocity_h1_error, *s.velocity_h1_error, p.dofs, s.dofs, dim);
          }
        for (const auto &[id, f] : s.boundary_force)
          {
            cycle["force_x_" + std::to_string(id)] = f[0];
            cycle["force_y_" + std::to_string(id)] = f[1];
            if (f.size() > 2)
              cycle["force_z_" + std::to_string(id)] = f[2];
          }
        for (const auto &[id, value] : s.flux)
          cycle["flux_" + std::to_string(id)] = value;
        for (const auto &[id, value] : s.boundary_area)
          cycle["area_" + std::to_string(id)] = value;
        for (const auto &[id, value] : s.die_normal_force)
          cycle["die_normal_" + std::to_string(id)] = value;
        for (const auto &[id, value] : s.die_friction_force)
          cycle["die_friction_" + std::to_string(id)] = value;
        // Each die's separated, sticking and slipping length (area in 3D).
        for (const auto &[id, length] : s.contact_length)
          {
            cycle["separated_length_" + std::to_string(id)] = length[0];
            cycle["stick_length_" + std::to_string(id)]     = length[1];
            cycle["slip_length_" + std::to_string(id)]      = length[2];
          }
        // The quantities of interest and their estimated errors:
        // F_x[1] -> q_F_x_1 and estimate_F_x_1, v_x(probe) -> q_v_x_probe ...
        const auto key = [](const std::string &prefix, const std::string &name) {
          std::string k = prefix;
          for (const char ch : name)
            if (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_')
              k += ch;
            else if (ch == '[' || ch == '(')
              k += '_';
          return k;
        };
        for (const auto &[name, value] : s.quantities)
          cycle[key("q_", name)] = value;
        for (const auto &[name, value] : s.estimated_errors)
          cycle[key("estimate_", name)] = value;
        for (const auto &[name, value] : cycle)
          {
            q[name + "_c" + std::to_string(c)] = value;
            if (c + 1 == summary.cycles.size())
              q[name] = value;
          }
      }
    return q;
  }

  std::string
  format(const double x, const unsigned int precision, const double round_off)
  {
    if (std::isnan(x))
      return "-";
    std::ostringstream s;
    if (x != 0 && std::abs(x) < round_off)
      {
        s << '<' << round_off;
        return s.str();
      }
    if (x == std::round(x) && std::abs(x) < 1e9)
      s << static_cast<long long>(x);
    else
      s << std::scientific << std::setprecision(precision - 1) << x;
    return s.str();
  }
} // namespace



int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (argc != 2)
    {
      std::cerr << "usage: dieflow_check TEST.prm" << std::endl;
      return 1;
    }
  ParameterHandler prm;
  RunSummary       summary;
  int              status = exit_converged;
  std::ofstream    log("log.txt");
  try
    {
      read_deck(argv[1], prm, declare_test_section);
      summary = run_deck(prm, std::filesystem::path(argv[1]).parent_path().string(), log);
      status  = summary.converged ? exit_converged : exit_not_converged;
    }
  catch (const InputError &error)
    {
      status = exit_bad_input;
      std::cout << "dieflow: error: " << error.what() << std::endl;
    }
  catch (const dealii::ExceptionBase &exc)
    {
      status = exit_bad_input;
      std::cout << "dieflow: error: " << deck_error_message(exc, argv[1]) << std::endl;
    }
  std::cout << "exit status: " << status << std::endl;
  if (status == exit_bad_input)
    return 0;
  if (!summary.failure.empty())
    std::cout << "failure: " << summary.failure << std::endl;

  prm.enter_subsection("Test");
  const auto         columns   = dealii::Utilities::split_string_list(prm.get("Columns"));
  const unsigned int precision = prm.get_integer("Precision");
  const double       round_off = prm.get_double("Round-off");
  const auto         checks    = dealii::Utilities::split_string_list(prm.get("Checks"), ';');
  prm.leave_subsection();

  const auto q = quantities(summary, status);
  if (!columns.empty())
    {
      std::cout << "cycle";
      for (const auto &c : columns)
        std::cout << ' ' << c;
      std::cout << std::endl;
      for (unsigned int c = 0; c < summary.cycles.size(); ++c)
        {
          std::cout << c;
          for (const auto &name : columns)
            {
              const auto it = q.find(name + "_c" + std::to_string(c));
              std::cout << ' ' << (it == q.end() ? "?" : format(it->second, precision, round_off));
            }
          std::cout << std::endl;
        }
    }

  for (const auto &check : checks)
    {
      if (check.empty())
        continue;
      const auto colon      = check.find(':');
      const auto label      = check.substr(0, colon);
      const auto expression = check.substr(colon + 1);
      std::string verdict;
      // deal.II's muparser wrapper writes parse errors to std::cerr too.
      std::ostringstream muted;
      std::streambuf *   cerr_buffer = std::cerr.rdbuf(muted.rdbuf());
      try
        {
          dealii::FunctionParser<1> parser(1);
          parser.initialize("unused", expression, q);
          const double value = parser.value(dealii::Point<1>());
          verdict            = (value != 0 && std::isfinite(value)) ? "PASS" : "FAIL";
        }
      catch (const std::exception &exc)
        {
          verdict = "cannot evaluate: " + one_line_message(exc);
        }
      std::cerr.rdbuf(cerr_buffer);
      std::cout << "check " << label << ": " << verdict << std::endl;
    }
  return 0;
}
