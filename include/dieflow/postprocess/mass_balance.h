// How much mass the penalty lets the metal lose: the two measures, the guard's verdict on them, and what to change when it fails.
#ifndef dieflow_mass_balance_h
#define dieflow_mass_balance_h

#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/base/parameters.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <string>

namespace dieflow
{
  using dealii::DoFHandler;
  using dealii::Vector;

  /**
   * How much mass the penalty lets the metal lose. The penalty enforces
   * div v = -p / lambda only approximately (paper, eq. 3), so a steady
   * field carries less out than in. With Q = max(inflow, outflow) over the
   * boundary parts:
   *
   *   loss          = |sum_parts int v.n ds| / Q  (= |int div v dx| / Q),
   *   volume_change = sum_K |int_K div v dx| / Q,
   *
   * the second also seeing compression in one place and expansion in
   * another, which cancel in the first. Both are 0 when nothing flows
   * (Q = 0). A relative force error of about the loss follows
   * (doc/benchmarks.md, "Figures behind the code's rules").
   */
  struct MassBalance
  {
    double loss           = 0;
    double volume_change  = 0;
    double reference_flux = 0;

    /// The larger of the two measures: what the guard compares.
    double
    worst() const
    {
      return std::max(loss, volume_change);
    }
  };

  template <int dim>
  MassBalance
  mass_balance(const CoordinateSystem<dim> &         coordinates,
               const DoFHandler<dim> &               dof_handler,
               const Vector<double> &                velocity,
               const std::map<BoundaryId, double> &  flux);

  /// The mass-balance guard's verdict on a cycle.
  enum class MassBalanceStatus
  {
    /// not judged (the cycle did not converge)
    unchecked,
    /// the guard is off (tolerance 0)
    off,
    ok,
    warning,
    failed
  };

  /// "", "off", "ok", "warning", "failed" (summary.json).
  std::string
  status_name(const MassBalanceStatus status);

  /**
   * The guard on a converged result (Nonlinear solver/Mass balance
   * tolerance = tol): failed when MassBalance::worst() > tol (the run is
   * then not converged), warning above tol / 10, else ok.
   */
  MassBalanceStatus
  mass_balance_status(const MassBalance &balance, const double tolerance);

  /// How incompressibility was held in the cycle the guard judges.
  enum class MassHold
  {
    /// the penalty alone (div v of order 1/factor)
    penalty,
    /// the augmented Lagrangian's Uzawa steps, to Divergence tolerance
    uzawa,
    /// Uzawa steps that stopped reducing P div v (the mesh locks)
    uzawa_stalled
  };

  /**
   * What to change when the mass balance fails or warns: with the direct
   * solver's penalty, a factor that would bring the loss (which scales as
   * 1/factor) to a hundredth of the tolerance, up to 1e10 (round-off
   * beyond); with the augmented Lagrangian, its Divergence tolerance; where
   * its Uzawa steps stalled, a finer mesh or velocity degree 2 (no
   * discretely incompressible flow on this mesh meets the boundary
   * conditions).
   */
  std::string
  mass_balance_advice(const MassBalance &balance,
                      const double       tolerance,
                      const double       penalty_factor,
                      const MassHold     hold,
                      const double       divergence_tolerance);
} // namespace dieflow

#endif
