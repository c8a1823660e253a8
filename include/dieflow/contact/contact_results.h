// What the contact reports of a solution: node by node, and node counts by state.
#ifndef dieflow_contact_results_h
#define dieflow_contact_results_h

#include <dieflow/base/parameters.h>
#include <dieflow/contact/contact_element.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

namespace dieflow
{
  using dealii::Tensor;

  /// Node-wise results for the die-wall profiles and the checks.
  template <int dim>
  struct ContactNodeResult
  {
    dealii::Point<dim> position;
    /// The triangulation's vertex (invalid at a degree-2 edge midpoint).
    unsigned int       vertex;
    BoundaryId         id;
    Tensor<1, dim>     normal;
    /// t (2D: the direction of the signed profile values; 3D: t_1).
    Tensor<1, dim>     tangent;
    /// The node's boundary weight (int phi dA) and its share of the wall's arc length (int phi ds).
    double             weight, length;
    ContactStatus      status;
    /// F_n (<= 0 pressing), a nodal force, and v.n.
    double normal_force, normal_rate;
    /// The friction force (nodal, in the tangent plane) and the slip velocity.
    Tensor<1, dim> friction_force, slip_velocity;
    /// The normal reaction where separated (must vanish at equilibrium).
    double free_reaction;
    double friction_bound;
    /// Whether friction_force is the law's value on or below its bound by
    /// construction (a slipping node's mu |F_n| outside the 3D semismooth
    /// method, the regularised law): the friction check skips it, since
    /// only a reaction (exact stick), the stick penalty or the semismooth
    /// force can leave the cone.
    bool friction_from_law = false;
  };

  /// Node counts of the contact state.
  struct ContactCounts
  {
    unsigned int separated = 0;
    unsigned int stick     = 0;
    unsigned int slip      = 0;
  };
} // namespace dieflow

#endif
