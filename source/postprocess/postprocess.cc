#include <dieflow/flow/pressure_projection.h>
#include <dieflow/postprocess/postprocess.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>
#include <deal.II/numerics/vector_tools.h>

#include <fstream>

namespace dieflow
{
  template <int dim>
  std::map<BoundaryId, double>
  boundary_fluxes(const DoFHandler<dim> &dof_handler, const Vector<double> &velocity)
  {
    std::map<BoundaryId, double> flux;
    for (const auto id : dof_handler.get_triangulation().get_boundary_ids())
      flux[id] = 0;

    dealii::FEFaceValues<dim> fe_face(dof_handler.get_fe(),
                                      dealii::QGauss<dim - 1>(dof_handler.get_fe().degree + 1),
                                      dealii::update_values | dealii::update_normal_vectors |
                                        dealii::update_JxW_values);
    const dealii::FEValuesExtractors::Vector velocities(0);
    std::vector<Tensor<1, dim>>              v(fe_face.n_quadrature_points);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            fe_face.reinit(cell, f);
            fe_face[velocities].get_function_values(velocity, v);
            double sum = 0;
            for (const unsigned int q : fe_face.quadrature_point_indices())
              sum += v[q] * fe_face.normal_vector(q) * fe_face.JxW(q);
            flux[cell->face(f)->boundary_id()] += sum;
          }
    return flux;
  }



  template <int dim>
  std::map<BoundaryId, std::vector<double>>
  boundary_forces(const DoFHandler<dim> &           dof_handler,
                  const Vector<double> &            reactions,
                  const BoundaryConditions<dim> &   boundary_conditions,
                  const std::vector<WallNode<dim>> &wall_nodes)
  {
    std::map<BoundaryId, std::vector<double>> force;
    for (const auto id : dof_handler.get_triangulation().get_boundary_ids())
      force[id] = std::vector<double>(dim, 0.);

    // The parts that can carry a force at each boundary node, with their
    // lumped weights.
    struct NodeParts
    {
      std::array<GlobalDof, dim>          dofs;
      std::map<BoundaryId, double>        weight;
    };
    std::map<GlobalDof, NodeParts> nodes;
    dealii::FEFaceValues<dim>      face_values(dof_handler.get_fe(),
                                          dealii::QGauss<dim - 1>(dof_handler.get_fe().degree + 1),
                                          dealii::update_values | dealii::update_JxW_values);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            boundary_conditions.traction_free_ids.count(cell->face(f)->boundary_id()) == 0)
          for (const auto &face_node : face_nodes<dim>(cell, f, face_values))
            {
              auto &node = nodes[face_node.dofs[0]];
              node.dofs  = face_node.dofs;
              node.weight[cell->face(f)->boundary_id()] += cell->face(f)->measure();
            }

    std::map<GlobalDof, const WallNode<dim> *> wall_node_of;
    for (const auto &node : wall_nodes)
      wall_node_of[node.dofs[0]] = &node;

    for (const auto &[first_dof, node] : nodes)
      {
        Tensor<1, dim> reaction;
        for (unsigned int d = 0; d < dim; ++d)
          reaction[d] = reactions[node.dofs[d]];

        // Prescribed-velocity parts take the whole reaction, shared by weight.
        double prescribed_weight = 0;
        for (const auto &[id, w] : node.weight)
          if (boundary_conditions.velocity_ids.count(id))
            prescribed_weight += w;
        if (prescribed_weight > 0 || node.weight.size() == 1)
          {
            const double total = prescribed_weight > 0 ? prescribed_weight : node.weight.begin()->second;
            for (const auto &[id, w] : node.weight)
              if (prescribed_weight == 0 || boundary_conditions.velocity_ids.count(id))
                for (unsigned int d = 0; d < dim; ++d)
                  force[id][d] += w / total * reaction[d];
            continue;
          }

        // Between walls: the reaction along each wall's normal belongs to that
        // wall (a 2D corner: solve R = a_1 n_1 + a_2 n_2); what remains (the
        // part along a shared tangent) is shared by weight.
        const auto wall = wall_node_of.find(first_dof);
        if (wall == wall_node_of.end() || wall->second->directions.size() < 2)
          {
            double total = 0;
            for (const auto &[id, w] : node.weight)
              total += w;
            for (const auto &[id, w] : node.weight)
              for (unsigned int d = 0; d < dim; ++d)
                force[id][d] += w / total * reaction[d];
            continue;
          }
        const auto &directions = wall->second->directions;
        // Least-squares split on the normals: G a = N^T R, G = N^T N.
        const unsigned int       k = directions.size();
        dealii::FullMatrix<double> G(k, k);
        Vector<double>           rhs(k), a(k);
        for (unsigned int i = 0; i < k; ++i)
          {
            rhs[i] = directions[i].normal * reaction;
            for (unsigned int j = 0; j < k; ++j)
              G(i, j) = directions[i].normal * directions[j].normal;
          }
        G.gauss_jordan();
        G.vmult(a, rhs);
        Tensor<1, dim> remainder = reaction;
        for (unsigned int i = 0; i < k; ++i)
          {
            for (unsigned int d = 0; d < dim; ++d)
              force[directions[i].id][d] += a[i] * directions[i].normal[d];
            remainder -= a[i] * directions[i].normal;
          }
        double total = 0;
        for (const auto &direction : directions)
          total += direction.weight;
        for (const auto &direction : directions)
          for (unsigned int d = 0; d < dim; ++d)
            force[direction.id][d] += direction.weight / total * remainder[d];
      }
    return force;
  }



  template <int dim>
  double
  divergence_ratio(const DoFHandler<dim> &dof_handler, const Vector<double> &velocity)
  {
    const dealii::FEValuesExtractors::Vector velocities(0);
    const auto &                             fe = dof_handler.get_fe();
    dealii::FEValues<dim> centre(fe, dealii::QGauss<dim>(1), dealii::update_gradients | dealii::update_JxW_values);
    dealii::FEValues<dim> gauss(fe, dealii::QGauss<dim>(fe.degree + 1), dealii::update_gradients | dealii::update_JxW_values);
    PressureProjection<dim>              projection(fe);
    const Vector<double>                 coefficients = cell_divergence(dof_handler, velocity);
    std::vector<double>                  div(1);
    std::vector<Tensor<2, dim>>          grad(gauss.n_quadrature_points);
    double                               div_squared = 0, grad_squared = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (fe.degree == 1)
          {
            centre.reinit(cell);
            centre[velocities].get_function_divergences(velocity, div);
            div_squared += div[0] * div[0] * centre.JxW(0);
          }
        else
          {
            projection.reinit(cell);
            div_squared +=
              projection.square_integral(coefficients.begin() + cell->active_cell_index() * projection.n_modes());
          }
        gauss.reinit(cell);
        gauss[velocities].get_function_gradients(velocity, grad);
        for (const unsigned int q : gauss.quadrature_point_indices())
          grad_squared += grad[q].norm_square() * gauss.JxW(q);
      }
    return grad_squared > 0 ? std::sqrt(div_squared / grad_squared) : 0.;
  }



  template <int dim>
  std::pair<double, double>
  velocity_errors(const DoFHandler<dim> &       dof_handler,
                  const Vector<double> &        velocity,
                  const dealii::Function<dim> & exact)
  {
    const auto &      triangulation = dof_handler.get_triangulation();
    Vector<float>     per_cell(triangulation.n_active_cells());
    const dealii::QGauss<dim> quadrature(dof_handler.get_fe().degree + 2);
    dealii::VectorTools::integrate_difference(
      dof_handler, velocity, exact, per_cell, quadrature, dealii::VectorTools::L2_norm);
    const double l2 = dealii::VectorTools::compute_global_error(triangulation, per_cell, dealii::VectorTools::L2_norm);
    dealii::VectorTools::integrate_difference(
      dof_handler, velocity, exact, per_cell, quadrature, dealii::VectorTools::H1_seminorm);
    const double h1 =
      dealii::VectorTools::compute_global_error(triangulation, per_cell, dealii::VectorTools::H1_seminorm);
    return {l2, h1};
  }



  template <int dim>
  Vector<double>
  cell_divergence(const DoFHandler<dim> &dof_handler, const Vector<double> &velocity)
  {
    if (dof_handler.get_fe().degree > 1)
      return PressureProjection<dim>::project_all(dof_handler, velocity);
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
  cell_pressure(const DoFHandler<dim> &dof_handler,
                const Vector<double> & velocity,
                const double           penalty,
                const Vector<double> * multiplier,
                const Vector<double> * cell_penalty)
  {
    Vector<double>     pressure = cell_divergence(dof_handler, velocity);
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



  namespace
  {
    /// Equivalent strain rate, equivalent stress and viscosity from the
    /// velocity gradient at the output points.
    template <int dim>
    class MaterialFields : public dealii::DataPostprocessor<dim>
    {
    public:
      explicit MaterialFields(const Material &material)
        : material(material)
      {}

      void
      evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<dim> &inputs,
                            std::vector<Vector<double>> &computed) const override
      {
        for (unsigned int q = 0; q < computed.size(); ++q)
          {
            Tensor<2, dim> grad;
            for (unsigned int d = 0; d < dim; ++d)
              grad[d] = inputs.solution_gradients[q][d];
            const auto   D     = dealii::symmetrize(grad);
            const double rate  = std::sqrt(2. / 3. * (D * D));
            const double eta   = material.evaluate(rate).eta;
            computed[q][0]     = rate;
            computed[q][1]     = 3. * eta * rate;
            computed[q][2]     = eta;
          }
      }

      std::vector<std::string>
      get_names() const override
      {
        return {"equivalent_strain_rate", "equivalent_stress", "viscosity"};
      }

      dealii::UpdateFlags
      get_needed_update_flags() const override
      {
        return dealii::update_gradients;
      }

    private:
      const Material &material;
    };

    /// Values per vertex of the triangulation as a Q1 field.
    template <int dim>
    Vector<double>
    vertex_field_to_q1(const DoFHandler<dim> &scalar_dofs, const std::vector<double> &per_vertex)
    {
      Vector<double> field(scalar_dofs.n_dofs());
      for (const auto &cell : scalar_dofs.active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          field[cell->vertex_dof_index(v, 0)] = per_vertex[cell->vertex_index(v)];
      return field;
    }
  } // namespace



  template <int dim>
  void
  write_fields(const DoFHandler<dim> &                         dof_handler,
            const Vector<double> &                          velocity,
            const Material &                                material,
            const Vector<double> &                          p_cell,
            const std::map<std::string, Vector<double>> &   nodal_fields,
            const std::string &                             directory,
            const unsigned int                              cycle,
            const bool                                      vtu,
            const bool                                      gnuplot,
            std::vector<std::pair<double, std::string>> &   pvd_records)
  {
    const auto &triangulation = dof_handler.get_triangulation();
    const dealii::FE_Q<dim>  scalar_fe(1);
    DoFHandler<dim>          scalar_dofs(triangulation);
    scalar_dofs.distribute_dofs(scalar_fe);

    // Each cell's pressure at its vertices, averaged with the cells' areas
    // as weights.
    PressureProjection<dim> projection(dof_handler.get_fe());
    const unsigned int      n_modes = projection.n_modes();
    Vector<double>          p_mean(triangulation.n_active_cells());
    std::vector<double>  p_sum(triangulation.n_vertices(), 0.), volume(triangulation.n_vertices(), 0.);
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const double *coefficients = p_cell.begin() + cell->active_cell_index() * n_modes;
        p_mean[cell->active_cell_index()] = coefficients[0];
        if (n_modes > 1)
          projection.reinit(cell);
        for (const unsigned int v : cell->vertex_indices())
          {
            const double p = n_modes > 1 ? projection.value(coefficients, cell->vertex(v)) : coefficients[0];
            p_sum[cell->vertex_index(v)] += p * cell->measure();
            volume[cell->vertex_index(v)] += cell->measure();
          }
      }
    for (unsigned int i = 0; i < p_sum.size(); ++i)
      if (volume[i] > 0)
        p_sum[i] /= volume[i];
    const Vector<double> p_nodal = vertex_field_to_q1(scalar_dofs, p_sum);

    dealii::DataOut<dim> data_out;
    data_out.attach_dof_handler(dof_handler);
    const std::vector<std::string> names(dim, "velocity");
    const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> interpretation(
      dim, dealii::DataComponentInterpretation::component_is_part_of_vector);
    data_out.add_data_vector(velocity, names, dealii::DataOut<dim>::type_dof_data, interpretation);
    const MaterialFields<dim> material_fields(material);
    data_out.add_data_vector(velocity, material_fields);
    data_out.add_data_vector(scalar_dofs, p_nodal, "pressure");
    std::vector<Vector<double>> extra;
    extra.reserve(nodal_fields.size());
    for (const auto &[name, values] : nodal_fields)
      {
        std::vector<double> per_vertex(values.begin(), values.end());
        extra.push_back(vertex_field_to_q1(scalar_dofs, per_vertex));
        data_out.add_data_vector(scalar_dofs, extra.back(), name);
      }
    data_out.add_data_vector(p_mean, "cell_pressure", dealii::DataOut<dim>::type_cell_data);
    // Degree 2: each cell subdivided, so the output shows the curved field.
    data_out.build_patches(dof_handler.get_fe().degree);

    const std::string stem = "solution-" + dealii::Utilities::int_to_string(cycle, 2);
    if (vtu)
      {
        std::ofstream out(directory + "/" + stem + ".vtu");
        data_out.write_vtu(out);
        pvd_records.emplace_back(cycle, stem + ".vtu");
        std::ofstream pvd(directory + "/solution.pvd");
        dealii::DataOutBase::write_pvd_record(pvd, pvd_records);
      }
    if (gnuplot)
      {
        std::ofstream out(directory + "/" + stem + ".gnuplot");
        data_out.write_gnuplot(out);
      }
  }

  template std::map<BoundaryId, double>
  boundary_fluxes<2>(const DoFHandler<2> &, const Vector<double> &);
  template std::map<BoundaryId, std::vector<double>>
  boundary_forces<2>(const DoFHandler<2> &, const Vector<double> &, const BoundaryConditions<2> &, const std::vector<WallNode<2>> &);
  template double
  divergence_ratio<2>(const DoFHandler<2> &, const Vector<double> &);
  template std::pair<double, double>
  velocity_errors<2>(const DoFHandler<2> &, const Vector<double> &, const dealii::Function<2> &);
  template Vector<double>
  cell_pressure<2>(const DoFHandler<2> &, const Vector<double> &, const double, const Vector<double> *,
                   const Vector<double> *);
  template Vector<double>
  cell_divergence<2>(const DoFHandler<2> &, const Vector<double> &);
  template void
  write_fields<2>(const DoFHandler<2> &, const Vector<double> &, const Material &, const Vector<double> &,
                  const std::map<std::string, Vector<double>> &, const std::string &, const unsigned int,
                  const bool, const bool, std::vector<std::pair<double, std::string>> &);
} // namespace dieflow
