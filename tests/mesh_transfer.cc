// Fields carried from a moved mesh to a new mesh of the domain (MeshTransfer,
// Problem = incremental's remeshing), velocity degrees 1 and 2. The old
// mesh: 4 x 3 cells on [0, 2] x [0, 1], the vertices left of x = 1.5 moved
// (curved lines of cells, the cells no parallelograms); the new mesh: 5 x 4
// cells on [0, 2.06] x [0, 1], its own vertices moved, so that its last
// column of nodes (x = 2.06) lies beyond the old domain, as nodes in the
// gap of a fold do.
//  1. A linear vector field, which the isoparametric Q1 and Q2 spaces hold
//     exactly on any quadrilateral, goes over exactly (round-off) at every
//     new node inside the old domain;
//  2. a node beyond x = 2 takes the field at the nearest point of the old
//     boundary (x = 2, the same y: the last old column is rectangular), and
//     these are counted, once per node: the 5 (degree 1) or 9 (degree 2)
//     nodes on x = 2.06;
//  3. a cell field (the old cell's index) goes to each new cell from the
//     old cell that holds its centre, found here by testing every old cell;
//  4. a field of the wrong size gives an empty (nodal) or zero (cell) field.
#include <dieflow/incremental/mesh_transfer.h>

#include "report.h"

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>
#include <iostream>

using namespace dieflow;
using dealii::Point;

namespace
{
  const double pi = dealii::numbers::PI;

  /// u = (1 + 2x - 3y, -0.5 + x + 4y).
  class Linear : public dealii::Function<2>
  {
  public:
    Linear()
      : dealii::Function<2>(2)
    {}
    double
    value(const Point<2> &p, const unsigned int component) const override
    {
      return component == 0 ? 1 + 2 * p[0] - 3 * p[1] : -0.5 + p[0] + 4 * p[1];
    }
  };

  void
  mesh(dealii::Triangulation<2> &triangulation, const unsigned int nx, const unsigned int ny, const double length,
       const double bend)
  {
    dealii::GridGenerator::subdivided_hyper_rectangle(triangulation, {nx, ny}, Point<2>(0, 0), Point<2>(length, 1));
    dealii::GridTools::transform(
      [bend](const Point<2> &p) {
        if (p[0] >= 1.5)
          return p;
        return Point<2>(p[0] + bend * std::sin(pi * p[0] / 1.5) * std::sin(pi * p[1]),
                        p[1] + bend * std::sin(2 * pi * p[0] / 1.5) * std::sin(pi * p[1]));
      },
      triangulation);
  }

  void
  check(const unsigned int degree)
  {
    std::cout << "velocity degree " << degree << std::endl;
    const dealii::FESystem<2> fe(dealii::FE_Q<2>(degree), 2);
    dealii::Triangulation<2>  old_mesh, new_mesh;
    mesh(old_mesh, 4, 3, 2, 0.08);
    mesh(new_mesh, 5, 4, 2.06, -0.05);
    dealii::DoFHandler<2> old_dofs(old_mesh), new_dofs(new_mesh);
    old_dofs.distribute_dofs(fe);
    new_dofs.distribute_dofs(fe);

    dealii::Vector<double> old_field(old_dofs.n_dofs());
    dealii::VectorTools::interpolate(old_dofs, Linear(), old_field);
    const MeshTransfer<2>        transfer(old_dofs, new_dofs, "in the test");
    const dealii::Vector<double> new_field = transfer.nodal(old_field);

    const dealii::MappingQ1<2>   mapping;
    std::vector<Point<2>>        support(new_dofs.n_dofs());
    dealii::DoFTools::map_dofs_to_support_points(mapping, new_dofs, support);
    double       inside_error = 0, beyond_error = 0;
    unsigned int beyond       = 0;
    const Linear exact;
    for (const auto &cell : new_dofs.active_cell_iterators())
      {
        std::vector<dealii::types::global_dof_index> indices(fe.n_dofs_per_cell());
        cell->get_dof_indices(indices);
        for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
          {
            const Point<2>     p         = support[indices[i]];
            const unsigned int component = fe.system_to_component_index(i).first;
            if (p[0] <= 2 + 1e-12)
              inside_error = std::max(inside_error, std::abs(new_field[indices[i]] - exact.value(p, component)));
            else
              beyond_error = std::max(beyond_error,
                                      std::abs(new_field[indices[i]] - exact.value(Point<2>(2, p[1]), component)));
          }
      }
    for (const Point<2> &p : support)
      beyond += p[0] > 2 + 1e-12 ? 1 : 0;
    report("  1. the linear field exact at the new nodes inside (error < 1e-12)", inside_error < 1e-12);
    report("  2. nodes beyond x = 2 take the field at x = 2 (error < 1e-12)", beyond_error < 1e-12);
    report("     counted once per node: " + std::to_string(transfer.n_in_folds()) + " (" +
             std::to_string(beyond / 2) + " nodes beyond)",
           transfer.n_in_folds() == beyond / 2 && beyond / 2 == 4 * degree + 1);

    dealii::Vector<double> old_index(old_mesh.n_active_cells());
    for (unsigned int c = 0; c < old_index.size(); ++c)
      old_index[c] = c;
    const dealii::Vector<double> new_index = transfer.per_cell(old_index);
    bool                         holds     = true;
    for (const auto &cell : new_mesh.active_cell_iterators())
      {
        unsigned int holding = 0, holders = 0;
        for (const auto &old_cell : old_mesh.active_cell_iterators())
          if (old_cell->point_inside(cell->center()))
            {
              holding = old_cell->active_cell_index();
              ++holders;
            }
        holds = holds && holders == 1 && new_index[cell->active_cell_index()] == holding;
      }
    report("  3. each new cell takes the value of the one old cell holding its centre", holds);

    report("  4. a field of another size: empty nodal, zero cell field",
           transfer.nodal(dealii::Vector<double>(3)).size() == 0 &&
             transfer.per_cell(dealii::Vector<double>(3)).l2_norm() == 0 &&
             transfer.per_cell(dealii::Vector<double>(3)).size() == new_mesh.n_active_cells());
  }
} // namespace

int
main()
{
  check(1);
  check(2);
}
