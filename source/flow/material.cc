// The material: the viscosity laws (Newtonian, Norton-Hoff, Sellars-Tegart, Hansel-Spittel), their regularisation and bounds, strain hardening, the penalty factor.
#include <dieflow/flow/material.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dieflow
{
  namespace
  {
    // Universal gas constant, J/(mol K).
    constexpr double gas_constant = 8.314462618;
    // 0 C in K: Hansel-Spittel's constants are fitted to T in degrees Celsius.
    constexpr double zero_celsius = 273.15;
  } // namespace

  NewtonianLaw::NewtonianLaw(const double eta)
    : eta(eta)
  {}

  double
  NewtonianLaw::viscosity(const double) const
  {
    return eta;
  }

  double
  NewtonianLaw::derivative(const double) const
  {
    return 0;
  }



  NortonHoffLaw::NortonHoffLaw(const double K, const double m)
    : K(K)
    , m(m)
  {}

  double
  NortonHoffLaw::viscosity(const double rate) const
  {
    return K / 3. * std::pow(rate, m - 1.);
  }

  double
  NortonHoffLaw::derivative(const double rate) const
  {
    return (m - 1.) * viscosity(rate) / rate;
  }



  SellarsTegartLaw::SellarsTegartLaw(const double alpha,
                                     const double n,
                                     const double Q,
                                     const double ln_A,
                                     const double temperature)
    : alpha(alpha)
    , n(n)
    , ln_Z_over_A_shift(Q / (gas_constant * temperature) - ln_A)
  {}

  double
  SellarsTegartLaw::zener_ratio_root(const double rate) const
  {
    return std::exp((std::log(rate) + ln_Z_over_A_shift) / n);
  }

  double
  SellarsTegartLaw::flow_stress(const double rate) const
  {
    return std::asinh(zener_ratio_root(rate)) / alpha;
  }

  double
  SellarsTegartLaw::viscosity(const double rate) const
  {
    return flow_stress(rate) / (3. * rate);
  }

  double
  SellarsTegartLaw::derivative(const double rate) const
  {
    const double s              = zener_ratio_root(rate);
    const double d_stress_d_rate = s / (n * alpha * rate * std::sqrt(1. + s * s));
    return (d_stress_d_rate - 3. * viscosity(rate)) / (3. * rate);
  }



  HanselSpittelLaw::HanselSpittelLaw(const double A,
                                     const double m1,
                                     const double m3,
                                     const double m8,
                                     const double m9,
                                     const double reference_temperature)
    : A(A)
    , m1(m1)
    , m3(m3)
    , m8(m8)
    , m9(m9)
    , reference_temperature(reference_temperature)
  {}

  double
  HanselSpittelLaw::rate_exponent(const double T) const
  {
    return std::clamp(m3 + m8 * (T - zero_celsius), 1e-3, 1.);
  }

  double
  HanselSpittelLaw::viscosity_at(const double rate, const double T) const
  {
    const double celsius = T - zero_celsius;
    const double factor  = A * std::exp(m1 * celsius) * (m9 != 0 ? std::pow(std::max(celsius, 1.), m9) : 1.);
    return factor / 3. * std::pow(rate, rate_exponent(T) - 1.);
  }

  double
  HanselSpittelLaw::derivative_at(const double rate, const double T) const
  {
    return (rate_exponent(T) - 1.) * viscosity_at(rate, T) / rate;
  }

  double
  HanselSpittelLaw::viscosity(const double rate) const
  {
    return viscosity_at(rate, reference_temperature);
  }

  double
  HanselSpittelLaw::derivative(const double rate) const
  {
    return derivative_at(rate, reference_temperature);
  }



  void
  Material::declare_parameters(ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Material");
    {
      prm.declare_entry("Law",
                        "Newtonian",
                        Selection("Newtonian|Norton-Hoff|Sellars-Tegart|Hansel-Spittel"),
                        "Viscosity law eta(epsdot_eq) with epsdot_eq = sqrt(2/3 D:D) "
                        "and sigma_eq = 3 eta epsdot_eq. Newtonian: eta = Viscosity. "
                        "Norton-Hoff: sigma_eq = K epsdot_eq^m. Sellars-Tegart: "
                        "sigma_eq = asinh((Z/A)^(1/n))/alpha with Z = epsdot_eq "
                        "exp(Q/(R T)). Hansel-Spittel: sigma_eq = A e^(m1 T) T^m9 "
                        "eps^m2 e^(m4/eps) (1 + eps)^(m5 T) e^(m7 eps) epsdot_eq^(m3 + m8 T), "
                        "T in degrees Celsius (the Hansel-Spittel entries).");
      prm.declare_entry("Viscosity",
                        "0.278",
                        Double(),
                        "Newtonian viscosity eta (MPa s).");
      prm.declare_entry("Consistency K",
                        "0.834",
                        Double(),
                        "Norton-Hoff consistency K (MPa s^m).");
      prm.declare_entry("Rate sensitivity m",
                        "0.2",
                        Double(),
                        "Norton-Hoff rate sensitivity m, in (0, 1]; m = 1 is "
                        "Newtonian with eta = K/3, m -> 0 is rigid-plastic.");
      prm.declare_entry("Rate sensitivity continuation",
                        "true",
                        Bool(),
                        "Where Newton's method fails with a Norton-Hoff m below 0.5 (nearly "
                        "rigid-plastic; after the friction's fallbacks, Contact/Friction "
                        "continuation), solve the mesh again at m = 0.5 and lower m in stages "
                        "to the deck's, each stage from the last converged one; only the "
                        "deck's m is reported.");
      prm.declare_entry("Sellars-Tegart alpha",
                        "0.040",
                        Double(),
                        "Sellars-Tegart stress multiplier alpha (1/MPa); AA6063: 0.040.");
      prm.declare_entry("Sellars-Tegart n",
                        "5.385",
                        Double(),
                        "Sellars-Tegart stress exponent n; AA6063: 5.385.");
      prm.declare_entry("Activation energy Q",
                        "141550",
                        Double(),
                        "Activation energy Q (J/mol) of the Zener-Hollomon rate Z = "
                        "epsdot exp(Q/(R T)): Sellars-Tegart's; with a temperature field "
                        "(Heat/Model = steady) every law depends on T through it "
                        "(Newtonian eta exp(Q/R (1/T - 1/T0)), Norton-Hoff K exp(m Q/R "
                        "(1/T - 1/T0)), T0 = Temperature); 0: a law independent of T. "
                        "AA6063: 141550.");
      prm.declare_entry("ln A",
                        "22.5",
                        Double(),
                        "Natural logarithm of the Sellars-Tegart constant A (A in "
                        "1/s); AA6063: A = exp(22.5).");
      struct Constant
      {
        const char *name, *value, *doc;
      };
      const std::vector<Constant> hansel_spittel = {
        {"A", "1", "A (MPa) of Hansel-Spittel's law"},
        {"m1", "0", "m1 (1/C): the temperature's e^(m1 T)"},
        {"m2", "0", "m2: the strain's eps^m2 (eps taken no smaller than Hardening strain eps0)"},
        {"m3", "0.1", "m3: the rate's exponent m3 + m8 T, which must lie in (0, 1] at Temperature"},
        {"m4", "0", "m4: the strain's e^(m4/eps)"},
        {"m5", "0", "m5 (1/C): the strain's and temperature's (1 + eps)^(m5 T)"},
        {"m7", "0", "m7: the strain's e^(m7 eps)"},
        {"m8", "0", "m8 (1/C): the rate's exponent m3 + m8 T"},
        {"m9", "0", "m9: the temperature's T^m9 (T taken no lower than 1 C)"}};
      for (const auto &[name, value, doc] : hansel_spittel)
        prm.declare_entry(std::string("Hansel-Spittel ") + name,
                          value,
                          Double(),
                          std::string(doc) +
                            " (Law = Hansel-Spittel; T in degrees Celsius, as the published constants).");
      prm.declare_entry("Temperature",
                        "723.15",
                        Double(),
                        "Uniform temperature T (K) for Sellars-Tegart "
                        "(723.15 K = 450 C, a usual billet temperature); with a "
                        "temperature field, T0 at which the law's constants hold and "
                        "the field's start.");
      prm.declare_entry("Minimum strain rate",
                        "1e-4",
                        Double(),
                        "Regularisation epsdot_min (1/s): laws are evaluated at "
                        "sqrt(epsdot_eq^2 + epsdot_min^2), so rigid zones keep a "
                        "finite viscosity. Keep it well below the process strain "
                        "rates.");
      prm.declare_entry("Minimum viscosity",
                        "0",
                        Double(),
                        "Lower bound of eta (MPa s); 0 for none.");
      prm.declare_entry("Maximum viscosity",
                        "1e300",
                        Double(),
                        "Upper bound of eta (MPa s); 1e300 for none.");
      prm.declare_entry("Penalty factor",
                        "1e7",
                        Double(),
                        "Incompressibility penalty lambda = factor x eta_m, eta_m "
                        "the mean viscosity of the first iterate (the paper's "
                        "eps = 1e-7 eta_m). The pressure is p = -lambda div v; "
                        "div v is of the order of 1/factor. Where the penalty loses "
                        "more of the flow than Nonlinear solver/Mass balance "
                        "tolerance, the iteration goes on with Uzawa steps (r = "
                        "factor x the cell's viscosity) to the incompressible answer. "
                        "A factor above 1e10 is solved at 1e10 (and the run warns): "
                        "beyond it round-off in the reactions (1e-16 x factor) "
                        "exceeds the change it would make (1/factor). For the same "
                        "reason lambda is at most 1e10 x the law's viscosity at the "
                        "process's strain rate, the root mean square of the Newtonian "
                        "start's (a strongly shear-thinning law's mean viscosity is its "
                        "dead zones', up to a thousand times that).");
      prm.declare_entry("Hardening exponent n",
                        "0",
                        Double(),
                        "Strain hardening: the law's flow stress times (eps_0 + eps)^n, "
                        "eps the equivalent strain the metal has taken (Problem = "
                        "incremental: carried per cell from step to step; steady: the "
                        "field v.grad eps = epsdot_eq, Equivalent strain); with Norton-Hoff "
                        "sigma_eq = K (eps_0 + eps)^n epsdot^m. 0: no hardening.");
      prm.declare_entry("Hardening strain eps0",
                        "0.01",
                        Double(),
                        "eps_0 of the hardening factor (eps_0 + eps)^n: the flow stress "
                        "of the undeformed metal is the law's times eps_0^n.");
      prm.declare_entry("Reference strain rate",
                        "0",
                        Double(),
                        "Strain rate (1/s) at which the law gives the viscosity of "
                        "the Newtonian start of nonlinear laws. 0: the largest "
                        "prescribed speed over the domain diameter.");
    }
    prm.leave_subsection();
  }



  void
  Material::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    law_name = prm.get("Law");
    const auto positive = [&](const std::string &entry) { return get_positive(prm, "Material/", entry); };

    kind = law_name == "Newtonian"      ? Kind::newtonian :
           law_name == "Norton-Hoff"    ? Kind::norton_hoff :
           law_name == "Sellars-Tegart" ? Kind::sellars_tegart :
                                          Kind::hansel_spittel;
    if (kind == Kind::newtonian)
      law = std::make_shared<NewtonianLaw>(positive("Viscosity"));
    else if (kind == Kind::hansel_spittel)
      {
        const auto finite = [&](const std::string &name) {
          const double value = prm.get_double("Hansel-Spittel " + name);
          require(std::isfinite(value), "Material/Hansel-Spittel " + name, "must be a finite number");
          return value;
        };
        const double T_0 = positive("Temperature");
        const double m3 = finite("m3"), m8 = finite("m8");
        const double m  = m3 + m8 * (T_0 - zero_celsius);
        require(m > 0 && m <= 1,
                "Material/Hansel-Spittel m3",
                "with m8 gives the rate exponent m3 + m8 T = " + deck_number(m) + " at Material/Temperature (" +
                  deck_number(T_0 - zero_celsius) + " C): it must lie in (0, 1]");
        law   = std::make_shared<HanselSpittelLaw>(positive("Hansel-Spittel A"), finite("m1"), m3, m8, finite("m9"), T_0);
        hs_m2 = finite("m2");
        hs_m4 = finite("m4");
        hs_m5 = finite("m5");
        hs_m7 = finite("m7");
      }
    else if (kind == Kind::norton_hoff)
      {
        const double m = prm.get_double("Rate sensitivity m");
        require(std::isfinite(m) && m > 0 && m <= 1,
                "Material/Rate sensitivity m",
                "must lie in (0, 1], got " + prm.get("Rate sensitivity m"));
        consistency      = positive("Consistency K");
        rate_sensitivity = m;
        law              = std::make_shared<NortonHoffLaw>(consistency, m);
      }
    else
      {
        const double ln_A = prm.get_double("ln A");
        require(std::isfinite(ln_A), "Material/ln A", "must be a finite number");
        law = std::make_shared<SellarsTegartLaw>(positive("Sellars-Tegart alpha"),
                                                 positive("Sellars-Tegart n"),
                                                 positive("Activation energy Q"),
                                                 ln_A,
                                                 positive("Temperature"));
      }

    temperature = positive("Temperature");
    activation_energy = prm.get_double("Activation energy Q");
    require(std::isfinite(activation_energy) && activation_energy >= 0,
            "Material/Activation energy Q",
            "must be zero or positive, got " + prm.get("Activation energy Q"));
    // Hansel-Spittel's temperature is its own (e^(m1 T) T^m9, m8, m5), not Zener-Hollomon's.
    if (kind == Kind::hansel_spittel)
      activation_energy = 0;
    minimum_strain_rate = positive("Minimum strain rate");
    minimum_viscosity = prm.get_double("Minimum viscosity");
    maximum_viscosity = prm.get_double("Maximum viscosity");
    require(std::isfinite(minimum_viscosity) && minimum_viscosity >= 0,
            "Material/Minimum viscosity",
            "must be zero or positive, got " + prm.get("Minimum viscosity"));
    require(maximum_viscosity > minimum_viscosity,
            "Material/Maximum viscosity",
            "must exceed Minimum viscosity");
    deck_penalty_factor = positive("Penalty factor");
    penalty_factor      = std::min(deck_penalty_factor, largest_penalty_factor);
    hardening_exponent = prm.get_double("Hardening exponent n");
    require(std::isfinite(hardening_exponent) && hardening_exponent >= 0 && hardening_exponent <= 1,
            "Material/Hardening exponent n",
            "must be in [0, 1], got " + prm.get("Hardening exponent n"));
    require(kind != Kind::hansel_spittel || hardening_exponent == 0,
            "Material/Hardening exponent n",
            "must be 0 with Law = Hansel-Spittel (its strain terms m2, m4, m5, m7 are its hardening)");
    if (hardens())
      hardening_strain = positive("Hardening strain eps0");
    rate_sensitivity_continuation = prm.get_bool("Rate sensitivity continuation");
    reference_strain_rate = prm.get_double("Reference strain rate");
    require(std::isfinite(reference_strain_rate) && reference_strain_rate >= 0,
            "Material/Reference strain rate",
            "must be zero (auto) or positive");
    prm.leave_subsection();
  }



  void
  Material::set_newtonian(const double eta)
  {
    law      = std::make_shared<NewtonianLaw>(eta);
    law_name = "Newtonian";
  }



  void
  Material::set_rate_sensitivity(const double m)
  {
    Assert(kind == Kind::norton_hoff, dealii::ExcInternalError());
    rate_sensitivity = m;
    law              = std::make_shared<NortonHoffLaw>(consistency, m);
  }



  ViscosityValue
  Material::evaluate(const double equivalent_rate) const
  {
    // At T_0 the rate factor is exp(0) = 1 exactly: the law itself, to every digit.
    return evaluate(equivalent_rate, temperature);
  }



  double
  Material::rate_factor(const double T) const
  {
    return std::exp(activation_energy / gas_constant * (1. / T - 1. / temperature));
  }



  double
  Material::hardening(const double strain, const double T) const
  {
    if (!hardens())
      return 1.;
    if (kind != Kind::hansel_spittel)
      return std::pow(hardening_strain + strain, hardening_exponent);
    const double eps = std::max(strain, hardening_strain);
    return std::pow(eps, hs_m2) * std::exp(hs_m4 / eps + hs_m7 * eps) *
           std::pow(1. + eps, hs_m5 * (T - zero_celsius));
  }



  ViscosityValue
  Material::evaluate(const double equivalent_rate, const double T) const
  {
    ViscosityValue value;
    value.rate = std::sqrt(equivalent_rate * equivalent_rate + minimum_strain_rate * minimum_strain_rate);
    if (law->has_own_temperature())
      {
        value.eta   = law->viscosity_at(value.rate, T);
        value.d_eta = law->derivative_at(value.rate, T);
      }
    else
      {
        const double f = rate_factor(T);
        value.eta      = f * law->viscosity(f * value.rate);
        value.d_eta    = f * f * law->derivative(f * value.rate);
      }
    if (value.eta < minimum_viscosity)
      {
        value.eta   = minimum_viscosity;
        value.d_eta = 0;
      }
    else if (value.eta > maximum_viscosity)
      {
        value.eta   = maximum_viscosity;
        value.d_eta = 0;
      }
    return value;
  }
} // namespace dieflow
