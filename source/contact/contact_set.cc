// The contact set: its nodes on a mesh, their states across meshes, the constraints and element terms they make.
#include <dieflow/base/serialization.h>
#include <dieflow/contact/contact_set.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dieflow
{
  template <int dim>
  unsigned int
  ContactSet<dim>::Node::n_active() const
  {
    return std::count_if(directions.begin(), directions.end(), [](const Direction &d) { return d.active; });
  }



  template <int dim>
  void
  ContactSet<dim>::initialize(const ContactParameters &p)
  {
    parameters = &p;
    die_velocity.clear();
    for (const auto &[id, components] : parameters->die_velocities)
      {
        // ProblemParameters checked the count.
        Assert(components.size() == dim, dealii::ExcDimensionMismatch(components.size(), dim));
        for (unsigned int d = 0; d < dim; ++d)
          die_velocity[id][d] = components[d];
      }
  }



  template <int dim>
  Tensor<1, dim>
  ContactSet<dim>::velocity_of(const BoundaryId id) const
  {
    const auto it = die_velocity.find(id);
    return it == die_velocity.end() ? Tensor<1, dim>() : it->second;
  }



  template <int dim>
  std::pair<unsigned int, unsigned int>
  ContactSet<dim>::cycle_breaks() const
  {
    unsigned int held = 0, regularised = 0;
    for (const auto &node : nodes)
      for (const auto &dir : node.directions)
        {
          held += dir.held_in_contact;
          regularised += dir.regularised;
        }
    return {held, regularised};
  }



  template <int dim>
  std::string
  ContactSet<dim>::cycling_note() const
  {
    const auto [held, regularised] = cycle_breaks();
    if (held + regularised == 0)
      return "";
    return "the states cycled: " + std::to_string(held) + " direction(s) held in contact, " +
           std::to_string(regularised) + " friction law(s) regularised";
  }



  template <int dim>
  double
  ContactSet<dim>::penalty_of(const double factor, const WallDirection<dim> &wall) const
  {
    // The weight is the node's area (2 pi r h in the axisymmetric geometry), h its mesh size.
    const double h = std::pow(wall.length, 1. / (dim - 1));
    return factor * penalty_scale * wall.weight / h;
  }



  template <int dim>
  double
  ContactSet<dim>::contact_constant(const Direction &direction) const
  {
    const double h = std::pow(direction.wall.length, 1. / (dim - 1));
    return parameters->active_set_constant * viscosity_scale * direction.wall.weight / h;
  }



  template <int dim>
  FrictionLaw
  ContactSet<dim>::law_of(const Direction &direction) const
  {
    FrictionLaw law             = parameters->law_of(direction.wall.id, direction.wall.weight);
    law.mu *= friction_scale;
    law.shear_bound *= friction_scale;
    law.kind                    = direction.regularised ? FrictionLaw::Kind::regularised_coulomb : parameters->law;
    law.tangential_penalty      = penalty_of(parameters->tangential_penalty_factor, direction.wall);
    if (law.kind == FrictionLaw::Kind::coulomb && !uses_penalty() &&
        (parameters->coulomb_coupling == ContactParameters::CoulombCoupling::fixed_point || direction.bound_frozen))
      {
        // Tresca with the bound of the last reaction: no F_n in the tangent.
        law.shear_bound = law.bound(direction.normal_force);
        law.kind        = FrictionLaw::Kind::tresca;
      }
    law.regularisation_velocity = direction.regularised                    ? cycling_velocity :
                                  parameters->regularisation_velocity > 0 ? parameters->regularisation_velocity :
                                                                            0.01 * speed_scale;
    law.slip_floor              = 1e-9 * largest_speed;
    // 3D slip: the semismooth Newton method on the carried friction force
    // (ContactElement::friction()), from the first state update that gives
    // the node one (its stick force when it leaves the cone).
    if (dim != 3 || direction.status != ContactStatus::slip || direction.regularised ||
        direction.multiplier.norm() == 0)
      return law;
    const double c = contact_constant(direction);
    if ((direction.multiplier - c * direction.multiplier_rate).norm() > 0)
      {
        law.multiplier.constant = c;
        law.multiplier.bound    = direction.multiplier_bound;
        for (int i = 0; i < dim - 1; ++i)
          {
            law.multiplier.force[i] = direction.multiplier[i];
            law.multiplier.rate[i]  = direction.multiplier_rate[i];
          }
      }
    return law;
  }



  template <int dim>
  typename ContactElement<dim>::Vector
  ContactSet<dim>::element_velocity(const Node &node, const Direction &direction, const dealii::Vector<double> &v) const
  {
    // The die is rigid: its master nodes all move with its translation.
    typename ContactElement<dim>::Vector u = ContactElement<dim>::Vector::Zero();
    const Tensor<1, dim>                 die = velocity_of(direction.wall.id);
    for (unsigned int d = 0; d < dim; ++d)
      {
        u[d] = v[node.dofs[d]];
        for (unsigned int a = 1; a <= dim; ++a)
          u[a * dim + d] = die[d];
      }
    return u;
  }



  template <int dim>
  double
  ContactSet<dim>::normal_rate(const Node &node, const Direction &direction, const dealii::Vector<double> &v) const
  {
    return direction.element.normal_rate(element_velocity(node, direction, v)) - direction.wall.gap_rate;
  }



  template <int dim>
  std::vector<typename ContactSet<dim>::StateRecord>
  ContactSet<dim>::state_records() const
  {
    std::vector<StateRecord> records;
    for (const auto &node : nodes)
      for (const auto &direction : node.directions)
        if (!(direction.approaching && !direction.active))
          records.push_back({node.position,
                             direction.wall.id,
                             direction.wall.normal,
                             direction.wall.weight,
                             direction.active,
                             direction.status,
                             std::vector<double>(direction.slip_direction.data(),
                                                 direction.slip_direction.data() + direction.slip_direction.size()),
                             direction.normal_force,
                             direction.bound_frozen});
    return records;
  }



  template <int dim>
  void
  ContactSet<dim>::save(OutputArchive &ar) const
  {
    std::vector<StateRecord> records = state_records();
    serialize_each(ar, records, [&](StateRecord &r) {
      int status = static_cast<int>(r.status);
      ar << r.position << r.id << r.normal << r.weight << r.active << status << r.slip_direction << r.normal_force
         << r.bound_frozen;
    });
  }



  template <int dim>
  void
  ContactSet<dim>::load(InputArchive &ar)
  {
    serialize_each(ar, restored_states, [&](StateRecord &r) {
      int status = 0;
      ar >> r.position >> r.id >> r.normal >> r.weight >> r.active >> status >> r.slip_direction >> r.normal_force >>
        r.bound_frozen;
      r.status = static_cast<ContactStatus>(status);
    });
  }



  template <int dim>
  void
  ContactSet<dim>::setup(const std::vector<WallNode<dim>> &die_nodes,
                         const AffineConstraints<double> & prescribed,
                         const bool                        keep_state,
                         const std::vector<WallNode<dim>> &approaching)
  {
    // The states of the previous mesh: a node that remains keeps its own; a
    // new one (the midpoint of a refined wall face) takes that of the
    // nearest old node with the same wall direction.
    const std::vector<StateRecord> previous =
      !keep_state ? std::vector<StateRecord>() : restored_states.empty() ? state_records() : restored_states;
    restored_states.clear();
    const auto inherit = [&](const dealii::Point<dim> &position, Direction &direction) {
      double             nearest = std::numeric_limits<double>::max();
      const StateRecord *source  = nullptr;
      for (const auto &candidate : previous)
        if (candidate.id == direction.wall.id && candidate.normal * direction.wall.normal > 0.999 &&
            candidate.position.distance(position) < nearest)
          {
            nearest = candidate.position.distance(position);
            source  = &candidate;
          }
      if (source != nullptr)
        {
          direction.active = source->active;
          direction.status = source->status;
          for (unsigned int i = 0; i < direction.slip_direction.size(); ++i)
            direction.slip_direction[i] = source->slip_direction[i];
          // The contact pressure too: Coulomb slip linearises about the
          // normal force, and with none the first solve on the new mesh
          // would let every slipping node slide frictionless.
          direction.normal_force = source->normal_force / source->weight * direction.wall.weight;
          // A Coulomb coupling that cycled here cycles again on the moved or
          // refined mesh if Newton couples it again: die2d with its free
          // surface at 508k and 749k dofs repeated the cycle of three and its
          // freeze on every solve (doc/benchmarks.md).
          direction.bound_frozen = source->bound_frozen;
        }
    };

    // The die's wall nodes start in contact and slipping (or as on the
    // previous mesh); the free surface's approaching nodes start separated
    // and inherit nothing. Walls that are no die hold a node always.
    const auto add_nodes = [&](const std::vector<WallNode<dim>> &wall_nodes, const bool approach) {
      for (const auto &wall_node : wall_nodes)
        {
          bool is_prescribed = false;
          for (const auto dof : wall_node.dofs)
            is_prescribed |= prescribed.is_constrained(dof);
          if (is_prescribed)
            continue;
          Node node;
          node.dofs     = wall_node.dofs;
          node.position = wall_node.position;
          node.vertex   = wall_node.vertex;
          for (const auto &wall : wall_node.directions)
            if (parameters->die_ids.count(wall.id))
              {
                node.directions.push_back({wall,
                                           ContactElement<dim>(wall_node.position, wall.facet, wall.normal),
                                           !approach,
                                           approach ? ContactStatus::separated : ContactStatus::slip,
                                           Slip::Unit(0),
                                           0.,
                                           Slip::Zero(),
                                           0.,
                                           Slip::Zero(),
                                           Slip::Zero(),
                                           0.,
                                           0,
                                           false,
                                           false,
                                           false,
                                           approach});
                if (keep_state && !approach)
                  inherit(wall_node.position, node.directions.back());
              }
            else
              node.fixed_normals.push_back(wall.normal);
          if (!node.directions.empty())
            nodes.push_back(node);
        }
    };
    nodes.clear();
    recent_signatures.clear();
    recent_changes.clear();
    quiet_updates = thaws = 0;
    add_nodes(die_nodes, false);
    add_nodes(approaching, true);
  }



  template <int dim>
  void
  ContactSet<dim>::restart_states()
  {
    release_holds();
    for (auto &node : nodes)
      for (auto &dir : node.directions)
        {
          dir.active         = !dir.approaching;
          dir.status         = dir.approaching ? ContactStatus::separated : ContactStatus::slip;
          dir.slip_direction = Slip::Unit(0);
          dir.normal_force   = 0;
          dir.stick_force = dir.multiplier = dir.multiplier_rate = Slip::Zero();
          dir.multiplier_bound = 0;
        }
    previous_velocity.reinit(0);
  }



  template <int dim>
  void
  ContactSet<dim>::release_holds()
  {
    for (auto &node : nodes)
      for (auto &dir : node.directions)
        {
          dir.reversals       = 0;
          dir.held_in_contact = false;
          dir.regularised     = false;
          dir.bound_frozen    = bounds_frozen_everywhere;
        }
    recent_signatures.clear();
    recent_changes.clear();
    quiet_updates = thaws = 0;
  }



  template <int dim>
  ContactSet<dim>
  ContactSet<dim>::frozen_on(const std::vector<WallNode<dim>> &die_nodes, const AffineConstraints<double> &prescribed) const
  {
    ContactSet<dim> other = *this;
    if (!empty())
      other.setup(die_nodes, prescribed, true);
    return other;
  }



  template <int dim>
  bool
  ContactSet<dim>::sticks_exactly(const Node &node, const Direction &direction) const
  {
    return parameters->stick_enforcement == ContactParameters::StickEnforcement::exact && !uses_penalty() && !direction.regularised &&
           parameters->law != FrictionLaw::Kind::regularised_coulomb && direction.active &&
           direction.status == ContactStatus::stick && node.n_held() < dim;
  }



  template <int dim>
  void
  ContactSet<dim>::add_constraints(AffineConstraints<double> &constraints, const bool homogeneous) const
  {
    if (uses_penalty())
      return;
    for (const auto &node : nodes)
      {
        // v.n_k = V.n_k + g_k / dt (the die's translation V; the gap of a
        // node approaching it), and v.t_i = V.t_i where the node sticks; the
        // Newton updates' constraints are homogeneous.
        std::vector<Tensor<1, dim>> normals;
        std::vector<double>         values;
        for (const auto &dir : node.directions)
          if (dir.active)
            {
              const Tensor<1, dim> die = homogeneous ? Tensor<1, dim>() : velocity_of(dir.wall.id);
              normals.push_back(dir.wall.normal);
              values.push_back(die * dir.wall.normal + (homogeneous ? 0. : dir.wall.gap_rate));
              if (sticks_exactly(node, dir))
                for (const auto &t : dir.element.tangents)
                  {
                    normals.push_back(t);
                    values.push_back(die * t);
                  }
            }
        if (!normals.empty())
          constrain_normal_components<dim>(node.dofs, normals, values, constraints);
      }
  }



  template <int dim>
  std::vector<ContactContribution<dim>>
  ContactSet<dim>::contributions(const dealii::Vector<double> &v) const
  {
    std::vector<ContactContribution<dim>> result;
    const bool                            penalty = uses_penalty();
    for (const auto &node : nodes)
      {
        if (!penalty && node.n_held() >= dim)
          continue; // separated, or held by two walls: no friction work
        for (const auto &dir : node.directions)
          {
            if (!dir.active)
              continue;
            const auto u = element_velocity(node, dir, v);
            const FrictionLaw law = law_of(dir);
            if (!penalty && (law.frictionless() || sticks_exactly(node, dir)))
              continue;
            const auto r = penalty ?
                             dir.element.penalty(u,
                                                 penalty_of(parameters->normal_penalty_factor, dir.wall),
                                                 true,
                                                 law,
                                                 dir.status,
                                                 dir.slip_direction) :
                             dir.element.friction_part(u, dir.normal_force, law, dir.status, dir.slip_direction);
            ContactContribution<dim> c;
            c.dofs = node.dofs;
            c.residual.reinit(dim);
            c.tangent.reinit(dim, dim);
            for (unsigned int a = 0; a < dim; ++a)
              {
                c.residual[a] = r.residual[a];
                for (unsigned int b = 0; b < dim; ++b)
                  c.tangent(a, b) = r.tangent(a, b);
              }
            if (!penalty)
              {
                // R_total = T R_flow + (R_c - b F_n), T = I + b n^T: exact
                // when F_t is linear in F_n (Coulomb slip), and R_c itself
                // when it does not depend on F_n (stick, Tresca).
                // With several normals at the node (3D: on the edge where
                // two dies meet), F_n = m.R_flow with m the dual vector of
                // n among them (the least squares of decompose_reaction());
                // m = n for one normal, or normals at right angles.
                double b_norm = 0;
                for (unsigned int a = 0; a < dim; ++a)
                  b_norm += std::abs(r.d_residual_d_normal_force[a]);
                if (b_norm > 0)
                  {
                    const Tensor<1, dim> m = dual_normal(node, dir);
                    c.has_row_transform    = true;
                    c.row_transform.reinit(dim, dim);
                    for (unsigned int a = 0; a < dim; ++a)
                      {
                        c.residual[a] -= r.d_residual_d_normal_force[a] * dir.normal_force;
                        for (unsigned int b = 0; b < dim; ++b)
                          c.row_transform(a, b) = (a == b ? 1. : 0.) + r.d_residual_d_normal_force[a] * m[b];
                      }
                  }
              }
            result.push_back(std::move(c));
          }
      }
    return result;
  }



  template <int dim>
  std::vector<ContactNodeResult<dim>>
  ContactSet<dim>::results(const dealii::Vector<double> &v) const
  {
    std::vector<ContactNodeResult<dim>> result;
    for (const auto &node : nodes)
      {
        for (const auto &dir : node.directions)
          {
            // A free node that stays off the die is no part of its contact.
            if (dir.approaching && !dir.active)
              continue;
            const auto             u = element_velocity(node, dir, v);
            ContactNodeResult<dim> r;
            r.position       = node.position;
            r.vertex         = node.vertex;
            r.id             = dir.wall.id;
            r.normal         = dir.wall.normal;
            r.tangent        = dir.element.tangents[0];
            r.weight         = dir.wall.weight;
            r.length         = dir.wall.length;
            r.status         = dir.active ? dir.status : ContactStatus::separated;
            r.normal_rate    = normal_rate(node, dir, v);
            const Slip slip  = dir.element.tangential_rate(u);
            r.slip_velocity  = dir.element.in_space(slip);
            r.normal_force   = dir.active ? dir.normal_force : 0.;
            r.free_reaction  = dir.active ? 0. : dir.free_reaction;
            const auto law   = law_of(dir);
            r.friction_bound = law.kind == FrictionLaw::Kind::tresca ? law.shear_bound : law.mu * std::abs(r.normal_force);
            const Slip friction =
              sticks_exactly(node, dir) ? dir.stick_force :
              (dir.active && (uses_penalty() || node.n_held() < dim)) ?
                                          ContactElement<dim>::friction(law, dir.status, dir.slip_direction, slip, r.normal_force).force :
                                          Slip::Zero();
            r.friction_force = dir.element.in_space(friction);
            r.friction_from_law =
              dir.active && !sticks_exactly(node, dir) &&
              ((dir.status == ContactStatus::slip && !(dim == 3 && law.multiplier.constant > 0)) ||
               law.kind == FrictionLaw::Kind::regularised_coulomb);
            result.push_back(r);
          }
      }
    return result;
  }



  template <int dim>
  dealii::Vector<double>
  ContactSet<dim>::vertex_status(const DoFHandler<dim> &dof_handler) const
  {
    dealii::Vector<double> status(dof_handler.get_triangulation().n_vertices());
    status = -1;
    for (const auto &node : nodes)
      {
        int s = static_cast<int>(ContactStatus::separated);
        for (const auto &dir : node.directions)
          if (dir.active)
            s = std::max(s, static_cast<int>(node.n_held() >= dim && !uses_penalty() ? ContactStatus::stick : dir.status));
        if (node.vertex != dealii::numbers::invalid_unsigned_int) // not an edge node
          status[node.vertex] = s;
      }
    return status;
  }



  template <int dim>
  std::vector<dealii::Point<dim>>
  ContactSet<dim>::corner_points() const
  {
    std::vector<dealii::Point<dim>> corners;
    for (const auto &node : nodes)
      if (node.directions.size() + node.fixed_normals.size() > 1)
        corners.push_back(node.position);
    return corners;
  }



  template <int dim>
  ContactCounts
  ContactSet<dim>::node_counts() const
  {
    ContactCounts counts;
    for (const auto &node : nodes)
      {
        if (node.n_active() == 0)
          ++counts.separated;
        else if (node.n_held() >= dim && !uses_penalty())
          ++counts.stick;
        else
          {
            bool slipping = false;
            for (const auto &dir : node.directions)
              slipping |= dir.active && dir.status == ContactStatus::slip;
            ++(slipping ? counts.slip : counts.stick);
          }
      }
    return counts;
  }

  template class ContactSet<2>;
  template class ContactSet<3>;
} // namespace dieflow
