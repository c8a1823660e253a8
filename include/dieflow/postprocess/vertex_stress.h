// The stress and the pressure at every vertex: the values of the cells around it, averaged with the cells' areas as weights.
#ifndef dieflow_vertex_stress_h
#define dieflow_vertex_stress_h

#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/flow/material.h>

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace dieflow
{
  using dealii::DoFHandler;
  using dealii::SymmetricTensor;
  using dealii::Vector;

  /**
   * The stress sigma = 2 eta(epsdot_eq) D(v) - p I (paper, eqs. (2) and
   * (8); p from the cell's pressure coefficients as cell_pressure() gives
   * them) at every vertex: each cell's value at the vertex, averaged over
   * the cells around it with the cells' areas as weights.
   *
   * With @p vertex_temperature the law at each vertex's T; with
   * @p cell_hardening (per active cell) the viscosity times the cell's
   * hardening factor.
   *
   * What it is for: the shear t.sigma n of degree-1 die profiles. The
   * nodal reaction of a node that sticks zigzags from node to node, sign
   * changes included, with the Q1-P0 pressure's alternating mode, which
   * the average over the cells around a wall node cancels (measured in
   * doc/contact.md). Not for the wall pressure: at a wall the cell-constant
   * pressures are one-sided, an O(h) bias where the pressure varies
   * across the wall (as in a Couette layer whose weight makes p linear in
   * y; doc/benchmarks.md); the profiles recover that along the wall.
   */
  template <int dim>
  std::vector<SymmetricTensor<2, dim>>
  vertex_stresses(const CoordinateSystem<dim> &coordinates,
                  const DoFHandler<dim> &dof_handler,
                  const Vector<double> & velocity,
                  const Material &       material,
                  const Vector<double> & cell_pressure,
                  const std::vector<double> *vertex_temperature = nullptr,
                  const Vector<double> *     cell_hardening     = nullptr);

  /// The pressure alone, averaged the same way, per vertex (for the
  /// fields written to VTU).
  template <int dim>
  std::vector<double>
  vertex_pressures(const DoFHandler<dim> &dof_handler, const Vector<double> &cell_pressure);
} // namespace dieflow

#endif
