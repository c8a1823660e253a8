// The metal's temperature: assembly (SUPG), solve, the flow's temperatures, the heat balance and the exit temperature.
#include <dieflow/base/expressions.h>
#include <dieflow/heat/heat_equation.h>
#include <dieflow/incremental/mesh_transfer.h>
#include <dieflow/mesh/scalar_field.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace dieflow
{
  namespace
  {
    /// coth(Pe) - 1/Pe, the optimal upwinding of 1D linear elements (Pe/3 for small Pe).
    double
    upwind_function(const double Pe)
    {
      if (Pe < 1e-3)
        return Pe / 3.;
      if (Pe > 20)
        return 1. - 1. / Pe;
      return 1. / std::tanh(Pe) - 1. / Pe;
    }
  } // namespace



  template <int dim>
  HeatEquation<dim>::HeatEquation(const HeatParameters &            parameters,
                                  const Material &                  material,
                                  const CoordinateSystem<dim> &     coordinates,
                                  const dealii::Triangulation<dim> &triangulation,
                                  const unsigned int                velocity_degree)
    : parameters(parameters)
    , material(material)
    , coordinates(coordinates)
    , triangulation(triangulation)
    , flow_quadrature(velocity_degree + 1)
    , fe(parameters.degree == 0 ? velocity_degree : parameters.degree)
    , dof_handler(triangulation)
  {
    prescribed = parse_vector_expression<dim>("Heat/Prescribed temperature", parameters.prescribed_temperature, "", 1);
    if (!parameters.exact_temperature.empty())
      {
        exact = parse_vector_expression<dim>("Heat/Exact temperature", parameters.exact_temperature, "", 1);
      }
  }



  template <int dim>
  void
  HeatEquation<dim>::setup()
  {
    dof_handler.distribute_dofs(fe);
    // The first mesh: T starts at Material/Temperature (a checkpoint's,
    // a refinement's or a new mesh's T is of this mesh's size).
    const bool first = temperature.size() == 0;
    if (first)
      {
        temperature.reinit(dof_handler.n_dofs());
        temperature = material.temperature;
      }
    AssertDimension(temperature.size(), dof_handler.n_dofs());
    constraints.clear();
    dealii::DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    for (const BoundaryId id : parameters.prescribed_ids)
      dealii::VectorTools::interpolate_boundary_values(dof_handler, id, *prescribed, constraints);
    constraints.close();
    dealii::DynamicSparsityPattern dsp(dof_handler.n_dofs());
    dealii::DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, false);
    sparsity.copy_from(dsp);
    matrix.reinit(sparsity);
    rhs.reinit(dof_handler.n_dofs());
    update_flow_temperatures();
    if (first)
      record_state();
  }



  template <int dim>
  dealii::Vector<double>
  HeatEquation<dim>::on_new_mesh(const dealii::Triangulation<dim> &fresh, const std::string &when) const
  {
    dealii::DoFHandler<dim> fresh_dofs(fresh);
    fresh_dofs.distribute_dofs(fe);
    return MeshTransfer<dim>(dof_handler, fresh_dofs, when).nodal(temperature);
  }



  template <int dim>
  bool
  HeatEquation<dim>::temperature_fits() const
  {
    dealii::DoFHandler<dim> dofs(triangulation);
    dofs.distribute_dofs(fe);
    return temperature.size() == dofs.n_dofs();
  }



  template <int dim>
  void
  HeatEquation<dim>::take_new_mesh(dealii::Vector<double> &&carried)
  {
    // distribute_dofs() numbers the copy of the new mesh as on_new_mesh()'s handler numbered the new mesh.
    dof_handler.reinit(triangulation);
    dof_handler.distribute_dofs(fe);
    AssertDimension(carried.size(), dof_handler.n_dofs());
    temperature = std::move(carried);
    record_state();
  }



  template <int dim>
  void
  HeatEquation<dim>::prepare_refinement()
  {
    transfer = std::make_unique<dealii::SolutionTransfer<dim, dealii::Vector<double>>>(dof_handler);
    transfer->prepare_for_coarsening_and_refinement(temperature);
  }



  template <int dim>
  void
  HeatEquation<dim>::finish_refinement()
  {
    dof_handler.distribute_dofs(fe);
    dealii::Vector<double> carried(dof_handler.n_dofs());
    transfer->interpolate(temperature, carried);
    temperature = carried;
    transfer.reset();
  }



  template <int dim>
  double
  HeatEquation<dim>::solve(const dealii::DoFHandler<dim> &                           flow_dofs,
                           const dealii::Vector<double> &                            velocity,
                           const std::vector<std::pair<dealii::Point<dim>, double>> &friction,
                           const double                                              dt,
                           const dealii::Vector<double> *                            cell_hardening,
                           const std::vector<double> *                               point_hardening)
  {
    const double rho_c = parameters.heat_capacity, k = parameters.conductivity, beta = parameters.taylor_quinney;
    // In time the mesh moves with the metal: no advection, nothing to stabilise.
    const bool   transient = dt > 0;
    const bool   supg  = parameters.stabilisation == HeatParameters::Stabilisation::supg && !transient;
    const bool   second_derivatives = supg && fe.degree > 1;
    const dealii::QGauss<dim>     quadrature(fe.degree + 1);
    const dealii::QGauss<dim - 1> face_quadrature(fe.degree + 1);
    Assert(point_hardening == nullptr || fe.degree + 1 == flow_quadrature,
           dealii::ExcMessage("The point hardening factors are at the flow's quadrature points."));
    dealii::FEValues<dim>         fe_values(fe,
                                    quadrature,
                                    dealii::update_values | dealii::update_gradients | dealii::update_quadrature_points |
                                      dealii::update_JxW_values |
                                      (second_derivatives ? dealii::update_hessians : dealii::update_default));
    dealii::FEValues<dim>     flow_values(flow_dofs.get_fe(),
                                      quadrature,
                                      dealii::update_values | dealii::update_gradients | coordinates.flags());
    dealii::FEFaceValues<dim> face_values(fe,
                                          face_quadrature,
                                          dealii::update_values | dealii::update_quadrature_points |
                                            dealii::update_JxW_values);
    const dealii::FEValuesExtractors::Vector velocities(0);
    const unsigned int                       n = fe.n_dofs_per_cell(), n_q = quadrature.size();
    dealii::FullMatrix<double>               cell_matrix(n, n);
    dealii::Vector<double>                   cell_rhs(n);
    std::vector<dealii::types::global_dof_index> dofs(n);
    std::vector<double>                          T_old(n_q);
    std::vector<dealii::Tensor<1, dim>>          v(n_q);
    std::vector<StrainRate<dim>>                 D(n_q);
    std::vector<double>                          advection(n), strong(n);

    matrix = 0;
    rhs    = 0;
    last   = HeatRecord();
    prescribed_rows.clear();
    auto flow_cell = flow_dofs.begin_active();
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        flow_values.reinit(flow_cell);
        fe_values.get_function_values(temperature, T_old);
        flow_values[velocities].get_function_values(velocity, v);
        coordinates.strain_rates(flow_values, velocity, D);
        cell_matrix = 0;
        cell_rhs    = 0;
        const double h = cell->diameter() / std::sqrt(double(dim)) / fe.degree;
        const double cell_factor = cell_hardening != nullptr ? (*cell_hardening)[cell->active_cell_index()] : 1.;
        for (unsigned int q = 0; q < n_q; ++q)
          {
            const auto & x    = fe_values.quadrature_point(q);
            const double dx   = fe_values.JxW(q) * coordinates.weight(x);
            const double rate = std::sqrt(2. / 3. * (D[q] * D[q]));
            const double factor =
              cell_factor * (point_hardening != nullptr ? (*point_hardening)[cell->active_cell_index() * n_q + q] : 1.);
            const double work = 2. * factor * material.evaluate(rate, T_old[q]).eta * (D[q] * D[q]);
            const double source = beta * work;
            last.plastic_work += work * dx;
            const double speed  = transient ? 0. : v[q].norm();
            const double Pe     = speed * h * rho_c / (2. * k);
            last.peclet         = std::max(last.peclet, Pe);
            const double tau    = (supg && speed > 0) ? h / (2. * speed) * upwind_function(Pe) : 0.;
            // Backward Euler: rho c (T - T_old)/dt, the mass term in place of the advection.
            const double mass   = transient ? rho_c / dt : 0.;
            for (unsigned int j = 0; j < n; ++j)
              {
                advection[j] = transient ? 0. : v[q] * fe_values.shape_grad(j, q);
                // -k (Laplacian of phi_j) in the strong residual: the cylindrical one in the axisymmetric geometry.
                double laplacian = 0;
                if (second_derivatives)
                  laplacian = dealii::trace(fe_values.shape_hessian(j, q));
                if (coordinates.axisymmetric() && supg)
                  laplacian += fe_values.shape_grad(j, q)[1] / x[1];
                strong[j] = rho_c * advection[j] - k * laplacian;
              }
            for (unsigned int i = 0; i < n; ++i)
              {
                const double phi_i = fe_values.shape_value(i, q);
                const double test  = phi_i + tau * advection[i];
                for (unsigned int j = 0; j < n; ++j)
                  cell_matrix(i, j) +=
                    ((rho_c * advection[j] + mass * fe_values.shape_value(j, q)) * phi_i +
                     k * (fe_values.shape_grad(i, q) * fe_values.shape_grad(j, q)) + tau * advection[i] * strong[j]) *
                    dx;
                cell_rhs(i) += (source * test + mass * T_old[q] * phi_i) * dx;
              }
          }
        for (const auto &face : cell->face_iterators())
          {
            if (!face->at_boundary())
              continue;
            const auto h_face = parameters.transfer_coefficient.find(face->boundary_id());
            if (h_face == parameters.transfer_coefficient.end())
              continue;
            const double T_ambient = parameters.ambient_temperature.at(face->boundary_id());
            face_values.reinit(cell, face);
            for (unsigned int q = 0; q < face_values.n_quadrature_points; ++q)
              {
                const double ds = face_values.JxW(q) * coordinates.weight(face_values.quadrature_point(q));
                for (unsigned int i = 0; i < n; ++i)
                  {
                    for (unsigned int j = 0; j < n; ++j)
                      cell_matrix(i, j) +=
                        h_face->second * face_values.shape_value(i, q) * face_values.shape_value(j, q) * ds;
                    cell_rhs(i) += h_face->second * T_ambient * face_values.shape_value(i, q) * ds;
                  }
              }
          }
        cell->get_dof_indices(dofs);
        // The prescribed rows' sum, kept for their reaction (the heat conducted out there).
        // A hanging node's row goes to its parents': the prescribed ones' share counts.
        PrescribedRows rows;
        for (unsigned int i = 0; i < n; ++i)
          {
            const double weight = prescribed_weight(dofs[i]);
            if (weight == 0)
              continue;
            rows.columns.resize(n);
            for (unsigned int j = 0; j < n; ++j)
              rows.columns[j] += weight * cell_matrix(i, j);
            rows.load += weight * cell_rhs(i);
          }
        if (!rows.columns.empty())
          {
            rows.dofs = dofs;
            prescribed_rows.push_back(std::move(rows));
          }
        constraints.distribute_local_to_global(cell_matrix, cell_rhs, dofs, matrix, rhs);
        ++flow_cell;
      }

    // The metal's share of each contact node's friction work, at the
    // temperature's node there (the same point: a boundary support point).
    double       friction_heat = 0;
    unsigned int matched       = 0;
    if (!friction.empty())
      {
        std::map<dealii::types::global_dof_index, dealii::Point<dim>> support;
        dealii::DoFTools::map_dofs_to_support_points(dealii::MappingQ1<dim>(), dof_handler, support);
        const double tolerance = 1e-9 * dealii::GridTools::diameter(triangulation);
        std::vector<std::pair<dealii::Point<dim>, dealii::types::global_dof_index>> boundary;
        for (const auto &[dof, point] : support)
          boundary.emplace_back(point, dof);
        std::sort(boundary.begin(), boundary.end(), [](const auto &a, const auto &b) { return a.first[0] < b.first[0]; });
        for (const auto &[position, work] : friction)
          {
            friction_heat += parameters.friction_share * work;
            last.friction_work += work;
            auto it = std::lower_bound(boundary.begin(), boundary.end(), position[0] - tolerance,
                                       [](const auto &a, const double x) { return a.first[0] < x; });
            for (; it != boundary.end() && it->first[0] <= position[0] + tolerance; ++it)
              if (it->first.distance(position) <= tolerance)
                {
                  // Through the constraints: a node on a prescribed part takes none.
                  dealii::Vector<double>                       value(1);
                  std::vector<dealii::types::global_dof_index> index(1, it->second);
                  value[0] = parameters.friction_share * work;
                  constraints.distribute_local_to_global(value, index, rhs);
                  if (const double weight = prescribed_weight(it->second); weight != 0)
                    prescribed_rows.push_back({index, {0.}, weight * value[0]});
                  ++matched;
                  break;
                }
          }
      }

    dealii::Vector<double> previous = temperature;
    dealii::SparseDirectUMFPACK solver;
    solver.initialize(matrix);
    solver.vmult(temperature, rhs);
    constraints.distribute(temperature);
    dealii::Vector<double> change = previous;
    change -= temperature;
    AssertThrow(matched == friction.size(),
                dealii::ExcMessage("a contact node without a temperature node: " + std::to_string(matched) + " of " +
                                   std::to_string(friction.size()) + " found"));
    last.last_change = change.linfty_norm();
    make_record(flow_dofs, velocity, friction_heat, previous, dt);
    return last.last_change;
  }



  template <int dim>
  double
  HeatEquation<dim>::prescribed_weight(const dealii::types::global_dof_index dof) const
  {
    // Closed constraints point to free dofs only: the weights a line lost
    // went to prescribed dofs (a hanging node's parents on a prescribed
    // part), and a prescribed dof has none left.
    if (!constraints.is_constrained(dof))
      return 0;
    double weight = 1;
    for (const auto &[parent, c] : *constraints.get_constraint_entries(dof))
      weight -= c;
    return std::abs(weight) < 1e-12 ? 0. : weight;
  }



  template <int dim>
  void
  HeatEquation<dim>::update_flow_temperatures()
  {
    point_temperature = values_at_points(dof_handler, temperature, flow_quadrature);
  }



  template <int dim>
  double
  HeatEquation<dim>::range() const
  {
    return value_range(temperature);
  }



  template class HeatEquation<2>;
  template class HeatEquation<3>;
} // namespace dieflow
