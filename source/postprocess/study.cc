// The mesh study of a run: a row per cycle, and the Richardson extrapolation and error estimates of the quantities of interest.
#include <dieflow/postprocess/study.h>

#include <deal.II/base/convergence_table.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <iomanip>

namespace dieflow
{
  namespace
  {
    Extrapolation
    from_triple(const double N0, const double N1, const double N2, const double Q0, const double Q1, const double Q2)
    {
      Extrapolation e;
      e.value = Q2;
      e.error = std::abs(Q2 - Q1);
      const double d1 = Q1 - Q0, d2 = Q2 - Q1;
      if (d1 == 0 || d2 == 0 || d2 / d1 <= 0 || std::abs(d2 / d1) >= 1)
        return e;
      // ratio(p) = (N2^-p - N1^-p) / (N1^-p - N0^-p) falls from its p -> 0
      // limit ln(N2/N1)/ln(N1/N0) towards 0 as p grows.
      const auto ratio = [&](const double p) {
        return (std::pow(N2, -p) - std::pow(N1, -p)) / (std::pow(N1, -p) - std::pow(N0, -p));
      };
      const double target = d2 / d1;
      double       low = 1e-3, high = 10;
      if (ratio(low) < target || ratio(high) > target)
        return e;
      for (unsigned int i = 0; i < 200; ++i)
        {
          const double mid = 0.5 * (low + high);
          (ratio(mid) > target ? low : high) = mid;
        }
      const double p = 0.5 * (low + high);
      const double C = d2 / (std::pow(N2, -p) - std::pow(N1, -p));
      e.value        = Q2 - C * std::pow(N2, -p);
      e.error        = std::abs(e.value - Q2);
      e.order        = p;
      e.valid        = true;
      return e;
    }
  } // namespace



  namespace
  {
    /// Extrapolation::estimate for the last of @p n >= 2 values.
    double
    error_estimate(const std::vector<double> &N, const std::vector<double> &Q, const Extrapolation &triple)
    {
      const unsigned int n      = Q.size();
      const double       growth = N[n - 1] / N[n - 2];
      if (!(growth > 1))
        return std::numeric_limits<double>::infinity();
      double change = std::abs(Q[n - 1] - Q[n - 2]);
      double p      = 0.5;
      if (triple.valid)
        p = std::min(p, triple.order);
      else if (n >= 3)
        change = std::max(change, std::abs(Q[n - 2] - Q[n - 3]));
      return change / (std::pow(growth, p) - 1);
    }
  } // namespace



  Extrapolation
  extrapolate(const std::vector<double> &N, const std::vector<double> &Q)
  {
    const unsigned int n = Q.size();
    if (n == 0)
      return {};
    if (n < 3)
      {
        Extrapolation e{Q.back(), n == 2 ? std::abs(Q[1] - Q[0]) : 0., 0., false};
        if (n == 2)
          e.estimate = error_estimate(N, Q, e);
        return e;
      }
    Extrapolation last = from_triple(N[n - 3], N[n - 2], N[n - 1], Q[n - 3], Q[n - 2], Q[n - 1]);
    last.estimate      = error_estimate(N, Q, last);
    if (last.valid && n >= 4)
      {
        const Extrapolation previous = from_triple(N[n - 4], N[n - 3], N[n - 2], Q[n - 4], Q[n - 3], Q[n - 2]);
        if (previous.valid)
          last.error = std::max(std::abs(last.value - previous.value), 0.1 * last.error);
      }
    return last;
  }



  void
  StudyTable::add(const CycleSummary &cycle)
  {
    cycles.push_back(cycle);
  }



  std::vector<std::pair<std::string, Extrapolation>>
  StudyTable::extrapolations() const
  {
    std::vector<std::pair<std::string, Extrapolation>> result;
    if (cycles.empty())
      return result;
    // Each quantity of the last cycle over the cycles before it that have
    // it too (h_extrudate exists only while the free surface runs to the
    // outlet): a sequence of one quantity, never a mix.
    for (const auto &[name, last] : cycles.back().quantities)
      {
        std::vector<double> N, values;
        for (auto c = cycles.rbegin(); c != cycles.rend(); ++c)
          {
            const auto q = std::find_if(c->quantities.begin(), c->quantities.end(), [&](const auto &named) {
              return named.first == name;
            });
            if (q == c->quantities.end())
              break;
            N.insert(N.begin(), c->dofs);
            values.insert(values.begin(), q->second);
          }
        result.emplace_back(name, extrapolate(N, values));
      }
    return result;
  }



  void
  StudyTable::write(std::ostream &out) const
  {
    dealii::ConvergenceTable table;
    const bool               exact = !cycles.empty() && cycles.front().velocity_l2_error.has_value();
    std::vector<std::string> names;
    for (const auto &c : cycles)
      for (const auto &[name, value] : c.quantities)
        if (std::find(names.begin(), names.end(), name) == names.end())
          names.push_back(name);
    for (const auto &c : cycles)
      {
        table.add_value("cycle", c.cycle);
        table.add_value("cells", c.cells);
        table.add_value("dofs", c.dofs);
        table.add_value("its", c.nonlinear_iterations);
        table.add_value("time[s]", c.wall_time);
        // A quantity some cycles lack (h_extrudate while the free surface
        // does not run to the outlet) is a '-' in their rows.
        for (const std::string &name : names)
          {
            const auto q = std::find_if(c.quantities.begin(), c.quantities.end(), [&](const auto &named) {
              return named.first == name;
            });
            if (q != c.quantities.end())
              table.add_value(name, q->second);
            else
              table.add_value(name, std::string("-"));
          }
        table.add_value("estimate", c.error_estimate);
        if (exact)
          {
            table.add_value("L2", *c.velocity_l2_error);
            table.add_value("H1", *c.velocity_h1_error);
          }
      }
    table.set_precision("time[s]", 3);
    table.set_scientific("estimate", true);
    table.set_precision("estimate", 3);
    for (const std::string &name : names)
      table.set_precision(name, 7);
    if (exact)
      {
        for (const std::string key : {"L2", "H1"})
          {
            table.set_scientific(key, true);
            table.set_precision(key, 3);
            table.evaluate_convergence_rates(key, "dofs", dealii::ConvergenceTable::reduction_rate_log2, 2);
          }
      }
    table.write_text(out, dealii::TableHandler::org_mode_table);

    out << "extrapolated (Richardson, Q = Q* + C N^-p from the last three cycles):\n";
    for (const auto &[name, e] : extrapolations())
      {
        const double last = named_value(cycles.back().quantities, name);
        out << "  " << std::setw(10) << std::left << name << std::right << " = " << std::setprecision(8) << e.value
            << " +- " << std::setprecision(2) << e.error << " (" << std::setprecision(2)
            << (e.value != 0 ? 100 * e.error / std::abs(e.value) : 0.) << "%); last value " << std::setprecision(8)
            << last << ", its estimated error " << std::setprecision(2) << e.estimate << " ("
            << (last != 0 ? 100 * e.estimate / std::abs(last) : 0.) << "%)";
        if (e.valid)
          out << ", order p = " << std::setprecision(3) << e.order << " in N";
        else
          out << ", no monotone convergence: the last value and its last change";
        out << '\n';
      }
    out << std::defaultfloat;
  }
} // namespace dieflow
