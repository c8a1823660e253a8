// The heat and the flow coupled: plane Couette flow whose viscosity falls with its own viscous heating (the Nahme-Griffith problem), against an independent solution of its ODE.
//
// A layer 0 < y < H = 1 (4 mm long) between a wall at rest (id 3) and one
// moving at U = 10 mm/s (id 4), both at T_0 = 300 K; the ends (ids 1, 2)
// hold v_y = 0 only and are insulated, so the flow and the temperature do
// not depend on x: sigma_xx = -p = 0 and k dT/dx = 0 there. Newtonian with
// the Arrhenius viscosity of Material::evaluate(rate, T):
//   eta(T) = eta_0 exp(Q/R (1/T - 1/T_0)),  eta_0 = 1 MPa s, Q = 20 kJ/mol,
// rho c = 1 N/(mm^2 K), k = 1 N/(s K), beta = 1. The shear stress tau is
// uniform, u' = tau/eta(T), and k T'' = -tau u' = -tau^2/eta(T) with
// T(0) = T(H) = T_0, int u' = U. Independently of the program: shooting on
// (tau, T'(0)) with Newton over RK4 (4000 steps to y = H/2, where T' = 0
// and u = U/2 by symmetry), converged to 1e-12. The viscous heating lowers
// eta by a quarter in the middle: the isothermal tau is eta_0 U/H = 10 MPa.
// The program (velocity and temperature of degree 2, SUPG, 2 to 32 cells
// across) must converge to it: the wall shear F_x[4]/L and T_max = T(H/2)
// within 1e-4 relative on the finest mesh and at an order of at least 3
// (measured 3.9-4.0: quadratic elements, smooth solution), every cycle's
// coupling settled and its heat balance closed to 1e-9. The dual-weighted
// estimate of F_x[4] (Refinement/Dual-weighted estimate; its dual problem
// and its residual at the field's T) has the true error's sign and 10 to
// 100 % of it on the first three meshes (measured 0.25, 0.23, 0.17; after
// that the error reaches the solvers' tolerance): not all of it, as the
// dual is the flow's at a frozen T and misses T's own discretisation
// error, here the larger part. Before 2026-12-03 the dual problem read the
// flow's point temperatures at its own quadrature (another size: the run
// stopped in UMFPACK); with the residual's viscosity at Material/Temperature
// the estimate is 1e-6 of the error (tried: the check fails).
#include "fuzz.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <iostream>

namespace
{
  constexpr double eta_0 = 1, U = 10, H = 1, k = 1, T_0 = 300, Q = 20000, R = 8.314462618, L = 4;

  double
  viscosity(const double T)
  {
    return eta_0 * std::exp(Q / R * (1. / T - 1. / T_0));
  }

  /// (T'(H/2), u(H/2) - U/2) for the shot (tau, T'(0)); T(H/2) into @p T_mid.
  std::array<double, 2>
  shoot(const double tau, const double slope, double &T_mid)
  {
    const unsigned int    n = 4000;
    const double          h = H / 2 / n;
    std::array<double, 3> y{{T_0, slope, 0}}; // T, T', u
    const auto            f = [&](const std::array<double, 3> &s) {
      const double eta = viscosity(s[0]);
      return std::array<double, 3>{{s[1], -tau * tau / (k * eta), tau / eta}};
    };
    for (unsigned int i = 0; i < n; ++i)
      {
        const auto            k1 = f(y);
        std::array<double, 3> s;
        for (unsigned int j = 0; j < 3; ++j)
          s[j] = y[j] + h / 2 * k1[j];
        const auto k2 = f(s);
        for (unsigned int j = 0; j < 3; ++j)
          s[j] = y[j] + h / 2 * k2[j];
        const auto k3 = f(s);
        for (unsigned int j = 0; j < 3; ++j)
          s[j] = y[j] + h * k3[j];
        const auto k4 = f(s);
        for (unsigned int j = 0; j < 3; ++j)
          y[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
      }
    T_mid = y[0];
    return {{y[1], y[2] - U / 2}};
  }

  std::string
  deck(const unsigned int cycles)
  {
    return "set Output directory = nahme\nset Write VTU = false\n"
           "subsection Mesh\n  set Source = box\n  subsection Box\n    set Lower corner = 0, 0\n"
           "    set Upper corner = 4, 1\n    set Subdivisions = 4, 2\n  end\nend\n"
           "subsection Material\n  set Law = Newtonian\n  set Viscosity = 1\n  set Temperature = 300\n"
           "  set Activation energy Q = 20000\nend\n"
           "subsection Boundary conditions\n  set Prescribed velocity ids = 1, 2, 3, 4\n  set Symmetry ids =\n"
           "  set Slip wall ids =\n  set Traction free ids =\n"
           "  subsection Prescribed velocity 1\n    set Velocity = 0; 0\n    set Components = y\n  end\n"
           "  subsection Prescribed velocity 2\n    set Velocity = 0; 0\n    set Components = y\n  end\n"
           "  subsection Prescribed velocity 3\n    set Velocity = 0; 0\n  end\n"
           "  subsection Prescribed velocity 4\n    set Velocity = 10; 0\n  end\nend\n"
           "subsection Contact\n  set Die ids =\nend\n"
           "subsection Refinement\n  set Cycles = " +
           std::to_string(cycles) +
           "\n  set Strategy = global\n  set Dual-weighted estimate = true\n  set Target quantity = F_x[4]\nend\n"
           "subsection Discretisation\n  set Velocity degree = 2\nend\n"
           "subsection Heat\n  set Model = steady\n  set Density = 1000\n  set Specific heat = 1000\n"
           "  set Conductivity = 1\n  set Taylor-Quinney coefficient = 1\n"
           "  set Prescribed temperature ids = 3, 4\n  set Prescribed temperature = 300\n"
           "  set Coupling tolerance = 1e-10\n  set Coupling iterations = 40\nend\n";
  }
} // namespace

int
main()
{
  // The ODE's solution: Newton on the shot with central differences.
  double tau = eta_0 * U / H, slope = tau * U / (2 * k * H), T_mid = 0;
  for (unsigned int it = 0; it < 50; ++it)
    {
      const auto   r = shoot(tau, slope, T_mid);
      const double d_tau = 1e-6 * tau, d_slope = 1e-6 * slope;
      double       dummy;
      const auto   r_tau_p = shoot(tau + d_tau, slope, dummy), r_tau_m = shoot(tau - d_tau, slope, dummy);
      const auto   r_s_p = shoot(tau, slope + d_slope, dummy), r_s_m = shoot(tau, slope - d_slope, dummy);
      const double a = (r_tau_p[0] - r_tau_m[0]) / (2 * d_tau), b = (r_s_p[0] - r_s_m[0]) / (2 * d_slope);
      const double c = (r_tau_p[1] - r_tau_m[1]) / (2 * d_tau), d = (r_s_p[1] - r_s_m[1]) / (2 * d_slope);
      const double det = a * d - b * c;
      tau -= (d * r[0] - b * r[1]) / det;
      slope -= (-c * r[0] + a * r[1]) / det;
      if (std::abs(r[0]) < 1e-12 && std::abs(r[1]) < 1e-12)
        break;
    }
  shoot(tau, slope, T_mid);
  std::cout << std::setprecision(6) << "ODE: wall shear tau = " << tau << " MPa (isothermal " << eta_0 * U / H
            << "), T(H/2) = " << T_mid << " K, eta(T(H/2)) / eta_0 = " << viscosity(T_mid) / eta_0 << std::endl;

  const unsigned int  cycles  = 5;
  const fuzz::Outcome outcome = fuzz::run("nahme.prm", deck(cycles));
  const auto          tree    = fuzz::summary("nahme");
  std::cout << "exit status " << outcome.status << std::endl;
  std::vector<double> tau_error, T_error, effectivity;
  bool                settled = true, balanced = true;
  for (const auto &[key, cycle] : tree.get_child("cycles"))
    {
      const double shear = fuzz::number(cycle, "quantities|F_x[4]") / L;
      const double T_max = fuzz::number(cycle, "heat|T_max");
      tau_error.push_back(std::abs(shear - tau) / tau);
      // The dual-weighted estimate of F_x[4] exact - computed, against the true error tau L - F_x[4].
      effectivity.push_back(fuzz::number(cycle, "dual_weighted_error") / (tau * L - fuzz::number(cycle, "quantities|F_x[4]")));
      T_error.push_back(std::abs(T_max - T_mid) / (T_mid - T_0));
      settled = settled && cycle.get<std::string>("heat.settled", "false") == "true";
      balanced = balanced && std::abs(fuzz::number(cycle, "heat|balance_error")) < 1e-9;
      // (Errors below 1e-5 are left unprinted: the solvers' tolerances reach them.)
      if (tau_error.back() > 1e-5 && T_error.back() > 1e-5)
        std::cout << "cycle " << cycle.get<std::string>("cycle") << ": tau error " << std::scientific
                  << std::setprecision(1) << tau_error.back() << ", T(H/2) error (of the rise) " << T_error.back()
                  << std::defaultfloat << std::endl;
    }
  const auto order = [](const std::vector<double> &e) {
    return e.size() < 2 ? 0. : std::log(e[e.size() - 2] / e.back()) / std::log(2.);
  };
  const auto verdict = [](const bool ok) { return ok ? "yes" : "NO"; };
  const bool all_cycles = tau_error.size() == cycles;
  std::cout << "converged, every cycle: " << verdict(outcome.status == 0 && all_cycles) << std::endl
            << "the coupling settled in every cycle: " << verdict(settled) << std::endl
            << "heat balance closed to 1e-9 in every cycle: " << verdict(balanced) << std::endl
            << "wall shear within 1e-4 of the ODE's: " << verdict(all_cycles && tau_error.back() < 1e-4) << std::endl
            << "T(H/2) within 1e-4 (of the rise) of the ODE's: " << verdict(all_cycles && T_error.back() < 1e-4)
            << std::endl
            << "orders at least 3: " << verdict(all_cycles && order(tau_error) > 3 && order(T_error) > 3) << std::endl
            << "the dual-weighted estimate has the true error's sign and 10 to 100 % of it on the first three meshes: "
            << verdict(all_cycles && std::all_of(effectivity.begin(), effectivity.begin() + 3,
                                                 [](const double e) { return e > 0.1 && e < 1; }))
            << std::endl;
  return 0;
}
