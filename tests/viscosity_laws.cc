// The viscosity laws against independent computations:
//  - d eta / d epsdot against central finite differences (step 1e-6 relative:
//    truncation 1e-12, round-off 1e-10 relative to eta; tolerance 1e-7);
//  - the values against the formulas written out here (Norton-Hoff with
//    m = 1 is Newtonian with eta = K/3; Sellars-Tegart in its textbook form
//    with Z computed directly);
//  - Hansel-Spittel's rate and temperature part at two temperatures, its
//    strain terms (the Material's hardening factor) with their floor eps_0;
//  - the Material's regularisation: eta at epsdot_eq = 0 is the law at
//    epsdot_min, and its derivative is the chain rule of sqrt(e^2 + e0^2).
#include <dieflow/flow/material.h>

#include "report.h"

#include <cmath>
#include <iomanip>
#include <iostream>

using namespace dieflow;

namespace
{
  double
  worst_derivative_error(const ViscosityLaw &law)
  {
    double worst = 0;
    for (double rate = 1e-3; rate <= 1e3; rate *= 3.7)
      {
        const double h  = 1e-6 * rate;
        const double fd = (law.viscosity(rate + h) - law.viscosity(rate - h)) / (2 * h);
        const double scale = std::max(std::abs(law.derivative(rate)), law.viscosity(rate) / rate);
        worst = std::max(worst, std::abs(fd - law.derivative(rate)) / scale);
      }
    return worst;
  }
} // namespace

int
main()
{
  const NewtonianLaw     newtonian(0.278);
  const NortonHoffLaw    norton_hoff(0.834, 0.2);
  const NortonHoffLaw    linear_norton_hoff(0.834, 1.0);
  const SellarsTegartLaw sellars_tegart(0.040, 5.385, 141550, 22.5, 723.15);

  report("Newtonian derivative matches finite differences (1e-7)", worst_derivative_error(newtonian) < 1e-7);
  report("Norton-Hoff derivative matches finite differences (1e-7)", worst_derivative_error(norton_hoff) < 1e-7);
  report("Sellars-Tegart derivative matches finite differences (1e-7)",
         worst_derivative_error(sellars_tegart) < 1e-7);

  // Norton-Hoff: sigma_eq = K e^m and eta = sigma_eq / (3 e).
  bool values_ok = true;
  for (double rate = 1e-3; rate <= 1e3; rate *= 10)
    {
      values_ok &= std::abs(norton_hoff.viscosity(rate) * 3 * rate / (0.834 * std::pow(rate, 0.2)) - 1) < 1e-14;
      values_ok &= std::abs(linear_norton_hoff.viscosity(rate) / (0.834 / 3) - 1) < 1e-14;
    }
  report("Norton-Hoff gives sigma_eq = K epsdot^m, and K/3 for m = 1", values_ok);

  // Sellars-Tegart at 450 C: Z = e exp(Q/(R T)), sigma = asinh((Z/A)^(1/n))/alpha.
  bool st_ok = true;
  for (double rate : {0.01, 1.0, 10.0, 100.0})
    {
      const double Z     = rate * std::exp(141550. / (8.314462618 * 723.15));
      const double sigma = std::asinh(std::pow(Z / std::exp(22.5), 1. / 5.385)) / 0.040;
      st_ok &= std::abs(sellars_tegart.flow_stress(rate) / sigma - 1) < 1e-12;
      st_ok &= std::abs(sellars_tegart.viscosity(rate) * 3 * rate / sigma - 1) < 1e-12;
    }
  report("Sellars-Tegart gives the textbook flow stress", st_ok);
  std::cout << "AA6063 flow stress at 450 C and 10 1/s: " << std::fixed << std::setprecision(2)
            << sellars_tegart.flow_stress(10.) << " MPa" << std::endl;

  // Hansel-Spittel's rate and temperature part, T in C: A e^(m1 T) T^m9 epsdot^(m3 + m8 T).
  const HanselSpittelLaw hansel_spittel(2., -0.002, 0.12, 2e-4, 0.1, 573.15);
  report("Hansel-Spittel derivative matches finite differences (1e-7)",
         worst_derivative_error(hansel_spittel) < 1e-7);
  bool hs_ok = true;
  for (const double T : {573.15, 723.15})
    for (double rate = 1e-3; rate <= 1e3; rate *= 10)
      {
        const double celsius = T - 273.15;
        const double sigma   = 2. * std::exp(-0.002 * celsius) * std::pow(celsius, 0.1) * std::pow(rate, 0.12 + 2e-4 * celsius);
        hs_ok &= std::abs(hansel_spittel.viscosity_at(rate, T) * 3 * rate / sigma - 1) < 1e-12;
        const double h  = 1e-6 * rate;
        const double fd = (hansel_spittel.viscosity_at(rate + h, T) - hansel_spittel.viscosity_at(rate - h, T)) / (2 * h);
        hs_ok &= std::abs(fd - hansel_spittel.derivative_at(rate, T)) < 1e-7 * hansel_spittel.viscosity_at(rate, T) / rate;
      }
  report("Hansel-Spittel gives A e^(m1 T) T^m9 epsdot^(m3 + m8 T), T in C, at 300 and 450 C", hs_ok);
  {
    // Its strain terms, the Material's hardening factor: eps^m2 e^(m4/eps) (1 + eps)^(m5 T) e^(m7 eps), eps >= eps_0.
    ParameterHandler hs;
    Material::declare_parameters(hs);
    hs.parse_input_from_string("subsection Material\n set Law = Hansel-Spittel\n set Hansel-Spittel m2 = 0.2\n"
                               " set Hansel-Spittel m4 = -0.01\n set Hansel-Spittel m5 = 5e-4\n"
                               " set Hansel-Spittel m7 = -0.3\n set Hardening strain eps0 = 0.02\nend\n");
    Material hs_material;
    hs_material.parse_parameters(hs);
    const auto g = [](const double eps, const double celsius) {
      return std::pow(eps, 0.2) * std::exp(-0.01 / eps) * std::pow(1 + eps, 5e-4 * celsius) * std::exp(-0.3 * eps);
    };
    bool g_ok = hs_material.hardens();
    for (const double T : {573.15, 723.15})
      for (const double eps : {0.05, 0.5, 2.0})
        g_ok &= std::abs(hs_material.hardening(eps, T) / g(eps, T - 273.15) - 1) < 1e-14;
    g_ok &= hs_material.hardening(0., 723.15) == hs_material.hardening(0.02, 723.15);
    g_ok &= std::abs(hs_material.hardening(0.5) / g(0.5, 450.) - 1) < 1e-14; // at Material/Temperature, 450 C
    report("Hansel-Spittel's strain terms are the hardening factor, eps taken no smaller than eps_0", g_ok);
  }

  // The Material's regularisation and bounds, through a deck.
  ParameterHandler prm;
  Material::declare_parameters(prm);
  prm.parse_input_from_string("subsection Material\n set Law = Norton-Hoff\n set Minimum strain rate = 0.01\n"
                              " set Minimum viscosity = 0.05\nend\n");
  Material material;
  material.parse_parameters(prm);
  const auto at_rest = material.evaluate(0.);
  report("at rest, eta = law at epsdot_min", std::abs(at_rest.eta / norton_hoff.viscosity(0.01) - 1) < 1e-14);
  bool chain_ok = true;
  for (double rate = 0.1; rate <= 8.5; rate *= 3) // eta above its 0.05 bound
    {
      const double h  = 1e-6 * rate;
      const double fd = (material.evaluate(rate + h).eta - material.evaluate(rate - h).eta) / (2 * h);
      const auto   v  = material.evaluate(rate);
      chain_ok &= std::abs(fd - v.d_eta * rate / v.rate) < 1e-7 * v.eta / rate;
    }
  report("regularised derivative is d eta/d r x d r/d epsdot", chain_ok);
  const auto clipped = material.evaluate(1000.);
  report("minimum viscosity clips eta to 0.05 with zero derivative",
         norton_hoff.viscosity(1000.) < 0.05 && clipped.eta == 0.05 && clipped.d_eta == 0);
}
