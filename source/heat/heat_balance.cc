// The record of a temperature solution: the heat balance, the extremes, the temperature where the metal leaves, T at the vertices.
#include <dieflow/heat/heat_equation.h>
#include <dieflow/mesh/scalar_field.h>
#include <dieflow/mesh/whole_mesh.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace dieflow
{
  template <int dim>
  void
  HeatEquation<dim>::make_record(const dealii::DoFHandler<dim> &flow_dofs,
                                 const dealii::Vector<double> & velocity,
                                 const double                   friction_heat,
                                 const dealii::Vector<double> & previous,
                                 const double                   dt)
  {
    const bool                               transient = dt > 0;
    const ThermalProperty &                  rho_c = parameters.heat_capacity;
    const dealii::QGauss<dim>                quadrature(fe.degree + 1);
    const dealii::QGauss<dim - 1>            face_quadrature(fe.degree + 1);
    const dealii::FEValuesExtractors::Vector velocities(0);
    dealii::FEValues<dim>                    fe_values(fe,
                                    quadrature,
                                    dealii::update_values | dealii::update_gradients |
                                      dealii::update_quadrature_points | dealii::update_JxW_values);
    dealii::FEValues<dim>     flow_values(flow_dofs.get_fe(), quadrature, dealii::update_values);
    dealii::FEFaceValues<dim> face_values(fe,
                                          face_quadrature,
                                          dealii::update_values | dealii::update_quadrature_points |
                                            dealii::update_JxW_values | dealii::update_normal_vectors);
    dealii::FEFaceValues<dim> flow_face_values(flow_dofs.get_fe(), face_quadrature, dealii::update_values);
    std::vector<dealii::Tensor<1, dim>> grad_T(quadrature.size()), v(quadrature.size()), v_face(face_quadrature.size());
    std::vector<double>                 T_face(face_quadrature.size()), T(quadrature.size()),
      T_previous(quadrature.size());

    last.plastic_heat  = parameters.taylor_quinney * last.plastic_work;
    last.friction_heat = friction_heat;
    last.carried = last.transferred = last.stored = 0;
    // Where the metal leaves: faces it crosses, their mean v.n above half
    // its mean speed there (not a die's or a free surface's small v.n, which
    // on a surface just refined may reach 1e-3 of the speed).
    double exit_flux = 0, exit_heat = 0;
    last.T_exit_min = std::numeric_limits<double>::max();
    last.T_exit_max = std::numeric_limits<double>::lowest();

    auto flow_cell = flow_dofs.begin_active();
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        flow_values.reinit(flow_cell);
        fe_values.get_function_gradients(temperature, grad_T);
        flow_values[velocities].get_function_values(velocity, v);
        // Steady: carried by the flow through the fixed mesh; in time: stored
        // in the metal the mesh follows, at the assembly's quadrature.
        fe_values.get_function_values(temperature, T);
        if (transient)
          fe_values.get_function_values(previous, T_previous);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            const double dx = fe_values.JxW(q) * coordinates.weight(fe_values.quadrature_point(q));
            // The heat content's change, int_{T_n}^{T_n+1} rho c dT, and rho c(T) v.grad T = v.grad H(T).
            if (transient)
              last.stored += (rho_c.is_constant() ? rho_c.value(T[q]) * (T[q] - T_previous[q]) :
                                                    rho_c.integral(T[q]) - rho_c.integral(T_previous[q])) /
                             dt * dx;
            else
              last.carried += rho_c.value(T[q]) * (v[q] * grad_T[q]) * dx;
          }
        for (const unsigned int f : cell->face_indices())
          {
            const auto face = cell->face(f);
            if (!face->at_boundary())
              continue;
            const bool exchanges = parameters.exchanges(face->boundary_id());
            face_values.reinit(cell, f);
            flow_face_values.reinit(flow_cell, f);
            face_values.get_function_values(temperature, T_face);
            flow_face_values[velocities].get_function_values(velocity, v_face);
            double face_flux = 0, face_heat = 0, face_speed = 0;
            for (unsigned int q = 0; q < face_quadrature.size(); ++q)
              {
                const double ds = face_values.JxW(q) * coordinates.weight(face_values.quadrature_point(q));
                if (exchanges)
                  {
                    const double out = parameters.wall_flux(face->boundary_id(), T_face[q]) * ds;
                    last.transferred += out;
                    last.transferred_by_id[face->boundary_id()] += out;
                  }
                const double vn = v_face[q] * face_values.normal_vector(q);
                face_flux += vn * ds;
                face_heat += vn * T_face[q] * ds;
                face_speed += v_face[q].norm() * ds;
              }
            if (!transient && face_flux > 0.5 * face_speed && face_flux > 0)
              {
                exit_flux += face_flux;
                exit_heat += face_heat;
                for (const double T : T_face)
                  {
                    last.T_exit_min = std::min(last.T_exit_min, T);
                    last.T_exit_max = std::max(last.T_exit_max, T);
                  }
              }
          }
        ++flow_cell;
      }
    last.T_exit = exit_flux > 0 ? exit_heat / exit_flux : 0;
    if (!(exit_flux > 0))
      last.T_exit_min = last.T_exit_max = 0;

    // The prescribed rows' reaction: minus the heat they take in.
    double reaction = 0;
    for (const auto &rows : prescribed_rows)
      {
        for (unsigned int j = 0; j < rows.dofs.size(); ++j)
          reaction += rows.columns[j] * temperature[rows.dofs[j]];
        reaction -= rows.load;
      }
    last.prescribed_outflow = -reaction;
    const double made       = last.plastic_heat + last.friction_heat;
    last.balance_error =
      made > 0 ? (made - last.carried - last.stored - last.transferred - last.prescribed_outflow) / made : 0;
    record_state();
  }



  template <int dim>
  void
  HeatEquation<dim>::record_state()
  {
    const auto [lowest, highest] = std::minmax_element(temperature.begin(), temperature.end());
    last.T_min                   = *lowest;
    last.T_max                   = *highest;
    const Integrals sums = integrals();
    last.T_mean          = sums.temperature / sums.volume;
    last.transient               = parameters.model == HeatParameters::Model::transient;
    if (exact)
      std::tie(last.T_l2_error, last.T_nodal_error) = errors_against(coordinates, dof_handler, temperature, *exact);
    last.vertex_temperature = vertex_values(dof_handler, temperature);
  }

  template <int dim>
  double
  HeatEquation<dim>::value_at(const dealii::Point<dim> &point) const
  {
    try
      {
        return whole_mesh::point_value(dof_handler, temperature, point);
      }
    catch (...)
      {
        return std::numeric_limits<double>::quiet_NaN();
      }
  }



  template <int dim>
  double
  HeatEquation<dim>::wall_flux(const dealii::types::boundary_id id, const double T) const
  {
    return parameters.wall_flux(id, T);
  }



  template <int dim>
  typename HeatEquation<dim>::Integrals
  HeatEquation<dim>::integrals() const
  {
    const dealii::QGauss<dim> quadrature(fe.degree + 1);
    dealii::FEValues<dim>     fe_values(fe, quadrature, dealii::update_values | dealii::update_quadrature_points | dealii::update_JxW_values);
    std::vector<double>       T(quadrature.size());
    Integrals                 sums;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        fe_values.get_function_values(temperature, T);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            const double dx = fe_values.JxW(q) * coordinates.weight(fe_values.quadrature_point(q));
            sums.content += parameters.heat_capacity.integral(T[q]) * dx;
            sums.temperature += T[q] * dx;
            sums.volume += dx;
          }
      }
    return sums;
  }



  template <int dim>
  double
  HeatEquation<dim>::restore_content(const double content)
  {
    const dealii::QGauss<dim>             quadrature(fe.degree + 1);
    dealii::FEValues<dim>                 fe_values(fe, quadrature, dealii::update_values | dealii::update_quadrature_points | dealii::update_JxW_values);
    std::vector<double>                   T(quadrature.size());
    std::vector<std::pair<double, double>> points;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        fe_values.get_function_values(temperature, T);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          points.emplace_back(T[q], fe_values.JxW(q) * coordinates.weight(fe_values.quadrature_point(q)));
      }
    const ThermalProperty &rho_c = parameters.heat_capacity;
    double                 shift = 0;
    for (unsigned int iteration = 0; iteration < 50; ++iteration)
      {
        double excess = -content, slope = 0;
        for (const auto &[value, dx] : points)
          {
            excess += rho_c.integral(value + shift) * dx;
            slope += rho_c.value(value + shift) * dx;
          }
        if (std::abs(excess) <= 1e-15 * std::abs(content))
          break;
        shift -= excess / slope;
      }
    temperature.add(shift);
    record_state();
    return shift;
  }



  template void
  HeatEquation<2>::make_record(const dealii::DoFHandler<2> &, const dealii::Vector<double> &, const double, const dealii::Vector<double> &, const double);
  template void
  HeatEquation<3>::make_record(const dealii::DoFHandler<3> &, const dealii::Vector<double> &, const double, const dealii::Vector<double> &, const double);
  template void
  HeatEquation<2>::record_state();
  template void
  HeatEquation<3>::record_state();
  template double
  HeatEquation<2>::value_at(const dealii::Point<2> &) const;
  template double
  HeatEquation<3>::value_at(const dealii::Point<3> &) const;
  template double
  HeatEquation<2>::wall_flux(const dealii::types::boundary_id, const double) const;
  template double
  HeatEquation<3>::wall_flux(const dealii::types::boundary_id, const double) const;
  template double
  HeatEquation<2>::restore_content(const double);
  template double
  HeatEquation<3>::restore_content(const double);
  template HeatEquation<2>::Integrals
  HeatEquation<2>::integrals() const;
  template HeatEquation<3>::Integrals
  HeatEquation<3>::integrals() const;
} // namespace dieflow
