// What the continuous scalar fields on the flow's mesh share: values at the flow's points and vertices, range, errors against an exact field.
#include <dieflow/mesh/scalar_field.h>
#include <dieflow/mesh/whole_mesh.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <algorithm>
#include <cmath>

namespace dieflow
{
  template <int dim>
  std::vector<double>
  values_at_points(const dealii::DoFHandler<dim> &dof_handler,
                   const dealii::Vector<double> & field,
                   const unsigned int             points_per_direction)
  {
    const dealii::QGauss<dim> quadrature(points_per_direction);
    dealii::FEValues<dim>     fe_values(dof_handler.get_fe(), quadrature, dealii::update_values);
    std::vector<double>       values(quadrature.size());
    std::vector<double>       points(dof_handler.get_triangulation().n_active_cells() * quadrature.size());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        fe_values.get_function_values(field, values);
        std::copy(values.begin(), values.end(), points.begin() + cell->active_cell_index() * quadrature.size());
      }
    return points;
  }



  template <int dim>
  std::vector<double>
  vertex_values(const dealii::DoFHandler<dim> &dof_handler, const dealii::Vector<double> &field)
  {
    std::vector<double> values(dof_handler.get_triangulation().n_vertices(), 0.);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int i : cell->vertex_indices())
        values[cell->vertex_index(i)] = field[cell->vertex_dof_index(i, 0)];
    return values;
  }



  double
  value_range(const dealii::Vector<double> &field)
  {
    if (field.size() == 0)
      return 0;
    const auto [lowest, highest] = std::minmax_element(field.begin(), field.end());
    return *highest - *lowest;
  }



  template <int dim>
  std::pair<double, double>
  errors_against(const CoordinateSystem<dim> &  coordinates,
                 const dealii::DoFHandler<dim> &dof_handler,
                 const dealii::Vector<double> & field,
                 const dealii::Function<dim> &  exact)
  {
    const dealii::QGauss<dim> quadrature(dof_handler.get_fe().degree + 2);
    dealii::FEValues<dim>     fe_values(dof_handler.get_fe(),
                                    quadrature,
                                    dealii::update_values | dealii::update_quadrature_points | dealii::update_JxW_values);
    std::vector<double>       values(quadrature.size());
    double                    squared = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        fe_values.get_function_values(field, values);
        for (unsigned int q = 0; q < values.size(); ++q)
          squared += std::pow(values[q] - exact.value(fe_values.quadrature_point(q)), 2) * fe_values.JxW(q) *
                     coordinates.weight(fe_values.quadrature_point(q));
      }
    dealii::Vector<double> nodal(dof_handler.n_dofs());
    whole_mesh::interpolate(dof_handler, exact, nodal);
    nodal -= field;
    return {std::sqrt(squared), nodal.linfty_norm()};
  }



  template std::vector<double>
  values_at_points(const dealii::DoFHandler<2> &, const dealii::Vector<double> &, const unsigned int);
  template std::vector<double>
  values_at_points(const dealii::DoFHandler<3> &, const dealii::Vector<double> &, const unsigned int);
  template std::vector<double>
  vertex_values(const dealii::DoFHandler<2> &, const dealii::Vector<double> &);
  template std::vector<double>
  vertex_values(const dealii::DoFHandler<3> &, const dealii::Vector<double> &);
  template std::pair<double, double>
  errors_against(const CoordinateSystem<2> &, const dealii::DoFHandler<2> &, const dealii::Vector<double> &, const dealii::Function<2> &);
  template std::pair<double, double>
  errors_against(const CoordinateSystem<3> &, const dealii::DoFHandler<3> &, const dealii::Vector<double> &, const dealii::Function<3> &);
} // namespace dieflow
