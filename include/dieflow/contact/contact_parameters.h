// The deck's Contact subsection: die ids, how contact and stick are enforced, the friction law of each die.
#ifndef dieflow_contact_parameters_h
#define dieflow_contact_parameters_h

#include <dieflow/base/parameters.h>
#include <dieflow/contact/contact_element.h>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace dieflow
{
  /// The deck's "Contact" subsection.
  struct ContactParameters
  {
    std::set<BoundaryId>         die_ids;
    /// How the unilateral condition v.n <= 0 is kept.
    enum class NormalEnforcement
    {
      /// exactly, by the primal-dual active set (deal.II step-41/42)
      active_set,
      /// by the paper's perturbed Lagrangian F_n = -omega_n max(v.n, 0)
      penalty
    };
    /// How a sticking node is held.
    enum class StickEnforcement
    {
      /// v.t = 0 as a constraint (active set only)
      exact,
      /// the paper's F_t = -omega_t v_t
      penalty
    };
    /// How Coulomb's bound mu |F_n| follows the normal force in Newton's
    /// iteration.
    enum class CoulombCoupling
    {
      /// linearised with it: T = I + b n^T (ContactSet::contributions())
      newton,
      /// frozen at the last iteration's normal force: a Tresca law whose
      /// bound mu max(-F_n, 0) each iteration renews (Coulomb at the fixed
      /// point)
      fixed_point,
      /// Newton until the states cycle, then the fixed point (per mesh)
      automatic
    };
    NormalEnforcement            normal_enforcement = NormalEnforcement::active_set;
    CoulombCoupling              coulomb_coupling   = CoulombCoupling::automatic;
    StickEnforcement             stick_enforcement  = StickEnforcement::exact;
    FrictionLaw::Kind            law                = FrictionLaw::Kind::coulomb;
    std::map<BoundaryId, double> friction_coefficient;
    std::map<BoundaryId, double> tresca_factor;
    double                       shear_flow_stress         = 0;
    double                       normal_penalty_factor     = 1;
    double                       tangential_penalty_factor = 100;
    double                       regularisation_velocity   = 0;
    double                       active_set_constant       = 1;
    /// A mesh whose Newton iteration fails at the deck's friction is solved
    /// again: with Coulomb's bound at its fixed point, then from the
    /// frictionless problem with the friction raised in stages.
    bool                         friction_continuation     = true;
    /// Die ids whose die is a surface mesh of its own (Gmsh file names).
    std::map<BoundaryId, std::string> die_surface_files;
    /// Die ids that move: their rigid translation velocity (components as
    /// written; the problem checks there are dim of them).
    std::map<BoundaryId, std::vector<double>> die_velocities;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    bool
    uses_penalty() const
    {
      return normal_enforcement == NormalEnforcement::penalty;
    }

    /// Friction coefficient of a die id (0 if none given).
    double
    friction_coefficient_of(const BoundaryId id) const;

    /// The deck's law of die id @p id for a node of boundary weight
    /// @p weight (the Tresca bound scales with it).
    FrictionLaw
    law_of(const BoundaryId id, const double weight) const;

    /// True where the law of die id @p id transmits no tangential force
    /// (mu = 0, or a zero Tresca bound).
    bool
    frictionless(const BoundaryId id) const;
    /// True where some die's law transmits a tangential force.
    bool
    has_friction() const;

    /// Deck changes that may let contact states that keep changing settle,
    /// none of them in use already (for the failure message).
    std::vector<std::string>
    settling_changes() const;
    /// A Tresca deck with Coulomb coefficients and a zero bound: the
    /// warning that it runs frictionless (empty otherwise).
    std::string
    unused_friction_warning() const;
  };
} // namespace dieflow

#endif
