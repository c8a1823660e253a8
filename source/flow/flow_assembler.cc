// The flow's cell terms: the residual and the Jacobian (standard or primal-dual Newton) of the penalised velocity problem, with its loads.
#include <dieflow/base/processes.h>
#include <dieflow/flow/flow_assembler.h>
#include <dieflow/flow/pressure_projection.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/work_stream.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>

namespace dieflow
{
  namespace
  {
    template <int dim>
    struct ScratchData
    {
      ScratchData(const dealii::FiniteElement<dim> &fe, const CoordinateSystem<dim> &coordinates)
        : coordinates(coordinates)
        , viscous(fe,
                  dealii::QGauss<dim>(fe.degree + 1),
                  dealii::update_values | dealii::update_gradients |
                    dealii::update_JxW_values | dealii::update_quadrature_points)
        , centre(fe, dealii::QGauss<dim>(1), dealii::update_gradients | dealii::update_JxW_values)
        , face(fe,
               dealii::QGauss<dim - 1>(fe.degree + 1),
               dealii::update_values | dealii::update_JxW_values | dealii::update_quadrature_points)
        , projection(fe, coordinates)
        , divergence_coefficients(projection.n_modes())
        , cell_stress(projection.n_modes())
        , symmetric_gradients(fe.n_dofs_per_cell())
        , strain_projections(fe.n_dofs_per_cell())
        , dual_projections(fe.n_dofs_per_cell())
        , local_velocity(fe.n_dofs_per_cell())
        , force(dim)
      {}

      ScratchData(const ScratchData &other)
        : ScratchData(other.viscous.get_fe(), other.coordinates)
      {}

      CoordinateSystem<dim>                             coordinates;
      dealii::FEValues<dim>                             viscous;
      dealii::FEValues<dim>                             centre;
      dealii::FEFaceValues<dim>                         face;
      PressureProjection<dim>                           projection;
      dealii::Vector<double>                            divergence_coefficients;
      dealii::Vector<double>                            cell_stress;
      std::vector<StrainRate<dim>>                      symmetric_gradients;
      std::vector<double>                               strain_projections;
      std::vector<double>                               dual_projections;
      std::vector<double>                               local_velocity;
      dealii::Vector<double>                            force;
    };

    /// Rows of each transformed node of the cell: (rows_a) <- sum_b T(a,b) (rows_b).
    template <int dim>
    void
    apply_row_transforms(const dealii::FiniteElement<dim> &                  fe,
                         const RowTransforms &                               transforms,
                         const std::vector<dealii::types::global_dof_index> &dofs,
                         dealii::FullMatrix<double> *                        matrix,
                         dealii::Vector<double> &                            residual)
    {
      // Every node of the cell (vertices, and edge and cell nodes for degree 2).
      for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
        {
          if (fe.system_to_component_index(i).first != 0)
            continue;
          const unsigned int node = fe.system_to_component_index(i).second;
          unsigned int rows[dim];
          for (unsigned int d = 0; d < dim; ++d)
            rows[d] = fe.component_to_system_index(d, node);
          const auto found = transforms.find(dofs[rows[0]]);
          if (found == transforms.end())
            continue;
          const auto &T = found->second;
          double      r[dim];
          for (unsigned int a = 0; a < dim; ++a)
            {
              r[a] = 0;
              for (unsigned int b = 0; b < dim; ++b)
                r[a] += T(a, b) * residual[rows[b]];
            }
          for (unsigned int a = 0; a < dim; ++a)
            residual[rows[a]] = r[a];
          if (matrix == nullptr)
            continue;
          for (unsigned int j = 0; j < matrix->n(); ++j)
            {
              double m[dim];
              for (unsigned int a = 0; a < dim; ++a)
                {
                  m[a] = 0;
                  for (unsigned int b = 0; b < dim; ++b)
                    m[a] += T(a, b) * (*matrix)(rows[b], j);
                }
              for (unsigned int a = 0; a < dim; ++a)
                (*matrix)(rows[a], j) = m[a];
            }
        }
    }

    struct CopyData
    {
      dealii::FullMatrix<double>                   matrix;
      dealii::Vector<double>                       residual;
      std::vector<dealii::types::global_dof_index> dofs;
      /// The mixed form's cell data (see MixedPenalty): B_K, M_K, M_K^-1,
      /// the pressure unknowns, lambda_K, the mean eta_K, h_K.
      dealii::FullMatrix<double>                   divergence, mass, inverse_mass;
      std::vector<dealii::types::global_dof_index> modes;
      unsigned int                                 cell = 0;
      double                                       penalty = 0, viscosity = 0, size = 0;
    };

    /// lambda div v div w at the cell centre, and q div w (Q1-P0).
    template <int dim, typename CellIterator>
    void
    add_centre_penalty(const CellIterator &          cell,
                       const double                  lambda,
                       const dealii::Vector<double> *multiplier,
                       ScratchData<dim> &            scratch,
                       CopyData &                    copy,
                       const bool                    with_matrix)
    {
      const dealii::FEValuesExtractors::Vector velocities(0);
      const unsigned int                       dofs_per_cell = copy.dofs.size();
      scratch.centre.reinit(cell);
      const double         JxW        = scratch.centre.JxW(0);
      std::vector<double> &div        = scratch.strain_projections;
      double               divergence = 0;
      for (unsigned int i = 0; i < dofs_per_cell; ++i)
        {
          div[i] = scratch.centre[velocities].divergence(i, 0);
          divergence += scratch.local_velocity[i] * div[i];
        }
      const unsigned int c           = cell->active_cell_index();
      const double       cell_stress = lambda * divergence + (multiplier != nullptr ? (*multiplier)[c] : 0.);
      for (unsigned int i = 0; i < dofs_per_cell; ++i)
        {
          copy.residual[i] += cell_stress * div[i] * JxW;
          if (with_matrix)
            for (unsigned int j = 0; j <= i; ++j)
              copy.matrix(i, j) += lambda * div[i] * div[j] * JxW;
        }
    }

    /**
     * lambda (P div v)(P div w) with P the L2 projection onto P1disc, and
     * q_h div w for a multiplier q_h in the same space: B^T (lambda c + q)
     * with c = M^-1 B v, and the matrix lambda B^T M^-1 B (lower triangle).
     */
    template <int dim, typename CellIterator>
    void
    add_projected_penalty(const CellIterator &          cell,
                          const double                  lambda,
                          const dealii::Vector<double> *multiplier,
                          ScratchData<dim> &            scratch,
                          CopyData &                    copy,
                          const bool                    with_matrix,
                          const bool                    mixed)
    {
      auto &             projection    = scratch.projection;
      const unsigned int n_modes       = projection.n_modes();
      const unsigned int dofs_per_cell = copy.dofs.size();
      projection.reinit(cell);
      projection.project(scratch.local_velocity, scratch.divergence_coefficients);
      const unsigned int first = cell->active_cell_index() * n_modes;
      for (unsigned int m = 0; m < n_modes; ++m)
        scratch.cell_stress[m] =
          lambda * scratch.divergence_coefficients[m] + (multiplier != nullptr ? (*multiplier)[first + m] : 0.);
      const auto &B    = projection.divergence_matrix();
      const auto &Minv = projection.inverse_mass();
      for (unsigned int i = 0; i < dofs_per_cell; ++i)
        for (unsigned int m = 0; m < n_modes; ++m)
          copy.residual[i] += B(m, i) * scratch.cell_stress[m];
      if (!with_matrix)
        return;
      if (mixed)
        {
          copy.divergence   = B;
          copy.mass         = projection.mass();
          copy.inverse_mass = Minv;
          copy.size         = projection.cell_size();
          copy.penalty      = lambda;
          copy.modes.resize(n_modes);
          for (unsigned int m = 0; m < n_modes; ++m)
            copy.modes[m] = first + m;
          return;
        }
      // (M^-1 B) once, then B^T (M^-1 B).
      dealii::FullMatrix<double> MinvB(n_modes, dofs_per_cell);
      Minv.mmult(MinvB, B);
      for (unsigned int i = 0; i < dofs_per_cell; ++i)
        for (unsigned int j = 0; j <= i; ++j)
          {
            double sum = 0;
            for (unsigned int m = 0; m < n_modes; ++m)
              sum += B(m, i) * MinvB(m, j);
            copy.matrix(i, j) += lambda * sum;
          }
    }
  } // namespace



  template <int dim>
  FlowAssembler<dim>::FlowAssembler(const Material &material, const dealii::Function<dim> *body_force)
    : material(&material)
    , body_force(body_force)
  {}



  template <int dim>
  void
  FlowAssembler<dim>::assemble(const DoFHandler<dim> &          dof_handler,
                               const Vector<double> &           velocity,
                               const FlowTerms<dim> &           terms,
                               const AffineConstraints<double> &update_constraints,
                               const Linearization              linearization,
                               SparseMatrix<double> *           matrix,
                               Vector<double> &                 rhs,
                               Vector<double> &                 raw_residual,
                               const RowTransforms *            transforms,
                               const processes::RowSums *       row_sums) const
  {
    Assert(terms.penalty > 0, dealii::ExcMessage("The penalty has not been set."));
    MixedPenalty<dim> *const    mixed          = (terms.mixed != nullptr && matrix != nullptr) ? terms.mixed : nullptr;
    const Vector<double> *const multiplier     = terms.multiplier;
    const Vector<double> *const cell_penalty   = terms.cell_penalty;
    const Vector<double> *const cell_hardening = terms.hardening;
    const auto &       fe            = dof_handler.get_fe();
    const unsigned int dofs_per_cell = fe.n_dofs_per_cell();
    const bool         newton        = (linearization == Linearization::newton);
    const bool use_dual = (tangent == Tangent::primal_dual) && dual.size() == n_dual_points(dof_handler);

    Assert(mixed == nullptr || fe.degree >= 2, dealii::ExcMessage("The mixed form needs the stable pair (degree 2)."));
    if (matrix != nullptr)
      *matrix = 0;
    if (mixed != nullptr)
      mixed->clear_values();
    dealii::AffineConstraints<double> no_constraints;
    no_constraints.close();
    rhs.reinit(dof_handler.n_dofs());
    raw_residual.reinit(dof_handler.n_dofs());

    const auto worker = [&](const typename DoFHandler<dim>::active_cell_iterator &cell,
                            ScratchData<dim> &                                    scratch,
                            CopyData &                                            copy) {
      // Another process's cell: summed in from that process below.
      if (!processes::owns(cell))
        {
          copy.dofs.clear();
          return;
        }
      copy.dofs.resize(dofs_per_cell);
      cell->get_dof_indices(copy.dofs);
      copy.residual.reinit(dofs_per_cell);
      if (matrix != nullptr)
        copy.matrix.reinit(dofs_per_cell, dofs_per_cell);
      for (unsigned int i = 0; i < dofs_per_cell; ++i)
        scratch.local_velocity[i] = velocity[copy.dofs[i]];

      // Viscous term, 2x2 Gauss points.
      scratch.viscous.reinit(cell);
      const auto &viscous = scratch.viscous;
      double      eta_integral = 0, volume = 0;
      for (const unsigned int q : viscous.quadrature_point_indices())
        {
          StrainRate<dim> D;
          for (unsigned int i = 0; i < dofs_per_cell; ++i)
            {
              scratch.symmetric_gradients[i] = coordinates.strain_rate(viscous, i, q);
              D += scratch.local_velocity[i] * scratch.symmetric_gradients[i];
            }
          const double rate  = std::sqrt(2. / 3. * (D * D));
          auto         value = terms.temperature == nullptr ?
                         material->evaluate(rate) :
                         material->evaluate(
                           rate, (*terms.temperature)[cell->active_cell_index() * viscous.n_quadrature_points + q]);
          if (cell_hardening != nullptr)
            {
              value.eta *= (*cell_hardening)[cell->active_cell_index()];
              value.d_eta *= (*cell_hardening)[cell->active_cell_index()];
            }
          if (terms.point_hardening != nullptr)
            {
              const double factor = (*terms.point_hardening)[cell->active_cell_index() * viscous.n_quadrature_points + q];
              value.eta *= factor;
              value.d_eta *= factor;
            }
          const double JxW = viscous.JxW(q) * coordinates.weight(viscous.quadrature_point(q));
          eta_integral += value.eta * JxW;
          volume += JxW;
          if (body_force != nullptr)
            body_force->vector_value(viscous.quadrature_point(q), scratch.force);

          for (unsigned int i = 0; i < dofs_per_cell; ++i)
            {
              double r = 2. * value.eta * (D * scratch.symmetric_gradients[i]);
              if (body_force != nullptr)
                r -= scratch.force[fe.system_to_component_index(i).first] *
                     viscous.shape_value(i, q);
              copy.residual[i] += r * JxW;
            }
          if (matrix == nullptr)
            continue;
          // Standard Newton: (4/3) eta' r (S^:D(dv)) (S^:D(w)), S^ = D/r. The
          // primal-dual variant replaces one S^ by the dual iterate S and
          // symmetrises; with S = S^ both agree.
          const double newton_factor = newton ? 4. / 3. * value.d_eta * value.rate : 0.;
          const auto   S_hat         = D / value.rate;
          const auto & S = (newton && use_dual) ? dual[cell->active_cell_index() * viscous.n_quadrature_points + q] : S_hat;
          for (unsigned int i = 0; i < dofs_per_cell; ++i)
            {
              scratch.strain_projections[i] = S_hat * scratch.symmetric_gradients[i];
              scratch.dual_projections[i]   = S * scratch.symmetric_gradients[i];
            }
          for (unsigned int i = 0; i < dofs_per_cell; ++i)
            for (unsigned int j = 0; j <= i; ++j)
              copy.matrix(i, j) +=
                (2. * value.eta * (scratch.symmetric_gradients[i] * scratch.symmetric_gradients[j]) +
                 newton_factor * 0.5 *
                   (scratch.strain_projections[i] * scratch.dual_projections[j] +
                    scratch.dual_projections[i] * scratch.strain_projections[j])) *
                JxW;
        }

      if (traction != nullptr && cell->at_boundary())
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary() && traction_ids.count(cell->face(f)->boundary_id()))
            {
              scratch.face.reinit(cell, f);
              for (const unsigned int q : scratch.face.quadrature_point_indices())
                {
                  traction->vector_value(scratch.face.quadrature_point(q), scratch.force);
                  for (unsigned int i = 0; i < dofs_per_cell; ++i)
                    copy.residual[i] -= scratch.force[fe.system_to_component_index(i).first] *
                                        scratch.face.shape_value(i, q) * scratch.face.JxW(q) *
                                        coordinates.weight(scratch.face.quadrature_point(q));
                }
            }

      const double lambda = (cell_penalty != nullptr) ? (*cell_penalty)[cell->active_cell_index()] : terms.penalty;
      // Axisymmetric and 3D Q1: the cell mean of div v (PressureProjection).
      if (fe.degree == 1 && coordinates.centre_rule_is_mean())
        add_centre_penalty<dim>(cell, lambda, multiplier, scratch, copy, matrix != nullptr);
      else
        add_projected_penalty<dim>(cell, lambda, multiplier, scratch, copy, matrix != nullptr, mixed != nullptr);
      copy.cell      = cell->active_cell_index();
      copy.viscosity = eta_integral / volume;

      if (matrix != nullptr)
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
          for (unsigned int j = i + 1; j < dofs_per_cell; ++j)
            copy.matrix(i, j) = copy.matrix(j, i);
    };

    const auto copier = [&](const CopyData &copy) {
      if (copy.dofs.empty())
        return;
      for (unsigned int i = 0; i < copy.dofs.size(); ++i)
        raw_residual[copy.dofs[i]] += copy.residual[i];
      Vector<double>                    minus_residual(copy.residual);
      dealii::FullMatrix<double>        transformed;
      const dealii::FullMatrix<double> *local_matrix = &copy.matrix;
      if (transforms != nullptr && !transforms->empty())
        {
          if (matrix != nullptr)
            {
              transformed  = copy.matrix;
              local_matrix = &transformed;
            }
          apply_row_transforms(fe, *transforms, copy.dofs, matrix != nullptr ? &transformed : nullptr, minus_residual);
        }
      minus_residual *= -1.;
      if (mixed != nullptr)
        {
          no_constraints.distribute_local_to_global(copy.divergence, copy.modes, update_constraints, copy.dofs, mixed->divergence);
          dealii::FullMatrix<double> gradient(copy.dofs.size(), copy.modes.size());
          gradient.copy_transposed(copy.divergence);
          if (transforms != nullptr && !transforms->empty())
            {
              Vector<double> unused(copy.dofs.size());
              apply_row_transforms(fe, *transforms, copy.dofs, &gradient, unused);
            }
          update_constraints.distribute_local_to_global(gradient, copy.dofs, no_constraints, copy.modes, mixed->gradient);
          mixed->set_cell(copy.cell, copy.mass, copy.inverse_mass, copy.penalty, copy.viscosity, copy.size);
        }
      if (matrix != nullptr)
        update_constraints.distribute_local_to_global(*local_matrix, minus_residual, copy.dofs, *matrix, rhs);
      else
        update_constraints.distribute_local_to_global(minus_residual, copy.dofs, rhs);
    };

    dealii::WorkStream::run(dof_handler.begin_active(),
                            dof_handler.end(),
                            worker,
                            copier,
                            ScratchData<dim>(fe, coordinates),
                            CopyData());
    // Each process assembled its own cells: the sums are the whole system
    // (the matrix only in each process's own rows where @p row_sums is given).
    if (matrix != nullptr && row_sums != nullptr)
      row_sums->sum(*matrix);
    else if (matrix != nullptr)
      processes::sum(*matrix);
    if (mixed != nullptr)
      mixed->sum_over_processes();
    processes::sum(rhs);
    processes::sum(raw_residual);
  }



  template <int dim>
  void
  FlowAssembler<dim>::assemble_system(const DoFHandler<dim> &          dof_handler,
                                      const Vector<double> &           velocity,
                                      const FlowTerms<dim> &           terms,
                                      const AffineConstraints<double> &update_constraints,
                                      const Linearization              linearization,
                                      SparseMatrix<double> &           matrix,
                                      Vector<double> &                 rhs,
                                      Vector<double> &                 raw_residual,
                                      const RowTransforms *            transforms,
                                      const processes::RowSums *       row_sums) const
  {
    assemble(dof_handler, velocity, terms, update_constraints, linearization, &matrix, rhs, raw_residual, transforms, row_sums);
  }



  template <int dim>
  void
  FlowAssembler<dim>::assemble_residual(const DoFHandler<dim> &          dof_handler,
                                        const Vector<double> &           velocity,
                                        const FlowTerms<dim> &           terms,
                                        const AffineConstraints<double> &update_constraints,
                                        Vector<double> &                 rhs,
                                        Vector<double> &                 raw_residual,
                                        const RowTransforms *            transforms) const
  {
    assemble(dof_handler, velocity, terms, update_constraints, Linearization::picard, nullptr, rhs, raw_residual, transforms,
             nullptr);
  }



  template <int dim>
  double
  FlowAssembler<dim>::mean_viscosity(const DoFHandler<dim> &dof_handler,
                                     const Vector<double> & velocity) const
  {
    dealii::FEValues<dim> fe_values(dof_handler.get_fe(),
                                    dealii::QGauss<dim>(dof_handler.get_fe().degree + 1),
                                    dealii::update_gradients | dealii::update_JxW_values | dealii::update_quadrature_points |
                                      coordinates.flags());
    std::vector<StrainRate<dim>> D(fe_values.n_quadrature_points);
    double                       integral = 0, volume = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        coordinates.strain_rates(fe_values, velocity, D);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            const double JxW = fe_values.JxW(q) * coordinates.weight(fe_values.quadrature_point(q));
            integral += material->evaluate(std::sqrt(2. / 3. * (D[q] * D[q]))).eta * JxW;
            volume += JxW;
          }
      }
    return integral / volume;
  }

  template <int dim>
  unsigned int
  FlowAssembler<dim>::n_dual_points(const DoFHandler<dim> &dof_handler) const
  {
    return dof_handler.get_triangulation().n_active_cells() * dealii::QGauss<dim>(dof_handler.get_fe().degree + 1).size();
  }



  template <int dim>
  void
  FlowAssembler<dim>::update_dual(const DoFHandler<dim> &dof_handler,
                                  const Vector<double> & velocity,
                                  const Vector<double> * update,
                                  const double           step)
  {
    dealii::FEValues<dim> fe_values(dof_handler.get_fe(),
                                    dealii::QGauss<dim>(dof_handler.get_fe().degree + 1),
                                    dealii::update_gradients | coordinates.flags());
    std::vector<StrainRate<dim>> D(fe_values.n_quadrature_points), dD(fe_values.n_quadrature_points);
    const bool reset = (update == nullptr) || dual.size() != n_dual_points(dof_handler);
    if (reset)
      dual.resize(n_dual_points(dof_handler));
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        coordinates.strain_rates(fe_values, velocity, D);
        if (!reset)
          coordinates.strain_rates(fe_values, *update, dD);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            const double rate = material->evaluate(std::sqrt(2. / 3. * (D[q] * D[q]))).rate;
            auto &       S    = dual[cell->active_cell_index() * fe_values.n_quadrature_points + q];
            if (reset)
              S = D[q] / rate;
            else
              {
                // Newton step for S r(v) = D(v): S + dS = (D + dD - S dr)/r,
                // dr = (2/3) D:dD / r.
                const double d_rate = 2. / 3. * (D[q] * dD[q]) / rate;
                S += step * ((D[q] + dD[q] - S * d_rate) / rate - S);
              }
            // |S| = sqrt(2/3 S:S) <= 1, as for S^ = D/r.
            const double norm = std::sqrt(2. / 3. * (S * S));
            if (norm > 1)
              S /= norm;
          }
      }
  }

  template class FlowAssembler<2>;
  template class FlowAssembler<3>;
} // namespace dieflow
