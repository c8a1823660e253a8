// What the contact of a solution reports: forces and checks per die, die-wall profiles and surfaces, where the mesh needs refining.
#include <dieflow/base/atomic_file.h>
#include <dieflow/postprocess/contact_output.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <tuple>

namespace dieflow
{
  template <int dim>
  void
  summarise_contact(const ContactSet<dim> &                    contact,
                    const std::vector<ContactNodeResult<dim>> &results,
                    const double                               speed_scale,
                    CycleSummary &                             summary)
  {
    for (const auto id : contact.get_parameters().die_ids)
      {
        summary.die_normal_force[id] = summary.die_friction_force[id] = 0;
        summary.contact_length[id]   = {{0, 0, 0}};
      }
    for (const auto &r : results)
      {
        summary.die_normal_force[r.id] += std::abs(r.normal_force);
        summary.die_friction_force[r.id] += r.friction_force.norm();
        summary.contact_length[r.id][r.status == ContactStatus::separated ? 0 :
                                     r.status == ContactStatus::stick     ? 1 :
                                                                            2] += r.length;
      }
    double largest_force = 0, largest_bound = 0, largest_friction = 0;
    for (const auto &r : results)
      {
        largest_force    = std::max(largest_force, std::abs(r.normal_force));
        largest_bound    = std::max(largest_bound, r.friction_bound);
        largest_friction = std::max(largest_friction, r.friction_force.norm());
      }
    summary.friction_power = 0;
    summary.contact_penetration = summary.contact_tension = summary.friction_excess = summary.stick_slip_rate = 0;
    summary.separated_reaction = 0;
    summary.friction_checked_nodes = 0;
    for (const auto &r : results)
      {
        summary.contact_penetration = std::max(summary.contact_penetration, r.normal_rate);
        summary.separated_reaction  = std::max(summary.separated_reaction, std::abs(r.free_reaction));
        if (r.status == ContactStatus::separated)
          continue;
        summary.contact_tension = std::max(summary.contact_tension, r.normal_force);
        if (!r.friction_from_law)
          {
            summary.friction_excess = std::max(summary.friction_excess, r.friction_force.norm() - r.friction_bound);
            ++summary.friction_checked_nodes;
          }
        if (r.status == ContactStatus::stick)
          summary.stick_slip_rate = std::max(summary.stick_slip_rate, r.slip_velocity.norm());
        summary.friction_power = std::max(summary.friction_power, r.friction_force * r.slip_velocity);
      }
    summary.friction_power /= std::max(largest_friction * speed_scale, 1e-300);
    summary.contact_penetration /= std::max(speed_scale, 1e-300);
    summary.stick_slip_rate /= std::max(speed_scale, 1e-300);
    summary.contact_tension /= std::max(largest_force, 1e-300);
    summary.friction_excess /= std::max(largest_bound, 1e-300);
    summary.separated_reaction /= std::max(largest_force, 1e-300);
    std::tie(summary.held_in_contact, summary.regularised_friction) = contact.cycle_breaks();
    summary.contact_nodes = contact.node_counts();
  }



  namespace
  {
    /// The results of one wall in order along it: start at the point
    /// farthest from the centroid (an end of the wall), then always the
    /// nearest next point.
    template <int dim>
    std::vector<const ContactNodeResult<dim> *>
    along_the_wall(std::vector<const ContactNodeResult<dim> *> points)
    {
      std::vector<const ContactNodeResult<dim> *> chain;
      if (points.empty())
        return chain;
      dealii::Point<dim> centroid;
      for (const auto *p : points)
        centroid += p->position / static_cast<double>(points.size());
      auto start = std::max_element(points.begin(), points.end(), [&](auto a, auto b) {
        return a->position.distance(centroid) < b->position.distance(centroid);
      });
      chain.push_back(*start);
      points.erase(start);
      while (!points.empty())
        {
          auto next = std::min_element(points.begin(), points.end(), [&](auto a, auto b) {
            return a->position.distance(chain.back()->position) < b->position.distance(chain.back()->position);
          });
          chain.push_back(*next);
          points.erase(next);
        }
      return chain;
    }



    /**
     * The degree-1 contact pressure recovered along the wall: at each node,
     * the least-squares line p = a + b s through the raw values (nodal
     * normal force over boundary weight) of the node and its two
     * neighbours, weighted by their boundary weights, where all three lie
     * on one straight stretch of wall (no corner between) in one contact
     * state (no stick/slip end or separation point between), evaluated at
     * the node. A pressure linear along the wall is kept exactly, a curved
     * one within O(h^2); a pattern that repeats every three nodes (as the
     * corner grading leaves on die2d) is averaged out on equal spacing,
     * the node-to-node alternation +c, -c damped to a third.
     */
    template <int dim>
    std::vector<double>
    pressures_along(const std::vector<const ContactNodeResult<dim> *> &chain, const std::vector<double> &s)
    {
      const auto joined = [&](const unsigned int i, const unsigned int j) {
        return chain[i]->status == chain[j]->status && chain[i]->normal * chain[j]->normal > std::cos(5. * M_PI / 180);
      };
      // The end of a stretch (a corner, a change of state) is where the raw
      // value is least accurate (first order at a corner): it keeps its
      // own value and does not enter its neighbour's fit.
      const auto end = [&](const unsigned int j) {
        return j == 0 || j + 1 == chain.size() || !joined(j - 1, j) || !joined(j, j + 1);
      };
      std::vector<double> recovered(chain.size());
      for (unsigned int i = 0; i < chain.size(); ++i)
        {
          const auto raw = [&](const unsigned int j) { return -chain[j]->normal_force / chain[j]->weight; };
          unsigned int first = i, last = i;
          if (!end(i))
            {
              if (!end(i - 1))
                --first;
              if (!end(i + 1))
                ++last;
            }
          double w = 0, ws = 0, wss = 0, wp = 0, wsp = 0;
          for (unsigned int j = first; j <= last; ++j)
            {
              const double weight = chain[j]->weight, x = s[j] - s[i];
              w += weight;
              ws += weight * x;
              wss += weight * x * x;
              wp += weight * raw(j);
              wsp += weight * x * raw(j);
            }
          const double determinant = w * wss - ws * ws;
          recovered[i] = (last - first >= 2 && determinant > 1e-12 * w * wss) ? (wp * wss - ws * wsp) / determinant : raw(i);
        }
      return recovered;
    }
  } // namespace



  template <int dim>
  std::vector<dealii::Point<dim>>
  contact_hot_points(const ContactSet<dim> &contact, const std::vector<ContactNodeResult<dim>> &results)
  {
    std::vector<dealii::Point<dim>> hot = contact.corner_points();
    // 3D: the corners and edges only (a wall there is a surface, whose
    // state boundaries are lines that no chain of nodes follows).
    if constexpr (dim == 3)
      return hot;
    for (const auto id : contact.get_parameters().die_ids)
      {
        std::vector<const ContactNodeResult<dim> *> points;
        for (const auto &r : results)
          if (r.id == id)
            points.push_back(&r);
        const auto chain = along_the_wall(points);
        for (unsigned int i = 1; i < chain.size(); ++i)
          if (chain[i]->status != chain[i - 1]->status && chain[i]->position.distance(chain[i - 1]->position) > 0)
            {
              hot.push_back(chain[i]->position);
              hot.push_back(chain[i - 1]->position);
            }
      }
    return hot;
  }



  namespace
  {
    /// The metal's T at a contact node: its vertex's (the record's), else (a degree-2 node between vertices) found in the mesh.
    template <int dim>
    double
    node_temperature(const HeatEquation<dim> &heat, const ContactNodeResult<dim> &node)
    {
      const auto &vertices = heat.record().vertex_temperature;
      return node.vertex < vertices.size() ? vertices[node.vertex] : heat.value_at(node.position);
    }
  } // namespace



  template <int dim>
  void
  write_die_profiles(const std::set<BoundaryId> &                        die_ids,
                     const std::vector<ContactNodeResult<dim>> &         results,
                     const std::vector<dealii::SymmetricTensor<2, dim>> *vertex_stress,
                     const HeatEquation<dim> *                           heat,
                     const std::string &                                 directory)
  {
    if constexpr (dim == 3)
      {
        write_die_surfaces(die_ids, results, heat, directory);
        return;
      }
    for (const auto id : die_ids)
      {
        std::vector<const ContactNodeResult<dim> *> points;
        for (const auto &r : results)
          if (r.id == id)
            points.push_back(&r);
        if (points.empty())
          continue;
        const auto          chain = along_the_wall(points);
        std::vector<double> s(chain.size(), 0.);
        for (unsigned int i = 1; i < chain.size(); ++i)
          s[i] = s[i - 1] + chain[i]->position.distance(chain[i - 1]->position);
        const std::vector<double> recovered = vertex_stress ? pressures_along(chain, s) : std::vector<double>();
        AtomicFile    file(directory + "/die-profile-" + std::to_string(id) + ".dat");
        std::ostream &out = file.stream();
        out << "# die wall id " << id
            << ", ordered along the wall. contact_pressure, friction_stress: the nodal forces over their boundary "
               "weights"
            << (vertex_stress ? " (raw: they zigzag from node to node with the Q1-P0 pressure). recovered_pressure: a "
                                "least-squares line through 3 raw values along one stretch of wall in one contact "
                                "state; recovered_shear: t.sigma n of the stress averaged at the node from the cells "
                                "around it (doc/contact.md)" :
                                "; degree 2: the recovered columns repeat them") << "\n"
            << "# s(mm) x(mm) y(mm) contact_pressure(MPa) friction_stress(MPa) normal_velocity(mm/s) "
               "slip_velocity(mm/s) status(0 separated, 1 stick, 2 slip) recovered_pressure(MPa) "
               "recovered_shear(MPa)"
            << (heat ? " temperature(K) heat_flux(mW/mm^2: h (T - T_ambient), into the die)" : "") << '\n';
        for (unsigned int i = 0; i < chain.size(); ++i)
          {
            const auto & r        = *chain[i];
            const double pressure = -r.normal_force / r.weight;
            const double friction = r.friction_force * r.tangent / r.weight;
            const double shear    = (vertex_stress && r.vertex != dealii::numbers::invalid_unsigned_int &&
                                  r.status != ContactStatus::separated) ?
                                      r.tangent * ((*vertex_stress)[r.vertex] * r.normal) :
                                      friction;
            out << std::setprecision(8) << s[i] << ' ' << r.position[0] << ' ' << r.position[1] << ' '
                << pressure << ' ' << friction << ' ' << r.normal_rate << ' ' << r.slip_velocity * r.tangent << ' '
                << static_cast<int>(r.status) << ' ' << (vertex_stress ? recovered[i] : pressure) << ' ' << shear;
            if (heat)
              {
                const double T = node_temperature(*heat, r);
                out << ' ' << T << ' ' << heat->wall_flux(id, T);
              }
            out << '\n';
          }
        file.commit();
      }
  }



  template <int dim>
  void
  write_die_surfaces(const std::set<BoundaryId> &               die_ids,
                     const std::vector<ContactNodeResult<dim>> &results,
                     const HeatEquation<dim> *                  heat,
                     const std::string &                        directory)
  {
    for (const auto id : die_ids)
      {
        AtomicFile    file(directory + "/die-surface-" + std::to_string(id) + ".dat");
        std::ostream &out = file.stream();
        out << "# die wall id " << id
            << ": one line per contact node (and wall direction). contact_pressure, friction_stress: the nodal "
               "forces over their boundary weights; the friction stress and the slip velocity are vectors in the "
               "tangent plane\n"
            << "# x(mm) y(mm) z(mm) contact_pressure(MPa) friction_stress_x friction_stress_y friction_stress_z "
               "|friction_stress|(MPa) normal_velocity(mm/s) slip_velocity_x slip_velocity_y slip_velocity_z "
               "status(0 separated, 1 stick, 2 slip)"
            << (heat ? " temperature(K) heat_flux(mW/mm^2, into the die)" : "") << '\n';
        for (const auto &r : results)
          if (r.id == id)
            {
              const Tensor<1, dim> friction = r.friction_force / r.weight;
              out << std::setprecision(8);
              for (unsigned int d = 0; d < dim; ++d)
                out << r.position[d] << ' ';
              out << -r.normal_force / r.weight << ' ';
              for (unsigned int d = 0; d < dim; ++d)
                out << friction[d] << ' ';
              out << friction.norm() << ' ' << r.normal_rate;
              for (unsigned int d = 0; d < dim; ++d)
                out << ' ' << r.slip_velocity[d];
              out << ' ' << static_cast<int>(r.status);
              if (heat)
                {
                  const double T = node_temperature(*heat, r);
                  out << ' ' << T << ' ' << heat->wall_flux(id, T);
                }
              out << '\n';
            }
        file.commit();
      }
  }

  template void
  summarise_contact(const ContactSet<2> &, const std::vector<ContactNodeResult<2>> &, const double, CycleSummary &);
  template void
  summarise_contact(const ContactSet<3> &, const std::vector<ContactNodeResult<3>> &, const double, CycleSummary &);
  template std::vector<dealii::Point<2>>
  contact_hot_points(const ContactSet<2> &, const std::vector<ContactNodeResult<2>> &);
  template std::vector<dealii::Point<3>>
  contact_hot_points(const ContactSet<3> &, const std::vector<ContactNodeResult<3>> &);
  template void
  write_die_profiles(const std::set<BoundaryId> &, const std::vector<ContactNodeResult<2>> &,
                     const std::vector<dealii::SymmetricTensor<2, 2>> *, const HeatEquation<2> *, const std::string &);
  template void
  write_die_profiles(const std::set<BoundaryId> &, const std::vector<ContactNodeResult<3>> &,
                     const std::vector<dealii::SymmetricTensor<2, 3>> *, const HeatEquation<3> *, const std::string &);
  template void
  write_die_surfaces(const std::set<BoundaryId> &, const std::vector<ContactNodeResult<2>> &, const HeatEquation<2> *, const std::string &);
  template void
  write_die_surfaces(const std::set<BoundaryId> &, const std::vector<ContactNodeResult<3>> &, const HeatEquation<3> *, const std::string &);
} // namespace dieflow
