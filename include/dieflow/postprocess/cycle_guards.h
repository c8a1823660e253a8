// The verdicts on a converged cycle: the mass the penalty lost, and the contact conditions its state must keep.
#ifndef dieflow_cycle_guards_h
#define dieflow_cycle_guards_h

#include <dieflow/contact/contact_parameters.h>
#include <dieflow/postprocess/mass_balance.h>
#include <dieflow/postprocess/summary.h>

#include <string>
#include <vector>

namespace dieflow
{
  /// A guard's verdict: empty where the cycle stands, else why it is not
  /// converged (and what to change); a warning to log and keep.
  struct GuardVerdict
  {
    std::string failure;
    std::string warning;
  };

  /**
   * The mass-balance guard (mass_balance.h) on a converged @p cycle with
   * Nonlinear solver/Mass balance tolerance = @p tolerance (0: off): its
   * status into the cycle; a failure beyond the tolerance, a warning above
   * a tenth of it, each saying what to change (the incompressibility's
   * @p penalty_factor, how it was held, @p hold, and the augmented
   * Lagrangian's @p divergence_tolerance).
   */
  GuardVerdict
  guard_mass_balance(CycleSummary &     cycle,
                     const double       tolerance,
                     const double       penalty_factor,
                     const MassHold     hold,
                     const double       divergence_tolerance);

  /**
   * A converged state that breaks the contact conditions (the checks of
   * summarise_contact(), relative) is not converged: penetration or pull
   * beyond 1e-6 (a pull to 1e-4 where directions were held in contact to
   * end a cycle of the states: the transition from contact to separation
   * falls between nodes), friction beyond its cone to round-off (1e-12;
   * in 3D 1e-8, where the semismooth Newton method reaches the cone as it
   * converges, not by construction), friction driving its slip, sticking
   * nodes sliding beyond 1e-8. Penalty enforcement keeps the first and
   * the last only approximately: not checked. The failure names one of
   * @p changes (a penalty factor beyond 1e10, whose round-off broke these
   * conditions, is solved at 1e10: Material::largest_penalty_factor).
   */
  GuardVerdict
  guard_contact(const CycleSummary &            cycle,
                const unsigned int              dim,
                const ContactParameters &       contact,
                const std::vector<std::string> &changes);
} // namespace dieflow

#endif
