// Fields carried from a moved mesh to a new mesh of the same domain: nodal fields at the new nodes, cell fields at the new cells' centres.
#ifndef dieflow_incremental_mesh_transfer_h
#define dieflow_incremental_mesh_transfer_h

#include <dieflow/base/parameters.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace dieflow
{
  /**
   * The fields of a moved mesh carried over to a new mesh of the same domain
   * (the seed paper's "remeshing of the domain": the velocity, the next
   * solve's first iterate, and the material's history). Two meshes that do
   * not share cells: deal.II's SolutionTransfer and
   * interpolate_to_different_mesh need a common coarse mesh.
   *
   * A nodal field u_h = sum_j u_j phi_j of the old mesh goes to the new
   * mesh's nodes by interpolation, u_i' = u_h(x_i) = sum_j u_j phi_j(x_i),
   * x_i the support point of the new degree of freedom i and phi_j the old
   * cell's shape functions of i's vector component (exact for fields the old
   * element reproduces); a cell field (one value per cell: the equivalent
   * strain) goes to each new cell from the old cell that holds its centre.
   * The old cells are searched once, at construction: the weights
   * phi_j(x_i) are kept, and each field is then a sparse product.
   *
   * The search: the cells of the nearest vertex (GridTools::Cache), then,
   * for a point those miss (a long thin cell, as moved cells near a crowded
   * boundary are), the search that widens over the neighbours. A step can
   * fold the cells at a die's corner (the metal turning round the exit)
   * before the new mesh comes: a point in the gap of the fold lies in no
   * cell, and takes the value at the nearest point of the nearest vertex's
   * cell nearest to it (counted: n_in_folds()).
   */
  template <int dim>
  class MeshTransfer
  {
  public:
    /**
     * Locates the nodes of @p fresh (its element's support points, mapped
     * by Q1) and the centres of its cells in @p old's mesh; both handlers
     * have the same element. Throws InputError naming Incremental/Remesh
     * below Jacobian, and saying @p when, if a point lies in no cell of the
     * nearest vertex even by projection.
     */
    MeshTransfer(const dealii::DoFHandler<dim> &old, const dealii::DoFHandler<dim> &fresh, const std::string &when);

    /// The nodal field @p old_values of the old mesh at the new nodes; an
    /// empty vector if it is not of the old mesh's size (a field not yet set).
    dealii::Vector<double>
    nodal(const dealii::Vector<double> &old_values) const;

    /// The cell field @p old_values (one value per old active cell) on the
    /// new cells; zeros if it is not of the old mesh's size.
    dealii::Vector<double>
    per_cell(const dealii::Vector<double> &old_values) const;

    /// New nodes and cell centres that lay in no old cell (a fold's gap).
    unsigned int
    n_in_folds() const
    {
      return in_folds;
    }

  private:
    /// Row i of the interpolation: u_i' = sum over k in [row_start[i],
    /// row_start[i+1]) of weight[k] u_{column[k]}.
    std::vector<std::size_t>                     row_start;
    std::vector<dealii::types::global_dof_index> column;
    std::vector<double>                          weight;
    /// The old active cell index of each new cell's centre.
    std::vector<unsigned int>                    old_cell;
    std::size_t                                  old_n_dofs;
    unsigned int                                 old_n_cells;
    unsigned int                                 in_folds = 0;
  };
} // namespace dieflow

#endif
