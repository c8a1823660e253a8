// The deck's Heat subsection: its entries, their units and their checks.
#include <dieflow/heat/heat_parameters.h>

#include <deal.II/base/utilities.h>

#include <cmath>

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
      prm.declare_entry("Taylor-Quinney coefficient",
                        "0.9",
                        Double(),
                        "beta in [0, 1]: the share of the plastic work that becomes heat.");
      prm.declare_entry("Friction heat share",
                        "0.5",
                        Double(),
                        "The share in [0, 1] of the friction work at a die that heats the "
                        "metal (the rest goes into the die).");
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
                        "each id of Heat transfer coefficients.");
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
    heat_capacity       = 1e-6 * positive("Density") * positive("Specific heat");
    conductivity        = positive("Conductivity");
    taylor_quinney      = share("Taylor-Quinney coefficient");
    friction_share      = share("Friction heat share");
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
    for (const auto &[id, T] : parse_id_value_map("Heat/Ambient temperatures", prm.get("Ambient temperatures")))
      {
        require(std::isfinite(T) && T > 0,
                "Heat/Ambient temperatures",
                "T of id " + std::to_string(id) + " must be above absolute zero (K)");
        require(transfer_coefficient.count(id),
                "Heat/Ambient temperatures",
                "id " + std::to_string(id) + " has no Heat transfer coefficient");
        ambient_temperature[id] = T;
      }
    for (const auto &[id, h] : transfer_coefficient)
      require(ambient_temperature.count(id),
              "Heat/Ambient temperatures",
              "id " + std::to_string(id) + " of Heat transfer coefficients needs one");
    coupling_iterations = prm.get_integer("Coupling iterations");
    coupling_tolerance  = prm.get_double("Coupling tolerance");
    require(std::isfinite(coupling_tolerance) && coupling_tolerance > 0,
            "Heat/Coupling tolerance",
            "must be positive");
    prm.leave_subsection();
  }
} // namespace dieflow
