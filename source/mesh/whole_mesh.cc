// deal.II's helpers that on a parallel::shared::Triangulation see only this process's cells, over every cell of the mesh.
#include <dieflow/mesh/whole_mesh.h>

#include <deal.II/base/geometry_info.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/fe/fe_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/full_matrix.h>

#include <stdexcept>

namespace dieflow
{
  namespace whole_mesh
  {
    template <int dim>
    void
    make_sparsity_pattern(const dealii::DoFHandler<dim> &          dof_handler,
                          dealii::DynamicSparsityPattern &         dsp,
                          const dealii::AffineConstraints<double> &constraints)
    {
      std::vector<dealii::types::global_dof_index> dofs(dof_handler.get_fe().n_dofs_per_cell());
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          constraints.add_entries_local_to_global(dofs, dsp, false);
        }
    }



    template <int dim>
    void
    interpolate(const dealii::DoFHandler<dim> &          from,
                const dealii::Vector<double> &           u_from,
                const dealii::DoFHandler<dim> &          to,
                const dealii::AffineConstraints<double> &constraints,
                dealii::Vector<double> &                 u_to)
    {
      AssertDimension(u_from.size(), from.n_dofs());
      AssertDimension(u_to.size(), to.n_dofs());
      dealii::FullMatrix<double> matrix(to.get_fe().n_dofs_per_cell(), from.get_fe().n_dofs_per_cell());
      dealii::FETools::get_interpolation_matrix(from.get_fe(), to.get_fe(), matrix);
      dealii::Vector<double> local_from(from.get_fe().n_dofs_per_cell()), local_to(to.get_fe().n_dofs_per_cell());
      std::vector<dealii::types::global_dof_index> dofs(to.get_fe().n_dofs_per_cell());
      dealii::Vector<double>                       touched(u_to.size());
      u_to       = 0.;
      auto cell2 = to.begin_active();
      for (const auto &cell : from.active_cell_iterators())
        {
          cell->get_dof_values(u_from, local_from);
          matrix.vmult(local_to, local_from);
          cell2->get_dof_indices(dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            {
              u_to[dofs[i]] += local_to[i];
              touched[dofs[i]] += 1;
            }
          ++cell2;
        }
      for (unsigned int i = 0; i < u_to.size(); ++i)
        u_to[i] = u_to[i] / touched[i];
      constraints.distribute(u_to);
    }



    template <int dim>
    void
    interpolate(const dealii::DoFHandler<dim> &dof_handler,
                const dealii::Function<dim> &  function,
                dealii::Vector<double> &       u)
    {
      const auto &fe = dof_handler.get_fe();
      Assert(fe.n_components() == 1 && fe.has_support_points(), dealii::ExcNotImplemented());
      AssertDimension(u.size(), dof_handler.n_dofs());
      // deal.II's flags: with them the mapping computes the points as it does there.
      dealii::FEValues<dim> fe_values(dealii::get_default_linear_mapping(dof_handler.get_triangulation()),
                                      fe,
                                      dealii::Quadrature<dim>(fe.get_generalized_support_points()),
                                      dealii::update_quadrature_points | dealii::update_jacobians |
                                        dealii::update_inverse_jacobians);
      std::vector<dealii::Vector<double>>          values(fe.n_dofs_per_cell(), dealii::Vector<double>(1));
      std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
      dealii::Vector<double>                       sum(u.size()), weight(u.size());
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          fe_values.reinit(cell);
          function.vector_value_list(fe_values.get_quadrature_points(), values);
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            {
              sum[dofs[i]] += values[i][0];
              weight[dofs[i]] += 1;
            }
        }
      for (unsigned int i = 0; i < u.size(); ++i)
        if (weight[i] != 0)
          u[i] = sum[i] / weight[i];
    }



    template <int dim>
    void
    point_value(const dealii::DoFHandler<dim> &dof_handler,
                const dealii::Vector<double> & u,
                const dealii::Point<dim> &     point,
                dealii::Vector<double> &       value)
    {
      const auto &fe      = dof_handler.get_fe();
      const auto &mapping = dealii::get_default_linear_mapping(dof_handler.get_triangulation());
      const auto  found   = dealii::GridTools::find_active_cell_around_point(mapping, dof_handler, point);
      if (found.first.state() != dealii::IteratorState::valid)
        throw std::runtime_error("the point is not in the mesh");
      const dealii::Quadrature<dim> quadrature(dealii::GeometryInfo<dim>::project_to_unit_cell(found.second));
      dealii::FEValues<dim>         fe_values(mapping, fe, quadrature, dealii::update_values);
      fe_values.reinit(found.first);
      std::vector<dealii::Vector<double>> values(1, dealii::Vector<double>(fe.n_components()));
      fe_values.get_function_values(u, values);
      value = values[0];
    }

    template <int dim>
    double
    point_value(const dealii::DoFHandler<dim> &dof_handler,
                const dealii::Vector<double> & u,
                const dealii::Point<dim> &     point)
    {
      dealii::Vector<double> value(1);
      point_value(dof_handler, u, point, value);
      return value[0];
    }



    template <int dim>
    std::vector<std::vector<bool>>
    constant_modes(const dealii::DoFHandler<dim> &dof_handler)
    {
      const auto &fe = dof_handler.get_fe();
      Assert(fe.is_primitive(), dealii::ExcNotImplemented());
      std::vector<std::vector<bool>>               modes(fe.n_components(), std::vector<bool>(dof_handler.n_dofs()));
      std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            modes[fe.system_to_component_index(i).first][dofs[i]] = true;
        }
      return modes;
    }



    template <int dim>
    void
    laplace_transform(const std::map<unsigned int, dealii::Point<dim>> &new_points, dealii::Triangulation<dim> &mesh)
    {
      if (dynamic_cast<const dealii::parallel::TriangulationBase<dim> *>(&mesh) == nullptr)
        {
          dealii::GridTools::laplace_transform(new_points, mesh);
          return;
        }
      dealii::Triangulation<dim> plain;
      plain.copy_triangulation(mesh);
      dealii::GridTools::laplace_transform(new_points, plain);
      const std::vector<dealii::Point<dim>> &moved = plain.get_vertices();
      for (const auto &cell : mesh.cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          cell->vertex(v) = moved[cell->vertex_index(v)];
    }



    template void
    make_sparsity_pattern(const dealii::DoFHandler<2> &, dealii::DynamicSparsityPattern &,
                          const dealii::AffineConstraints<double> &);
    template void
    make_sparsity_pattern(const dealii::DoFHandler<3> &, dealii::DynamicSparsityPattern &,
                          const dealii::AffineConstraints<double> &);
    template void
    interpolate(const dealii::DoFHandler<2> &, const dealii::Vector<double> &, const dealii::DoFHandler<2> &,
                const dealii::AffineConstraints<double> &, dealii::Vector<double> &);
    template void
    interpolate(const dealii::DoFHandler<3> &, const dealii::Vector<double> &, const dealii::DoFHandler<3> &,
                const dealii::AffineConstraints<double> &, dealii::Vector<double> &);
    template void
    interpolate(const dealii::DoFHandler<2> &, const dealii::Function<2> &, dealii::Vector<double> &);
    template void
    interpolate(const dealii::DoFHandler<3> &, const dealii::Function<3> &, dealii::Vector<double> &);
    template void
    point_value(const dealii::DoFHandler<2> &, const dealii::Vector<double> &, const dealii::Point<2> &,
                dealii::Vector<double> &);
    template void
    point_value(const dealii::DoFHandler<3> &, const dealii::Vector<double> &, const dealii::Point<3> &,
                dealii::Vector<double> &);
    template double
    point_value(const dealii::DoFHandler<2> &, const dealii::Vector<double> &, const dealii::Point<2> &);
    template double
    point_value(const dealii::DoFHandler<3> &, const dealii::Vector<double> &, const dealii::Point<3> &);
    template std::vector<std::vector<bool>>
    constant_modes(const dealii::DoFHandler<2> &);
    template std::vector<std::vector<bool>>
    constant_modes(const dealii::DoFHandler<3> &);
    template void
    laplace_transform(const std::map<unsigned int, dealii::Point<2>> &, dealii::Triangulation<2> &);
    template void
    laplace_transform(const std::map<unsigned int, dealii::Point<3>> &, dealii::Triangulation<3> &);
  } // namespace whole_mesh
} // namespace dieflow
