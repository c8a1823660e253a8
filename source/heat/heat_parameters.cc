// The deck's Heat subsection: its entries, their units and their checks.
#include <dieflow/heat/heat_parameters.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace dieflow
{
  void
  HeatParameters::declare_parameters(ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Heat");
    {
      prm.declare_entry("Model",
                        "off",
                        Selection("off|steady|transient"),
                        "off: isothermal, every law at Material/Temperature. steady: the "
                        "steady heat equation rho c v.grad T = div(k grad T) + beta sigma:D "
                        "on the flow's domain (Problem = steady), solved in turn with the "
                        "flow until both settle. transient: rho c dT/dt = div(k grad T) + "
                        "beta sigma:D on the mesh that moves with the metal (Problem = "
                        "incremental), one heat step per time step with the step's flow. "
                        "The laws take T from the field (Material/Activation energy Q, "
                        "doc/heat.md); T starts at Material/Temperature.");
      prm.declare_entry("Degree",
                        "0",
                        Integer(0, 2),
                        "Degree of the continuous temperature element; 0: the velocity's.");
      prm.declare_entry("Density", "2700", Double(), "Density rho of the metal (kg/m^3); AA6063: 2700.");
      prm.declare_entry("Specific heat",
                        "900",
                        Double(),
                        "Specific heat capacity c of the metal (J/(kg K)); AA6063: 900.");
      prm.declare_entry("Conductivity",
                        "209",
                        Double(),
                        "Thermal conductivity k of the metal (W/(m K)); AA6063: 209.");
      prm.declare_entry("Specific heat table",
                        "",
                        Anything(),
                        "c tabulated in T: 'T: c, T: c, ...' (K: J/(kg K), T ascending), "
                        "linear between the points and constant beyond them; the heat "
                        "content is int rho c dT. Empty: the constant Specific heat.");
      prm.declare_entry("Density table",
                        "",
                        Anything(),
                        "rho tabulated in T: 'T: rho, T: rho, ...' (K: kg/m^3, T ascending), "
                        "linear between the points and constant beyond them; with the "
                        "Specific heat (table) it makes the heat capacity per volume rho c "
                        "and the heat content int rho c dT. The flow stays incompressible: "
                        "the density's change with T (a few % over hot working) enters the "
                        "heat equation only. Empty: the constant Density.");
      prm.declare_entry("Conductivity table",
                        "",
                        Anything(),
                        "k tabulated in T: 'T: k, T: k, ...' (K: W/(m K), T ascending), "
                        "linear between the points and constant beyond them. Empty: the "
                        "constant Conductivity.");
      prm.declare_entry("Taylor-Quinney coefficient",
                        "0.9",
                        Double(),
                        "beta in [0, 1]: the share of the plastic work that becomes heat.");
      prm.declare_entry("Friction heat share",
                        "0.5",
                        Double(),
                        "The share in [0, 1] of the friction work at a die that heats the "
                        "metal (the rest goes into the die).");
      prm.declare_entry("Die effusivities",
                        "",
                        Anything(),
                        "'id: e, ...' (W s^1/2/(m^2 K)): for these dies the metal takes "
                        "e_m/(e_m + e) of the friction work instead of the Friction heat "
                        "share, e_m = sqrt(k rho c) the metal's at its temperature there "
                        "(the split of two half-spaces in sliding contact: Blok, "
                        "Jaeger). Hot-work tool steel (H13): about 9,000; AA6063: 22,000.");
      prm.declare_entry("Prescribed temperature ids",
                        "1",
                        Anything(),
                        "Boundary ids where T is given (the billet entering: die2d's 1).");
      prm.declare_entry("Prescribed temperature",
                        "723.15",
                        Anything(),
                        "T (K) on the Prescribed temperature ids, an expression in x, y[, z].");
      prm.declare_entry("Exact temperature",
                        "",
                        Anything(),
                        "For verification: the exact T (K) as an expression in x, y[, z]; "
                        "the L2 and largest nodal errors of T are reported (summary.json). "
                        "Empty: none.");
      prm.declare_entry("Heat transfer coefficients",
                        "",
                        Anything(),
                        "'id: h, ...' (W/(m^2 K)): the heat h (T - T_ambient) leaves "
                        "through these parts (dies: 5e3-5e4 in hot working; free "
                        "surfaces: 10-50 for air). Parts not listed (and not prescribed) "
                        "are insulated: symmetry lines, the ram.");
      prm.declare_entry("Ambient temperatures",
                        "",
                        Anything(),
                        "'id: T, ...' (K): the die's (or air's) temperature T_ambient of "
                        "each id of Heat transfer coefficients and Emissivities.");
      prm.declare_entry("Emissivities",
                        "",
                        Anything(),
                        "'id: e, ...' (e in [0, 1]): these parts also radiate "
                        "e sigma (T^4 - T_ambient^4), sigma = 5.670374e-8 W/(m^2 K^4) "
                        "(free surfaces in hot working: oxidised steel 0.8, aluminium "
                        "0.1-0.3).");
      prm.declare_entry("Conservative transfer",
                        "true",
                        Bool(),
                        "Runs in time: when the domain is meshed anew, T interpolated at the "
                        "new nodes is shifted uniformly so that the heat content per volume "
                        "is what it was (the interpolation's error, reported in the log, "
                        "spread over the metal). false: interpolated only.");
      prm.declare_entry("Step coupling",
                        "explicit",
                        Selection("explicit|trapezoid"),
                        "Runs in time: the sources of the heat step from t_n to t_n+1. "
                        "explicit: the flow of t_n's (one heat solve per step, first order "
                        "in dt). trapezoid: the mean of t_n's and t_n+1's, the step made "
                        "again with the flow of t_n+1 and that flow solved again at its T "
                        "until T changes by less than the Coupling tolerance (at most "
                        "Coupling iterations; second order in dt; a step onto a new mesh "
                        "stays explicit).");
      prm.declare_entry("Coupling iterations",
                        "10",
                        Integer(1, 100),
                        "The most heat solves per cycle, each followed by the flow's "
                        "Newton iteration at the new temperature.");
      prm.declare_entry("Coupling tolerance",
                        "1e-3",
                        Double(0),
                        "Heat and flow have settled when a heat solve changes T by less "
                        "than this part of the temperature's range over the metal (or "
                        "1e-6 K where it is uniform).");
      prm.declare_entry("Stabilisation",
                        "SUPG",
                        Selection("SUPG|none"),
                        "SUPG: streamline upwind Petrov-Galerkin (consistent; needed "
                        "where the cell Peclet number |v| h rho c / (2 k) exceeds 1). "
                        "none: Galerkin, for tests.");
    }
    prm.leave_subsection();
  }



  void
  ThermalProperty::set_constant(const double value)
  {
    points = {{0., value}};
  }



  void
  ThermalProperty::parse_table(const std::string &entry, const std::string &text, const double scale)
  {
    points.clear();
    std::stringstream items(text);
    std::string       item;
    while (std::getline(items, item, ','))
      {
        const auto colon = item.find(':');
        require(colon != std::string::npos, entry, "'" + item + "' is not 'T: value'");
        const auto number = [&](const std::string &part) {
          char *       end   = nullptr;
          const double value = std::strtod(part.c_str(), &end);
          while (end != nullptr && (*end == ' ' || *end == '\t'))
            ++end;
          require(end != part.c_str() && *end == '\0' && std::isfinite(value), entry, "'" + part + "' is not a number");
          return value;
        };
        const double T = number(item.substr(0, colon)), value = number(item.substr(colon + 1));
        require(T > 0, entry, "T = " + deck_number(T) + " is not above absolute zero (K)");
        require(value > 0, entry, "the value at T = " + deck_number(T) + " must be positive");
        require(points.empty() || T > points.back().first, entry, "the temperatures must ascend");
        points.emplace_back(T, scale * value);
      }
    require(!points.empty(), entry, "has no points");
  }



  namespace
  {
    /// A table's value at @p T: linear between its points, constant beyond them.
    double
    table_value(const std::vector<std::pair<double, double>> &table, const double T)
    {
      if (T <= table.front().first)
        return table.front().second;
      if (T >= table.back().first)
        return table.back().second;
      const auto upper =
        std::upper_bound(table.begin(), table.end(), T, [](const double t, const auto &p) { return t < p.first; });
      const auto lower = upper - 1;
      return lower->second + (upper->second - lower->second) * (T - lower->first) / (upper->first - lower->first);
    }

    /// A table's slope at @p T (0 beyond its ends and for a constant).
    double
    table_slope(const std::vector<std::pair<double, double>> &table, const double T)
    {
      if (T <= table.front().first || T >= table.back().first)
        return 0;
      const auto upper =
        std::upper_bound(table.begin(), table.end(), T, [](const double t, const auto &p) { return t < p.first; });
      const auto lower = upper - 1;
      return (upper->second - lower->second) / (upper->first - lower->first);
    }
  } // namespace



  void
  ThermalProperty::times(const ThermalProperty &other)
  {
    // (Two tables at most: parse_parameters() multiplies c by rho once.)
    factor = other.points;
    if (factor.size() == 1)
      {
        // A constant factor scales the table.
        for (auto &p : points)
          p.second *= factor.front().second;
        factor = {{0., 1.}};
      }
  }



  double
  ThermalProperty::value(const double T) const
  {
    return table_value(points, T) * table_value(factor, T);
  }



  double
  ThermalProperty::slope(const double T) const
  {
    return table_slope(points, T) * table_value(factor, T) + table_value(points, T) * table_slope(factor, T);
  }



  double
  ThermalProperty::integral(const double T) const
  {
    if (is_constant())
      return value(0.) * T;
    // From 0 K over the pieces between the tables' points, on each of
    // which the value is at most quadratic: Simpson's rule is exact.
    std::vector<double> breaks;
    for (const Table *table : {&points, &factor})
      if (table->size() > 1)
        for (const auto &p : *table)
          if (p.first < T)
            breaks.push_back(p.first);
    breaks.push_back(T);
    std::sort(breaks.begin(), breaks.end());
    double sum = 0, a = 0;
    for (const double b : breaks)
      {
        if (b > a)
          sum += (b - a) / 6 * (value(a) + 4 * value(0.5 * (a + b)) + value(b));
        a = std::max(a, b);
      }
    return sum;
  }



  double
  HeatParameters::wall_flux(const BoundaryId id, const double T) const
  {
    if (!exchanges(id))
      return 0;
    const double T_a = ambient_temperature.at(id);
    const auto   h   = transfer_coefficient.find(id);
    const auto   e   = emissivity.find(id);
    return (h != transfer_coefficient.end() ? h->second * (T - T_a) : 0.) +
           (e != emissivity.end() ? e->second * stefan_boltzmann * (T * T * T * T - T_a * T_a * T_a * T_a) : 0.);
  }



  double
  HeatParameters::friction_share_at(const BoundaryId die, const double T) const
  {
    const auto e = die_effusivity.find(die);
    if (e == die_effusivity.end())
      return friction_share;
    // k rho c in N^2/(mm^2 s K^2): its root in N/(mm s^1/2 K), as the die's.
    const double metal = std::sqrt(conductivity.value(T) * heat_capacity.value(T));
    return metal / (metal + e->second);
  }



  void
  HeatParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Heat");
    model         = prm.get("Model") == "steady" ? Model::steady : prm.get("Model") == "transient" ? Model::transient : Model::off;
    stabilisation = prm.get("Stabilisation") == "SUPG" ? Stabilisation::supg : Stabilisation::none;
    degree        = prm.get_integer("Degree");
    const auto positive = [&](const std::string &entry) { return get_positive(prm, "Heat/", entry); };
    const auto share    = [&](const std::string &entry) {
      const double x = prm.get_double(entry);
      require(std::isfinite(x) && x >= 0 && x <= 1, "Heat/" + entry, "must lie in [0, 1], got " + prm.get(entry));
      return x;
    };
    // SI to mm, s, N, K (heat_parameters.h).
    const auto tabulated = [&](const std::string &entry) {
      return prm.get(entry).find_first_not_of(" \t") != std::string::npos;
    };
    // rho c in N/(mm^2 K) = 1e-6 rho[kg/m^3] c[J/(kg K)].
    ThermalProperty density;
    if (tabulated("Density table"))
      density.parse_table("Heat/Density table", prm.get("Density table"), 1e-6);
    else
      density.set_constant(1e-6 * positive("Density"));
    if (tabulated("Specific heat table"))
      heat_capacity.parse_table("Heat/Specific heat table", prm.get("Specific heat table"), 1.);
    else
      heat_capacity.set_constant(positive("Specific heat"));
    heat_capacity.times(density);
    if (prm.get("Conductivity table").find_first_not_of(" \t") == std::string::npos)
      conductivity.set_constant(positive("Conductivity"));
    else
      conductivity.parse_table("Heat/Conductivity table", prm.get("Conductivity table"), 1.);
    taylor_quinney      = share("Taylor-Quinney coefficient");
    friction_share      = share("Friction heat share");
    die_effusivity.clear();
    for (const auto &[id, e] : parse_id_value_map("Heat/Die effusivities", prm.get("Die effusivities")))
      {
        require(std::isfinite(e) && e > 0, "Heat/Die effusivities", "e of id " + std::to_string(id) + " must be positive");
        die_effusivity[id] = 1e-3 * e;
      }
    prescribed_ids      = parse_id_list("Heat/Prescribed temperature ids", prm.get("Prescribed temperature ids"));
    prescribed_temperature = prm.get("Prescribed temperature");
    exact_temperature      = prm.get("Exact temperature");
    transfer_coefficient.clear();
    ambient_temperature.clear();
    for (const auto &[id, h] : parse_id_value_map("Heat/Heat transfer coefficients", prm.get("Heat transfer coefficients")))
      {
        require(std::isfinite(h) && h >= 0,
                "Heat/Heat transfer coefficients",
                "h of id " + std::to_string(id) + " must not be negative");
        require(!prescribed_ids.count(id),
                "Heat/Heat transfer coefficients",
                "id " + std::to_string(id) + " is also under Prescribed temperature ids");
        transfer_coefficient[id] = 1e-3 * h;
      }
    emissivity.clear();
    for (const auto &[id, e] : parse_id_value_map("Heat/Emissivities", prm.get("Emissivities")))
      {
        require(std::isfinite(e) && e >= 0 && e <= 1,
                "Heat/Emissivities",
                "e of id " + std::to_string(id) + " must lie in [0, 1]");
        require(!prescribed_ids.count(id),
                "Heat/Emissivities",
                "id " + std::to_string(id) + " is also under Prescribed temperature ids");
        emissivity[id] = e;
      }
    for (const auto &[id, T] : parse_id_value_map("Heat/Ambient temperatures", prm.get("Ambient temperatures")))
      {
        require(std::isfinite(T) && T > 0,
                "Heat/Ambient temperatures",
                "T of id " + std::to_string(id) + " must be above absolute zero (K)");
        require(transfer_coefficient.count(id) || emissivity.count(id),
                "Heat/Ambient temperatures",
                "id " + std::to_string(id) + " has no Heat transfer coefficient or Emissivity");
        ambient_temperature[id] = T;
      }
    for (const auto &[id, h] : transfer_coefficient)
      require(ambient_temperature.count(id),
              "Heat/Ambient temperatures",
              "id " + std::to_string(id) + " of Heat transfer coefficients needs one");
    for (const auto &[id, e] : emissivity)
      require(ambient_temperature.count(id),
              "Heat/Ambient temperatures",
              "id " + std::to_string(id) + " of Emissivities needs one");
    conservative_transfer = prm.get_bool("Conservative transfer");
    step_coupling = prm.get("Step coupling") == "trapezoid" ? StepCoupling::trapezoid : StepCoupling::explicit_sources;
    coupling_iterations = prm.get_integer("Coupling iterations");
    coupling_tolerance  = prm.get_double("Coupling tolerance");
    require(std::isfinite(coupling_tolerance) && coupling_tolerance > 0,
            "Heat/Coupling tolerance",
            "must be positive");
    prm.leave_subsection();
  }
} // namespace dieflow
