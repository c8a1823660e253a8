// What a solution gives: the boundary parts' fluxes, areas and forces, errors against an exact velocity, and the fields written to files.
#include <dieflow/flow/pressure_projection.h>
#include <dieflow/base/atomic_file.h>
#include <dieflow/base/processes.h>
#include <dieflow/postprocess/postprocess.h>
#include <dieflow/postprocess/vertex_stress.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>
#include <fstream>
#include <iomanip>

namespace dieflow
{
  template <int dim>
  std::map<BoundaryId, double>
  boundary_fluxes(const CoordinateSystem<dim> &coordinates, const DoFHandler<dim> &dof_handler, const Vector<double> &velocity)
  {
    std::map<BoundaryId, double> flux;
    for (const auto id : dof_handler.get_triangulation().get_boundary_ids())
      flux[id] = 0;

    dealii::FEFaceValues<dim> fe_face(dof_handler.get_fe(),
                                      dealii::QGauss<dim - 1>(dof_handler.get_fe().degree + 1),
                                      dealii::update_values | dealii::update_normal_vectors |
                                        dealii::update_JxW_values | dealii::update_quadrature_points);
    const dealii::FEValuesExtractors::Vector velocities(0);
    std::vector<Tensor<1, dim>>              v(fe_face.n_quadrature_points);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            fe_face.reinit(cell, f);
            fe_face[velocities].get_function_values(velocity, v);
            double sum = 0;
            for (const unsigned int q : fe_face.quadrature_point_indices())
              sum += v[q] * fe_face.normal_vector(q) * fe_face.JxW(q) * coordinates.weight(fe_face.quadrature_point(q));
            flux[cell->face(f)->boundary_id()] += sum;
          }
    return flux;
  }



  template <int dim>
  std::map<BoundaryId, double>
  boundary_areas(const CoordinateSystem<dim> &coordinates, const DoFHandler<dim> &dof_handler)
  {
    std::map<BoundaryId, double> area;
    for (const auto id : dof_handler.get_triangulation().get_boundary_ids())
      area[id] = 0;
    // Exact for the straight faces of the meshes (r is linear along a face).
    const dealii::QGauss<dim - 1> quadrature(2);
    dealii::FEFaceValues<dim>     face_values(dof_handler.get_fe(), quadrature,
                                          dealii::update_JxW_values | dealii::update_quadrature_points);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            face_values.reinit(cell, f);
            for (const unsigned int q : face_values.quadrature_point_indices())
              area[cell->face(f)->boundary_id()] += face_values.JxW(q) * coordinates.weight(face_values.quadrature_point(q));
          }
    return area;
  }



  namespace
  {
    /// The parts of one boundary node: per part id, the integral of the
    /// node's basis function over the part's faces and its first moment.
    template <int dim>
    struct NodeParts
    {
      std::array<GlobalDof, dim>           dofs;
      std::map<BoundaryId, double>         weight;
      std::map<BoundaryId, Tensor<1, dim>> moment;
    };

    /// Where a wall's traction is known from a node of its own: t = R / w
    /// at the node's moment point.
    template <int dim>
    struct TractionSample
    {
      dealii::Point<dim> position;
      Tensor<1, dim>     traction;
    };

    template <int dim>
    bool
    carries_prescribed_traction(const BoundaryConditions<dim> &boundary_conditions, const BoundaryId id)
    {
      return boundary_conditions.traction_free_ids.count(id) || boundary_conditions.traction_ids.count(id);
    }

    /// Whether part @p id prescribes velocity component @p d.
    template <int dim>
    bool
    prescribes(const BoundaryConditions<dim> &boundary_conditions, const BoundaryId id, const unsigned int d)
    {
      if (!boundary_conditions.velocity_ids.count(id))
        return false;
      const auto mask = boundary_conditions.velocity_components.find(id);
      return mask == boundary_conditions.velocity_components.end() || mask->second[d];
    }

    /**
     * Shares @p reaction among the prescribed-velocity parts of @p node by
     * weight, each component among the parts that prescribe it: a part
     * whose x-velocity is free (Components = y) exerts no x-force, so at a
     * node it shares with a part that holds x, the x-reaction is the
     * other's. A component no part prescribes (round-off) goes to all.
     */
    template <int dim>
    void
    share_among_prescribed(const NodeParts<dim> &                     node,
                           const Tensor<1, dim> &                     reaction,
                           const BoundaryConditions<dim> &            boundary_conditions,
                           std::map<BoundaryId, std::vector<double>> &force)
    {
      for (unsigned int d = 0; d < dim; ++d)
        {
          double       total = 0, all = 0;
          unsigned int count = 0, all_count = 0;
          for (const auto &[id, w] : node.weight)
            if (boundary_conditions.velocity_ids.count(id))
              {
                all += w;
                ++all_count;
                if (prescribes(boundary_conditions, id, d))
                  {
                    total += w;
                    ++count;
                  }
              }
          const bool by_component = count > 0;
          if (!by_component)
            {
              total = all;
              count = all_count;
            }
          for (const auto &[id, w] : node.weight)
            if (by_component ? prescribes(boundary_conditions, id, d) : boundary_conditions.velocity_ids.count(id) > 0)
              // Weights can vanish (a degree-2 vertex on the axis): equal shares then.
              force[id][d] += (total != 0 ? w / total : 1. / count) * reaction[d];
        }
    }

    /// int t ds on each prescribed-traction part.
    template <int dim>
    void
    add_prescribed_tractions(const CoordinateSystem<dim> &              coordinates,
                             const DoFHandler<dim> &                    dof_handler,
                             const BoundaryConditions<dim> &            boundary_conditions,
                             std::map<BoundaryId, std::vector<double>> &force)
    {
      if (boundary_conditions.traction_ids.empty())
        return;
      dealii::FEFaceValues<dim> face_values(dof_handler.get_fe(),
                                            dealii::QGauss<dim - 1>(dof_handler.get_fe().degree + 2),
                                            dealii::update_JxW_values | dealii::update_quadrature_points);
      Vector<double> t(dim);
      for (const auto &cell : dof_handler.active_cell_iterators())
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary() && boundary_conditions.traction_ids.count(cell->face(f)->boundary_id()))
            {
              face_values.reinit(cell, f);
              for (const unsigned int q : face_values.quadrature_point_indices())
                {
                  boundary_conditions.traction->vector_value(face_values.quadrature_point(q), t);
                  for (unsigned int d = 0; d < dim; ++d)
                    force[cell->face(f)->boundary_id()][d] +=
                      t[d] * face_values.JxW(q) * coordinates.weight(face_values.quadrature_point(q));
                }
            }
    }

    /**
     * The reaction @p reaction at a node where the walls @p directions meet,
     * split among them: the part along each wall's normal belongs to that
     * wall (a 2D corner: R = a_1 n_1 + a_2 n_2; least squares), and what
     * remains (the part along a tangent they share, in 3D the edge between
     * two planes) is friction: it goes by weight to the walls that transmit
     * friction (all of them, if none does), so that a symmetry plane meeting
     * a die carries no friction of the die.
     */
    template <int dim>
    std::vector<std::pair<BoundaryId, Tensor<1, dim>>>
    split_between_walls(const std::vector<WallDirection<dim>> &directions,
                        const Tensor<1, dim> &                 reaction,
                        const std::set<BoundaryId> &           frictionless_ids)
    {
      const unsigned int          k = directions.size();
      std::vector<Tensor<1, dim>> normals;
      for (const auto &direction : directions)
        normals.push_back(direction.normal);
      const std::vector<double> a = normal_components(normals, reaction);
      std::vector<std::pair<BoundaryId, Tensor<1, dim>>> parts;
      Tensor<1, dim>                                     remainder = reaction;
      for (unsigned int i = 0; i < k; ++i)
        {
          parts.emplace_back(directions[i].id, a[i] * directions[i].normal);
          remainder -= a[i] * directions[i].normal;
        }
      double total = 0, frictional = 0;
      for (const auto &direction : directions)
        {
          total += direction.weight;
          if (!frictionless_ids.count(direction.id))
            frictional += direction.weight;
        }
      for (unsigned int i = 0; i < k; ++i)
        if (frictional == 0)
          parts[i].second += directions[i].weight / total * remainder;
        else if (!frictionless_ids.count(directions[i].id))
          parts[i].second += directions[i].weight / frictional * remainder;
      return parts;
    }

    /**
     * The traction samples of every part: its nodes that belong to no
     * other part and, on a wall, have one wall direction (not a corner). In
     * 3D also a wall's nodes on its edges with frictionless walls normal to
     * it (a die between symmetry planes: with one layer of cells, all its
     * nodes), each wall's share by split_between_walls().
     */
    template <int dim>
    std::map<BoundaryId, std::vector<TractionSample<dim>>>
    traction_samples(const std::map<GlobalDof, NodeParts<dim>> &          nodes,
                     const Vector<double> &                              reactions,
                     const std::map<GlobalDof, const WallNode<dim> *> &  wall_node_of,
                     const std::set<BoundaryId> &                        frictionless_ids)
    {
      std::map<BoundaryId, std::vector<TractionSample<dim>>> samples;
      for (const auto &[first_dof, node] : nodes)
        {
          Tensor<1, dim> reaction;
          for (unsigned int d = 0; d < dim; ++d)
            reaction[d] = reactions[node.dofs[d]];
          const auto wall = wall_node_of.find(first_dof);
          if (dim == 3 && node.weight.size() > 1 && wall != wall_node_of.end() &&
              wall->second->directions.size() == node.weight.size())
            {
              // An edge of walls only, each normal to the others that are frictionless.
              const auto &directions = wall->second->directions;
              bool        edge       = true;
              for (const auto &a : directions)
                for (const auto &b : directions)
                  if (a.id != b.id && std::abs(a.normal * b.normal) > 1e-6 &&
                      (frictionless_ids.count(a.id) || frictionless_ids.count(b.id)))
                    edge = false;
              for (const auto &[id, w] : node.weight)
                edge &= w > 0;
              if (!edge)
                continue;
              for (const auto &[id, force] : split_between_walls(directions, reaction, frictionless_ids))
                samples[id].push_back({dealii::Point<dim>(node.moment.at(id) / node.weight.at(id)),
                                       force / node.weight.at(id)});
              continue;
            }
          if (node.weight.size() != 1 || node.weight.begin()->second <= 0)
            continue;
          if (wall != wall_node_of.end() && wall->second->directions.size() != 1)
            continue;
          const auto &[id, w] = *node.weight.begin();
          samples[id].push_back({dealii::Point<dim>(node.moment.at(id) / w), reaction / w});
        }
      return samples;
    }

    /**
     * The traction at @p centre from wall samples sorted by their distance
     * from it (the distances in .first). 2D: Lagrange extrapolation to
     * distance 0 along the wall. 3D: the samples lie on a surface, where
     * several share a distance: least squares t = a + B xi over the two
     * principal directions xi of their positions, whose value a at the
     * centre is the answer (exact for a traction linear on a plane wall);
     * along one direction where the samples lie on a line.
     */
    template <int dim>
    Tensor<1, dim>
    extrapolated_traction(const std::vector<std::pair<double, const TractionSample<dim> *>> &nearest,
                          const dealii::Point<dim> &                                         centre)
    {
      Tensor<1, dim> t;
      const unsigned int n = nearest.size();
      if constexpr (dim == 2)
        {
          for (unsigned int j = 0; j < n; ++j)
            {
              double L = 1;
              for (unsigned int k = 0; k < n; ++k)
                if (k != j)
                  L *= nearest[k].first / (nearest[k].first - nearest[j].first);
              t += L * nearest[j].second->traction;
            }
          return t;
        }
      else
        {
          // Principal directions of the samples about their mean: two on a
          // surface, one where the nearest samples lie on a line (an edge).
          Tensor<1, dim> mean;
          for (const auto &[distance, sample] : nearest)
            mean += (sample->position - centre) / static_cast<double>(n);
          dealii::SymmetricTensor<2, dim> spread;
          for (const auto &[distance, sample] : nearest)
            spread += dealii::symmetrize(
              dealii::outer_product(sample->position - centre - mean, sample->position - centre - mean));
          const auto         axes = dealii::eigenvectors(spread);
          const unsigned int m    = 1 + (axes[0].first > 0 && n >= 2) + (axes[1].first > 1e-12 * axes[0].first && n >= 3);
          if (m == 1)
            return nearest.front().second->traction;
          // Normal equations of a + sum_k b_k xi_k, xi_k = (x - centre).e_k.
          dealii::FullMatrix<double>    G(m, m);
          std::array<Tensor<1, dim>, 3> rhs;
          for (const auto &[distance, sample] : nearest)
            {
              const Tensor<1, dim> x      = sample->position - centre;
              const double         phi[3] = {1., x * axes[0].second, x * axes[1].second};
              for (unsigned int i = 0; i < m; ++i)
                {
                  rhs[i] += phi[i] * sample->traction;
                  for (unsigned int j = 0; j < m; ++j)
                    G(i, j) += phi[i] * phi[j];
                }
            }
          G.gauss_jordan();
          for (unsigned int j = 0; j < m; ++j)
            t += G(0, j) * rhs[j];
          return t;
        }
    }



    /**
     * At a node shared by prescribed-velocity parts and walls, each wall
     * takes the integral of its own traction against the node's basis
     * function, w_W t_W(c_W): t_W extrapolated to the node's moment point
     * c_W on that wall by the polynomial through the wall's @p n_samples
     * nearest samples (degree + 1: the traction's own accuracy), and the
     * prescribed parts share the rest of the reaction by weight. Without
     * the split the prescribed part would also carry the wall's traction
     * over the node's half element, an O(h) error in its force. False (and
     * nothing added) when the node has no prescribed part or a wall has
     * too few samples.
     */
    template <int dim>
    bool
    split_at_prescribed_part(const NodeParts<dim> &                                       node,
                             const Tensor<1, dim> &                                       reaction,
                             const std::map<BoundaryId, std::vector<TractionSample<dim>>> &samples,
                             const BoundaryConditions<dim> &                              boundary_conditions,
                             const std::set<BoundaryId> &                                 frictionless_ids,
                             const WallNode<dim> *                                        wall_node,
                             const unsigned int                                           n_samples,
                             std::map<BoundaryId, std::vector<double>> &                  force,
                             std::vector<WallShare<dim>> *                                wall_shares)
    {
      const std::set<BoundaryId> &prescribed_ids    = boundary_conditions.velocity_ids;
      double                      prescribed_weight = 0;
      for (const auto &[id, w] : node.weight)
        if (prescribed_ids.count(id))
          prescribed_weight += w;
      if (prescribed_weight <= 0 || node.weight.size() < 2)
        return false;

      std::vector<WallShare<dim>> shares;
      for (const auto &[id, w] : node.weight)
        {
          // A part over which the node's basis function integrates to zero
          // (a degree-2 vertex on the axis of an axisymmetric body) takes nothing.
          if (prescribed_ids.count(id) || w == 0)
            continue;
          const auto found = samples.find(id);
          if (found == samples.end() || found->second.size() < 2)
            return false;
          const dealii::Point<dim> centre(node.moment.at(id) / w);
          // The nearest samples, by distance from the node's moment point.
          std::vector<std::pair<double, const TractionSample<dim> *>> nearest;
          for (const auto &sample : found->second)
            nearest.emplace_back(centre.distance(sample.position), &sample);
          // 2D: along the wall, the polynomial through the n nearest; 3D: on
          // the wall surface, a least-squares plane through 2n of them (which is
          // the line through the 2D n when the traction does not vary across).
          const unsigned int n = std::min<unsigned int>(dim == 2 ? n_samples : 2 * n_samples, nearest.size());
          std::partial_sort(nearest.begin(), nearest.begin() + n, nearest.end(),
                            [](const auto &a, const auto &b) { return a.first < b.first; });
          nearest.resize(n);
          Tensor<1, dim> t = extrapolated_traction(nearest, centre);
          // The wall's normal at the node; a frictionless wall (symmetry,
          // slip wall, die without friction) carries a normal traction only.
          Tensor<1, dim> normal;
          if (wall_node != nullptr)
            for (const auto &direction : wall_node->directions)
              if (direction.id == id)
                {
                  normal = direction.normal;
                  break;
                }
          if (frictionless_ids.count(id) && normal.norm_square() > 0)
            t = (t * normal) * normal;
          shares.push_back({id, normal, w * t});
        }

      Tensor<1, dim> rest = reaction;
      for (const auto &share : shares)
        {
          for (unsigned int d = 0; d < dim; ++d)
            force[share.id][d] += share.force[d];
          rest -= share.force;
          if (wall_shares != nullptr)
            wall_shares->push_back(share);
        }
      share_among_prescribed(node, rest, boundary_conditions, force);
      return true;
    }
  } // namespace



  template <int dim>
  std::map<BoundaryId, std::vector<double>>
  boundary_forces(const CoordinateSystem<dim> &     coordinates,
                  const DoFHandler<dim> &           dof_handler,
                  const Vector<double> &            reactions,
                  const BoundaryConditions<dim> &   boundary_conditions,
                  const std::vector<WallNode<dim>> &wall_nodes,
                  const std::set<BoundaryId> &      frictionless_ids,
                  std::vector<WallShare<dim>> *     wall_shares)
  {
    std::map<BoundaryId, std::vector<double>> force;
    for (const auto id : dof_handler.get_triangulation().get_boundary_ids())
      force[id] = std::vector<double>(dim, 0.);

    // The parts that can carry a force at each boundary node, with the
    // integral of the node's basis function over each part's faces (weight)
    // and its first moment. Traction-free and prescribed-traction parts
    // carry what is prescribed (their nodes' reactions vanish), added below.
    // The axis of an axisymmetric body has no area: it carries nothing
    // (its nodes' radial reactions are discretisation residue, not force).
    std::map<GlobalDof, NodeParts<dim>> nodes;
    dealii::FEFaceValues<dim>           face_values(dof_handler.get_fe(),
                                          dealii::QGauss<dim - 1>(dof_handler.get_fe().degree + 1),
                                          dealii::update_values | dealii::update_JxW_values |
                                            dealii::update_quadrature_points);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() && !carries_prescribed_traction(boundary_conditions, cell->face(f)->boundary_id()) &&
            !coordinates.on_axis(cell->face(f)))
          for (const auto &face_node : face_nodes<dim>(coordinates, cell, f, face_values))
            {
              auto &node = nodes[face_node.dofs[0]];
              node.dofs  = face_node.dofs;
              node.weight[cell->face(f)->boundary_id()] += face_node.weight;
              node.moment[cell->face(f)->boundary_id()] += face_node.moment;
            }
    add_prescribed_tractions(coordinates, dof_handler, boundary_conditions, force);

    std::map<GlobalDof, const WallNode<dim> *> wall_node_of;
    for (const auto &node : wall_nodes)
      wall_node_of[node.dofs[0]] = &node;
    const auto samples = traction_samples(nodes, reactions, wall_node_of, frictionless_ids);

    for (const auto &[first_dof, node] : nodes)
      {
        Tensor<1, dim> reaction;
        for (unsigned int d = 0; d < dim; ++d)
          reaction[d] = reactions[node.dofs[d]];

        const auto wall = wall_node_of.find(first_dof);
        if (split_at_prescribed_part(node,
                                     reaction,
                                     samples,
                                     boundary_conditions,
                                     frictionless_ids,
                                     wall == wall_node_of.end() ? nullptr : wall->second,
                                     dof_handler.get_fe().degree + 1,
                                     force,
                                     wall_shares))
          continue;

        // Prescribed-velocity parts take the whole reaction, shared by weight.
        double prescribed_weight = 0;
        for (const auto &[id, w] : node.weight)
          if (boundary_conditions.velocity_ids.count(id))
            prescribed_weight += w;
        if (prescribed_weight > 0 || node.weight.size() == 1)
          {
            if (prescribed_weight > 0)
              share_among_prescribed(node, reaction, boundary_conditions, force);
            else // one part takes the whole reaction, even where its weight vanishes
              for (unsigned int d = 0; d < dim; ++d)
                force[node.weight.begin()->first][d] += reaction[d];
            continue;
          }

        // Between walls (split_between_walls()).
        if (wall == wall_node_of.end() || wall->second->directions.size() < 2)
          {
            double total = 0;
            for (const auto &[id, w] : node.weight)
              total += w;
            for (const auto &[id, w] : node.weight)
              for (unsigned int d = 0; d < dim; ++d)
                force[id][d] += w / total * reaction[d];
            continue;
          }
        for (const auto &[id, part] : split_between_walls(wall->second->directions, reaction, frictionless_ids))
          for (unsigned int d = 0; d < dim; ++d)
            force[id][d] += part[d];
      }
    return force;
  }



  template <int dim>
  std::pair<double, double>
  velocity_errors(const DoFHandler<dim> &       dof_handler,
                  const Vector<double> &        velocity,
                  const dealii::Function<dim> & exact)
  {
    Vector<float>             per_cell(dof_handler.get_triangulation().n_active_cells());
    const dealii::QGauss<dim> quadrature(dof_handler.get_fe().degree + 2);
    // On a shared mesh (P > 1) integrate_difference gives this process's
    // cells alone (the others 0) and compute_global_error all-reduces: each
    // cell's error is summed from its owner instead (exact: the others add
    // zeros), the norm compute_global_error's on a plain mesh.
    const auto global = [&](const dealii::VectorTools::NormType norm) {
      dealii::VectorTools::integrate_difference(dof_handler, velocity, exact, per_cell, quadrature, norm);
      Vector<double> whole(per_cell);
      processes::sum(whole);
      per_cell           = whole;
      const double local = per_cell.l2_norm();
      return std::sqrt(local * local);
    };
    return {global(dealii::VectorTools::L2_norm), global(dealii::VectorTools::H1_seminorm)};
  }



  namespace
  {
    /// Equivalent strain rate, equivalent stress and viscosity from the
    /// velocity gradient at the output points.
    template <int dim>
    class MaterialFields : public dealii::DataPostprocessor<dim>
    {
    public:
      /// @p vertex_temperature: T per vertex of the mesh (a temperature field), or null;
      /// @p cell_hardening: the hardening factor per active cell, or null.
      MaterialFields(const Material &             material,
                     const CoordinateSystem<dim> &coordinates,
                     const Vector<double> *       vertex_temperature,
                     const Vector<double> *       cell_hardening)
        : material(material)
        , coordinates(coordinates)
        , vertex_temperature(vertex_temperature)
        , cell_hardening(cell_hardening)
      {}

      void
      evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<dim> &inputs,
                            std::vector<Vector<double>> &computed) const override
      {
        // With a temperature field the law at the cell's mean vertex T (an output, not the solve's quadrature).
        double     T      = 0;
        const auto cell   = inputs.template get_cell<dim>();
        const double factor = cell_hardening != nullptr ? (*cell_hardening)[cell->active_cell_index()] : 1.;
        if (vertex_temperature != nullptr)
          {
            for (const unsigned int v : cell->vertex_indices())
              T += (*vertex_temperature)[cell->vertex_index(v)] / cell->n_vertices();
          }
        for (unsigned int q = 0; q < computed.size(); ++q)
          {
            Tensor<2, dim> grad;
            for (unsigned int d = 0; d < dim; ++d)
              grad[d] = inputs.solution_gradients[q][d];
            StrainRate<dim> D;
            D.in_plane = dealii::symmetrize(grad);
            if (coordinates.axisymmetric())
              D.hoop = hoop_rate(inputs.evaluation_points[q], inputs.solution_values[q][1], grad[1][1]);
            const double rate  = std::sqrt(2. / 3. * (D * D));
            const double eta =
              factor * (vertex_temperature != nullptr ? material.evaluate(rate, T).eta : material.evaluate(rate).eta);
            computed[q][0]     = rate;
            computed[q][1]     = 3. * eta * rate;
            computed[q][2]     = eta;
          }
      }

      std::vector<std::string>
      get_names() const override
      {
        return {"equivalent_strain_rate", "equivalent_stress", "viscosity"};
      }

      dealii::UpdateFlags
      get_needed_update_flags() const override
      {
        return dealii::update_gradients | dealii::update_values | dealii::update_quadrature_points;
      }

    private:
      const Material &             material;
      const CoordinateSystem<dim> &coordinates;
      const Vector<double> *       vertex_temperature;
      const Vector<double> *       cell_hardening;
    };

    /// Values per vertex of the triangulation as a Q1 field.
    template <int dim>
    Vector<double>
    vertex_field_to_q1(const DoFHandler<dim> &scalar_dofs, const std::vector<double> &per_vertex)
    {
      Vector<double> field(scalar_dofs.n_dofs());
      for (const auto &cell : scalar_dofs.active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          field[cell->vertex_dof_index(v, 0)] = per_vertex[cell->vertex_index(v)];
      return field;
    }
  } // namespace



  template <int dim>
  void
  write_fields(const CoordinateSystem<dim> &                    coordinates,
            const DoFHandler<dim> &                         dof_handler,
            const Vector<double> &                          velocity,
            const Material &                                material,
            const Vector<double> &                          p_cell,
            const std::map<std::string, Vector<double>> &   nodal_fields,
            const std::map<std::string, Vector<double>> &   cell_fields,
            const std::string &                             directory,
            const unsigned int                              cycle,
            const double                                    record_time,
            const bool                                      vtu,
            const bool                                      gnuplot,
            std::vector<std::pair<double, std::string>> &   pvd_records)
  {
    const auto &triangulation = dof_handler.get_triangulation();
    const dealii::FE_Q<dim>  scalar_fe(1);
    DoFHandler<dim>          scalar_dofs(triangulation);
    scalar_dofs.distribute_dofs(scalar_fe);

    const unsigned int n_modes = PressureProjection<dim>::n_modes_for(dof_handler.get_fe());
    Vector<double>     p_mean(triangulation.n_active_cells());
    for (unsigned int c = 0; c < p_mean.size(); ++c)
      p_mean[c] = p_cell[c * n_modes];
    const std::vector<double> p_sum = vertex_pressures(dof_handler, p_cell);
    const Vector<double> p_nodal = vertex_field_to_q1(scalar_dofs, p_sum);

    dealii::DataOut<dim> data_out;
    data_out.attach_dof_handler(dof_handler);
    const std::vector<std::string> names(dim, "velocity");
    const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> interpretation(
      dim, dealii::DataComponentInterpretation::component_is_part_of_vector);
    data_out.add_data_vector(velocity, names, dealii::DataOut<dim>::type_dof_data, interpretation);
    const auto                temperature = nodal_fields.find("temperature");
    const auto                hardening   = cell_fields.find("hardening_factor");
    const MaterialFields<dim> material_fields(material,
                                              coordinates,
                                              temperature == nodal_fields.end() ? nullptr : &temperature->second,
                                              hardening == cell_fields.end() ? nullptr : &hardening->second);
    data_out.add_data_vector(velocity, material_fields);
    data_out.add_data_vector(scalar_dofs, p_nodal, "pressure");
    std::vector<Vector<double>> extra;
    extra.reserve(nodal_fields.size());
    for (const auto &[name, values] : nodal_fields)
      {
        std::vector<double> per_vertex(values.begin(), values.end());
        extra.push_back(vertex_field_to_q1(scalar_dofs, per_vertex));
        data_out.add_data_vector(scalar_dofs, extra.back(), name);
      }
    data_out.add_data_vector(p_mean, "cell_pressure", dealii::DataOut<dim>::type_cell_data);
    for (const auto &[name, values] : cell_fields)
      data_out.add_data_vector(values, name, dealii::DataOut<dim>::type_cell_data);
    // On several processes each writes the piece of the cells it assembles
    // (a .vtu per process, and a .pvtu that lists them, from the first):
    // the patches are built where the cells are, and no process holds the
    // whole output. Gnuplot has no pieces: the first process writes it whole.
    using cell_iterator = typename dealii::DataOut<dim>::cell_iterator;
    const bool pieces   = processes::n() > 1;
    const bool gnuplot_here = gnuplot && processes::writes_output();
    const std::string stem  = "solution-" + dealii::Utilities::int_to_string(cycle, 2);
    // Degree 2: each cell subdivided, so the output shows the curved field.
    const unsigned int subdivisions = dof_handler.get_fe().degree;
    // zlib's fastest level, not deal.II's default (its best): measured on
    // die2d's 13-cycle run to 749k dofs (doc/benchmarks.md), the VTUs took
    // most of the postprocessing's 23 s.
    dealii::DataOutBase::VtkFlags flags;
    flags.compression_level = dealii::DataOutBase::VtkFlags::best_speed;
    data_out.set_flags(flags);
    if (vtu)
      {
        if (pieces)
          data_out.set_cell_selection(
            [](const cell_iterator &cell) { return cell->is_active() && processes::owns(cell); });
        data_out.build_patches(subdivisions);
        std::string record = stem + ".vtu";
        if (pieces)
          {
            const auto piece = [&](const unsigned int rank) {
              return stem + "." + dealii::Utilities::int_to_string(rank, 4) + ".vtu";
            };
            std::ofstream out = output_stream(directory + "/" + piece(processes::rank()));
            data_out.write_vtu(out);
            record = stem + ".pvtu";
            if (processes::writes_output())
              {
                std::vector<std::string> names;
                for (unsigned int rank = 0; rank < processes::n(); ++rank)
                  names.push_back(piece(rank));
                std::ofstream list = output_stream(directory + "/" + record);
                data_out.write_pvtu_record(list, names);
              }
          }
        else if (processes::writes_output())
          {
            std::ofstream out = output_stream(directory + "/" + record);
            data_out.write_vtu(out);
          }
        pvd_records.emplace_back(record_time, record);
      }
    if (gnuplot_here)
      {
        if (!vtu || pieces)
          {
            data_out.set_cell_selection([](const cell_iterator &cell) { return cell->is_active(); });
            data_out.build_patches(subdivisions);
          }
        std::ofstream out = output_stream(directory + "/" + stem + ".gnuplot");
        data_out.write_gnuplot(out);
      }
  }

  void
  write_pvd(const std::vector<std::pair<double, std::string>> &records, const std::string &directory)
  {
    // deal.II's write_pvd_record gives every file part 0: ParaView would
    // read a time's second file as another time step of the first.
    AtomicFile    pvd(directory + "/solution.pvd");
    std::ostream &out = pvd.stream();
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" ByteOrder=\"LittleEndian\">\n"
        << "  <Collection>\n";
    for (std::size_t i = 0; i < records.size(); ++i)
      {
        unsigned int part = 0;
        while (part < i && records[i - part - 1].first == records[i].first)
          ++part;
        out << "    <DataSet timestep=\"" << std::setprecision(16) << records[i].first << "\" group=\"\" part=\"" << part
            << "\" file=\"" << records[i].second << "\"/>\n";
      }
    out << "  </Collection>\n</VTKFile>\n";
    pvd.commit();
  }



  template std::map<BoundaryId, double>
  boundary_fluxes<2>(const CoordinateSystem<2> &, const DoFHandler<2> &, const Vector<double> &);
  template std::map<BoundaryId, double>
  boundary_areas<2>(const CoordinateSystem<2> &, const DoFHandler<2> &);
  template std::map<BoundaryId, std::vector<double>>
  boundary_forces<2>(const CoordinateSystem<2> &, const DoFHandler<2> &, const Vector<double> &, const BoundaryConditions<2> &, const std::vector<WallNode<2>> &,
                     const std::set<BoundaryId> &, std::vector<WallShare<2>> *);
  template std::pair<double, double>
  velocity_errors<2>(const DoFHandler<2> &, const Vector<double> &, const dealii::Function<2> &);
  template void
  write_fields<2>(const CoordinateSystem<2> &, const DoFHandler<2> &, const Vector<double> &, const Material &, const Vector<double> &,
                  const std::map<std::string, Vector<double>> &, const std::map<std::string, Vector<double>> &, const std::string &, const unsigned int,
                  const double, const bool, const bool, std::vector<std::pair<double, std::string>> &);
  template std::map<BoundaryId, double>
  boundary_fluxes<3>(const CoordinateSystem<3> &, const DoFHandler<3> &, const Vector<double> &);
  template std::map<BoundaryId, double>
  boundary_areas<3>(const CoordinateSystem<3> &, const DoFHandler<3> &);
  template std::map<BoundaryId, std::vector<double>>
  boundary_forces<3>(const CoordinateSystem<3> &, const DoFHandler<3> &, const Vector<double> &, const BoundaryConditions<3> &, const std::vector<WallNode<3>> &,
                     const std::set<BoundaryId> &, std::vector<WallShare<3>> *);
  template std::pair<double, double>
  velocity_errors<3>(const DoFHandler<3> &, const Vector<double> &, const dealii::Function<3> &);
  template void
  write_fields<3>(const CoordinateSystem<3> &, const DoFHandler<3> &, const Vector<double> &, const Material &, const Vector<double> &,
                  const std::map<std::string, Vector<double>> &, const std::map<std::string, Vector<double>> &, const std::string &, const unsigned int,
                  const double, const bool, const bool, std::vector<std::pair<double, std::string>> &);
} // namespace dieflow
