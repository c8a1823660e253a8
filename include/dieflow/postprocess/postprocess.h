// What a solution gives: the boundary parts' fluxes, areas and forces, errors against an exact velocity, and the fields written to files.
#ifndef dieflow_postprocess_h
#define dieflow_postprocess_h

#include <dieflow/flow/boundary_conditions.h>
#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/flow/material.h>
#include <dieflow/mesh/wall_nodes.h>

#include <deal.II/base/function.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace dieflow
{
  using dealii::Vector;

  /// Integral of v.n over each boundary part (all ids of the mesh).
  template <int dim>
  std::map<BoundaryId, double>
  boundary_fluxes(const CoordinateSystem<dim> &coordinates, const DoFHandler<dim> &dof_handler, const Vector<double> &velocity);

  /// A wall's share w_W t_W of the reaction at a node it shares with a
  /// prescribed-velocity part (see boundary_forces()).
  /// The area of each boundary part: int ds (mm per mm of depth in plane
  /// strain), or int 2 pi r ds (mm^2) in the axisymmetric geometry.
  template <int dim>
  std::map<BoundaryId, double>
  boundary_areas(const CoordinateSystem<dim> &coordinates, const DoFHandler<dim> &dof_handler);

  template <int dim>
  struct WallShare
  {
    BoundaryId     id;
    /// The wall's unit normal at the node.
    Tensor<1, dim> normal;
    Tensor<1, dim> force;
  };

  /**
   * Integral of the traction sigma n over each boundary part, from the
   * reaction forces: the unconstrained residual R_i = int sigma(v):grad phi_i
   * - f.phi_i is, at a boundary node, int_Gamma (sigma n).phi_i ds, so summing
   * it over a part's nodes gives the part's force exactly for the discrete
   * solution (and more accurately than integrating the Q1 stress, which is
   * one order lower). The parts' forces sum to minus the body force, a
   * conservation check. A node shared by several parts: traction-free and
   * prescribed-traction parts carry what is prescribed (int t ds); where a
   * prescribed-velocity part meets walls, each wall takes w_W t_W, its own
   * traction extrapolated along the wall from its nearest degree + 1 nodes
   * (t = R/w at each node's moment point) times the node's weight on the
   * wall, and the prescribed part the rest, so each part's force converges
   * at the rate of the discretisation (taking the whole reaction made an
   * O(h) error); between walls the reaction is split along the walls'
   * normals. The share of a wall in @p frictionless_ids (symmetry lines,
   * slip walls, dies without friction) is normal to it. The walls' shares
   * at the split nodes go to @p wall_shares (if given): a die's normal and
   * friction forces include them.
   */
  template <int dim>
  std::map<BoundaryId, std::vector<double>>
  boundary_forces(const CoordinateSystem<dim> &     coordinates,
                  const DoFHandler<dim> &           dof_handler,
                  const Vector<double> &            reactions,
                  const BoundaryConditions<dim> &   boundary_conditions,
                  const std::vector<WallNode<dim>> &wall_nodes,
                  const std::set<BoundaryId> &      frictionless_ids = {},
                  std::vector<WallShare<dim>> *     wall_shares      = nullptr);

  /// L2 norm of v - v_exact and of grad (v - v_exact) (3x3 Gauss points).
  template <int dim>
  std::pair<double, double>
  velocity_errors(const DoFHandler<dim> &        dof_handler,
                  const Vector<double> &         velocity,
                  const dealii::Function<dim> &  exact);

  /**
   * Writes velocity, pressure (the cell mean of the pressure given as
   * cell_pressure() coefficients, and the area-weighted average of the
   * cells' values at each vertex, which filters the checkerboard mode of
   * Q1-P0), equivalent strain rate and stress, and viscosity as
   * VTU (appended to @p pvd_records at @p record_time: the cycle, or the
   * time of an incremental step; write_pvd() writes the index) and/or
   * gnuplot; @p nodal_fields
   * per vertex, @p cell_fields per active cell (the equivalent strain).
   */
  template <int dim>
  void
  write_fields(const CoordinateSystem<dim> &                          coordinates,
            const DoFHandler<dim> &                               dof_handler,
            const Vector<double> &                                velocity,
            const Material &                                      material,
            const Vector<double> &                                pressure,
            const std::map<std::string, Vector<double>> &        nodal_fields,
            const std::map<std::string, Vector<double>> &        cell_fields,
            const std::string &                                   directory,
            const unsigned int                                    cycle,
            const double                                          record_time,
            const bool                                            vtu,
            const bool                                            gnuplot,
            std::vector<std::pair<double, std::string>> &         pvd_records);

  /**
   * The run's ParaView index @p directory/solution.pvd of @p records (time,
   * file): the files of one time are its parts, in order (part 0 the
   * fields' VTU, part 1 the steady free surface's polyline), so that
   * ParaView opens them together as one block each.
   */
  void
  write_pvd(const std::vector<std::pair<double, std::string>> &records, const std::string &directory);
} // namespace dieflow

#endif
