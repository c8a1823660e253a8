// The metal's temperature: assembly (SUPG), solve, the flow's temperatures, the heat balance and the exit temperature.
#include <dieflow/base/expressions.h>
#include <dieflow/heat/heat_equation.h>
#include <dieflow/incremental/mesh_transfer.h>
#include <dieflow/mesh/scalar_field.h>
#include <dieflow/mesh/whole_mesh.h>

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
    whole_mesh::make_sparsity_pattern(dof_handler, dsp, constraints);
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
    // Another mesh's cells: the step onto it is not made again (correct_step()).
    step_start.reinit(0);
    step_sources = StepSources();
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
                           const std::vector<FrictionWork<dim>> &                    friction,
                           const double                                              dt,
                           const dealii::Vector<double> *                            cell_hardening,
                           const std::vector<double> *                               point_hardening)
  {
    return solve_from(flow_dofs, velocity, friction, dt, cell_hardening, point_hardening, nullptr, nullptr);
  }



  template <int dim>
  double
  HeatEquation<dim>::correct_step(const dealii::DoFHandler<dim> &        flow_dofs,
                                  const dealii::Vector<double> &         velocity,
                                  const std::vector<FrictionWork<dim>> & friction,
                                  const double                           dt,
                                  const dealii::Vector<double> *         cell_hardening)
  {
    Assert(can_correct(), dealii::ExcMessage("no first solve of the step on this mesh"));
    return solve_from(flow_dofs, velocity, friction, dt, cell_hardening, nullptr, &step_start, &step_sources);
  }



  template <int dim>
  double
  HeatEquation<dim>::solve_from(const dealii::DoFHandler<dim> &        flow_dofs,
                                const dealii::Vector<double> &         velocity,
                                const std::vector<FrictionWork<dim>> & friction,
                                const double                           dt,
                                const dealii::Vector<double> *         cell_hardening,
                                const std::vector<double> *            point_hardening,
                                const dealii::Vector<double> *         start,
                                const StepSources *                    earlier)
  {
    const double beta = parameters.taylor_quinney;
    // Properties tabulated in T make the equation nonlinear: solved again
    // with rho c and k at the last solution (Picard) until it settles; the
    // sources stay those of the flow at the temperature it read.
    const bool tabulated = !parameters.heat_capacity.is_constant() || !parameters.conductivity.is_constant();
    // So does radiation (linearised at the last T: Newton's passes).
    const bool nonlinear = tabulated || !parameters.emissivity.empty();
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
    std::vector<double>                          T_old(n_q), T_now(n_q), T_face(face_quadrature.size());
    std::vector<dealii::Tensor<1, dim>>          grad_T_now(n_q);
    std::vector<dealii::Tensor<1, dim>>          v(n_q);
    std::vector<StrainRate<dim>>                 D(n_q);
    std::vector<double>                          advection(n), strong(n);

    // T at the start: T_n in time, the coupling's last T when steady; the
    // flow's T (the sources'), the current one.
    const dealii::Vector<double> flow_temperature = temperature;
    const dealii::Vector<double> previous         = start != nullptr ? *start : temperature;
    double                       friction_heat    = 0;
    // The trapezoid (correct_step()): half these sources, half the earlier.
    const double own = earlier != nullptr ? 0.5 : 1.;
    // A step's first solve keeps its sources for correct_step().
    const bool keep = transient && earlier == nullptr;
    StepSources sources;
    if (keep)
      sources.cells.resize(triangulation.n_active_cells());
    std::vector<double> T_flow(n_q);
    for (unsigned int pass = 1;; ++pass)
    {
    matrix = 0;
    rhs    = 0;
    last   = HeatRecord();
    sources.plastic_work = sources.friction_work = 0;
    sources.nodes.clear();
    prescribed_rows.clear();
    auto flow_cell = flow_dofs.begin_active();
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        flow_values.reinit(flow_cell);
        fe_values.get_function_values(previous, T_old);
        fe_values.get_function_values(temperature, T_now);
        fe_values.get_function_values(flow_temperature, T_flow);
        if (supg && tabulated)
          fe_values.get_function_gradients(temperature, grad_T_now);
        flow_values[velocities].get_function_values(velocity, v);
        coordinates.strain_rates(flow_values, velocity, D);
        cell_matrix = 0;
        cell_rhs    = 0;
        const double h = cell->diameter() / std::sqrt(double(dim)) / fe.degree;
        const double cell_factor = cell_hardening != nullptr ? (*cell_hardening)[cell->active_cell_index()] : 1.;
        if (keep)
          sources.cells[cell->active_cell_index()].reinit(n);
        for (unsigned int q = 0; q < n_q; ++q)
          {
            const auto & x    = fe_values.quadrature_point(q);
            const double dx   = fe_values.JxW(q) * coordinates.weight(x);
            const double rate = std::sqrt(2. / 3. * (D[q] * D[q]));
            const double factor =
              cell_factor * (point_hardening != nullptr ? (*point_hardening)[cell->active_cell_index() * n_q + q] : 1.);
            const double work = 2. * factor * material.evaluate(rate, T_flow[q]).eta * (D[q] * D[q]);
            const double rho_c = parameters.heat_capacity.value(T_now[q]), k = parameters.conductivity.value(T_now[q]);
            const double k_slope = supg ? parameters.conductivity.slope(T_now[q]) : 0.;
            const double source = beta * work;
            last.plastic_work += own * work * dx;
            sources.plastic_work += work * dx;
            const double speed  = transient ? 0. : v[q].norm();
            const double Pe     = speed * h * rho_c / (2. * k);
            last.peclet         = std::max(last.peclet, Pe);
            const double tau    = (supg && speed > 0) ? h / (2. * speed) * upwind_function(Pe) : 0.;
            // Backward Euler: rho c (T - T_old)/dt, the mass term in place of the advection;
            // tabulated, (H(T) - H(T_old))/dt with H linearised at the last T, T*:
            // H(T) = H(T*) + rho c(T*) (T - T*), exact once T = T* (the heat content conserved).
            const double mass   = transient ? rho_c / dt : 0.;
            const double mass_load =
              !transient ? 0. :
              !tabulated ? mass * T_old[q] :
                           (rho_c * T_now[q] - parameters.heat_capacity.integral(T_now[q]) +
                            parameters.heat_capacity.integral(T_old[q])) /
                             dt;
            for (unsigned int j = 0; j < n; ++j)
              {
                advection[j] = transient ? 0. : v[q] * fe_values.shape_grad(j, q);
                // -k (Laplacian of phi_j) in the strong residual: the cylindrical one in the axisymmetric geometry.
                double laplacian = 0;
                if (second_derivatives)
                  laplacian = dealii::trace(fe_values.shape_hessian(j, q));
                if (coordinates.axisymmetric() && supg)
                  laplacian += fe_values.shape_grad(j, q)[1] / x[1];
                // div(k(T*) grad T) = k Laplacian T + k'(T*) grad T*.grad T (k tabulated).
                strong[j] = rho_c * advection[j] - k * laplacian - k_slope * (grad_T_now[q] * fe_values.shape_grad(j, q));
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
                cell_rhs(i) += (own * source * test + mass_load * phi_i) * dx;
                if (keep)
                  sources.cells[cell->active_cell_index()](i) += source * phi_i * dx;
              }
          }
        if (earlier != nullptr)
          cell_rhs.add(0.5, earlier->cells[cell->active_cell_index()]);
        for (const auto &face : cell->face_iterators())
          {
            if (!face->at_boundary())
              continue;
            const BoundaryId id = face->boundary_id();
            if (!parameters.exchanges(id))
              continue;
            const auto   h_face    = parameters.transfer_coefficient.find(id);
            const auto   e_face    = parameters.emissivity.find(id);
            const double h         = h_face != parameters.transfer_coefficient.end() ? h_face->second : 0.;
            const double e_sigma   = e_face != parameters.emissivity.end() ?
                                       e_face->second * HeatParameters::stefan_boltzmann :
                                       0.;
            const double T_ambient = parameters.ambient_temperature.at(id);
            face_values.reinit(cell, face);
            face_values.get_function_values(temperature, T_face);
            for (unsigned int q = 0; q < face_values.n_quadrature_points; ++q)
              {
                const double ds = face_values.JxW(q) * coordinates.weight(face_values.quadrature_point(q));
                // h (T - T_a) + e sigma (T^4 - T_a^4), the radiation linearised at the last T, T* (Newton):
                // e sigma (T*^4 - T_a^4) + 4 e sigma T*^3 (T - T*), exact once T = T*.
                const double T_star = T_face[q], T3 = T_star * T_star * T_star;
                const double coefficient = h + 4. * e_sigma * T3;
                const double load =
                  h * T_ambient + e_sigma * (3. * T3 * T_star + T_ambient * T_ambient * T_ambient * T_ambient);
                for (unsigned int i = 0; i < n; ++i)
                  {
                    for (unsigned int j = 0; j < n; ++j)
                      cell_matrix(i, j) +=
                        coefficient * face_values.shape_value(i, q) * face_values.shape_value(j, q) * ds;
                    cell_rhs(i) += load * face_values.shape_value(i, q) * ds;
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
    friction_heat        = 0;
    unsigned int matched = 0;
    // A nodal heat source (friction), through the constraints: a node on a
    // prescribed part takes none; its share of the prescribed rows' load.
    const auto add_node_heat = [&](const dealii::types::global_dof_index dof, const double heat) {
      dealii::Vector<double>                       value(1);
      std::vector<dealii::types::global_dof_index> index(1, dof);
      value[0] = heat;
      friction_heat += heat;
      constraints.distribute_local_to_global(value, index, rhs);
      if (const double weight = prescribed_weight(dof); weight != 0)
        prescribed_rows.push_back({index, {0.}, weight * heat});
    };
    if (!friction.empty())
      {
        std::map<dealii::types::global_dof_index, dealii::Point<dim>> support;
        dealii::DoFTools::map_dofs_to_support_points(dealii::MappingQ1<dim>(), dof_handler, support);
        const double tolerance = 1e-9 * dealii::GridTools::diameter(triangulation);
        std::vector<std::pair<dealii::Point<dim>, dealii::types::global_dof_index>> boundary;
        for (const auto &[dof, point] : support)
          boundary.emplace_back(point, dof);
        std::sort(boundary.begin(), boundary.end(), [](const auto &a, const auto &b) { return a.first[0] < b.first[0]; });
        for (const auto &[position, work, die] : friction)
          {
            last.friction_work += own * work;
            sources.friction_work += work;
            auto it = std::lower_bound(boundary.begin(), boundary.end(), position[0] - tolerance,
                                       [](const auto &a, const double x) { return a.first[0] < x; });
            for (; it != boundary.end() && it->first[0] <= position[0] + tolerance; ++it)
              if (it->first.distance(position) <= tolerance)
                {
                  // The metal's share at its T there (by effusivities: the last T's).
                  const double heat = parameters.friction_share_at(die, temperature[it->second]) * work;
                  sources.nodes[it->second] += heat;
                  add_node_heat(it->second, own * heat);
                  ++matched;
                  break;
                }
          }
      }

    // The trapezoid's other half: the step's first sources.
    if (earlier != nullptr)
      {
        last.plastic_work += 0.5 * earlier->plastic_work;
        last.friction_work += 0.5 * earlier->friction_work;
        for (const auto &[dof, heat] : earlier->nodes)
          add_node_heat(dof, 0.5 * heat);
      }
    AssertThrow(matched == friction.size(),
                dealii::ExcMessage("a contact node without a temperature node: " + std::to_string(matched) + " of " +
                                   std::to_string(friction.size()) + " found"));
    const dealii::Vector<double> last_pass = temperature;
    dealii::SparseDirectUMFPACK solver;
    solver.initialize(matrix);
    solver.vmult(temperature, rhs);
    constraints.distribute(temperature);
    if (!nonlinear)
      break;
    dealii::Vector<double> pass_change = last_pass;
    pass_change -= temperature;
    last.property_passes = pass;
    // Settled to the direct solve's round-off, relative to T.
    if (pass_change.linfty_norm() <= 1e-11 * temperature.linfty_norm())
      break;
    AssertThrow(pass < 100,
                dealii::ExcMessage("the temperature with Heat/Density table, Specific heat table, Conductivity table or Emissivities "
                                   "did not settle in 100 solves (the last changed T by " +
                                   deck_number(pass_change.linfty_norm()) + " K)"));
    }
    dealii::Vector<double> change = flow_temperature;
    change -= temperature;
    last.last_change = change.linfty_norm();
    if (keep)
      {
        step_start   = previous;
        step_sources = std::move(sources);
      }
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
