// Moving a mesh's vertices, and the volume and shape of its cells.
#ifndef dieflow_mesh_motion_h
#define dieflow_mesh_motion_h

#include <dieflow/mesh/coordinate_system.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <array>

namespace dieflow
{
  /**
   * Adds the vertex values of @p displacement (a dof vector of the
   * velocity's vector element) to the triangulation's vertices, each once.
   * A hanging vertex then goes to the mean of its parent edge's (face's)
   * vertices: the geometry is MappingQ1's, and a degree-2 field's value at a
   * hanging vertex would take it off its coarse neighbour's straight edge.
   */
  template <int dim>
  void
  move_vertices(const dealii::DoFHandler<dim> &dof_handler,
                const dealii::Vector<double> & displacement,
                dealii::Triangulation<dim> &   triangulation);

  /// Puts every hanging vertex at the mean of its parent edge's (face's)
  /// vertices, after the others moved (move_vertices(), a free surface's move).
  template <int dim>
  void
  place_hanging_vertices(dealii::Triangulation<dim> &triangulation);

  /// The volume of the mesh (plane strain: area per mm of depth; axisymmetric: 2 pi int y).
  template <int dim>
  double
  domain_volume(const CoordinateSystem<dim> &coordinates, const dealii::Triangulation<dim> &triangulation);

  /// Each active cell's volume, as domain_volume() counts it.
  template <int dim>
  dealii::Vector<double>
  cell_volumes(const CoordinateSystem<dim> &coordinates, const dealii::Triangulation<dim> &triangulation);

  /**
   * The smallest scaled Jacobian of the mesh: at every vertex of every cell,
   * det(e_1, ..., e_dim) / (|e_1| ... |e_dim|) with e_d the cell's edges
   * from that vertex (the sine of the corner angle in 2D). 1 for
   * rectangles, 0 for a degenerate corner, negative for an inverted cell.
   */
  template <int dim>
  double
  smallest_scaled_jacobian(const dealii::Triangulation<dim> &triangulation);

  /// The centre of a cell of smallest scaled Jacobian (where a mesh went bad: the log's).
  template <int dim>
  dealii::Point<dim>
  worst_cell_centre(const dealii::Triangulation<dim> &triangulation);

  /// The same for one cell: the smallest over its vertices.
  template <int dim>
  double
  scaled_jacobian(const typename dealii::Triangulation<dim>::cell_iterator &cell);

  /// The same for a cell given by its vertices in lexicographic order.
  template <int dim>
  double
  scaled_jacobian(const std::array<dealii::Point<dim>, (1u << dim)> &vertices);
} // namespace dieflow

#endif
