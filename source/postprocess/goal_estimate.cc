// The goal-oriented estimate of a force's error: the force's dual problem, its dual-weighted residual, and the refinement indicators it gives.
#include <dieflow/flow/pressure_projection.h>
#include <dieflow/mesh/refinement.h>
#include <dieflow/mesh/wall_nodes.h>
#include <dieflow/mesh/whole_mesh.h>
#include <dieflow/postprocess/goal_estimate.h>
#include <dieflow/system/system_assembler.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <functional>
#include <tuple>

namespace dieflow
{
  namespace
  {
    /// z <- T^T z at the slipping nodes (the test functions of their rows).
    template <int dim>
    void
    apply_transposed_row_transforms(const std::vector<ContactContribution<dim>> &contributions, Vector<double> &z)
    {
      for (const auto &c : contributions)
        if (c.has_row_transform)
          {
            double transformed[dim];
            for (unsigned int a = 0; a < dim; ++a)
              {
                transformed[a] = 0;
                for (unsigned int b = 0; b < dim; ++b)
                  transformed[a] += c.row_transform(b, a) * z[c.dofs[b]];
              }
            for (unsigned int a = 0; a < dim; ++a)
              z[c.dofs[a]] = transformed[a];
          }
    }

    /// int_K f.w dx + int_{dK on traction parts} t.w ds: the loads' share of R(v_h; w).
    template <int dim>
    double
    loads_on(const typename dealii::DoFHandler<dim>::active_cell_iterator &cell,
             const Vector<double> &                                         w,
             const BoundaryConditions<dim> &                                boundary_conditions,
             const dealii::FEValues<dim> &                                  values,
             dealii::FEFaceValues<dim> &                                    face_values,
             std::vector<dealii::Tensor<1, dim>> &                          w_values,
             std::vector<dealii::Tensor<1, dim>> &                          w_face_values,
             dealii::Vector<double> &                                       load)
    {
      const dealii::FEValuesExtractors::Vector velocities(0);
      double                                   work = 0;
      if (boundary_conditions.has_body_force)
        {
          values[velocities].get_function_values(w, w_values);
          for (const unsigned int q : values.quadrature_point_indices())
            {
              boundary_conditions.body_force->vector_value(values.quadrature_point(q), load);
              for (unsigned int d = 0; d < dim; ++d)
                work += load[d] * w_values[q][d] * values.JxW(q);
            }
        }
      if (boundary_conditions.traction && cell->at_boundary())
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary() && boundary_conditions.traction_ids.count(cell->face(f)->boundary_id()))
            {
              face_values.reinit(cell, f);
              face_values[velocities].get_function_values(w, w_face_values);
              for (const unsigned int q : face_values.quadrature_point_indices())
                {
                  boundary_conditions.traction->vector_value(face_values.quadrature_point(q), load);
                  for (unsigned int d = 0; d < dim; ++d)
                    work += load[d] * w_face_values[q][d] * face_values.JxW(q);
                }
            }
      return work;
    }
  } // namespace



  template <int dim>
  Vector<double>
  force_dual(const DoFHandler<dim> &                        dof_handler,
             const AffineConstraints<double> &              hanging_node_constraints,
             const AffineConstraints<double> &              constraints,
             const dealii::SparsityPattern &                pattern,
             const Vector<double> &                         velocity,
             const FlowAssembler<dim> &                     assembler,
             const FlowTerms<dim> &                         terms,
             const ContactSet<dim> &                        contact,
             const Vector<double> &                         psi,
             const std::function<void(Vector<double> &)> &  solve_transposed)
  {
    // g = C^T J_flow^T psi: dF/dv on the admissible variations. The matrix
    // condensed with the hanging nodes acts on master values: psi's hanging
    // entries would meet only its placeholder diagonal.
    Vector<double> g(dof_handler.n_dofs());
    {
      dealii::SparseMatrix<double> flow_jacobian(pattern);
      Vector<double>               rhs, raw;
      assembler.assemble_system(dof_handler, velocity, terms, hanging_node_constraints, Linearization::newton, flow_jacobian,
                                rhs, raw);
      Vector<double> psi_masters = psi;
      hanging_node_constraints.set_zero(psi_masters);
      flow_jacobian.Tvmult(g, psi_masters);
      constraints.condense(g);
    }
    // J_c^T y = -g, z = psi + T^T C y.
    Vector<double> z = g;
    z *= -1.;
    solve_transposed(z);
    constraints.distribute(z);
    if (!contact.empty())
      apply_transposed_row_transforms(contact.contributions(velocity), z);
    z += psi;
    return z;
  }



  template <int dim>
  Vector<double>
  force_direction(const DoFHandler<dim> &dof_handler, const AffineConstraints<double> &hanging_node_constraints, const BoundaryId part_id)
  {
    Vector<double>                               psi(dof_handler.n_dofs());
    const auto &                                 fe = dof_handler.get_fe();
    std::vector<dealii::types::global_dof_index> face_dofs(fe.n_dofs_per_face());
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == part_id)
          {
            cell->face(f)->get_dof_indices(face_dofs);
            for (unsigned int i = 0; i < face_dofs.size(); ++i)
              if (fe.face_system_to_component_index(i).first == 0 && !hanging_node_constraints.is_constrained(face_dofs[i]))
                psi[face_dofs[i]] = 1;
          }
    hanging_node_constraints.distribute(psi);
    return psi;
  }



  template <int dim>
  dealii::Vector<float>
  goal_indicators(const DoFHandler<dim> &dof_handler, const Vector<double> &velocity, const Vector<double> &dual)
  {
    dealii::Vector<float> indicators = kelly_indicators(dof_handler, velocity);
    indicators.scale(kelly_indicators(dof_handler, dual));
    return indicators;
  }



  template <int dim>
  GoalEstimate
  dual_weighted_force_error(const DoFHandler<dim> &          dof_handler,
                            const AffineConstraints<double> &hanging_node_constraints,
                            const Vector<double> &           velocity,
                            const FlowAssembler<dim> &       assembler,
                            const FlowTerms<dim> &           terms,
                            const Material &                 material,
                            const ContactSet<dim> &          contact,
                            const BoundaryConditions<dim> &  boundary_conditions,
                            const std::set<BoundaryId> &     die_ids,
                            const BoundaryId                 part_id,
                            const PointFields &              fields)
  {
    const auto &                  fe = dof_handler.get_fe();
    const dealii::FESystem<dim>   dual_fe(dealii::FE_Q<dim>(fe.degree + 1), dim);
    const auto &                  triangulation = dof_handler.get_triangulation();
    dealii::DoFHandler<dim>       dual_dofs(triangulation);
    dual_dofs.distribute_dofs(dual_fe);

    AffineConstraints<double> dual_hanging;
    dealii::DoFTools::make_hanging_node_constraints(dual_dofs, dual_hanging);
    dual_hanging.close();

    // The frozen states on the richer space: each new node takes the state
    // of the nearest node of the solution's space, as on a refined mesh.
    std::set<BoundaryId> walls = boundary_conditions.wall_ids();
    walls.insert(die_ids.begin(), die_ids.end());
    Assert(!assembler.coordinate_system().axisymmetric(),
           dealii::ExcMessage("The dual problem is assembled in plane strain."));
    const auto dual_wall_nodes = collect_wall_nodes(assembler.coordinate_system(), dual_dofs, walls, dual_hanging, boundary_conditions.corner_angle);
    AffineConstraints<double> prescribed;
    if (!contact.empty())
      boundary_conditions.make_prescribed_constraints(dual_dofs, prescribed);
    const ContactSet<dim> dual_contact = contact.frozen_on(dual_wall_nodes, prescribed);
    AffineConstraints<double> constraints;
    boundary_conditions.make_constraints(dual_dofs, dual_hanging, dual_wall_nodes, true, constraints);
    dual_contact.add_constraints(constraints, true);
    constraints.close();

    Vector<double> v(dual_dofs.n_dofs());
    whole_mesh::interpolate(dof_handler, velocity, dual_dofs, dual_hanging, v);

    dealii::DynamicSparsityPattern dsp(dual_dofs.n_dofs());
    whole_mesh::make_sparsity_pattern(dual_dofs, dsp, dual_hanging);
    dealii::SparsityPattern pattern;
    pattern.copy_from(dsp);

    // psi is the solution space's lifting (its hanging nodes distributed),
    // so that z - I_h z vanishes wherever the solution's values are held.
    Vector<double> psi(dual_dofs.n_dofs());
    whole_mesh::interpolate(dof_handler, force_direction(dof_handler, hanging_node_constraints, part_id), dual_dofs,
                            dual_hanging, psi);
    // The flow's T and hardening at the dual assembly's points, QGauss(dual degree + 1).
    FlowTerms<dim>      dual_terms = terms;
    std::vector<double> dual_temperature, dual_hardening;
    Assert((terms.temperature == nullptr && terms.point_hardening == nullptr) || fields,
           dealii::ExcMessage("The flow reads T or a hardening at its points: the dual needs them at its own."));
    if (fields)
      {
        std::tie(dual_temperature, dual_hardening) = fields(dual_fe.degree + 1);
        dual_terms.temperature     = dual_temperature.empty() ? nullptr : &dual_temperature;
        dual_terms.point_hardening = dual_hardening.empty() ? nullptr : &dual_hardening;
      }
    dealii::SparseMatrix<double> jacobian(pattern);
    Vector<double>               minus_residual;
    SystemAssembler<dim>(dual_dofs, constraints, assembler, dual_contact)
      .assemble(v, dual_terms, Linearization::newton, &jacobian, minus_residual);
    dealii::SparseDirectUMFPACK solver;
    solver.initialize(jacobian);
    const Vector<double> z = force_dual(dual_dofs, dual_hanging, constraints, pattern, v, assembler, dual_terms, dual_contact, psi,
                                        [&solver](Vector<double> &b) { solver.solve(b, true); });

    // I_h z must be a conforming function of the solution's space (its
    // hanging nodes constrained), else w jumps across the hanging edges and
    // the cell integrals below miss the jumps.
    Vector<double> interpolant(dof_handler.n_dofs()), w(dual_dofs.n_dofs());
    whole_mesh::interpolate(dual_dofs, z, dof_handler, hanging_node_constraints, interpolant);
    whole_mesh::interpolate(dof_handler, interpolant, dual_dofs, dual_hanging, w);
    w.sadd(-1., 1., z);

    GoalEstimate result;
    result.dual_dofs = dual_dofs.n_dofs();
    const double                             lambda = terms.penalty;
    const dealii::QGauss<dim>                quadrature(fe.degree + 3);
    std::vector<double>                      temperature_points, hardening_points;
    if (fields)
      std::tie(temperature_points, hardening_points) = fields(fe.degree + 3);
    const std::vector<double> *temperature = temperature_points.empty() ? nullptr : &temperature_points;
    const std::vector<double> *hardening   = hardening_points.empty() ? nullptr : &hardening_points;
    dealii::FEValues<dim>                    values(fe, quadrature, dealii::update_gradients | dealii::update_quadrature_points | dealii::update_JxW_values);
    dealii::FEValues<dim>                    dual_values(dual_fe, quadrature, dealii::update_values | dealii::update_gradients | dealii::update_quadrature_points | dealii::update_JxW_values);
    const dealii::QGauss<dim - 1>            face_quadrature(fe.degree + 3);
    dealii::FEFaceValues<dim>                dual_face_values(dual_fe, face_quadrature, dealii::update_values | dealii::update_quadrature_points | dealii::update_JxW_values);
    std::vector<dealii::Tensor<1, dim>>      w_values(quadrature.size()), w_face_values(face_quadrature.size());
    dealii::Vector<double>                   load(dim);
    const dealii::FEValuesExtractors::Vector velocities(0);
    PressureProjection<dim>                  projection(fe);
    PressureProjection<dim>                  dual_projection(dual_fe);
    dealii::Vector<double>                   divergence, dual_divergence;
    std::vector<dealii::SymmetricTensor<2, dim>> D(quadrature.size()), D_w(quadrature.size());
    std::vector<double>                          div_w(quadrature.size());
    auto dual_cell = dual_dofs.begin_active();
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        values.reinit(cell);
        dual_values.reinit(dual_cell);
        values[velocities].get_function_symmetric_gradients(velocity, D);
        dual_values[velocities].get_function_symmetric_gradients(w, D_w);
        dual_values[velocities].get_function_divergences(w, div_w);
        projection.project(cell, velocity, divergence);
        dual_projection.project(dual_cell, z, dual_divergence);
        double velocity_part = 0, pressure_part = 0;
        for (const unsigned int q : values.quadrature_point_indices())
          {
            const auto  &x     = values.quadrature_point(q);
            // The flow's stress: its viscosity at the field's T and hardening at these points.
            const std::size_t point = cell->active_cell_index() * quadrature.size() + q;
            const double      rate  = std::sqrt(2. / 3. * (D[q] * D[q]));
            const double      eta   = (temperature != nullptr ? material.evaluate(rate, (*temperature)[point]).eta :
                                                               material.evaluate(rate).eta) *
                                 (hardening != nullptr ? (*hardening)[point] : 1.) *
                                 (terms.hardening != nullptr ? (*terms.hardening)[cell->active_cell_index()] : 1.);
            const double p     = -lambda * projection.value(divergence.begin(), x);
            velocity_part += (2. * eta * (D[q] * D_w[q]) - p * div_w[q]) * values.JxW(q);
            // int (z_p - P z_p) div v_h = int z_p (div v_h - P div v_h),
            // as P div v_h = -p_h/lambda.
            const double z_p = -lambda * dual_projection.value(dual_divergence.begin(), x);
            pressure_part += z_p * (dealii::trace(D[q]) - projection.value(divergence.begin(), x)) * values.JxW(q);
          }
        velocity_part -= loads_on(dual_cell, w, boundary_conditions, dual_values, dual_face_values, w_values, w_face_values, load);
        result.velocity_part += velocity_part;
        result.pressure_part += pressure_part;
        ++dual_cell;
      }
    result.error = result.velocity_part - result.pressure_part;

    return result;
  }

  template Vector<double>
  force_dual<2>(const DoFHandler<2> &, const AffineConstraints<double> &, const AffineConstraints<double> &,
                const dealii::SparsityPattern &, const Vector<double> &, const FlowAssembler<2> &, const FlowTerms<2> &, const ContactSet<2> &,
                const Vector<double> &, const std::function<void(Vector<double> &)> &);
  template Vector<double>
  force_direction<2>(const DoFHandler<2> &, const AffineConstraints<double> &, const BoundaryId);
  template dealii::Vector<float>
  goal_indicators<2>(const DoFHandler<2> &, const Vector<double> &, const Vector<double> &);
  template GoalEstimate
  dual_weighted_force_error<2>(const DoFHandler<2> &, const AffineConstraints<double> &, const Vector<double> &,
                               const FlowAssembler<2> &, const FlowTerms<2> &, const Material &, const ContactSet<2> &,
                               const BoundaryConditions<2> &, const std::set<BoundaryId> &, const BoundaryId,
                               const PointFields &);
  template Vector<double>
  force_dual<3>(const DoFHandler<3> &, const AffineConstraints<double> &, const AffineConstraints<double> &,
                const dealii::SparsityPattern &, const Vector<double> &, const FlowAssembler<3> &, const FlowTerms<3> &, const ContactSet<3> &,
                const Vector<double> &, const std::function<void(Vector<double> &)> &);
  template Vector<double>
  force_direction<3>(const DoFHandler<3> &, const AffineConstraints<double> &, const BoundaryId);
  template dealii::Vector<float>
  goal_indicators<3>(const DoFHandler<3> &, const Vector<double> &, const Vector<double> &);
  template GoalEstimate
  dual_weighted_force_error<3>(const DoFHandler<3> &, const AffineConstraints<double> &, const Vector<double> &,
                               const FlowAssembler<3> &, const FlowTerms<3> &, const Material &, const ContactSet<3> &,
                               const BoundaryConditions<3> &, const std::set<BoundaryId> &, const BoundaryId,
                               const PointFields &);
} // namespace dieflow
