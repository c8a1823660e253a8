// Fields carried from a moved mesh to a new mesh of the same domain: nodal fields at the new nodes, cell fields at the new cells' centres.
#include <dieflow/incremental/mesh_transfer.h>

#include <deal.II/fe/fe.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/grid_tools_cache.h>

#include <limits>
#include <map>
#include <sstream>

namespace dieflow
{
  namespace
  {
    template <int dim>
    using CellAndUnitPoint =
      std::pair<typename dealii::Triangulation<dim>::active_cell_iterator, dealii::Point<dim>>;

    /// The old cell holding @p p and p's unit coordinates in it, or, for a
    /// point in no cell, the nearest vertex's cell nearest to it and the
    /// nearest point of that cell (@p in_folds counts these); nothing (an
    /// invalid iterator) if no cell of the nearest vertex can be mapped back.
    template <int dim>
    CellAndUnitPoint<dim>
    old_cell_around(const dealii::GridTools::Cache<dim> &cache, const dealii::Point<dim> &p, unsigned int &in_folds)
    {
      const dealii::Triangulation<dim> &triangulation = cache.get_triangulation();
      const dealii::Mapping<dim> &      mapping       = cache.get_mapping();
      CellAndUnitPoint<dim>             found         = dealii::GridTools::find_active_cell_around_point(cache, p);
      if (found.first.state() != dealii::IteratorState::valid)
        found = dealii::GridTools::find_active_cell_around_point(mapping, triangulation, p);
      if (found.first.state() == dealii::IteratorState::valid)
        return found;
      const unsigned int vertex  = dealii::GridTools::find_closest_vertex(mapping, triangulation, p);
      double             nearest = std::numeric_limits<double>::infinity();
      for (const auto &cell : cache.get_vertex_to_cell_map()[vertex])
        try
          {
            const dealii::Point<dim> unit     = mapping.transform_real_to_unit_cell(cell, p);
            const double             distance = dealii::GeometryInfo<dim>::distance_to_unit_cell(unit);
            if (distance < nearest)
              {
                nearest = distance;
                found   = {cell, dealii::GeometryInfo<dim>::project_to_unit_cell(unit)};
              }
          }
        catch (const typename dealii::Mapping<dim>::ExcTransformationFailed &)
          {}
      if (found.first.state() == dealii::IteratorState::valid)
        ++in_folds;
      return found;
    }
  } // namespace



  template <int dim>
  MeshTransfer<dim>::MeshTransfer(const dealii::DoFHandler<dim> &old,
                                  const dealii::DoFHandler<dim> &fresh,
                                  const std::string &            when)
    : old_n_dofs(old.n_dofs())
    , old_n_cells(old.get_triangulation().n_active_cells())
  {
    const dealii::FiniteElement<dim> &  fe = old.get_fe();
    const dealii::GridTools::Cache<dim> cache(old.get_triangulation());
    const auto                          locate = [&](const dealii::Point<dim> &p) {
      const CellAndUnitPoint<dim> found = old_cell_around(cache, p, in_folds);
      if (found.first.state() != dealii::IteratorState::valid)
        {
          std::ostringstream message;
          message << "Incremental/Remesh below Jacobian: a point of the new mesh, (" << p
                  << "), lies in no cell of the moved mesh " << when
                  << " (the move tangled the cells there); lower Incremental/Time step, or raise Remesh below "
                     "Jacobian (new meshes sooner)";
          throw InputError(message.str());
        }
      return found;
    };

    // Row i of the interpolation, for each new degree of freedom once; the
    // components of one node share their support point, located once.
    std::vector<bool>                                         done(fresh.n_dofs(), false);
    std::vector<std::vector<dealii::types::global_dof_index>> columns(fresh.n_dofs());
    std::vector<std::vector<double>>                          weights(fresh.n_dofs());
    std::vector<dealii::types::global_dof_index> fresh_indices(fe.n_dofs_per_cell()), old_indices(fe.n_dofs_per_cell());
    const std::vector<dealii::Point<dim>> &      unit_support = fe.get_unit_support_points();
    for (const auto &cell : fresh.active_cell_iterators())
      {
        cell->get_dof_indices(fresh_indices);
        std::map<unsigned int, CellAndUnitPoint<dim>> located; // by the node's index within its component
        for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
          if (!done[fresh_indices[i]])
            {
              const auto [component, node] = fe.system_to_component_index(i);
              if (located.count(node) == 0)
                located.emplace(node, locate(cache.get_mapping().transform_unit_to_real_cell(cell, unit_support[i])));
              const auto &[old_cell_found, unit] = located.at(node);
              typename dealii::DoFHandler<dim>::active_cell_iterator(&old.get_triangulation(),
                                                                      old_cell_found->level(),
                                                                      old_cell_found->index(),
                                                                      &old)
                ->get_dof_indices(old_indices);
              for (unsigned int j = 0; j < fe.n_dofs_per_cell(); ++j)
                if (const double phi = fe.shape_value_component(j, unit, component); phi != 0)
                  {
                    columns[fresh_indices[i]].push_back(old_indices[j]);
                    weights[fresh_indices[i]].push_back(phi);
                  }
              done[fresh_indices[i]] = true;
            }
      }
    row_start.assign(1, 0);
    for (dealii::types::global_dof_index i = 0; i < fresh.n_dofs(); ++i)
      {
        column.insert(column.end(), columns[i].begin(), columns[i].end());
        weight.insert(weight.end(), weights[i].begin(), weights[i].end());
        row_start.push_back(column.size());
      }

    old_cell.resize(fresh.get_triangulation().n_active_cells());
    for (const auto &cell : fresh.get_triangulation().active_cell_iterators())
      old_cell[cell->active_cell_index()] = locate(cell->center()).first->active_cell_index();
  }



  template <int dim>
  dealii::Vector<double>
  MeshTransfer<dim>::nodal(const dealii::Vector<double> &old_values) const
  {
    if (old_values.size() != old_n_dofs)
      return {};
    dealii::Vector<double> values(row_start.size() - 1);
    for (std::size_t i = 0; i + 1 < row_start.size(); ++i)
      {
        double value = 0;
        for (std::size_t k = row_start[i]; k < row_start[i + 1]; ++k)
          value += weight[k] * old_values[column[k]];
        values[i] = value;
      }
    return values;
  }



  template <int dim>
  dealii::Vector<double>
  MeshTransfer<dim>::per_cell(const dealii::Vector<double> &old_values) const
  {
    dealii::Vector<double> values(old_cell.size());
    if (old_values.size() == old_n_cells)
      for (std::size_t c = 0; c < old_cell.size(); ++c)
        values[c] = old_values[old_cell[c]];
    return values;
  }



  template class MeshTransfer<2>;
  template class MeshTransfer<3>;
} // namespace dieflow
