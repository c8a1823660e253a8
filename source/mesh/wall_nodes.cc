// The nodes on the walls: their dofs, facet normals and weights, the constraints v.n = g there, and a reaction's components along the normals.
#include <dieflow/mesh/wall_nodes.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <Eigen/Dense>

#include <cmath>
#include <map>

namespace dieflow
{
  namespace
  {
    template <int dim>
    void
    add_to_directions(std::vector<WallDirection<dim>> &          directions,
                      const Tensor<1, dim> &                     normal,
                      const BoundaryId                           id,
                      const double                               weight,
                      const double                               length,
                      const std::array<dealii::Point<dim>, dim> &facet,
                      const double                               cos_corner)
    {
      for (auto &direction : directions)
        if (direction.normal * normal >= cos_corner)
          {
            // Weighted mean: a gently curved wall has one direction.
            Tensor<1, dim> sum = direction.normal * direction.weight + normal * weight;
            direction.normal   = sum / sum.norm();
            direction.weight += weight;
            direction.length += length;
            return;
          }
      directions.push_back({normal, id, weight, length, facet});
    }
  } // namespace



  template <int dim>
  std::vector<FaceNode<dim>>
  face_nodes(const CoordinateSystem<dim> &                             coordinates,
             const typename DoFHandler<dim>::active_cell_iterator &cell,
             const unsigned int                                    face_no,
             dealii::FEFaceValues<dim> &                           face_values)
  {
    const auto &       fe               = cell->get_fe();
    const unsigned int vertex_dofs_end  = fe.n_dofs_per_vertex() * cell->n_vertices();
    const auto         face             = cell->face(face_no);
    std::vector<GlobalDof> dofs(fe.n_dofs_per_cell());
    cell->get_dof_indices(dofs);
    face_values.reinit(cell, face_no);

    std::vector<FaceNode<dim>> nodes;
    for (unsigned int j = 0; j < fe.n_dofs_per_cell(); ++j)
      if (fe.system_to_component_index(j).first == 0 && fe.has_support_on_face(j, face_no))
        {
          FaceNode<dim>      node;
          const unsigned int index = fe.system_to_component_index(j).second;
          for (unsigned int d = 0; d < dim; ++d)
            node.dofs[d] = dofs[fe.component_to_system_index(d, index)];
          node.vertex = j < vertex_dofs_end ? cell->vertex_index(j / fe.n_dofs_per_vertex()) :
                                              dealii::numbers::invalid_unsigned_int;
          if (fe.degree == 1 && !coordinates.axisymmetric())
            {
              // Exact for affine faces, as the quadrature would be, and
              // without its round-off.
              node.weight   = face->measure() / face->n_vertices();
              node.length   = node.weight;
              node.position = cell->vertex(j / fe.n_dofs_per_vertex());
            }
          else
            {
              node.weight = node.length = 0;
              for (const unsigned int q : face_values.quadrature_point_indices())
                {
                  node.weight += face_values.shape_value(j, q) * face_values.JxW(q) *
                                 coordinates.weight(face_values.quadrature_point(q));
                  node.length += face_values.shape_value(j, q) * face_values.JxW(q);
                }
              node.position = face_values.get_mapping().transform_unit_to_real_cell(
                cell, fe.get_unit_support_points()[j]);
            }
          node.moment = Tensor<1, dim>();
          for (const unsigned int q : face_values.quadrature_point_indices())
            node.moment += face_values.shape_value(j, q) * face_values.JxW(q) *
                           coordinates.weight(face_values.quadrature_point(q)) * face_values.quadrature_point(q);
          nodes.push_back(node);
        }
    return nodes;
  }



  template <int dim>
  std::vector<WallNode<dim>>
  collect_wall_nodes(const CoordinateSystem<dim> &     coordinates,
                     const DoFHandler<dim> &           dof_handler,
                     const std::set<BoundaryId> &      ids,
                     const AffineConstraints<double> & hanging_node_constraints,
                     const double                      corner_angle_degrees)
  {
    const double cos_corner = std::cos(corner_angle_degrees * dealii::numbers::PI / 180.);
    std::map<GlobalDof, WallNode<dim>> nodes; // keyed by the x-velocity dof
    std::vector<std::tuple<GlobalDof, Tensor<1, dim>, BoundaryId, double, double, std::array<dealii::Point<dim>, dim>>>
      hanging;
    dealii::FEFaceValues<dim> face_values(dof_handler.get_fe(),
                                          dealii::QGauss<dim - 1>(dof_handler.get_fe().degree + 1),
                                          dealii::update_values | dealii::update_JxW_values |
                                            dealii::update_quadrature_points);

    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() && ids.count(cell->face(f)->boundary_id()))
          {
            const auto           face   = cell->face(f);
            const Tensor<1, dim> normal = outward_unit_normal<dim>(cell, f);
            // For the contact element: a segment in 2D, three vertices of
            // the facet's plane in 3D.
            std::array<dealii::Point<dim>, dim> facet;
            for (unsigned int d = 0; d < dim; ++d)
              facet[d] = face->vertex(d);
            for (const auto &face_node : face_nodes<dim>(coordinates, cell, f, face_values))
              {
                const GlobalDof first = face_node.dofs[0];
                if (hanging_node_constraints.is_constrained(first))
                  {
                    hanging.emplace_back(first, normal, face->boundary_id(), face_node.weight, face_node.length, facet);
                    continue;
                  }
                auto &node = nodes[first];
                if (node.directions.empty())
                  {
                    node.dofs     = face_node.dofs;
                    node.position = face_node.position;
                    node.vertex   = face_node.vertex;
                  }
                add_to_directions<dim>(
                  node.directions, normal, face->boundary_id(), face_node.weight, face_node.length, facet, cos_corner);
              }
          }

    // A hanging node's share of the boundary integral belongs to the
    // nodes it hangs from (same coefficients as its constraint).
    for (const auto &[dof, normal, id, weight, length, facet] : hanging)
      for (const auto &[parent, coefficient] : *hanging_node_constraints.get_constraint_entries(dof))
        {
          const auto it = nodes.find(parent);
          if (it != nodes.end())
            add_to_directions<dim>(
                it->second.directions, normal, id, coefficient * weight, coefficient * length, facet, cos_corner);
        }

    std::vector<WallNode<dim>> result;
    result.reserve(nodes.size());
    for (auto &entry : nodes)
      result.push_back(std::move(entry.second));
    return result;
  }



  template <int dim>
  void
  constrain_normal_components(const std::array<GlobalDof, dim> &  dofs,
                              const std::vector<Tensor<1, dim>> & normals,
                              const std::vector<double> &         values,
                              AffineConstraints<double> &         constraints)
  {
    AssertDimension(normals.size(), values.size());
    // Rows [n_k | g_k]; columns of components that are free to be solved for.
    std::vector<std::array<double, dim + 1>> rows;
    for (unsigned int k = 0; k < normals.size(); ++k)
      {
        std::array<double, dim + 1> row;
        for (unsigned int d = 0; d < dim; ++d)
          row[d] = normals[k][d];
        row[dim] = values[k];
        rows.push_back(row);
      }
    std::array<bool, dim> free;
    for (unsigned int d = 0; d < dim; ++d)
      free[d] = !constraints.is_constrained(dofs[d]);

    // Gauss-Jordan elimination with partial pivoting over the free columns.
    std::vector<std::pair<unsigned int, unsigned int>> pivots; // (row, column)
    for (unsigned int r = 0; r < rows.size(); ++r)
      {
        unsigned int column = dim;
        double       best   = 1e-8;
        for (unsigned int d = 0; d < dim; ++d)
          if (free[d] && std::abs(rows[r][d]) > best)
            {
              best   = std::abs(rows[r][d]);
              column = d;
            }
        if (column == dim)
          continue; // dependent on the others, or on constrained components only
        const double pivot = rows[r][column];
        for (auto &x : rows[r])
          x /= pivot;
        for (unsigned int s = 0; s < rows.size(); ++s)
          if (s != r)
            {
              const double factor = rows[s][column];
              for (unsigned int d = 0; d <= dim; ++d)
                rows[s][d] -= factor * rows[r][d];
            }
        free[column] = false;
        pivots.emplace_back(r, column);
      }

    // Each pivot row reads v_p + sum_d a_d v_d = g, so v_p = g - sum_d a_d v_d.
    for (const auto &[r, p] : pivots)
      {
        constraints.add_line(dofs[p]);
        for (unsigned int d = 0; d < dim; ++d)
          if (d != p && std::abs(rows[r][d]) > 1e-14)
            constraints.add_entry(dofs[p], dofs[d], -rows[r][d]);
        constraints.set_inhomogeneity(dofs[p], rows[r][dim]);
      }
  }



  template <int dim>
  std::vector<double>
  normal_components(const std::vector<Tensor<1, dim>> &normals, const Tensor<1, dim> &reaction)
  {
    const unsigned int         m = normals.size();
    dealii::FullMatrix<double> G(m, m);
    for (unsigned int i = 0; i < m; ++i)
      for (unsigned int j = 0; j < m; ++j)
        G(i, j) = normals[i] * normals[j];
    std::vector<double> a(m);
    // Independent unit normals: the Gram matrix is regular (its determinant
    // is the squared volume they span: 1 for orthogonal walls, sin^2 of the
    // angle between two).
    if (m <= dim && std::abs(G.determinant()) > 1e-12)
      {
        dealii::Vector<double> rhs(m), solution(m);
        for (unsigned int i = 0; i < m; ++i)
          rhs[i] = normals[i] * reaction;
        G.gauss_jordan();
        G.vmult(solution, rhs);
        std::copy(solution.begin(), solution.end(), a.begin());
        return a;
      }
    Eigen::Matrix<double, dim, Eigen::Dynamic> N(dim, m);
    Eigen::Matrix<double, dim, 1>              r;
    for (unsigned int d = 0; d < dim; ++d)
      {
        r(d) = reaction[d];
        for (unsigned int i = 0; i < m; ++i)
          N(d, i) = normals[i][d];
      }
    const Eigen::VectorXd least_norm = N.completeOrthogonalDecomposition().solve(r);
    for (unsigned int i = 0; i < m; ++i)
      a[i] = least_norm(i);
    return a;
  }


  template std::vector<FaceNode<2>>
  face_nodes<2>(const CoordinateSystem<2> &, const DoFHandler<2>::active_cell_iterator &, const unsigned int, dealii::FEFaceValues<2> &);
  template std::vector<WallNode<2>>
  collect_wall_nodes<2>(const CoordinateSystem<2> &, const DoFHandler<2> &, const std::set<BoundaryId> &, const AffineConstraints<double> &, const double);
  template void
  constrain_normal_components<2>(const std::array<GlobalDof, 2> &, const std::vector<Tensor<1, 2>> &, const std::vector<double> &, AffineConstraints<double> &);
  template std::vector<FaceNode<3>>
  face_nodes<3>(const CoordinateSystem<3> &, const DoFHandler<3>::active_cell_iterator &, const unsigned int, dealii::FEFaceValues<3> &);
  template std::vector<WallNode<3>>
  collect_wall_nodes<3>(const CoordinateSystem<3> &, const DoFHandler<3> &, const std::set<BoundaryId> &, const AffineConstraints<double> &, const double);
  template void
  constrain_normal_components<3>(const std::array<GlobalDof, 3> &, const std::vector<Tensor<1, 3>> &, const std::vector<double> &, AffineConstraints<double> &);
  template std::vector<double>
  normal_components<2>(const std::vector<Tensor<1, 2>> &, const Tensor<1, 2> &);
  template std::vector<double>
  normal_components<3>(const std::vector<Tensor<1, 3>> &, const Tensor<1, 3> &);
} // namespace dieflow
