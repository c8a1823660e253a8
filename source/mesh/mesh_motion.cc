// Moving a mesh's vertices, and the volume and shape of its cells.
#include <dieflow/mesh/mesh_motion.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace dieflow
{
  template <int dim>
  void
  move_vertices(const dealii::DoFHandler<dim> &dof_handler,
                const dealii::Vector<double> & displacement,
                dealii::Triangulation<dim> &   triangulation)
  {
    std::vector<bool> moved(triangulation.n_vertices(), false);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (!moved[cell->vertex_index(v)])
          {
            moved[cell->vertex_index(v)] = true;
            for (unsigned int d = 0; d < dim; ++d)
              cell->vertex(v)[d] += displacement[cell->vertex_dof_index(v, d)];
          }
    place_hanging_vertices(triangulation);
  }



  template <int dim>
  void
  place_hanging_vertices(dealii::Triangulation<dim> &triangulation)
  {
    // Coarse cells first, so that a vertex hanging on a face of a cell
    // that is itself refined at a coarser level is placed after its parents.
    for (unsigned int level = 0; level < triangulation.n_levels(); ++level)
      for (const auto &cell : triangulation.active_cell_iterators_on_level(level))
        for (const auto &face : cell->face_iterators())
          if (face->has_children())
            {
              if constexpr (dim == 2)
                face->child(0)->vertex(1) = 0.5 * (face->vertex(0) + face->vertex(1));
              else
                {
                  for (unsigned int l = 0; l < 4; ++l)
                    if (face->line(l)->has_children())
                      face->line(l)->child(0)->vertex(1) = 0.5 * (face->line(l)->vertex(0) + face->line(l)->vertex(1));
                  if (face->n_children() == 4)
                    face->child(0)->vertex(3) =
                      0.25 * (face->vertex(0) + face->vertex(1) + face->vertex(2) + face->vertex(3));
                }
            }
  }



  template <int dim>
  dealii::Vector<double>
  cell_volumes(const CoordinateSystem<dim> &coordinates, const dealii::Triangulation<dim> &triangulation)
  {
    const dealii::FE_Q<dim>   fe(1);
    const dealii::QGauss<dim> quadrature(2);
    dealii::FEValues<dim>     fe_values(dealii::StaticMappingQ1<dim>::mapping,
                                    fe,
                                    quadrature,
                                    dealii::update_JxW_values | dealii::update_quadrature_points);
    dealii::Vector<double>    volumes(triangulation.n_active_cells());
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        fe_values.reinit(cell);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          volumes[cell->active_cell_index()] += coordinates.weight(fe_values.quadrature_point(q)) * fe_values.JxW(q);
      }
    return volumes;
  }



  template <int dim>
  double
  domain_volume(const CoordinateSystem<dim> &coordinates, const dealii::Triangulation<dim> &triangulation)
  {
    // Each volume is positive on a valid mesh: the sum is the l1 norm.
    const dealii::Vector<double> volumes = cell_volumes(coordinates, triangulation);
    return std::accumulate(volumes.begin(), volumes.end(), 0.);
  }



  template <int dim>
  double
  scaled_jacobian(const std::array<dealii::Point<dim>, (1u << dim)> &vertices)
  {
    double smallest = std::numeric_limits<double>::max();
    for (unsigned int v = 0; v < vertices.size(); ++v)
      {
        // Lexicographic vertices: the edge along axis d joins v and v ^ 2^d,
        // pointing towards +xi_d.
        dealii::Tensor<2, dim> J;
        double                 lengths = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            dealii::Tensor<1, dim> edge = vertices[v ^ (1u << d)] - vertices[v];
            if (v & (1u << d))
              edge *= -1.;
            for (unsigned int i = 0; i < dim; ++i)
              J[i][d] = edge[i];
            lengths *= edge.norm();
          }
        smallest = std::min(smallest, lengths > 0 ? dealii::determinant(J) / lengths : 0.);
      }
    return smallest;
  }



  template <int dim>
  double
  scaled_jacobian(const typename dealii::Triangulation<dim>::cell_iterator &cell)
  {
    std::array<dealii::Point<dim>, (1u << dim)> vertices;
    for (const unsigned int v : cell->vertex_indices())
      vertices[v] = cell->vertex(v);
    return scaled_jacobian<dim>(vertices);
  }



  namespace
  {
    /// The smallest scaled Jacobian of the mesh's cells and a cell that has it.
    template <int dim>
    std::pair<double, typename dealii::Triangulation<dim>::active_cell_iterator>
    worst_cell(const dealii::Triangulation<dim> &triangulation)
    {
      std::pair<double, typename dealii::Triangulation<dim>::active_cell_iterator> worst(
        std::numeric_limits<double>::max(), {});
      for (const auto &cell : triangulation.active_cell_iterators())
        if (const double jacobian = scaled_jacobian<dim>(cell); jacobian < worst.first)
          worst = {jacobian, cell};
      return worst;
    }
  } // namespace

  template <int dim>
  double
  smallest_scaled_jacobian(const dealii::Triangulation<dim> &triangulation)
  {
    return worst_cell(triangulation).first;
  }

  template <int dim>
  dealii::Point<dim>
  worst_cell_centre(const dealii::Triangulation<dim> &triangulation)
  {
    const auto worst = worst_cell(triangulation);
    return worst.second.state() == dealii::IteratorState::valid ? worst.second->center() : dealii::Point<dim>();
  }

  template void
  place_hanging_vertices(dealii::Triangulation<2> &);
  template void
  place_hanging_vertices(dealii::Triangulation<3> &);
  template void
  move_vertices(const dealii::DoFHandler<2> &, const dealii::Vector<double> &, dealii::Triangulation<2> &);
  template void
  move_vertices(const dealii::DoFHandler<3> &, const dealii::Vector<double> &, dealii::Triangulation<3> &);
  template dealii::Vector<double>
  cell_volumes(const CoordinateSystem<2> &, const dealii::Triangulation<2> &);
  template dealii::Vector<double>
  cell_volumes(const CoordinateSystem<3> &, const dealii::Triangulation<3> &);
  template double
  domain_volume(const CoordinateSystem<2> &, const dealii::Triangulation<2> &);
  template double
  domain_volume(const CoordinateSystem<3> &, const dealii::Triangulation<3> &);
  template double
  scaled_jacobian<2>(const std::array<dealii::Point<2>, 4> &);
  template double
  scaled_jacobian<3>(const std::array<dealii::Point<3>, 8> &);
  template double
  scaled_jacobian<2>(const dealii::Triangulation<2>::cell_iterator &);
  template double
  scaled_jacobian<3>(const dealii::Triangulation<3>::cell_iterator &);
  template double
  smallest_scaled_jacobian(const dealii::Triangulation<2> &);
  template double
  smallest_scaled_jacobian(const dealii::Triangulation<3> &);
  template dealii::Point<2>
  worst_cell_centre(const dealii::Triangulation<2> &);
  template dealii::Point<3>
  worst_cell_centre(const dealii::Triangulation<3> &);
} // namespace dieflow
