// The penalty's discontinuous pressure space per cell, the projection P of div v onto it, and the divergence and pressure per cell.
#include <dieflow/flow/pressure_projection.h>

#include <deal.II/fe/fe_values.h>

#include <cmath>
#include <vector>

namespace dieflow
{
  namespace
  {
    template <int dim>
    dealii::Quadrature<dim>
    projection_quadrature(const dealii::FiniteElement<dim> &fe, const CoordinateSystem<dim> &coordinates)
    {
      // Degree 1: the one-point rule of the Q1-P0 element (axisymmetric and
      // 3D: the cell mean, 2^dim points, see centre_rule_is_mean()); degree
      // 2: exact for psi_m div phi_i on straight-sided cells.
      return dealii::QGauss<dim>(fe.degree == 1 ? (coordinates.centre_rule_is_mean() ? 1 : 2) : fe.degree + 1);
    }
  } // namespace



  template <int dim>
  PressureProjection<dim>::PressureProjection(const dealii::FiniteElement<dim> &fe,
                                              const CoordinateSystem<dim> &     coordinates)
    : modes(n_modes_for(fe))
    , coordinates(coordinates)
    , fe_values(fe,
                projection_quadrature(fe, coordinates),
                dealii::update_gradients | dealii::update_JxW_values | dealii::update_quadrature_points |
                  coordinates.flags())
    , B(modes, fe.n_dofs_per_cell())
    , M_inverse(modes, modes)
    , M(modes, modes)
    , cell_dofs(fe.n_dofs_per_cell())
    , cell_velocity(fe.n_dofs_per_cell())
  {}



  template <int dim>
  void
  PressureProjection<dim>::reinit(const typename dealii::DoFHandler<dim>::active_cell_iterator &cell)
  {
    fe_values.reinit(cell);
    const unsigned int n_dofs = fe_values.get_fe().n_dofs_per_cell();

    double volume = 0;
    centroid      = dealii::Point<dim>();
    for (const unsigned int q : fe_values.quadrature_point_indices())
      {
        volume += fe_values.JxW(q);
        centroid += fe_values.JxW(q) * fe_values.quadrature_point(q);
      }
    centroid /= volume;
    h = std::pow(volume, 1. / dim);

    B = 0;
    M = 0;
    std::vector<double> psi(modes);
    for (const unsigned int q : fe_values.quadrature_point_indices())
      {
        basis(fe_values.quadrature_point(q), psi.data());
        const double JxW = fe_values.JxW(q) * coordinates.weight(fe_values.quadrature_point(q));
        for (unsigned int m = 0; m < modes; ++m)
          {
            for (unsigned int n = 0; n < modes; ++n)
              M(m, n) += psi[m] * psi[n] * JxW;
            for (unsigned int i = 0; i < n_dofs; ++i)
              B(m, i) += psi[m] * coordinates.divergence(fe_values, i, q) * JxW;
          }
      }
    M_inverse.invert(M);
  }



  template <int dim>
  void
  PressureProjection<dim>::project(const std::vector<double> &local_velocity, dealii::Vector<double> &coefficients) const
  {
    coefficients.reinit(modes);
    dealii::Vector<double> Bv(modes);
    for (unsigned int m = 0; m < modes; ++m)
      for (unsigned int i = 0; i < B.n(); ++i)
        Bv[m] += B(m, i) * local_velocity[i];
    M_inverse.vmult(coefficients, Bv);
  }



  template <int dim>
  void
  PressureProjection<dim>::project(const typename dealii::DoFHandler<dim>::active_cell_iterator &cell,
                                   const dealii::Vector<double> &                                velocity,
                                   dealii::Vector<double> &                                      coefficients)
  {
    reinit(cell);
    cell->get_dof_indices(cell_dofs);
    for (unsigned int i = 0; i < cell_dofs.size(); ++i)
      cell_velocity[i] = velocity[cell_dofs[i]];
    project(cell_velocity, coefficients);
  }



  template <int dim>
  double
  PressureProjection<dim>::value(const double *coefficients, const dealii::Point<dim> &x) const
  {
    double psi[max_modes];
    basis(x, psi);
    double result = 0;
    for (unsigned int m = 0; m < modes; ++m)
      result += coefficients[m] * psi[m];
    return result;
  }



  template <int dim>
  void
  PressureProjection<dim>::basis(const dealii::Point<dim> &x, double *psi) const
  {
    // 1, then xi_d = (x_d - x_K,d)/h_K, then the products xi_d xi_e (d <= e).
    psi[0] = 1;
    unsigned int m = 1;
    for (unsigned int d = 0; d < dim && m < modes; ++d, ++m)
      psi[m] = (x[d] - centroid[d]) / h;
    for (unsigned int d = 0; d < dim && m < modes; ++d)
      for (unsigned int e = d; e < dim && m < modes; ++e, ++m)
        psi[m] = psi[1 + d] * psi[1 + e];
  }



  template <int dim>
  double
  PressureProjection<dim>::square_integral(const double *coefficients) const
  {
    double result = 0;
    for (unsigned int m = 0; m < modes; ++m)
      for (unsigned int n = 0; n < modes; ++n)
        result += coefficients[m] * M(m, n) * coefficients[n];
    return result;
  }



  template <int dim>
  dealii::Vector<double>
  PressureProjection<dim>::project_all(const dealii::DoFHandler<dim> &dof_handler,
                                       const dealii::Vector<double> & velocity,
                                       const CoordinateSystem<dim> &  coordinates)
  {
    PressureProjection<dim> projection(dof_handler.get_fe(), coordinates);
    const unsigned int      n_modes = projection.n_modes();
    dealii::Vector<double>  result(dof_handler.get_triangulation().n_active_cells() * n_modes);
    dealii::Vector<double>  coefficients(n_modes);
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        projection.project(cell, velocity, coefficients);
        for (unsigned int m = 0; m < n_modes; ++m)
          result[cell->active_cell_index() * n_modes + m] = coefficients[m];
      }
    return result;
  }

  template <int dim>
  double
  divergence_ratio(const CoordinateSystem<dim> &coordinates, const DoFHandler<dim> &dof_handler, const Vector<double> &velocity)
  {
    const dealii::FEValuesExtractors::Vector velocities(0);
    const auto &                             fe = dof_handler.get_fe();
    dealii::FEValues<dim> gauss(fe, dealii::QGauss<dim>(fe.degree + 1), dealii::update_gradients | dealii::update_JxW_values | dealii::update_quadrature_points);
    PressureProjection<dim>     projection(fe, coordinates);
    Vector<double>              coefficients(projection.n_modes());
    std::vector<Tensor<2, dim>> grad(gauss.n_quadrature_points);
    double                      div_squared = 0, grad_squared = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        // What the penalty controls: ||P div v||^2 on the cell.
        projection.project(cell, velocity, coefficients);
        div_squared += projection.square_integral(coefficients.begin());
        gauss.reinit(cell);
        gauss[velocities].get_function_gradients(velocity, grad);
        for (const unsigned int q : gauss.quadrature_point_indices())
          grad_squared += grad[q].norm_square() * gauss.JxW(q) * coordinates.weight(gauss.quadrature_point(q));
      }
    return grad_squared > 0 ? std::sqrt(div_squared / grad_squared) : 0.;
  }



  template <int dim>
  Vector<double>
  cell_divergence(const CoordinateSystem<dim> &coordinates, const DoFHandler<dim> &dof_handler, const Vector<double> &velocity)
  {
    if (dof_handler.get_fe().degree > 1 || !coordinates.centre_rule_is_mean())
      return PressureProjection<dim>::project_all(dof_handler, velocity, coordinates);
    const dealii::FEValuesExtractors::Vector velocities(0);
    dealii::FEValues<dim> centre(dof_handler.get_fe(), dealii::QGauss<dim>(1), dealii::update_gradients);
    std::vector<double>   div(1);
    Vector<double>        divergence(dof_handler.get_triangulation().n_active_cells());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        centre.reinit(cell);
        centre[velocities].get_function_divergences(velocity, div);
        divergence[cell->active_cell_index()] = div[0];
      }
    return divergence;
  }



  template <int dim>
  Vector<double>
  cell_pressure(const CoordinateSystem<dim> &coordinates,
                const DoFHandler<dim> &dof_handler,
                const Vector<double> & velocity,
                const double           penalty,
                const Vector<double> * multiplier,
                const Vector<double> * cell_penalty)
  {
    Vector<double>     pressure = cell_divergence(coordinates, dof_handler, velocity);
    const unsigned int n_modes  = pressure.size() / dof_handler.get_triangulation().n_active_cells();
    if (cell_penalty != nullptr)
      for (unsigned int i = 0; i < pressure.size(); ++i)
        pressure[i] *= (*cell_penalty)[i / n_modes];
    else
      pressure *= penalty;
    pressure *= -1.;
    if (multiplier != nullptr)
      pressure -= *multiplier;
    return pressure;
  }



  template double
  divergence_ratio<2>(const CoordinateSystem<2> &, const DoFHandler<2> &, const Vector<double> &);
  template Vector<double>
  cell_pressure<2>(const CoordinateSystem<2> &, const DoFHandler<2> &, const Vector<double> &, const double, const Vector<double> *,
                   const Vector<double> *);
  template Vector<double>
  cell_divergence<2>(const CoordinateSystem<2> &, const DoFHandler<2> &, const Vector<double> &);
  template double
  divergence_ratio<3>(const CoordinateSystem<3> &, const DoFHandler<3> &, const Vector<double> &);
  template Vector<double>
  cell_pressure<3>(const CoordinateSystem<3> &, const DoFHandler<3> &, const Vector<double> &, const double, const Vector<double> *,
                   const Vector<double> *);
  template Vector<double>
  cell_divergence<3>(const CoordinateSystem<3> &, const DoFHandler<3> &, const Vector<double> &);
  template class PressureProjection<2>;
  template class PressureProjection<3>;
} // namespace dieflow
