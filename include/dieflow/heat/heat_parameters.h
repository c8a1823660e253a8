// The deck's Heat subsection: the thermal model, the metal's thermal properties, its thermal boundary conditions and the coupling's iteration.
#ifndef dieflow_heat_parameters_h
#define dieflow_heat_parameters_h

#include <dieflow/base/parameters.h>

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace dieflow
{
  /**
   * A thermal property of the metal as a function of T: a constant, or
   * linear between the points (T_i, p_i) of a table and constant beyond
   * its ends; or the product of two such (times(): rho c with both rho and
   * c tabulated, quadratic between the union of their points).
   * integral(T) = int_0^T p(s) ds, exactly (Simpson's rule on each piece
   * between the points, where p is at most quadratic): with p = rho c the
   * heat content (enthalpy) per volume, with p = k Kirchhoff's transform.
   */
  class ThermalProperty
  {
  public:
    /// The constant @p value.
    void
    set_constant(const double value);
    /// "T: p, T: p, ..." (T in K, ascending, above 0; p positive) times @p scale; @p entry names the entry in errors.
    void
    parse_table(const std::string &entry, const std::string &text, const double scale);

    /// This property times @p other (both tables kept: the product is exact).
    void
    times(const ThermalProperty &other);

    double
    value(const double T) const;
    double
    integral(const double T) const;
    /// dp/dT (0 beyond the tables' ends and for a constant).
    double
    slope(const double T) const;
    bool
    is_constant() const
    {
      return points.size() == 1 && factor.size() == 1;
    }

  private:
    using Table = std::vector<std::pair<double, double>>;
    /// (T_i, p_i), ascending in T; one point for a constant (its T unused).
    Table points = {{0., 0.}};
    /// times()'s factor (the constant 1 otherwise).
    Table factor = {{0., 1.}};
  };

  /**
   * The temperature field of the metal (subsection Heat). Units: the deck
   * gives SI (kg/m^3, J/(kg K), W/(m K), W/(m^2 K)); the program works in
   * mm, s, N and K, in which rho c is in N/(mm^2 K) (= 1e-6 rho[kg/m^3]
   * c[J/(kg K)]), k in N/(s K) (= k[W/(m K)]) and h in N/(mm s K)
   * (= 1e-3 h[W/(m^2 K)]), so that sigma:D (MPa/s = mW/mm^3) is a heat
   * source without a factor.
   */
  struct HeatParameters
  {
    enum class Model
    {
      /// isothermal: every law at Material/Temperature
      off,
      /// the steady (Eulerian) heat equation on the flow's domain, coupled to the flow
      steady,
      /// rho c dT/dt on the mesh that moves with the metal (Problem = incremental), a step behind the flow's
      transient
    };
    /// Runs in time: the sources of a heat step.
    enum class StepCoupling
    {
      /// the flow of t_n's (forward Euler in the sources: one heat solve per step)
      explicit_sources,
      /// the mean of t_n's and t_n+1's, iterated with the flow of t_n+1 (HeatEquation::correct_step())
      trapezoid
    };
    enum class Stabilisation
    {
      /// streamline upwind Petrov-Galerkin (Brooks, Hughes 1982)
      supg,
      /// plain Galerkin (oscillates where the cell Peclet number exceeds 1)
      none
    };

    Model         model         = Model::off;
    Stabilisation stabilisation = Stabilisation::supg;
    /// Degree of the temperature element; 0: the velocity's.
    unsigned int degree = 0;
    /// rho c in N/(mm^2 K), k in N/(s K): constant, or tabulated in T (Density table and Specific heat table, Conductivity table).
    ThermalProperty heat_capacity, conductivity;
    /// The share of the plastic work that becomes heat (Taylor-Quinney), of the friction work that goes into the metal.
    double taylor_quinney = 0.9, friction_share = 0.5;
    /// T = expression on these ids (the billet entering).
    std::set<BoundaryId> prescribed_ids;
    std::string          prescribed_temperature;
    /// For tests: the exact T (an expression, or empty), against which the errors are reported.
    std::string exact_temperature;
    /// Heat lost through a part, h (T - T_ambient): h in N/(mm s K) and T_ambient per id (dies, free surfaces).
    std::map<BoundaryId, double> transfer_coefficient, ambient_temperature;
    /// Emissivity e per id: the part radiates e sigma (T^4 - T_ambient^4) too.
    std::map<BoundaryId, double> emissivity;
    /// Stefan-Boltzmann's sigma in N/(mm s K^4) (5.670374419e-8 W/(m^2 K^4)).
    static constexpr double stefan_boltzmann = 5.670374419e-11;

    /// The heat flux (N/(mm s)) out through part @p id at @p T: h (T - T_a) + e sigma (T^4 - T_a^4), 0 for an insulated part.
    double
    wall_flux(const BoundaryId id, const double T) const;
    /// Effusivity sqrt(k rho c) of a die per id, in the program's units (N/(mm s^1/2 K) = 1e-3 W s^1/2/(m^2 K)).
    std::map<BoundaryId, double> die_effusivity;
    /// The metal's share of the friction work at die @p die where the metal is at @p T: e_m/(e_m + e_die)
    /// with the metal's effusivity e_m = sqrt(k(T) rho c(T)) (two half-spaces in sliding contact), or Friction heat share.
    double
    friction_share_at(const BoundaryId die, const double T) const;
    /// Whether part @p id loses heat to its surroundings (a transfer coefficient or an emissivity).
    bool
    exchanges(const BoundaryId id) const
    {
      return transfer_coefficient.count(id) > 0 || emissivity.count(id) > 0;
    }
    /// Runs in time: T carried to a new mesh keeps the heat content per volume (a uniform shift after the interpolation).
    bool conservative_transfer = true;
    StepCoupling step_coupling = StepCoupling::explicit_sources;
    /// The most staggered solves (heat, then flow) per cycle, and when they have settled.
    unsigned int coupling_iterations = 10;
    double       coupling_tolerance  = 1e-3;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
    bool
    enabled() const
    {
      return model != Model::off;
    }
  };
} // namespace dieflow

#endif
