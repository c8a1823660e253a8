// What the continuous scalar fields on the flow's mesh (the temperature, the steady strain) share: their values at the flow's points and vertices, their range, their errors against an exact field.
#ifndef dieflow_scalar_field_h
#define dieflow_scalar_field_h

#include <dieflow/mesh/coordinate_system.h>

#include <deal.II/base/function.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/vector.h>

#include <utility>
#include <vector>

namespace dieflow
{
  /// The field at QGauss(@p points_per_direction)'s points of each active cell, indexed active cell x points + point (FlowTerms).
  template <int dim>
  std::vector<double>
  values_at_points(const dealii::DoFHandler<dim> &dof_handler,
                   const dealii::Vector<double> & field,
                   const unsigned int             points_per_direction);

  /// The field at each vertex of the mesh (for the VTU).
  template <int dim>
  std::vector<double>
  vertex_values(const dealii::DoFHandler<dim> &dof_handler, const dealii::Vector<double> &field);

  /// The largest nodal value minus the smallest (0 for an empty field).
  double
  value_range(const dealii::Vector<double> &field);

  /// Against @p exact: ||u_h - u||_L2 with the geometry's weight (2 pi r
  /// axisymmetric) at degree + 2 Gauss points, and the largest error at the
  /// element's nodes (the exact field interpolated).
  template <int dim>
  std::pair<double, double>
  errors_against(const CoordinateSystem<dim> &  coordinates,
                 const dealii::DoFHandler<dim> &dof_handler,
                 const dealii::Vector<double> & field,
                 const dealii::Function<dim> &  exact);
} // namespace dieflow

#endif
