// The deck's Boundary conditions subsection: which boundary part carries which condition, the loads, and the velocity's constraints.
#ifndef dieflow_boundary_conditions_h
#define dieflow_boundary_conditions_h

#include <dieflow/base/parameters.h>
#include <dieflow/mesh/wall_nodes.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/fe/component_mask.h>

#include <map>
#include <memory>
#include <set>
#include <string>

namespace dieflow
{
  /**
   * The deck's "Boundary conditions" subsection: which boundary part (id)
   * carries which condition, and the loads.
   *  - prescribed velocity: v = g(x) on the listed components (eqs. (4), (5));
   *  - symmetry and slip wall: v.n = 0, zero tangential traction (a fixed,
   *    frictionless rigid wall and a symmetry line are the same kinematics);
   *  - traction free: sigma n = 0 (natural, nothing to do);
   *  - prescribed traction: sigma n = t, the load -int t.w ds in the residual;
   *  - die contact ids belong to the Contact subsection.
   * A node shared by a prescribed-velocity part and a wall keeps the
   * prescribed velocity on the prescribed components; hanging nodes keep
   * their hanging-node constraints.
   */
  template <int dim>
  class BoundaryConditions
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm, const std::set<BoundaryId> &velocity_ids);
    /// The ids of the parts with a prescribed velocity (needed to declare
    /// their subsections in the second reading of the deck).
    static std::set<BoundaryId>
    read_velocity_ids(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * The constraints of the velocity for the given hanging-node constraints
     * and wall nodes (on the symmetry and slip-wall ids): the prescribed
     * values, or zero values for Newton updates when @p homogeneous.
     * Not closed: the caller adds contact constraints and closes.
     */
    void
    make_constraints(const DoFHandler<dim> &           dof_handler,
                     const AffineConstraints<double> & hanging_node_constraints,
                     const std::vector<WallNode<dim>> &wall_nodes,
                     const bool                        homogeneous,
                     AffineConstraints<double> &       constraints) const;

    /// The prescribed velocities alone (which nodes they hold).
    void
    make_prescribed_constraints(const DoFHandler<dim> &dof_handler, AffineConstraints<double> &constraints) const;

    /// Ids with v.n = 0 (symmetry and slip walls).
    std::set<BoundaryId>
    wall_ids() const;

    /// Every id the subsection names, with the entry that names it.
    std::map<BoundaryId, std::string>
    assigned_ids() const;

    /**
     * With no traction-free part, incompressibility demands that the
     * prescribed velocities carry as much in as out: throws InputError
     * otherwise (skipped where a prescribed part leaves its normal component
     * free, or when @p walls_can_open, i.e. die contact may separate).
     */
    void
    check_prescribed_fluxes(const dealii::Triangulation<dim> &triangulation, const bool walls_can_open) const;

    /// Largest prescribed speed, sampled at the given boundary points.
    double
    largest_prescribed_speed(const DoFHandler<dim> &dof_handler) const;

    std::set<BoundaryId>                                         velocity_ids;
    std::set<BoundaryId>                                         symmetry_ids;
    std::set<BoundaryId>                                         slip_wall_ids;
    std::set<BoundaryId>                                         traction_free_ids;
    /// Parts with the prescribed traction 'traction' (sigma n = t).
    std::set<BoundaryId>                                         traction_ids;
    std::unique_ptr<dealii::FunctionParser<dim>>                 traction;
    std::map<BoundaryId, std::unique_ptr<dealii::FunctionParser<dim>>> velocity;
    std::map<BoundaryId, dealii::ComponentMask>                  velocity_components;
    std::unique_ptr<dealii::FunctionParser<dim>>                 body_force;
    bool                                                         has_body_force = false;
    double                                                       corner_angle   = 10;
  };
} // namespace dieflow

#endif
