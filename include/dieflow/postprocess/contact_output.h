// What the contact of a solution reports: forces and checks per die, die-wall profiles and surfaces, where the mesh needs refining.
#ifndef dieflow_contact_output_h
#define dieflow_contact_output_h

#include <dieflow/contact/contact_results.h>
#include <dieflow/contact/contact_set.h>
#include <dieflow/postprocess/summary.h>

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>

#include <set>
#include <string>
#include <vector>

namespace dieflow
{
  /**
   * The contact's part of a cycle's report, from the node results of a
   * converged velocity (ContactSet::results()): the normal and friction
   * forces and the separated / stick / slip lengths per die id, the node
   * counts, and the inequalities the state must keep, relative (velocities
   * over @p speed_scale, forces over the largest force or bound): largest
   * v.n > 0, pull, friction beyond its bound, friction that drives its slip,
   * sliding of a sticking node, reaction at a separated node.
   */
  template <int dim>
  void
  summarise_contact(const ContactSet<dim> &                    contact,
                    const std::vector<ContactNodeResult<dim>> &results,
                    const double                               speed_scale,
                    CycleSummary &                             summary);

  /**
   * Where the die needs a fine mesh: the corners (nodes with more than one
   * wall direction) and, in 2D, the nodes whose state differs from the
   * next node's along the wall (stick turning to slip, contact opening).
   */
  template <int dim>
  std::vector<dealii::Point<dim>>
  contact_hot_points(const ContactSet<dim> &contact, const std::vector<ContactNodeResult<dim>> &results);

  /**
   * One gnuplot-ready profile per die id (die-profile-ID.dat): arc length,
   * x, y, contact pressure and friction stress (the nodal forces over their
   * boundary weights), normal and slip velocity, status, and a recovered
   * pressure and shear. With @p vertex_stress (degree 1, vertex_stresses()):
   * the pressure recovered along the wall (pressures_along() in the
   * source), the shear t.sigma n of the stress at the node; without
   * (degree 2, whose nodal values do not zigzag): the raw values again.
   * With @p heat (Heat/Model not off): the metal's T at the node and the heat
   * flux density h (T - T_ambient) into the die there.
   * 3D: write_die_surfaces().
   */
  template <int dim>
  void
  write_die_profiles(const std::set<BoundaryId> &                        die_ids,
                     const std::vector<ContactNodeResult<dim>> &         results,
                     const std::vector<dealii::SymmetricTensor<2, dim>> *vertex_stress,
                     const HeatEquation<dim> *                           heat,
                     const std::string &                                 directory);

  /**
   * 3D: one table per die id of the contact nodes (die-surface-ID.dat):
   * position, contact pressure, friction stress vector, normal and slip
   * velocity, status; with @p heat the metal's T at the node and the heat
   * flux density into the die there; a die-surface field to plot or to map.
   */
  template <int dim>
  void
  write_die_surfaces(const std::set<BoundaryId> &               die_ids,
                     const std::vector<ContactNodeResult<dim>> &results,
                     const HeatEquation<dim> *                  heat,
                     const std::string &                        directory);
} // namespace dieflow

#endif
