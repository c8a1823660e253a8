// The material: the viscosity laws (Newtonian, Norton-Hoff, Sellars-Tegart, Hansel-Spittel), their regularisation and bounds, strain hardening, the penalty factor.
#ifndef dieflow_material_h
#define dieflow_material_h

#include <dieflow/base/parameters.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace dieflow
{
  /**
   * A viscosity law of the constitutive equation (3) of the paper,
   *   sigma^D = 2 eta(epsdot_eq) D,  epsdot_eq = sqrt(2/3 D:D),
   * given by its equivalent stress sigma_eq(epsdot_eq) = 3 eta epsdot_eq
   * (sigma_eq = sqrt(3/2 s:s)). A law returns eta and d eta / d epsdot at a
   * strictly positive rate; regularisation and bounds are the Material's.
   */
  class ViscosityLaw
  {
  public:
    virtual ~ViscosityLaw() = default;

    /// eta(epsdot) for epsdot > 0.
    virtual double
    viscosity(const double rate) const = 0;

    /// d eta / d epsdot for epsdot > 0.
    virtual double
    derivative(const double rate) const = 0;

    /// True when eta does not depend on the rate (one linear solve suffices).
    virtual bool
    is_linear() const
    {
      return false;
    }

    /// True when the law has a temperature dependence of its own
    /// (viscosity_at()); otherwise the Material gives it the
    /// Zener-Hollomon rate factor.
    virtual bool
    has_own_temperature() const
    {
      return false;
    }

    /// eta(epsdot, T) and d eta/d epsdot of a law with its own temperature dependence (T in K).
    virtual double
    viscosity_at(const double rate, const double) const
    {
      return viscosity(rate);
    }
    virtual double
    derivative_at(const double rate, const double) const
    {
      return derivative(rate);
    }
  };

  /// eta = eta_0.
  class NewtonianLaw : public ViscosityLaw
  {
  public:
    explicit NewtonianLaw(const double eta);
    double
    viscosity(const double rate) const override;
    double
    derivative(const double rate) const override;
    bool
    is_linear() const override
    {
      return true;
    }

  private:
    const double eta;
  };

  /**
   * Norton-Hoff power law: sigma_eq = K epsdot^m, so
   *   eta = K/3 epsdot^(m-1),  d eta/d epsdot = (m-1) eta / epsdot.
   * m = 1 is Newtonian with eta = K/3.
   */
  class NortonHoffLaw : public ViscosityLaw
  {
  public:
    NortonHoffLaw(const double K, const double m);
    double
    viscosity(const double rate) const override;
    double
    derivative(const double rate) const override;

  private:
    const double K;
    const double m;
  };

  /**
   * Sellars-Tegart (Garofalo) law for hot working:
   *   sigma_eq = asinh((Z/A)^(1/n)) / alpha,  Z = epsdot exp(Q/(R T)),
   *   eta = sigma_eq / (3 epsdot).
   * With s = (Z/A)^(1/n): d sigma_eq/d epsdot = s / (n alpha epsdot sqrt(1+s^2)),
   * and d eta/d epsdot = (d sigma_eq/d epsdot - 3 eta) / (3 epsdot).
   * ln(Z/A) is formed as a sum of logarithms so cold temperatures do not
   * overflow.
   */
  class SellarsTegartLaw : public ViscosityLaw
  {
  public:
    SellarsTegartLaw(const double alpha,
                     const double n,
                     const double Q,
                     const double ln_A,
                     const double temperature);
    double
    viscosity(const double rate) const override;
    double
    derivative(const double rate) const override;

    /// sigma_eq(epsdot), exposed for the tests.
    double
    flow_stress(const double rate) const;

  private:
    double
    zener_ratio_root(const double rate) const;

    const double alpha;
    const double n;
    const double ln_Z_over_A_shift; // Q/(R T) - ln A
  };

  /**
   * The rate and temperature part of the Hansel-Spittel law (Hensel and
   * Spittel 1978, in the form of FORGE and QForm),
   *   sigma_eq = A e^(m1 T) T^m9 epsdot^(m3 + m8 T) g(eps, T),
   *   g(eps, T) = eps^m2 e^(m4/eps) (1 + eps)^(m5 T) e^(m7 eps),
   * with T in degrees Celsius (T^m9 taken at T >= 1 C) and the rate
   * exponent m = m3 + m8 T held in [1e-3, 1] outside the range the
   * constants were fitted in. The strain part g is the Material's
   * hardening factor (Material::hardening(eps, T)); here
   *   eta = A e^(m1 T) T^m9 epsdot^(m-1) / 3,  d eta/d epsdot = (m-1) eta/epsdot.
   */
  class HanselSpittelLaw : public ViscosityLaw
  {
  public:
    HanselSpittelLaw(const double A,
                     const double m1,
                     const double m3,
                     const double m8,
                     const double m9,
                     const double reference_temperature);
    double
    viscosity(const double rate) const override;
    double
    derivative(const double rate) const override;
    bool
    has_own_temperature() const override
    {
      return true;
    }
    double
    viscosity_at(const double rate, const double T) const override;
    double
    derivative_at(const double rate, const double T) const override;
    bool
    is_linear() const override
    {
      return m3 == 1 && m8 == 0;
    }

    /// The rate exponent m3 + m8 T at @p T (K), held in [1e-3, 1].
    double
    rate_exponent(const double T) const;

  private:
    const double A, m1, m3, m8, m9;
    const double reference_temperature;
  };

  /// Viscosity and its rate derivative at one point, with the regularised rate.
  struct ViscosityValue
  {
    /// Effective viscosity eta (after bounds).
    double eta;
    /// d eta / d epsdot_reg; zero where a viscosity bound is active.
    double d_eta;
    /// Regularised equivalent strain rate epsdot_reg = sqrt(epsdot^2 + epsdot_min^2).
    double rate;
  };

  /**
   * The material: one viscosity law, its regularisation and bounds, and the
   * penalty factor of the incompressibility term.
   *
   * Regularisation: the law is evaluated at
   *   epsdot_reg = sqrt(epsdot_eq^2 + epsdot_min^2),
   * which keeps a finite viscosity in rigid zones and a smooth derivative for
   * Newton; then eta is clipped to [eta_min, eta_max] (d eta = 0 where
   * clipped).
   *
   * Penalty: lambda = (penalty factor) x eta_ref, where eta_ref is the mean
   * viscosity (the paper's eps = 1e-7 eta_m, eq. (7)); the problem computes
   * eta_ref once from the first iterate.
   */
  class Material
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    ViscosityValue
    evaluate(const double equivalent_rate) const;

    /**
     * The law at the temperature @p T (a temperature field, Heat/Model):
     * every law is the law at Material/Temperature T_0 of the
     * temperature-compensated rate f epsdot, f = exp(Q/R (1/T - 1/T_0))
     * (Zener-Hollomon: Z = epsdot exp(Q/(R T))), so that
     *   eta(epsdot, T) = f eta_0(f epsdot),  d eta/d epsdot = f^2 eta_0'(f epsdot).
     * For Sellars-Tegart this is the law with T in Z; Newtonian:
     * eta_0 exp(Q/R (1/T - 1/T_0)); Norton-Hoff: K(T) = K exp(m Q/R (1/T - 1/T_0)).
     * The regularisation acts on epsdot, the bounds on eta, as in evaluate(rate).
     */
    ViscosityValue
    evaluate(const double equivalent_rate, const double T) const;

    /// f = exp(Q/R (1/T - 1/T_0)) of evaluate(rate, T).
    double
    rate_factor(const double T) const;

    bool
    is_newtonian() const
    {
      return law->is_linear() && minimum_viscosity <= 0 &&
             maximum_viscosity >= 1e300;
    }

    /// Deck changes that keep the law in its range when an iterate left it
    /// (a larger minimum strain rate); none for a linear law.
    std::vector<std::string>
    range_changes() const
    {
      if (law->is_linear())
        return {};
      return {"raise Material/Minimum strain rate (it is " + deck_number(minimum_strain_rate) + ")"};
    }

    /// Replaces the law by a Newtonian one (the Newtonian start).
    void
    set_newtonian(const double eta);
    /// Norton-Hoff's law with the rate sensitivity @p m (a continuation's stage).
    void
    set_rate_sensitivity(const double m);
    /// Whether a failed Newton iteration is solved again by continuation in
    /// m (DieFlowProblem::continue_in_friction()): Norton-Hoff below
    /// continuation_rate_sensitivity, and the deck allows it.
    bool
    continues_in_rate_sensitivity() const
    {
      return kind == Kind::norton_hoff && rate_sensitivity_continuation &&
             rate_sensitivity < continuation_rate_sensitivity;
    }

    const ViscosityLaw &
    viscosity_law() const
    {
      return *law;
    }

    /// Whether the flow stress depends on the strain (Hardening exponent n > 0, or Hansel-Spittel's strain terms).
    bool
    hardens() const
    {
      return hardening_exponent > 0 || (kind == Kind::hansel_spittel && (hs_m2 != 0 || hs_m4 != 0 || hs_m5 != 0 || hs_m7 != 0));
    }

    /// The hardening factor at the equivalent strain @p strain and the
    /// temperature @p T (K): (eps_0 + eps)^n, or Hansel-Spittel's
    /// g(max(eps, eps_0), T) (1 without hardening).
    double
    hardening(const double strain, const double T) const;
    /// The hardening factor at Material/Temperature.
    double
    hardening(const double strain) const
    {
      return hardening(strain, temperature);
    }

    /// The laws.
    enum class Kind
    {
      newtonian,
      norton_hoff,
      sellars_tegart,
      hansel_spittel
    };
    Kind kind = Kind::newtonian;
    /// Norton-Hoff's K and m (set_rate_sensitivity() keeps K).
    double consistency = 0, rate_sensitivity = 1;
    bool   rate_sensitivity_continuation = true;
    /// The m a continuation in m starts from: of the 20 decks of the extreme
    /// corpus (doc/stress.md) with m 0.02 to 0.25 whose Newton iteration
    /// failed, 14 converge when their m is set to 0.5, 10 at 0.2.
    static constexpr double continuation_rate_sensitivity = 0.5;
    /// Name of the law as in the deck.
    std::string law_name;
    /// Hansel-Spittel's strain constants (g(eps, T) of HanselSpittelLaw).
    double      hs_m2 = 0, hs_m4 = 0, hs_m5 = 0, hs_m7 = 0;
    double      hardening_exponent  = 0;
    double      hardening_strain    = 0.01;
    double      minimum_strain_rate = 1e-4;
    double      minimum_viscosity   = 0;
    double      maximum_viscosity   = 1e300;
    /// The factor the run uses: the deck's, at most largest_penalty_factor.
    double      penalty_factor      = 1e7;
    /// The deck's Penalty factor.
    double      deck_penalty_factor = 1e7;
    /// Beyond it the penalty's round-off (about 1e-16 x factor, relative,
    /// in the reactions the contact states read) outgrows the contact's
    /// dead band and the answer's difference from the incompressible limit
    /// (1/factor): a larger factor is solved at this one (doc/stress.md).
    static constexpr double largest_penalty_factor = 1e10;
    /// Strain rate at which the Newtonian start evaluates the law (0: auto).
    double reference_strain_rate = 0;
    /// T_0 (K), at which the law's constants hold, and Q (J/mol) of the Zener-Hollomon rate.
    double temperature       = 723.15;
    double activation_energy = 141550;

  private:
    std::shared_ptr<const ViscosityLaw> law;
  };
} // namespace dieflow

#endif
