// deal.II's helpers that on a parallel::shared::Triangulation see only this process's cells, over every cell of the mesh.
#ifndef dieflow_whole_mesh_h
#define dieflow_whole_mesh_h

#include <deal.II/base/function.h>
#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <vector>

namespace dieflow
{
  /**
   * On P > 1 the mesh is a parallel::shared::Triangulation: every process
   * holds every cell, but cell->is_locally_owned() is true only for its own
   * part's. deal.II's helpers below skip the other cells there (deal.II 9.4:
   * DoFTools::make_sparsity_pattern, FETools::interpolate,
   * VectorTools::interpolate and point_value, DoFTools::extract_constant_modes,
   * and GridTools::laplace_transform through its matrix), which would leave
   * each process a different part of a state that must be the same bits
   * everywhere. These are the same computations over every active cell, in
   * the cells' order, as deal.II makes them on a plain mesh (the same
   * arithmetic, so the same bits on one process as deal.II's).
   */
  namespace whole_mesh
  {
    /// DoFTools::make_sparsity_pattern(@p dof_handler, @p dsp, @p constraints, false).
    template <int dim>
    void
    make_sparsity_pattern(const dealii::DoFHandler<dim> &          dof_handler,
                          dealii::DynamicSparsityPattern &         dsp,
                          const dealii::AffineConstraints<double> &constraints);

    /// FETools::interpolate(@p from, @p u_from, @p to, @p constraints, @p u_to):
    /// cell by cell, each dof the mean of its cells' values, then @p constraints distributed.
    template <int dim>
    void
    interpolate(const dealii::DoFHandler<dim> &          from,
                const dealii::Vector<double> &           u_from,
                const dealii::DoFHandler<dim> &          to,
                const dealii::AffineConstraints<double> &constraints,
                dealii::Vector<double> &                 u_to);

    /// VectorTools::interpolate(@p dof_handler, @p function, @p u) for a
    /// scalar element with support points (FE_Q): each dof the mean of
    /// @p function at its cells' support points.
    template <int dim>
    void
    interpolate(const dealii::DoFHandler<dim> &dof_handler,
                const dealii::Function<dim> &  function,
                dealii::Vector<double> &       u);

    /// VectorTools::point_value(@p dof_handler, @p u, @p point, @p value):
    /// @p u in the cell GridTools::find_active_cell_around_point() finds,
    /// whoever owns it; throws where no cell holds @p point.
    template <int dim>
    void
    point_value(const dealii::DoFHandler<dim> &dof_handler,
                const dealii::Vector<double> & u,
                const dealii::Point<dim> &     point,
                dealii::Vector<double> &       value);

    /// The same for a scalar element.
    template <int dim>
    double
    point_value(const dealii::DoFHandler<dim> &dof_handler,
                const dealii::Vector<double> & u,
                const dealii::Point<dim> &     point);

    /// DoFTools::extract_constant_modes(@p dof_handler, ComponentMask(), modes)
    /// for a primitive element of one constant mode per component (FESystem
    /// of FE_Q): mode c marks every dof of component c, over all dofs.
    template <int dim>
    std::vector<std::vector<bool>>
    constant_modes(const dealii::DoFHandler<dim> &dof_handler);

    /// GridTools::laplace_transform(@p new_points, @p mesh); on a shared
    /// mesh computed on a plain copy of it (the same cells and vertices, so
    /// the same Laplace problem as one process solves) and the vertices
    /// moved as the copy's.
    template <int dim>
    void
    laplace_transform(const std::map<unsigned int, dealii::Point<dim>> &new_points, dealii::Triangulation<dim> &mesh);
  } // namespace whole_mesh
} // namespace dieflow

#endif
