// The deck's Heat subsection: the thermal model, the metal's thermal properties, its thermal boundary conditions and the coupling's iteration.
#ifndef dieflow_heat_parameters_h
#define dieflow_heat_parameters_h

#include <dieflow/base/parameters.h>

#include <map>
#include <set>
#include <string>

namespace dieflow
{
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
    /// rho c in N/(mm^2 K), k in N/(s K).
    double heat_capacity = 0, conductivity = 0;
    /// The share of the plastic work that becomes heat (Taylor-Quinney), of the friction work that goes into the metal.
    double taylor_quinney = 0.9, friction_share = 0.5;
    /// T = expression on these ids (the billet entering).
    std::set<BoundaryId> prescribed_ids;
    std::string          prescribed_temperature;
    /// For tests: the exact T (an expression, or empty), against which the errors are reported.
    std::string exact_temperature;
    /// Heat lost through a part, h (T - T_ambient): h in N/(mm s K) and T_ambient per id (dies, free surfaces).
    std::map<BoundaryId, double> transfer_coefficient, ambient_temperature;
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
