// The contact set's active set and stick/slip decisions (ContactSet::update()): the state of each node from an iterate.
#include <dieflow/contact/contact_set.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>

namespace dieflow
{
  namespace
  {
    /// The normals a node's reaction is split on: its active directions'
    /// (direction k's index into @p direction_of) and then its fixed walls'
    /// (-1 there).
    template <int dim, typename NodeType>
    std::vector<Tensor<1, dim>>
    held_normals(const NodeType &node, std::vector<int> &direction_of)
    {
      std::vector<Tensor<1, dim>> normals;
      direction_of.clear();
      for (unsigned int k = 0; k < node.directions.size(); ++k)
        if (node.directions[k].active)
          {
            normals.push_back(node.directions[k].wall.normal);
            direction_of.push_back(k);
          }
      for (const auto &n : node.fixed_normals)
        {
          normals.push_back(n);
          direction_of.push_back(-1);
        }
      return normals;
    }
  } // namespace



  template <int dim>
  Tensor<1, dim>
  ContactSet<dim>::dual_normal(const Node &node, const Direction &direction) const
  {
    if (node.n_held() == 1)
      return direction.wall.normal;
    std::vector<int>                  direction_of;
    const std::vector<Tensor<1, dim>> normals = held_normals<dim>(node, direction_of);
    const unsigned int index =
      std::find(direction_of.begin(), direction_of.end(), static_cast<int>(&direction - node.directions.data())) -
      direction_of.begin();
    // The split is linear in the reaction: its k-th component of e_d is m_d.
    Tensor<1, dim> m;
    for (unsigned int d = 0; d < dim; ++d)
      m[d] = normal_components(normals, Tensor<1, dim>(dealii::Point<dim>::unit_vector(d)))[index];
    return m;
  }



  template <int dim>
  void
  ContactSet<dim>::decompose_reaction(const Node &                  node,
                                      const dealii::Vector<double> &flow_residual,
                                      const dealii::Vector<double> &v,
                                      std::vector<double> &         forces,
                                      std::vector<Slip> &           stick_forces) const
  {
    // The reaction R at the node on the active normals and those of the
    // node's fixed walls: R = sum_k F_k n_k + a tangential part (the
    // friction); least squares (normal_components()). A node that sticks
    // exactly carries the rest, R - sum_k F_k n_k, as its friction force:
    // its components on the die's tangents t_i. (Not by least squares on
    // normals and tangents together: in 3D a tangent of the die can be the
    // normal of a symmetry plane through the node, whose reaction is no
    // friction.)
    forces.assign(node.directions.size(), 0.);
    stick_forces.assign(node.directions.size(), Slip::Zero());
    if (node.n_active() == 0)
      return;
    std::vector<int>                  direction_of;
    const std::vector<Tensor<1, dim>> normals = held_normals<dim>(node, direction_of);
    Tensor<1, dim> reaction;
    for (unsigned int d = 0; d < dim; ++d)
      reaction[d] = flow_residual[node.dofs[d]];
    const std::vector<double> a = normal_components(normals, reaction);
    const unsigned int        m = normals.size();
    Tensor<1, dim> tangential = reaction;
    for (unsigned int i = 0; i < m; ++i)
      {
        if (direction_of[i] >= 0)
          forces[direction_of[i]] = a[i];
        tangential -= a[i] * normals[i];
      }
    // In 3D a node held by two dies (on the edge where they meet) slides
    // along the edge, and its friction R_t is the sum of both walls'. A
    // slipping wall's share is its law's force; the rest falls on the
    // walls that stick, split in proportion to their bounds mu |F_n|, so
    // that each stays within its bound exactly when the node's friction
    // stays within their sum. Handing each sticking wall all of R_t would
    // count it twice in the die forces (tests/couette3d_edge_stick), and
    // the wall with the smaller bound would leave its cone first.
    double bound_sum = 0;
    int    n_sticking = 0;
    for (unsigned int k = 0; k < node.directions.size(); ++k)
      {
        const Direction &dir = node.directions[k];
        if (sticks_exactly(node, dir))
          {
            bound_sum += law_of(dir).bound(forces[k]);
            ++n_sticking;
          }
        else if (dir.active && node.n_held() < dim)
          {
            const Slip slip_rate = dir.element.tangential_rate(element_velocity(node, dir, v));
            tangential -= dir.element.in_space(
              ContactElement<dim>::friction(law_of(dir), dir.status, dir.slip_direction, slip_rate, forces[k]).force);
          }
      }
    for (unsigned int k = 0; k < node.directions.size(); ++k)
      if (sticks_exactly(node, node.directions[k]))
        {
          const double share =
            bound_sum > 0 ? law_of(node.directions[k]).bound(forces[k]) / bound_sum : 1. / n_sticking;
          stick_forces[k] = node.directions[k].element.in_tangent_plane(share * tangential);
        }
  }



  template <int dim>
  StateChanges
  ContactSet<dim>::update(const dealii::Vector<double> &v,
                          const dealii::Vector<double> &flow_residual,
                          std::ostream &                log)
  {
    StateChanges        changes;
    std::vector<double> forces;
    std::vector<Slip>   stick_forces;
    std::vector<std::pair<unsigned int, unsigned int>> changed_normal, changed_tangential; // (node, direction)
    const bool          penalty = uses_penalty();
    // The stick is the penalty law F_t = -omega_t v_t (not a constraint).
    const bool          penalty_stick = penalty || parameters->stick_enforcement == ContactParameters::StickEnforcement::penalty;

    // The active set's dead band: a direction changes its normal state only
    // when the rule p + c v.n > 0 is violated by more than 1e-6 of the
    // largest normal force. Where the metal just touches the die (p and v.n
    // both about zero, as along the end of a land), the plain rule flips
    // such nodes back and forth on round-off-sized forces. In 3D the band
    // is also at most c times 1e-7 of the largest speed, so that no
    // separated direction penetrates faster than that: the nodal forces
    // (~h^2) of a fine land are far below the largest one, and 1e-6 of it
    // let the land's nodes run into the die. In 2D that bound changed the
    // settled states of stress cases: the force band alone is kept for
    // leaving contact, and a separated node comes into it once it
    // penetrates faster than 5e-7 of the largest speed (half the guard's
    // bound: the graded land's end of the round bar with its free surface,
    // a penalty of 1e11; doc/benchmarks.md, "Figures behind the code's
    // rules").
    std::vector<std::vector<double>> all_forces(nodes.size());
    std::vector<std::vector<Slip>>   all_stick_forces(nodes.size());
    largest_speed = v.linfty_norm();
    double                           largest_force = 0;
    if (!penalty)
      for (unsigned int i = 0; i < nodes.size(); ++i)
        {
          decompose_reaction(nodes[i], flow_residual, v, all_forces[i], all_stick_forces[i]);
          for (const double f : all_forces[i])
            largest_force = std::max(largest_force, std::abs(f));
        }
    const double dead_band = 1e-6 * largest_force;
    // Only 3D asks whether Newton has stopped moving the solution (ties on
    // the cone below); 2D keeps no copy of the velocity.
    bool at_round_off = false;
    if (dim == 3)
      {
        if (previous_velocity.size() == v.size())
          {
            dealii::Vector<double> moved(v);
            moved -= previous_velocity;
            at_round_off = moved.l2_norm() <= 1e-10 * v.l2_norm();
          }
        previous_velocity = v;
      }

    for (unsigned int i = 0; i < nodes.size(); ++i)
      {
        Node &node = nodes[i];
        if (!penalty)
          {
            forces       = all_forces[i];
            stick_forces = all_stick_forces[i];
          }
        const bool held = node.n_held() > 0;

        // Normal direction.
        for (unsigned int k = 0; k < node.directions.size(); ++k)
          {
            Direction &  dir    = node.directions[k];
            const double g_n    = normal_rate(node, dir, v);
            bool         active = dir.active;
            dir.free_reaction = 0;
            if (penalty)
              {
                active           = g_n > 0;
                dir.normal_force = active ? -penalty_of(parameters->normal_penalty_factor, dir.wall) * g_n : 0.;
              }
            else
              {
                // p + c g_n > 0 with p = -F_n / w: in force units F_n - c w g_n < 0.
                const double c         = contact_constant(dir);
                const double band      = dim == 3 ? std::min(dead_band, 1e-7 * largest_speed * c) : dead_band;
                const double indicator = forces[k] - c * g_n;
                active = indicator < (dir.active ? band : -std::min(band, 5e-7 * largest_speed * c));
                dir.normal_force = dir.active ? forces[k] : 0.;
                dir.stick_force  = stick_forces[k];
                // A node no wall holds is free: its reaction must vanish.
                if (!held)
                  for (unsigned int d = 0; d < dim; ++d)
                    dir.free_reaction += dir.wall.normal[d] * flow_residual[node.dofs[d]];
              }
            if (dir.held_in_contact)
              continue;
            if (active != dir.active)
              {
                ++changes.normal;
                changed_normal.emplace_back(i, k);
              }
            dir.active = active;
          }

        // Tangential direction: a node held by one wall slides along it.
        const bool sliding = penalty || node.n_held() < dim;
        // A 3D node on the edge where two dies meet, held at rest by the
        // exact stick of one of them: the other walls' slip rates are zero
        // by that constraint and say nothing. The node moves when a
        // sticking wall's share of its friction leaves its cone (then
        // every wall slips, the way that wall's reaction pushes), and
        // otherwise stays at rest (every wall sticks). Left to their own
        // test, the walls trade stick and slip every iteration (|F_t| =
        // mu |F_n| with no slip is a tie), and Newton does not converge
        // (doc/benchmarks.md, "Figures behind the code's rules").
        bool                      held_at_rest = false, rest_holds = true;
        std::optional<Tensor<1, dim>> release_direction;
        for (const Direction &dir : node.directions)
          if (sliding && sticks_exactly(node, dir))
            {
              held_at_rest = true;
              const auto decision =
                ContactElement<dim>::decide(law_of(dir), Slip::Zero(), dir.normal_force, dir.stick_force, contact_constant(dir));
              if (decision.first == ContactStatus::slip)
                {
                  rest_holds = false;
                  release_direction = dir.element.in_space(decision.second);
                }
            }
        for (unsigned int k = 0; k < node.directions.size(); ++k)
          {
            Direction &dir   = node.directions[k];
            auto       state = std::make_pair(ContactStatus::separated, dir.slip_direction);
            // The friction force of this update, and where it is taken.
            Slip       multiplier = Slip::Zero(), multiplier_rate = Slip::Zero();
            double     multiplier_bound = 0;
            if (dir.active && sliding && held_at_rest && dir.status == ContactStatus::slip && !dir.regularised &&
                !law_of(dir).frictionless())
              {
                if (rest_holds)
                  state.first = ContactStatus::stick;
                else
                  {
                    const Slip along = dir.element.in_tangent_plane(*release_direction);
                    state = {ContactStatus::slip, along.norm() > 0 ? Slip(along / along.norm()) : dir.slip_direction};
                  }
              }
            else if (dir.active && sliding)
              {
                const FrictionLaw law       = law_of(dir);
                const Slip        slip_rate = dir.element.tangential_rate(element_velocity(node, dir, v));
                const Slip        current =
                  sticks_exactly(node, dir) ?
                    dir.stick_force :
                    ContactElement<dim>::friction(law, dir.status, dir.slip_direction, slip_rate, dir.normal_force).force;
                // The paper's penalty stick (eq. (16)) is the law F_t =
                // -omega_t v_t inside the cone: a node sticks where omega_t
                // |v_t| <= mu |F_n|, whatever force it carried (the penalty
                // law's return mapping). The exact law's rule (the carried
                // force less c v_t, c = eta/h) keeps a slipping node slipping
                // while it moves: with a soft omega_t it left nodes slipping
                // at omega_t |v_t| below their bound
                // (tests/couette_tangential_penalty_slip).
                state = penalty_stick ?
                          ContactElement<dim>::decide(law, slip_rate, dir.normal_force, Slip::Zero(), law.tangential_penalty) :
                          ContactElement<dim>::decide(law, slip_rate, dir.normal_force, current, contact_constant(dir));
                multiplier       = current;
                multiplier_rate  = slip_rate;
                multiplier_bound = law.bound(dir.normal_force);
                // A tie in 3D: once Newton no longer moves the solution, a
                // node exactly on the cone with no slip (|F_t| = mu |F_n|
                // to round-off) keeps its state; it otherwise flips between
                // stick and slip on round-off, at random, so that the cycle
                // test never sees a state return and Newton runs to its
                // limit (doc/benchmarks.md).
                // 2D keeps its rule: applied there from the first
                // iteration, or with a band of 1e-6, it changed the states
                // of the 2D stress cases.
                if (at_round_off && state.first != dir.status && dir.status != ContactStatus::separated &&
                    law.kind != FrictionLaw::Kind::regularised_coulomb)
                  {
                    const double excess =
                      (current - contact_constant(dir) * slip_rate).norm() - law.bound(dir.normal_force);
                    if (std::abs(excess) <= 1e-12 * largest_force)
                      state.first = dir.status;
                  }
                // A slipping node whose velocity reversed passed through rest
                // under the friction force. The second time it does so in a
                // run it sticks, and slips again only if its reaction leaves
                // the cone, then in the direction the reaction pushes: near
                // dead zones, where the slip rates are small, nodes otherwise
                // flip their slip direction from one iteration to the next.
                if (dir.status == ContactStatus::slip && slip_rate.dot(dir.slip_direction) < 0 && !law.frictionless() &&
                    law.kind != FrictionLaw::Kind::regularised_coulomb && ++dir.reversals >= 2)
                  state.first = ContactStatus::stick;
              }
            else if (dir.active)
              state = std::make_pair(ContactStatus::stick, dir.slip_direction);
            if (dir.regularised || parameters->law == FrictionLaw::Kind::regularised_coulomb)
              {
                // A smooth law has no stick and no states to settle.
                dir.status = dir.active ? ContactStatus::slip : ContactStatus::separated;
                continue;
              }
            // A direction that enters or leaves contact changed its normal
            // state; the tangential state counts among those that stay.
            const bool frictional = !law_of(dir).frictionless();
            const bool stays      = dir.active && dir.status != ContactStatus::separated;
            // The slip direction changed when it turned by more than 90
            // degrees (in 2D: reversed); in 3D it follows the slip rate
            // between updates, so smaller turns are no change of state.
            if (stays && (state.first != dir.status || (frictional && state.first == ContactStatus::slip &&
                                                        state.second.dot(dir.slip_direction) < 0)))
              {
                ++changes.tangential;
                changed_tangential.emplace_back(i, k);
              }
            dir.status = state.first;
            dir.slip_direction = state.second;
            // A node that goes on slipping, or starts to, carries its friction force.
            dir.multiplier       = dir.status == ContactStatus::slip ? multiplier : Slip::Zero();
            dir.multiplier_rate  = multiplier_rate;
            dir.multiplier_bound = multiplier_bound;
          }
      }

    // Cycling: a state seen a few iterations ago returns. The directions
    // that keep entering and leaving contact are held in contact; those
    // that keep switching between stick and slip get the regularised
    // Coulomb law (smooth, so nothing left to switch).
    std::size_t signature = nodes.size();
    for (const auto &node : nodes)
      for (const auto &dir : node.directions)
        signature = signature * 1000003u ^ (dir.active * 7 + static_cast<int>(dir.status) * 2 + (dir.slip_direction[0] > 0));
    const auto seen   = std::find(recent_signatures.begin(), recent_signatures.end(), signature);
    const bool cycled = changes.total() > 0 && seen != recent_signatures.end();
    // A cycle under Newton's coupling of the Coulomb bound to F_n: the
    // directions that changed get the bound frozen at each iteration's
    // normal force (at a die with mu of order 1, a small pull times mu
    // reverses the friction of the linearised step, and whole lands flip
    // between pulling and penetrating). The fixed point is Coulomb's
    // solution; only directions that cycle again are held or regularised.
    // The cycle's members are all the directions changed since its state
    // was last seen, not only this update's: with this update's alone, a
    // cycle of three (die2d with its free surface at 508k dofs, stick/slip
    // at the end of the contact on the land) ran once more before a second
    // freeze (9 Newton iterations, now 6; doc/benchmarks.md), and die2d at
    // mu = 1 on 8 cells across took 61 (now 47, linear once frozen:
    // tests/stress_mu_1_coarse_advice).
    std::vector<std::pair<unsigned int, unsigned int>> this_update(changed_normal);
    this_update.insert(this_update.end(), changed_tangential.begin(), changed_tangential.end());
    std::vector<std::pair<unsigned int, unsigned int>> changed(this_update);
    if (cycled)
      for (auto c = recent_changes.begin() + (seen - recent_signatures.begin()) + 1; c != recent_changes.end(); ++c)
        changed.insert(changed.end(), c->begin(), c->end());
    if (cycled && !penalty && parameters->coulomb_coupling == ContactParameters::CoulombCoupling::automatic &&
        parameters->law == FrictionLaw::Kind::coulomb)
      {
        unsigned int frozen = 0;
        for (const auto &[i, k] : changed)
          {
            Direction &dir = nodes[i].directions[k];
            if (!dir.bound_frozen && !dir.regularised && parameters->friction_coefficient_of(dir.wall.id) > 0)
              {
                dir.bound_frozen = true;
                ++frozen;
              }
          }
        if (frozen > 0)
          {
            recent_signatures.clear();
            recent_changes.clear();
            log << "    contact states cycle: " << frozen
                << " Coulomb bound(s) frozen at each iteration's normal force (Contact/Coulomb coupling = auto)"
                << std::endl;
            return changes;
          }
      }
    if (cycled)
      {
        for (const auto &[i, k] : changed_normal)
          {
            Direction &dir      = nodes[i].directions[k];
            dir.active          = true;
            dir.held_in_contact = true;
          }
        // v0: a hundredth of the largest speed, so that Newton can follow
        // the smooth law. Relative, not the deck's Regularisation velocity
        // (mm/s): a die pushed at 1e-6 mm/s is the same problem as at 1
        // mm/s, and an absolute v0 of 1 mm/s took its friction away.
        cycling_velocity = v.linfty_norm() > 0 ? 0.01 * v.linfty_norm() : parameters->regularisation_velocity;
        for (const auto &[i, k] : changed_tangential)
          nodes[i].directions[k].regularised = true;
        log << "    contact states cycle: " << changed_normal.size() << " direction(s) held in contact, "
            << changed_tangential.size() << " friction law(s) regularised (arctan, v0 = " << cycling_velocity
            << " mm/s)" << std::endl;
      }
    // Settled under frozen bounds: four updates without a change. The
    // fixed point on the bound converges linearly, at a rate that tends to
    // 1 as mu grows (die2d, mu 0.9 on 3 cells across: 0.84 per iteration);
    // with the states settled, what froze the bounds (a linearised step
    // that reversed the friction while the states still moved) is gone,
    // and Newton's coupling of the bound to F_n is restored, quadratic from
    // there. Once per set of states (setup(), release_holds()): a thaw
    // whose states cycle again is frozen again by the rule above and stays
    // so. Measured on the extreme corpus (doc/stress.md): two decks more
    // converge, none less, with 4 or 6 quiet updates; with 2 (and twice
    // per set) five that converged did not, with 3 two, with 4 twice one.
    quiet_updates = changes.total() == 0 ? quiet_updates + 1 : 0;
    if (quiet_updates >= 4 && thaws == 0 && !penalty &&
        parameters->coulomb_coupling == ContactParameters::CoulombCoupling::automatic &&
        parameters->law == FrictionLaw::Kind::coulomb)
      {
        unsigned int thawed = 0;
        for (auto &node : nodes)
          for (auto &dir : node.directions)
            if (dir.bound_frozen)
              {
                dir.bound_frozen = false;
                ++thawed;
              }
        if (thawed > 0)
          {
            ++thaws;
            log << "    contact states settled: " << thawed
                << " Coulomb bound(s) coupled to the normal force again (Contact/Coulomb coupling = auto)" << std::endl;
          }
      }
    recent_signatures.push_back(signature);
    recent_changes.push_back(this_update);
    if (recent_signatures.size() > 12)
      {
        recent_signatures.erase(recent_signatures.begin());
        recent_changes.erase(recent_changes.begin());
      }
    return changes;
  }

  template StateChanges
  ContactSet<2>::update(const dealii::Vector<double> &, const dealii::Vector<double> &, std::ostream &);
  template StateChanges
  ContactSet<3>::update(const dealii::Vector<double> &, const dealii::Vector<double> &, std::ostream &);
  template Tensor<1, 2>
  ContactSet<2>::dual_normal(const Node &, const Direction &) const;
  template Tensor<1, 3>
  ContactSet<3>::dual_normal(const Node &, const Direction &) const;
} // namespace dieflow
