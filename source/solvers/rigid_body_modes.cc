// The velocity's rigid-body motions at the nodes, and an ML smoothed-aggregation hierarchy with them as its near-null space.
#include <dieflow/solvers/rigid_body_modes.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping_q1.h>

#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

namespace dieflow
{
  template <int dim>
  std::vector<double>
  rigid_body_modes(const dealii::DoFHandler<dim> &dof_handler)
  {
    const unsigned int              n = dof_handler.n_dofs();
    std::vector<dealii::Point<dim>> points(n);
    dealii::DoFTools::map_dofs_to_support_points(dealii::MappingQ1<dim>(), dof_handler, points);
    dealii::Point<dim> centre;
    for (const auto &p : points)
      centre += p / static_cast<double>(n);

    std::vector<unsigned int>                  component(n);
    std::vector<dealii::types::global_dof_index> cell_dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell_dofs.resize(cell->get_fe().n_dofs_per_cell());
        cell->get_dof_indices(cell_dofs);
        for (unsigned int j = 0; j < cell_dofs.size(); ++j)
          component[cell_dofs[j]] = cell->get_fe().system_to_component_index(j).first;
      }

    std::vector<double> modes(n_rigid_body_modes<dim> * n, 0.);
    for (unsigned int i = 0; i < n; ++i)
      {
        const unsigned int           c = component[i];
        const dealii::Tensor<1, dim> d = points[i] - centre;
        modes[c * n + i]               = 1.;
        // Rotation in the plane (a, b): u_a = -d_b, u_b = d_a.
        unsigned int m = dim;
        for (unsigned int a = 0; a < dim; ++a)
          for (unsigned int b = a + 1; b < dim; ++b, ++m)
            modes[m * n + i] = c == a ? -d[b] : c == b ? d[a] : 0.;
      }
    return modes;
  }



  template <int dim>
  void
  initialize_with_rigid_body_modes(dealii::TrilinosWrappers::PreconditionAMG &                       amg,
                                   dealii::TrilinosWrappers::SparseMatrix &                          copy,
                                   const dealii::SparseMatrix<double> &                              matrix,
                                   const std::vector<double> &                                       modes,
                                   const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &data,
                                   const unsigned int pde_equations,
                                   const unsigned int prolongator_sweeps)
  {
    Assert(modes.size() % matrix.m() == 0 && modes.size() >= n_rigid_body_modes<dim> * matrix.m(),
           dealii::ExcInternalError());
    copy.reinit(matrix);
    Teuchos::ParameterList              parameters;
    std::unique_ptr<Epetra_MultiVector> constant_modes;
    data.set_parameters(parameters, constant_modes, copy);
    // One process: ML's local numbering is the global one. ML reads the
    // vectors while initialize() builds the hierarchy.
    parameters.set("null space: type", "pre-computed");
    parameters.set("null space: dimension", static_cast<int>(modes.size() / matrix.m()));
    parameters.set("null space: vectors", const_cast<double *>(modes.data()));
    if (pde_equations > 1)
      parameters.set("PDE equations", static_cast<int>(pde_equations));
    parameters.set("aggregation: smoothing sweeps", static_cast<int>(prolongator_sweeps));
    amg.initialize(copy, parameters);
  }

  template std::vector<double>
  rigid_body_modes(const dealii::DoFHandler<2> &);
  template void
  initialize_with_rigid_body_modes<2>(dealii::TrilinosWrappers::PreconditionAMG &,
                                      dealii::TrilinosWrappers::SparseMatrix &,
                                      const dealii::SparseMatrix<double> &,
                                      const std::vector<double> &,
                                      const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &,
                                      const unsigned int,
                                      const unsigned int);
  template std::vector<double>
  rigid_body_modes(const dealii::DoFHandler<3> &);
  template void
  initialize_with_rigid_body_modes<3>(dealii::TrilinosWrappers::PreconditionAMG &,
                                      dealii::TrilinosWrappers::SparseMatrix &,
                                      const dealii::SparseMatrix<double> &,
                                      const std::vector<double> &,
                                      const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &,
                                      const unsigned int,
                                      const unsigned int);
} // namespace dieflow
