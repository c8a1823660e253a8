// The nodes on the walls: their dofs, facet normals and weights, the constraints v.n = g there, and a reaction's components along the normals.
#ifndef dieflow_wall_nodes_h
#define dieflow_wall_nodes_h

#include <dieflow/base/parameters.h>

#include <dieflow/mesh/coordinate_system.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/affine_constraints.h>

#include <array>
#include <set>
#include <vector>

namespace dieflow
{
  using dealii::AffineConstraints;
  using dealii::DoFHandler;
  using dealii::Tensor;
  using GlobalDof = dealii::types::global_dof_index;

  /**
   * One facet direction at a wall node: the outward unit normal of the wall
   * facets that share it, their boundary id, and the lumped boundary weight
   * w = integral of the node's basis function over those facets (with the
   * geometry's measure: 2 pi r ds in the axisymmetric one), and its length
   * (the same integral over ds: the node's share of the wall's arc
   * length, its mesh size; equal to w in plane strain).
   */
  template <int dim>
  struct WallDirection
  {
    Tensor<1, dim> normal;
    BoundaryId     id;
    double         weight;
    double         length;
    /// The vertices of one wall facet with this normal at the node: the
    /// master segment (facet) of the node's contact element.
    std::array<dealii::Point<dim>, dim> facet;
    /// A node of the free surface approaching a die (Problem = incremental):
    /// g / dt, the normal velocity relative to the die at which it reaches
    /// the die's plane at the end of the step (0 for a node on the die).
    double gap_rate = 0;
  };

  /// Outward unit normal of a straight (planar) boundary face of @p cell.
  template <int dim, typename CellIterator>
  Tensor<1, dim>
  outward_unit_normal(const CellIterator &cell, const unsigned int face_no)
  {
    const auto     face = cell->face(face_no);
    Tensor<1, dim> n;
    if constexpr (dim == 2)
      {
        const Tensor<1, dim> t = face->vertex(1) - face->vertex(0);
        n[0]                   = t[1];
        n[1]                   = -t[0];
      }
    else
      n = dealii::cross_product_3d(face->vertex(3) - face->vertex(0), face->vertex(2) - face->vertex(1));
    if (n * (face->center() - cell->center()) < 0)
      n *= -1;
    return n / n.norm();
  }

  /**
   * A node of a boundary face as the velocity element sees it: a vertex,
   * or for degree 2 also an edge midpoint; its velocity dofs, position, the
   * integral of its basis function over the face (positive for Q1 and Q2:
   * h/2; h/6 at the vertices and 2h/3 at the midpoint), and the vertex
   * index of the triangulation (invalid for a midpoint).
   */
  template <int dim>
  struct FaceNode
  {
    std::array<GlobalDof, dim> dofs;
    dealii::Point<dim>         position;
    double                     weight;
    /// int phi ds over the face, without the geometry's factor.
    double                     length;
    /// int x phi ds over the face: moment / weight is where a nodal
    /// reaction over the weight samples the traction.
    Tensor<1, dim>             moment;
    unsigned int               vertex;
  };

  /**
   * The nodes of face @p face_no of @p cell, with weights and moments from
   * @p face_values (the cell's FE with QGauss(degree + 1), values, JxW and
   * quadrature points; reinit'ed here). The weight and moment carry the
   * geometry's measure: int phi 2 pi r ds in the axisymmetric one.
   */
  template <int dim>
  std::vector<FaceNode<dim>>
  face_nodes(const CoordinateSystem<dim> &                             coordinates,
             const typename DoFHandler<dim>::active_cell_iterator &cell,
             const unsigned int                                    face_no,
             dealii::FEFaceValues<dim> &                           face_values);

  /**
   * A node on the walls (slip walls, symmetry lines, die contact parts):
   * its velocity dofs and the distinct facet normals that meet there.
   *
   * Facets whose normals differ by less than the corner angle are one
   * direction (their weighted mean normal): a straight or gently curved wall.
   * Two or more directions make a corner. The kinematic rule at a corner is
   * one condition per direction, v.n_k = 0 (or <= 0 for contact), so a node
   * where two walls of a 2D corner both hold is at rest: exact at the convex
   * corners of the metal (the die entry C) and the limit of the continuous
   * solution at re-entrant ones (the die exit D), where a continuous velocity
   * tangent to both walls vanishes.
   */
  template <int dim>
  struct WallNode
  {
    std::array<GlobalDof, dim>        dofs;
    dealii::Point<dim>                position;
    /// The vertex of the triangulation, or invalid_unsigned_int (an edge node).
    unsigned int                      vertex;
    std::vector<WallDirection<dim>>   directions;
  };

  /**
   * Collects the wall nodes on the faces with the given boundary ids (every
   * node of the velocity element: for degree 2 the edge midpoints too).
   * Hanging nodes (constrained in @p hanging_node_constraints) are not
   * nodes: their weights go to the nodes they hang from.
   */
  template <int dim>
  std::vector<WallNode<dim>>
  collect_wall_nodes(const CoordinateSystem<dim> &      coordinates,
                     const DoFHandler<dim> &            dof_handler,
                     const std::set<BoundaryId> &       ids,
                     const AffineConstraints<double> &  hanging_node_constraints,
                     const double                       corner_angle_degrees);

  /**
   * Adds the constraints n_k . v = g_k for the given directions of one node
   * (k = 0..normals.size()-1), solved for the velocity components that no
   * other constraint holds yet (Gauss-Jordan with pivoting, so no line refers
   * to another). Components already constrained (a prescribed velocity, a
   * hanging node) stay as they are and enter as known terms.
   */
  template <int dim>
  void
  constrain_normal_components(const std::array<GlobalDof, dim> &      dofs,
                              const std::vector<Tensor<1, dim>> &     normals,
                              const std::vector<double> &             values,
                              AffineConstraints<double> &             constraints);

  /**
   * The components a_k of a node's reaction R along the normals n_k of the
   * walls that hold it: R = sum_k a_k n_k + a rest normal to all of them
   * (friction), a the least-squares solution of least norm. Up to dim
   * independent normals (a wall, a 2D corner, a 3D edge, a 3D corner of
   * three planes) it is unique; where more walls meet than there are
   * dimensions (a 3D die edge through the die entry: two container walls
   * and two die faces) the split is statically indeterminate, and the
   * least-norm one shares the reaction among the walls that can carry it.
   */
  template <int dim>
  std::vector<double>
  normal_components(const std::vector<Tensor<1, dim>> &normals, const Tensor<1, dim> &reaction);

} // namespace dieflow

#endif
