// Plane strain or axisymmetric: the measure of every integral (1 or 2 pi r), and the strain rate with its hoop part.
#include <dieflow/mesh/coordinate_system.h>

namespace dieflow
{
  std::string
  geometry_name(const Geometry geometry)
  {
    return geometry == Geometry::axisymmetric ? "axisymmetric" : "plane strain";
  }



  template <int dim>
  void
  CoordinateSystem<dim>::strain_rates(const dealii::FEValuesBase<dim> &fe_values,
                                      const dealii::Vector<double> &   v,
                                      std::vector<StrainRate<dim>> &   D) const
  {
    const unsigned int                           n = fe_values.n_quadrature_points;
    std::vector<dealii::SymmetricTensor<2, dim>> gradients(n);
    fe_values[velocities].get_function_symmetric_gradients(v, gradients);
    std::vector<dealii::Tensor<1, dim>> values(axisymmetric() ? n : 0);
    if (axisymmetric())
      fe_values[velocities].get_function_values(v, values);
    D.resize(n);
    for (unsigned int q = 0; q < n; ++q)
      {
        D[q].in_plane = gradients[q];
        D[q].hoop     = axisymmetric() ? values[q][1] / fe_values.quadrature_point(q)[1] : 0.;
      }
  }

  template class CoordinateSystem<2>;
  template class CoordinateSystem<3>;
} // namespace dieflow
