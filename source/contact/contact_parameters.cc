// The deck's Contact subsection: its entries, their checks, and the friction law of each die.
#include <dieflow/contact/contact_parameters.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace dieflow
{
  namespace
  {
    /// True where some id's value (a friction coefficient, a Tresca factor) is positive.
    bool
    any_positive(const std::map<BoundaryId, double> &values)
    {
      return std::any_of(values.begin(), values.end(), [](const auto &v) { return v.second > 0; });
    }
  } // namespace



  void
  ContactParameters::declare_parameters(ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Contact");
    prm.declare_entry("Die ids",
                      "3, 4",
                      Anything(),
                      "Boundary ids of the rigid die in unilateral contact with "
                      "friction: v.n <= 0, F_n <= 0, F_n v.n = 0, Coulomb stick or "
                      "slip. Empty: no contact (the friction entries are then "
                      "ignored).");
    prm.declare_entry("Normal enforcement",
                      "active set",
                      Selection("active set|penalty"),
                      "active set: v.n = 0 exactly where the die presses (a "
                      "primal-dual active set on the nodal contact pressure, as "
                      "deal.II step-41/42). penalty: the paper's perturbed "
                      "Lagrangian, F_n = -omega_n max(v.n, 0) (a small "
                      "penetration rate, which falls as 1/omega_n).");
    prm.declare_entry("Stick",
                      "exact",
                      Selection("exact|penalty"),
                      "exact: a sticking node is held at rest by the constraint "
                      "v.t = 0, and its friction force is the reaction (a "
                      "primal-dual active set for the tangential direction too). "
                      "penalty: the paper's F_t = -omega_t v_t (eq. (16)), see "
                      "Tangential penalty factor; always so with the penalty normal "
                      "enforcement.");
    prm.declare_entry("Friction law",
                      "Coulomb",
                      Selection("Coulomb|Tresca|regularised Coulomb"),
                      "Coulomb: |F_t| <= mu |F_n| (stick below, slip at the bound). "
                      "Tresca: |tau| <= m k. regularised Coulomb: tau = -mu |sigma_n| "
                      "(2/pi) atan(v_t / v0), smooth, without stick.");
    prm.declare_entry("Coulomb coupling",
                      "auto",
                      Selection("auto|Newton|fixed point"),
                      "How the Coulomb bound mu |F_n| follows the normal force. "
                      "Newton: linearised with it (quadratic near the solution). "
                      "fixed point: frozen at the last iteration's normal force, a "
                      "Tresca law whose bound each iteration renews; Coulomb at "
                      "convergence, slower, but it holds for dies with mu of order 1 "
                      "and above, where the linearised coupling makes the contact "
                      "states cycle. auto: Newton until the states cycle, then the "
                      "fixed point for the directions of the cycle (kept on the "
                      "moved or refined mesh), Newton's coupling again once the "
                      "states have settled for four iterations (once per mesh).");
    prm.declare_entry("Friction continuation",
                      "true",
                      Bool(),
                      "When Newton's method fails on a mesh at the deck's friction "
                      "(the contact does not settle, the iteration diverges or runs "
                      "out of iterations), solve that mesh again: with Coulomb's "
                      "bound frozen at each iteration's normal force (Coulomb "
                      "coupling = fixed point) from the start, with eight times "
                      "Nonlinear solver/Maximum iterations (the fixed point "
                      "converges linearly), and if that fails too, "
                      "from the frictionless problem, every friction bound (mu, the "
                      "Tresca factor) raised in stages to the deck's, each stage from "
                      "the last converged one (a smaller stage after one that fails). "
                      "Only the solution at the deck's friction is reported "
                      "converged; decks that converge without it are unchanged.");
    prm.declare_entry("Friction coefficients",
                      "3: 0.001, 4: 0.1",
                      Anything(),
                      "Coulomb coefficient mu per die id, as 'id: mu, id: mu' "
                      "(die2d: '3: 0.001, 4: 0.1'); ids not listed are frictionless.");
    prm.declare_entry("Tresca friction factors",
                      "",
                      Anything(),
                      "Tresca factor m in [0, 1] per die id, 'id: m, ...'; the wall "
                      "shear stress is at most m k.");
    prm.declare_entry("Shear flow stress",
                      "0",
                      Double(0),
                      "k (MPa) of the Tresca law: the shear flow stress of the "
                      "metal, sigma_0 / sqrt(3).");
    prm.declare_entry("Normal penalty factor",
                      "1",
                      Double(0),
                      "omega_n = factor x lambda (per unit boundary weight in 2D), "
                      "lambda the incompressibility penalty, for Normal "
                      "enforcement = penalty: the die pushes back with "
                      "F_n = -omega_n v.n where the metal penetrates at v.n > 0.");
    prm.declare_entry("Tangential penalty factor",
                      "100",
                      Double(0),
                      "omega_t = factor x lambda: the stick law F_t = -omega_t v_t "
                      "of the paper (eq. (16)). Sticking nodes slip at |F_t| / "
                      "omega_t, which the incompressibility penalty turns into a "
                      "pressure disturbance of about 1/factor of the wall shear; "
                      "hence a multiple of lambda.");
    prm.declare_entry("Regularisation velocity",
                      "0",
                      Double(0),
                      "v0 (mm/s) of the regularised Coulomb law; 0: a hundredth of "
                      "the largest prescribed or die speed, so that a run at "
                      "another speed is the same problem scaled.");
    prm.declare_entry("Active set constant",
                      "1",
                      Double(0),
                      "c = constant x eta_m / h in the active-set rule p + c v.n > 0.");
    prm.declare_entry("Die surfaces",
                      "",
                      Anything(),
                      "Dies given on their own, as 'id: file, ...': a Gmsh surface "
                      "mesh (lines in 2D; triangles or quadrilaterals in 3D, the "
                      "latter split in two) per die id. Each wall node of that id "
                      "takes its master facet and normal from the surface by the "
                      "node-to-facet search (doc/three-dimensional.md) instead of "
                      "from the metal's mesh; the metal's die boundary must lie on "
                      "the surface (within 1e-6 of its size). A relative path is "
                      "relative to the deck's directory. Empty: the dies are the "
                      "mesh's boundary faces.");
    prm.declare_entry("Die velocities",
                      "",
                      Anything(),
                      "Dies that move, as 'id: vx vy' (3D: 'id: vx vy vz'), mm/s: a "
                      "rigid translation. The contact conditions hold for the "
                      "velocity relative to the die (v - V).n <= 0, the friction "
                      "opposes the slip (v - V).t, and a sticking node moves with "
                      "the die. In Problem = incremental the die moves by V dt per "
                      "step (it may drive the flow without a prescribed-velocity "
                      "part: a platen, a punch); in a steady run only along its "
                      "own surface (V.n = 0: a belt, a moving mandrel). Ids not "
                      "listed are at rest.");
    prm.leave_subsection();
  }



  void
  ContactParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    die_ids            = parse_id_list("Contact/Die ids", prm.get("Die ids"));
    normal_enforcement = prm.get("Normal enforcement") == "penalty" ? NormalEnforcement::penalty : NormalEnforcement::active_set;
    stick_enforcement  = prm.get("Stick") == "penalty" ? StickEnforcement::penalty : StickEnforcement::exact;
    const std::string coupling = prm.get("Coulomb coupling");
    coulomb_coupling           = coupling == "fixed point" ? CoulombCoupling::fixed_point :
                                 coupling == "Newton"      ? CoulombCoupling::newton :
                                                             CoulombCoupling::automatic;
    const std::string law_name = prm.get("Friction law");
    law = (law_name == "Coulomb") ? FrictionLaw::Kind::coulomb :
          (law_name == "Tresca")  ? FrictionLaw::Kind::tresca :
                                    FrictionLaw::Kind::regularised_coulomb;
    friction_coefficient.clear();
    for (const auto &[id, mu] : parse_id_value_map("Contact/Friction coefficients", prm.get("Friction coefficients")))
      {
        require(mu >= 0,
                "Contact/Friction coefficients",
                "mu of id " + std::to_string(id) + " must not be negative");
        require(die_ids.empty() || die_ids.count(id),
                "Contact/Friction coefficients",
                "id " + std::to_string(id) + " is not listed under Die ids");
        friction_coefficient[id] = mu;
      }
    tresca_factor.clear();
    for (const auto &[id, m] : parse_id_value_map("Contact/Tresca friction factors", prm.get("Tresca friction factors")))
      {
        require(m >= 0 && m <= 1,
                "Contact/Tresca friction factors",
                "m of id " + std::to_string(id) + " must lie in [0, 1]");
        require(die_ids.empty() || die_ids.count(id),
                "Contact/Tresca friction factors",
                "id " + std::to_string(id) + " is not listed under Die ids");
        tresca_factor[id] = m;
      }
    friction_continuation     = prm.get_bool("Friction continuation");
    shear_flow_stress         = prm.get_double("Shear flow stress");
    normal_penalty_factor     = prm.get_double("Normal penalty factor");
    tangential_penalty_factor = prm.get_double("Tangential penalty factor");
    regularisation_velocity   = prm.get_double("Regularisation velocity");
    active_set_constant       = prm.get_double("Active set constant");
    die_surface_files.clear();
    for (const auto &[id, file] : parse_id_text_map("Contact/Die surfaces", prm.get("Die surfaces")))
      {
        require(die_ids.count(id),
                "Contact/Die surfaces",
                "id " + std::to_string(id) + " is not listed under Die ids");
        die_surface_files[id] = file;
      }
    die_velocities.clear();
    for (const auto &[id, text] : parse_id_text_map("Contact/Die velocities", prm.get("Die velocities")))
      {
        require(die_ids.count(id),
                "Contact/Die velocities",
                "id " + std::to_string(id) + " is not listed under Die ids");
        std::vector<double> components;
        for (const std::string &word : dealii::Utilities::split_string_list(text, ' '))
          {
            if (word.empty())
              continue;
            char *       end   = nullptr;
            const double value = std::strtod(word.c_str(), &end);
            require(end != word.c_str() && *end == '\0' && std::isfinite(value),
                    "Contact/Die velocities",
                    "'" + word + "' (id " + std::to_string(id) + ") is not a number");
            components.push_back(value);
          }
        die_velocities[id] = components;
      }
    require(!(uses_penalty() && normal_penalty_factor <= 0 && !die_ids.empty()),
            "Contact/Normal penalty factor",
            "must be positive for Normal enforcement = penalty");
    prm.leave_subsection();
  }



  std::vector<std::string>
  ContactParameters::settling_changes() const
  {
    // Only what the deck does not say already: a smooth or pressure-free
    // law has no stick/slip switch to cycle on.
    std::vector<std::string> changes;
    switch (law)
      {
        case FrictionLaw::Kind::coulomb:
          // The continuation tries the fixed point first.
          if (coulomb_coupling != CoulombCoupling::fixed_point && any_positive(friction_coefficient) &&
              !friction_continuation)
            changes.emplace_back("set Contact/Coulomb coupling = fixed point");
          // Where the fallbacks failed (doc/stress.md, 14 extreme decks whose
          // contact did not settle), Tresca's law with a bound converged 13
          // times, the regularised law twice, a mesh twice as fine once; a
          // frictionless deck has no friction law to change.
          if (any_positive(friction_coefficient))
            {
              changes.emplace_back("set Contact/Friction law = Tresca (with Contact/Tresca friction factors and "
                                   "Shear flow stress: a bound that does not follow the normal force) or "
                                   "regularised Coulomb");
              changes.emplace_back("lower Contact/Friction coefficients");
            }
          break;
        case FrictionLaw::Kind::tresca:
          changes.emplace_back("set Contact/Friction law = regularised Coulomb");
          if (any_positive(tresca_factor))
            changes.emplace_back("lower Contact/Tresca friction factors");
          break;
        case FrictionLaw::Kind::regularised_coulomb:
          changes.emplace_back(regularisation_velocity > 0 ?
                                 "raise Contact/Regularisation velocity (it is " + deck_number(regularisation_velocity) + ")" :
                                 "set Contact/Regularisation velocity to a tenth of the largest speed (it is 0: a "
                                 "hundredth)");
          if (any_positive(friction_coefficient))
            changes.emplace_back("lower Contact/Friction coefficients");
          break;
      }
    return changes;
  }



  std::string
  ContactParameters::unused_friction_warning() const
  {
    // Each law reads its own entries: a deck that names Tresca's law and
    // gives Coulomb's coefficients (as the settling advice may lead a user
    // to) would otherwise run frictionless without a word.
    if (law != FrictionLaw::Kind::tresca || has_friction() || !any_positive(friction_coefficient))
      return "";
    return "Contact/Friction law = Tresca bounds the wall shear by Contact/Tresca friction factors x Shear flow "
           "stress, zero here (the dies are frictionless); Contact/Friction coefficients are Coulomb's and unused";
  }



  double
  ContactParameters::friction_coefficient_of(const BoundaryId id) const
  {
    const auto it = friction_coefficient.find(id);
    return it == friction_coefficient.end() ? 0. : it->second;
  }



  FrictionLaw
  ContactParameters::law_of(const BoundaryId id, const double weight) const
  {
    FrictionLaw friction;
    friction.kind        = law;
    friction.mu          = friction_coefficient_of(id);
    const auto m         = tresca_factor.find(id);
    friction.shear_bound = (m == tresca_factor.end() ? 0. : m->second) * shear_flow_stress * weight;
    return friction;
  }



  bool
  ContactParameters::frictionless(const BoundaryId id) const
  {
    return law_of(id, 1.).frictionless();
  }



  bool
  ContactParameters::has_friction() const
  {
    return std::any_of(die_ids.begin(), die_ids.end(), [this](const BoundaryId id) { return !frictionless(id); });
  }
} // namespace dieflow
