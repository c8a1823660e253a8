// Heat in time: adiabatic frictionless upsetting heats the block uniformly, T(t) following an ODE solved here independently; the step's scheme exactly, its order in dt, the balance, and a restart that loses nothing.
//
// The plane-strain quarter block of incremental_upsetting_plane_strain
// (x in [0, h], y in [0, w], h_0 = 1, w_0 = 2; symmetry ids 1, 3, the platen
// id 2 moving at V = -1 with its tangential velocity free, the side id 4
// traction free), Newtonian with the Arrhenius viscosity
//   eta(T) = eta_0 exp(Q/R (1/T - 1/T_0)),  eta_0 = 1 MPa s, Q = 100 kJ/mol, T_0 = 300 K,
// insulated (no prescribed T, no transfer), rho c = 1 N/(mm^2 K), beta = 1.
// The flow is homogeneous, v = (-x, y)/h, 2 eta D:D = 4 eta/h^2, and so is
// T: rho c dT/dt = 4 beta eta(T)/h^2, h = 1 - t. Separating,
//   int_{T_0}^{T} exp(-Q/R (1/s - 1/T_0)) ds = 4 beta eta_0/(rho c) (1/h - 1),
// solved here with Simpson's rule (4000 intervals) and Newton: a rise of
// 2.2 K by t = 0.4 that lowers eta by a quarter, the platen force
// -4 eta(T)/h times the width w = volume/h.
// The program's step (heat_equation.h) is backward Euler with the sources
// of the flow at t_n: for this flow T_{n+1} = T_n + dt 4 beta eta(T_n)/(rho c h_n^2)
// exactly (forward Euler on the ODE: the flow of t_n at T_n). Checked: T at
// every step against that recurrence to 1e-6 of the rise (the source is
// quadratic in a velocity that the penalty's compressibility and Newton's
// stopping leave 1e-8 to 1e-7 off the homogeneous flow: measured 1.6e-7),
// uniform to 1e-9 K, the force at every step against -4 eta(T_n)/h_n w_n to
// 1e-6 (as in the isothermal test); the balance (plastic heat =
// stored) closed to 1e-9 every step; against the ODE at t = 0.4 with
// dt = 0.02 and 0.01: the error of T (of the rise) and of the force of first
// order (0.8 to 1.2); the run restarted from its checkpoint at t = 0.2 ends
// with the uninterrupted run's T and force to 1e-12.
#include "heat_upsetting.h"

#include <iomanip>
#include <iostream>

using namespace heat_upsetting;

namespace
{
  Run
  run(const std::string &output, const double dt, const double end = 0.4, const std::string &restart_from = "")
  {
    const fuzz::Outcome outcome = fuzz::run(output + ".prm", deck(output, dt, end, restart_from));
    const auto          tree    = fuzz::summary(output);
    Run                 r;
    r.converged = outcome.status == 0;
    double T    = T_0;
    bool   first = true;
    for (const auto &[key, cycle] : tree.get_child("cycles"))
      {
        const double t = fuzz::number(cycle, "step|time"), h = 1 - t;
        const double T_max = fuzz::number(cycle, "heat|T_max"), T_min = fuzz::number(cycle, "heat|T_min");
        const double width = fuzz::number(cycle, "step|volume") / h;
        r.T = T_max, r.F = fuzz::number(cycle, "quantities|F_x[2]"), r.h = h, r.width = width;
        // A restarted run's first cycle is the step after the checkpoint's: its T starts the recurrence.
        if (first && !restart_from.empty())
          T = T_max;
        first = false;
        r.converged = r.converged && cycle.get<std::string>("converged", "false") == "true";
        r.recurrence = r.recurrence && std::abs(T_max - T) <= 1e-6 * (T - T_0);
        r.uniform    = r.uniform && T_max - T_min < 1e-9;
        r.force      = r.force && std::abs(r.F / (-4 * viscosity(T_max) / h * width) - 1) < 1e-6;
        if (t > 0)
          r.balanced = r.balanced && std::abs(fuzz::number(cycle, "heat|balance_error")) < 1e-9;
        T += dt * 4 * beta * viscosity(T) / (rho_c * h * h);
      }
    return r;
  }
} // namespace

int
main()
{
  const double T_exact = exact_temperature(0.6);
  std::cout << std::setprecision(6) << "ODE at t = 0.4 (h = 0.6): T = " << T_exact << " K, eta/eta_0 = "
            << viscosity(T_exact) / eta_0 << std::endl;
  const auto verdict = [](const bool ok) { return ok ? "yes" : "NO"; };
  double     T_error[2], F_error[2];
  Run        runs[2];
  for (unsigned int i = 0; i < 2; ++i)
    {
      const double dt = i == 0 ? 0.02 : 0.01;
      runs[i]         = run(i == 0 ? "adiabatic_coarse" : "adiabatic_fine", dt);
      const Run &r    = runs[i];
      T_error[i]      = std::abs(r.T - T_exact) / (T_exact - T_0);
      F_error[i]      = std::abs(r.F / (-4 * viscosity(T_exact) / r.h * r.width) - 1);
      std::cout << "dt = " << dt << ": every step converged: " << verdict(r.converged)
                << "; T the recurrence's to 1e-6 of the rise: " << verdict(r.recurrence)
                << "; uniform: " << verdict(r.uniform) << "; force -4 eta(T)/h w to 1e-6: " << verdict(r.force)
                << "; balance to 1e-9: " << verdict(r.balanced) << std::endl
                << "  at t = 0.4: T error (of the rise) " << std::scientific << std::setprecision(2) << T_error[i]
                << ", force error " << F_error[i] << std::defaultfloat << std::setprecision(6) << std::endl;
    }
  const double T_order = std::log2(T_error[0] / T_error[1]), F_order = std::log2(F_error[0] / F_error[1]);
  std::cout << "first order in dt (0.8 to 1.2), T and force: "
            << verdict(T_order > 0.8 && T_order < 1.2 && F_order > 0.8 && F_order < 1.2) << std::endl;

  // The run stopped at t = 0.2 (its checkpoint: the last step's) and gone on from there.
  run("adiabatic_half", 0.02, 0.2);
  const Run restarted = run("adiabatic_restarted", 0.02, 0.4, "adiabatic_half/checkpoint.dat");
  std::cout << "restart from t = 0.2: converged " << verdict(restarted.converged) << ", the recurrence "
            << verdict(restarted.recurrence) << ", T and force the uninterrupted run's to 1e-12: "
            << verdict(std::abs(restarted.T / runs[0].T - 1) < 1e-12 && std::abs(restarted.F / runs[0].F - 1) < 1e-12)
            << std::endl;
  return 0;
}
