// The stress and the pressure at every vertex: the values of the cells around it, averaged with the cells' areas as weights.
#include <dieflow/flow/pressure_projection.h>
#include <dieflow/postprocess/vertex_stress.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

namespace dieflow
{
  namespace
  {
    /// Adds @p cell_values(cell, vertex) x |K| at each vertex and divides
    /// by the sum of the areas around it.
    template <int dim, typename T, typename CellValues>
    std::vector<T>
    area_weighted(const DoFHandler<dim> &dof_handler, const CellValues &cell_values)
    {
      const auto &        triangulation = dof_handler.get_triangulation();
      std::vector<T>      sum(triangulation.n_vertices(), T());
      std::vector<double> area(triangulation.n_vertices(), 0.);
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          const std::vector<T> values = cell_values(cell);
          for (const unsigned int v : cell->vertex_indices())
            {
              sum[cell->vertex_index(v)] += values[v] * cell->measure();
              area[cell->vertex_index(v)] += cell->measure();
            }
        }
      for (unsigned int i = 0; i < sum.size(); ++i)
        if (area[i] > 0)
          sum[i] /= area[i];
      return sum;
    }



    /// sigma = 2 eta D - p I at the points of @p fe_values (reinit on the
    /// cell), p from the cell's pressure coefficients.
    template <int dim>
    std::vector<SymmetricTensor<2, dim>>
    cell_stresses(const CoordinateSystem<dim> &   coordinates,
                  const dealii::FEValues<dim> &   fe_values,
                  const Vector<double> &          velocity,
                  const Material &                material,
                  const PressureProjection<dim> & projection,
                  const double *                  coefficients,
                  const std::vector<double> &     temperature,
                  const double                    hardening)
    {
      const dealii::FEValuesExtractors::Vector velocities(0);
      std::vector<SymmetricTensor<2, dim>>     D(fe_values.n_quadrature_points), sigma(D.size());
      std::vector<dealii::Tensor<1, dim>>      v(D.size());
      fe_values[velocities].get_function_symmetric_gradients(velocity, D);
      if (coordinates.axisymmetric())
        fe_values[velocities].get_function_values(velocity, v);
      for (unsigned int q = 0; q < D.size(); ++q)
        {
          // The points are vertices, some on the axis: the hoop rate's limit there.
          const double hoop =
            coordinates.axisymmetric() ? hoop_rate(fe_values.quadrature_point(q), v[q][1], D[q][1][1]) : 0.;
          const double eta =
            hardening * material.evaluate(std::sqrt(2. / 3. * (D[q] * D[q] + hoop * hoop)), temperature[q]).eta;
          const double p   = projection.n_modes() > 1 ? projection.value(coefficients, fe_values.quadrature_point(q)) :
                                                        coefficients[0];
          sigma[q] = 2 * eta * D[q] - p * dealii::unit_symmetric_tensor<dim>();
        }
      return sigma;
    }
  } // namespace



  template <int dim>
  std::vector<double>
  vertex_pressures(const DoFHandler<dim> &dof_handler, const Vector<double> &cell_pressure)
  {
    PressureProjection<dim> projection(dof_handler.get_fe());
    const unsigned int      n_modes = projection.n_modes();
    return area_weighted<dim, double>(dof_handler, [&](const auto &cell) {
      const double *coefficients = cell_pressure.begin() + cell->active_cell_index() * n_modes;
      if (n_modes > 1)
        projection.reinit(cell);
      std::vector<double> p(cell->n_vertices());
      for (const unsigned int v : cell->vertex_indices())
        p[v] = n_modes > 1 ? projection.value(coefficients, cell->vertex(v)) : coefficients[0];
      return p;
    });
  }



  template <int dim>
  std::vector<SymmetricTensor<2, dim>>
  vertex_stresses(const CoordinateSystem<dim> &coordinates,
                  const DoFHandler<dim> &dof_handler,
                  const Vector<double> & velocity,
                  const Material &       material,
                  const Vector<double> & cell_pressure,
                  const std::vector<double> *vertex_temperature,
                  const Vector<double> *     cell_hardening)
  {
    PressureProjection<dim> projection(dof_handler.get_fe());
    // The law at each vertex's T (Heat/Model), or at Material/Temperature.
    std::vector<double> temperature(dealii::GeometryInfo<dim>::vertices_per_cell, material.temperature);
    const unsigned int      n_modes = projection.n_modes();
    // The trapezoidal rule's points are the unit cell's vertices, in
    // deal.II's vertex order.
    dealii::FEValues<dim> fe_values(dof_handler.get_fe(),
                                    dealii::QTrapezoid<dim>(),
                                    dealii::update_gradients | dealii::update_quadrature_points | coordinates.flags());
    return area_weighted<dim, SymmetricTensor<2, dim>>(dof_handler, [&](const auto &cell) {
      fe_values.reinit(cell);
      if (n_modes > 1)
        projection.reinit(cell);
      if (vertex_temperature != nullptr)
        for (const unsigned int v : cell->vertex_indices())
          temperature[v] = (*vertex_temperature)[cell->vertex_index(v)];
      return cell_stresses(coordinates, fe_values, velocity, material, projection,
                           cell_pressure.begin() + cell->active_cell_index() * n_modes, temperature,
                           cell_hardening != nullptr ? (*cell_hardening)[cell->active_cell_index()] : 1.);
    });
  }



  template std::vector<SymmetricTensor<2, 2>>
  vertex_stresses<2>(const CoordinateSystem<2> &, const DoFHandler<2> &, const Vector<double> &, const Material &, const Vector<double> &, const std::vector<double> *, const Vector<double> *);
  template std::vector<double>
  vertex_pressures<2>(const DoFHandler<2> &, const Vector<double> &);
  template std::vector<SymmetricTensor<2, 3>>
  vertex_stresses<3>(const CoordinateSystem<3> &, const DoFHandler<3> &, const Vector<double> &, const Material &, const Vector<double> &, const std::vector<double> *, const Vector<double> *);
  template std::vector<double>
  vertex_pressures<3>(const DoFHandler<3> &, const Vector<double> &);
} // namespace dieflow
