// The adiabatic upsetting of the heat-in-time tests: the Newtonian-Arrhenius block, its ODE's T solved independently, the deck, and what a run is checked for.
#ifndef dieflow_tests_heat_upsetting_h
#define dieflow_tests_heat_upsetting_h

#include "fuzz.h"

#include <cmath>
#include <sstream>
#include <string>

namespace heat_upsetting
{
  inline constexpr double eta_0 = 1, Q = 1e5, R = 8.314462618, T_0 = 300, rho_c = 1, beta = 1;

  inline double
  viscosity(const double T)
  {
    return eta_0 * std::exp(Q / R * (1. / T - 1. / T_0));
  }

  /// The ODE's T at height h: int_{T_0}^{T} 1/f(s) ds = 4 beta eta_0 (1/h - 1)/(rho c), f = eta/eta_0.
  inline double
  exact_temperature(const double h)
  {
    const double target = 4 * beta * eta_0 * (1. / h - 1.) / rho_c;
    const auto   G      = [](const double T) {
      const unsigned int n = 4000;
      const double       d = (T - T_0) / n;
      double             sum = 0;
      for (unsigned int i = 0; i <= n; ++i)
        sum += (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2)) * eta_0 / viscosity(T_0 + i * d);
      return sum * d / 3;
    };
    double T = T_0 + target;
    for (unsigned int it = 0; it < 50; ++it)
      {
        const double step = (G(T) - target) / (eta_0 / viscosity(T));
        T -= step;
        if (std::abs(step) < 1e-13)
          break;
      }
    return T;
  }

  inline std::string
  deck(const std::string &output, const double dt, const double end, const std::string &restart_from,
       const std::string &heat_lines = "")
  {
    std::ostringstream text;
    text << "set Output directory = " << output << "\nset Write VTU = false\nset Problem = incremental\n"
         << "subsection Incremental\n  set Time step = " << dt << "\n  set End time = " << end << "\n"
         << "  set Checkpoint interval = 0\n"
         << "  set Restart from = " << restart_from << "\nend\n"
         << "subsection Mesh\n  set Source = box\n  subsection Box\n    set Lower corner = 0, 0\n"
         << "    set Upper corner = 1, 2\n    set Subdivisions = 4, 4\n  end\nend\n"
         << "subsection Material\n  set Law = Newtonian\n  set Viscosity = 1\n  set Temperature = 300\n"
         << "  set Activation energy Q = 100000\nend\n"
         << "subsection Boundary conditions\n  set Prescribed velocity ids = 2\n  set Symmetry ids = 1, 3\n"
         << "  set Slip wall ids =\n  set Traction free ids = 4\n"
         << "  subsection Prescribed velocity 2\n    set Velocity = -1; 0\n    set Components = x\n  end\nend\n"
         << "subsection Contact\n  set Die ids =\nend\n"
         << "subsection Heat\n  set Model = transient\n  set Density = 1000\n  set Specific heat = 1000\n"
         << "  set Conductivity = 1\n  set Taylor-Quinney coefficient = 1\n  set Prescribed temperature ids =\n"
         << heat_lines << "end\n";
    return text.str();
  }

  struct Run
  {
    bool   converged = true, recurrence = true, uniform = true, force = true, balanced = true;
    double T = 0, F = 0, h = 0, width = 0;
  };

} // namespace heat_upsetting

#endif
