// The velocity's rigid-body motions at the nodes, and an ML smoothed-aggregation hierarchy with them as its near-null space.
#ifndef dieflow_rigid_body_modes_h
#define dieflow_rigid_body_modes_h

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <vector>

namespace dieflow
{
  /**
   * The rigid-body motions of the velocity field, evaluated at the nodes:
   * dim translations e_k and the dim(dim-1)/2 rotations w x (x - x_c)
   * (about the nodes' centroid x_c, which keeps them of the translations'
   * size). They span the kernel of the viscous operator
   * 2 eta D(u):D(w) (eq. (4)) without boundary conditions, so smoothed
   * aggregation must interpolate them exactly on every level to keep its
   * convergence rate independent of the mesh (Vanek, Mandel, Brezina,
   * Computing 56 (1996) 179). With the translations alone, as for a
   * vector Laplacian, the outer iterations of die2d's mixed-form solver
   * grew faster with the mesh (doc/benchmarks.md).
   * Stored column by column: mode m of dof i at [m * n_dofs + i].
   */
  template <int dim>
  std::vector<double>
  rigid_body_modes(const dealii::DoFHandler<dim> &dof_handler);

  /// dim + dim(dim-1)/2.
  template <int dim>
  constexpr unsigned int n_rigid_body_modes = dim + dim * (dim - 1) / 2;

  /**
   * One ML smoothed-aggregation hierarchy for a velocity block @p matrix
   * with the @p modes of rigid_body_modes() (followed by any further
   * near-null vectors, each of the matrix's size) as near-null space and the
   * settings of @p data (velocity_amg_data()); @p copy receives the
   * Trilinos copy of @p matrix the preconditioner works on (keep it alive
   * as long as @p amg). @p pde_equations > 1: the matrix's dofs come in
   * blocks of that many per node (the components of one support point,
   * consecutive), and ML aggregates nodes, not single dofs.
   * @p prolongator_sweeps: damped-Jacobi sweeps that smooth ML's tentative
   * prolongator (its "aggregation: smoothing sweeps"; one is classical
   * smoothed aggregation).
   */
  template <int dim>
  void
  initialize_with_rigid_body_modes(dealii::TrilinosWrappers::PreconditionAMG &                       amg,
                                   dealii::TrilinosWrappers::SparseMatrix &                          copy,
                                   const dealii::SparseMatrix<double> &                              matrix,
                                   const std::vector<double> &                                       modes,
                                   const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &data,
                                   const unsigned int pde_equations      = 1,
                                   const unsigned int prolongator_sweeps = 1);
} // namespace dieflow

#endif
