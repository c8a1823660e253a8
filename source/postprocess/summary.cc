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
  write_summary_json(const RunSummary &summary, const std::string &file_name)
  {
    std::ofstream out(file_name);
    out << "{\n"
        << "  \"converged\": " << (summary.converged ? "true" : "false") << ",\n"
        << "  \"wall_time\": " << number(summary.wall_time) << ",\n";
    out << "  \"peak_memory_mb\": " << number(summary.peak_memory_mb) << ",\n"
        << "  \"stage_wall_time\": {";
    for (auto it = summary.stage_wall_time.begin(); it != summary.stage_wall_time.end(); ++it)
      out << (it == summary.stage_wall_time.begin() ? "" : ", ") << string(it->first) << ": "
          << number(it->second);
    out << "},\n"
        << "  \"extrapolated\": {";
    for (unsigned int i = 0; i < summary.extrapolated.size(); ++i)
      {
        const auto &[name, value, error, order] = summary.extrapolated[i];
        out << (i == 0 ? "" : ", ") << string(name) << ": {\"value\": " << number(value)
            << ", \"error\": " << number(error) << ", \"order\": " << number(order) << "}";
      }
    out << "},\n";
    if (!summary.failure.empty())
      out << "  \"failure\": " << string(summary.failure) << ",\n";
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
            << ", \"direct_fallbacks\": " << s.linear_counts.direct_fallbacks << "},\n"
            << "      \"boundary_force\": " << id_map(s.boundary_force, vector) << ",\n"
            << "      \"flux\": " << id_map(s.flux, number) << ",\n"
            << "      \"die_normal_force\": " << id_map(s.die_normal_force, number) << ",\n"
            << "      \"die_friction_force\": " << id_map(s.die_friction_force, number) << ",\n"
            << "      \"contact_nodes\": {\"separated\": " << s.contact_nodes.separated
            << ", \"stick\": " << s.contact_nodes.stick << ", \"slip\": " << s.contact_nodes.slip
            << "},\n"
            << "      \"contact_checks\": {\"penetration\": " << number(s.contact_penetration)
            << ", \"tension\": " << number(s.contact_tension) << ", \"friction_excess\": "
            << number(s.friction_excess) << ", \"stick_slip_rate\": " << number(s.stick_slip_rate)
            << ", \"separated_reaction\": " << number(s.separated_reaction)
            << ", \"friction_power\": " << number(s.friction_power) << "},\n"
            << "      \"divergence_ratio\": " << number(s.divergence_ratio) << ",\n"
            << "      \"quantities\": {";
        for (unsigned int q = 0; q < s.quantities.size(); ++q)
          out << (q == 0 ? "" : ", ") << string(s.quantities[q].first) << ": " << number(s.quantities[q].second);
        out << "},\n"
            << "      \"error_estimate\": " << number(s.error_estimate)
            << ", \"die_cell_share\": " << number(s.die_cell_share)
            << ", \"start_distance\": " << number(s.start_distance) << ",\n"
            << "      \"velocity_l2_error\": " << optional_number(s.velocity_l2_error)
            << ", \"velocity_h1_error\": " << optional_number(s.velocity_h1_error) << ",\n"
            << "      \"penalty\": " << number(s.penalty)
            << ", \"mean_viscosity\": " << number(s.mean_viscosity) << ",\n"
            << "      \"residual_history\": " << vector(residuals) << ",\n"
            << "      \"active_set_changes\": " << vector(normal_changes) << ",\n"
            << "      \"stick_slip_changes\": " << vector(tangential_changes) << ",\n"
            << "      \"wall_time\": " << number(s.wall_time) << "\n"
            << "    }";
      }
    out << "\n  ]\n}\n";
  }
} // namespace dieflow
