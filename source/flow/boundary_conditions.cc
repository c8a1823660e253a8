// The deck's Boundary conditions subsection: which boundary part carries which condition, the loads, and the velocity's constraints.
#include <dieflow/flow/boundary_conditions.h>
#include <dieflow/base/expressions.h>

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>

#include <sstream>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/numerics/vector_tools.h>

namespace dieflow
{
  namespace
  {
    std::string
    velocity_subsection(const BoundaryId id)
    {
      return "Prescribed velocity " + std::to_string(id);
    }

    std::string
    default_velocity(const BoundaryId id, const unsigned int dim)
    {
      // The default deck is die2d: the ram pushes at 190 mm/s on id 1.
      std::string text = (id == 1) ? "190" : "0";
      for (unsigned int d = 1; d < dim; ++d)
        text += "; 0";
      return text;
    }
  } // namespace



  template <int dim>
  void
  BoundaryConditions<dim>::declare_parameters(ParameterHandler &          prm,
                                              const std::set<BoundaryId> &velocity_ids)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Boundary conditions");
    {
      prm.declare_entry("Prescribed velocity ids",
                        "1",
                        Anything(),
                        "Comma-separated boundary ids with a prescribed velocity; "
                        "each id N gets a subsection 'Prescribed velocity N'.");
      prm.declare_entry("Symmetry ids",
                        "5",
                        Anything(),
                        "Boundary ids of symmetry lines (planes): v.n = 0, no shear.");
      prm.declare_entry("Slip wall ids",
                        "",
                        Anything(),
                        "Boundary ids of fixed frictionless walls: v.n = 0, no "
                        "shear. For contact with friction and separation, list "
                        "the ids under Contact/Die ids instead.");
      prm.declare_entry("Traction free ids",
                        "2",
                        Anything(),
                        "Boundary ids with zero traction (sigma n = 0), such as a "
                        "free outlet.");
      prm.declare_entry("Traction ids",
                        "",
                        Anything(),
                        "Boundary ids with a prescribed traction sigma n = t (N/mm^2), "
                        "the expression 'Traction' (a back tension, an exact "
                        "solution's outlet).");
      prm.declare_entry("Traction",
                        dim == 2 ? "0; 0" : "0; 0; 0",
                        Anything(),
                        "The traction t = sigma n (n the outward normal; a tension "
                        "pulls outwards) on the Traction ids: one expression in "
                        "x, y[, z] per component, separated by ';'.");
      prm.declare_entry("Traction constants",
                        "",
                        Anything(),
                        "Constants for the traction expressions: 'a=1, b=2'.");
      prm.declare_entry("Wall corner angle",
                        "10",
                        Double(0, 90),
                        "Wall facets meeting at a node whose normals differ by "
                        "more than this angle (degrees) form a corner, where each "
                        "facet's v.n = 0 holds (so a 2D corner node is at rest); "
                        "below it, the normals are averaged (a curved wall).");
      prm.declare_entry("Body force",
                        dim == 2 ? "0; 0" : "0; 0; 0",
                        Anything(),
                        "Body force density f (N/mm^3) in eq. (1), one expression "
                        "in x, y[, z] per component, separated by ';'.");
      prm.declare_entry("Body force constants",
                        "",
                        Anything(),
                        "Constants for the body force expressions: 'a=1, b=2'.");

      for (const BoundaryId id : velocity_ids)
        {
          prm.enter_subsection(velocity_subsection(id));
          prm.declare_entry("Velocity",
                            default_velocity(id, dim),
                            Anything(),
                            "Prescribed velocity (mm/s) on this boundary id: one "
                            "expression in x, y[, z] per component, separated by ';'.");
          prm.declare_entry("Components",
                            dim == 2 ? "x, y" : "x, y, z",
                            MultipleSelection(dim == 2 ? "x|y" : "x|y|z"),
                            "Components that are prescribed; the others are free "
                            "(zero traction), e.g. 'y' for a frictionless moving "
                            "platen.");
          prm.declare_entry("Constants",
                            "",
                            Anything(),
                            "Constants for the expressions: 'a=1, b=2'.");
          prm.leave_subsection();
        }
    }
    prm.leave_subsection();
  }



  template <int dim>
  std::set<BoundaryId>
  BoundaryConditions<dim>::read_velocity_ids(ParameterHandler &prm)
  {
    prm.enter_subsection("Boundary conditions");
    const auto ids = parse_id_list("Boundary conditions/Prescribed velocity ids",
                                   prm.get("Prescribed velocity ids"));
    prm.leave_subsection();
    return ids;
  }



  template <int dim>
  void
  BoundaryConditions<dim>::parse_parameters(ParameterHandler &prm)
  {
    const std::string section = "Boundary conditions/";
    prm.enter_subsection("Boundary conditions");
    velocity_ids  = parse_id_list(section + "Prescribed velocity ids", prm.get("Prescribed velocity ids"));
    symmetry_ids  = parse_id_list(section + "Symmetry ids", prm.get("Symmetry ids"));
    slip_wall_ids = parse_id_list(section + "Slip wall ids", prm.get("Slip wall ids"));
    traction_free_ids = parse_id_list(section + "Traction free ids", prm.get("Traction free ids"));
    traction_ids      = parse_id_list(section + "Traction ids", prm.get("Traction ids"));
    traction          = parse_vector_expression<dim>(section + "Traction",
                                            prm.get("Traction"),
                                            prm.get("Traction constants"));
    corner_angle  = prm.get_double("Wall corner angle");

    body_force = parse_vector_expression<dim>(section + "Body force",
                                              prm.get("Body force"),
                                              prm.get("Body force constants"));
    has_body_force = false;
    for (const auto &component : dealii::Utilities::split_string_list(prm.get("Body force"), ';'))
      has_body_force |= (component != "0" && component != "0.0");

    for (const BoundaryId id : velocity_ids)
      {
        const std::string name = velocity_subsection(id);
        prm.enter_subsection(name);
        velocity[id] = parse_vector_expression<dim>(section + name + "/Velocity",
                                                    prm.get("Velocity"),
                                                    prm.get("Constants"));
        std::vector<bool> mask(dim, false);
        for (const auto &c : dealii::Utilities::split_string_list(prm.get("Components")))
          mask[c[0] - 'x'] = true;
        velocity_components[id] = dealii::ComponentMask(mask);
        require(velocity_components[id].n_selected_components() > 0,
                section + name + "/Components",
                "selects no component");
        prm.leave_subsection();
      }
    prm.leave_subsection();

    // One id, one kind.
    std::map<BoundaryId, std::string> seen;
    const auto                        check = [&](const std::set<BoundaryId> &ids, const std::string &entry) {
      for (const BoundaryId id : ids)
        {
          const auto [it, inserted] = seen.emplace(id, entry);
          require(inserted,
                  section + entry,
                  "boundary id " + std::to_string(id) + " is already listed under " +
                    it->second + "; a boundary part has one condition");
        }
    };
    check(velocity_ids, "Prescribed velocity ids");
    check(symmetry_ids, "Symmetry ids");
    check(slip_wall_ids, "Slip wall ids");
    check(traction_free_ids, "Traction free ids");
    check(traction_ids, "Traction ids");
  }



  template <int dim>
  void
  BoundaryConditions<dim>::make_prescribed_constraints(const DoFHandler<dim> &    dof_handler,
                                                       AffineConstraints<double> &constraints) const
  {
    constraints.clear();
    for (const auto &[id, function] : velocity)
      dealii::VectorTools::interpolate_boundary_values(dof_handler, id, *function, constraints, velocity_components.at(id));
    constraints.close();
  }



  template <int dim>
  std::set<BoundaryId>
  BoundaryConditions<dim>::wall_ids() const
  {
    std::set<BoundaryId> ids = symmetry_ids;
    ids.insert(slip_wall_ids.begin(), slip_wall_ids.end());
    return ids;
  }



  template <int dim>
  std::map<BoundaryId, std::string>
  BoundaryConditions<dim>::assigned_ids() const
  {
    std::map<BoundaryId, std::string> assigned;
    const auto add = [&](const std::set<BoundaryId> &ids, const std::string &entry) {
      for (const BoundaryId id : ids)
        assigned[id] = "Boundary conditions/" + entry;
    };
    add(velocity_ids, "Prescribed velocity ids");
    add(symmetry_ids, "Symmetry ids");
    add(slip_wall_ids, "Slip wall ids");
    add(traction_free_ids, "Traction free ids");
    add(traction_ids, "Traction ids");
    return assigned;
  }



  template <int dim>
  void
  BoundaryConditions<dim>::make_constraints(const DoFHandler<dim> &           dof_handler,
                                            const AffineConstraints<double> & hanging_node_constraints,
                                            const std::vector<WallNode<dim>> &wall_nodes,
                                            const bool                        homogeneous,
                                            AffineConstraints<double> &       constraints) const
  {
    constraints.clear();
    constraints.merge(hanging_node_constraints);

    // interpolate_boundary_values() leaves dofs that are already constrained
    // (hanging nodes) alone.
    const dealii::Functions::ZeroFunction<dim> zero(dim);
    for (const auto &[id, function] : velocity)
      dealii::VectorTools::interpolate_boundary_values(dof_handler,
                                                       id,
                                                       homogeneous ? static_cast<const dealii::Function<dim> &>(zero) :
                                                                     *function,
                                                       constraints,
                                                       velocity_components.at(id));

    const std::set<BoundaryId> walls = wall_ids();
    for (const auto &node : wall_nodes)
      {
        std::vector<Tensor<1, dim>> normals;
        for (const auto &direction : node.directions)
          if (walls.count(direction.id))
            normals.push_back(direction.normal);
        if (!normals.empty())
          constrain_normal_components<dim>(node.dofs,
                                           normals,
                                           std::vector<double>(normals.size(), 0.),
                                           constraints);
      }
  }



  template <int dim>
  void
  BoundaryConditions<dim>::check_prescribed_fluxes(const dealii::Triangulation<dim> &triangulation,
                                                   const bool                        walls_can_open) const
  {
    if (!traction_free_ids.empty() || !traction_ids.empty() || walls_can_open)
      return;
    const dealii::FE_Q<dim>   geometry(1);
    dealii::FEFaceValues<dim> face_values(geometry,
                                          dealii::QGauss<dim - 1>(3),
                                          dealii::update_quadrature_points | dealii::update_normal_vectors |
                                            dealii::update_JxW_values);
    double                    inflow = 0, outflow = 0;
    dealii::Vector<double>    value(dim);
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() && velocity.count(cell->face(f)->boundary_id()))
          {
            const BoundaryId id   = cell->face(f)->boundary_id();
            const auto &     mask = velocity_components.at(id);
            face_values.reinit(cell, f);
            for (const unsigned int q : face_values.quadrature_point_indices())
              {
                const Tensor<1, dim> normal = face_values.normal_vector(q);
                for (unsigned int d = 0; d < dim; ++d)
                  if (!mask[d] && std::abs(normal[d]) > 1e-8)
                    return; // the normal velocity is free here: nothing to check
                velocity.at(id)->vector_value(face_values.quadrature_point(q), value);
                double vn = 0;
                for (unsigned int d = 0; d < dim; ++d)
                  vn += value[d] * normal[d];
                (vn > 0 ? outflow : inflow) += std::abs(vn) * face_values.JxW(q);
              }
          }
    std::ostringstream message;
    message << "the prescribed velocities carry " << inflow << " in and " << outflow
            << " out (volume per unit time), but with no traction-free part the "
               "incompressible metal cannot change volume; make them balance or "
               "list the outlet under Traction free ids";
    require(std::abs(inflow - outflow) <= 1e-6 * std::max(inflow + outflow, 1e-300) || inflow + outflow == 0,
            "Boundary conditions/Prescribed velocity ids",
            message.str());
  }



  template <int dim>
  double
  BoundaryConditions<dim>::largest_prescribed_speed(const DoFHandler<dim> &dof_handler) const
  {
    double                 speed = 0;
    dealii::Vector<double> value(dim);
    for (const auto &face : dof_handler.get_triangulation().active_face_iterators())
      if (face->at_boundary() && velocity.count(face->boundary_id()))
        for (const unsigned int v : face->vertex_indices())
          {
            velocity.at(face->boundary_id())->vector_value(face->vertex(v), value);
            speed = std::max(speed, value.l2_norm());
          }
    return speed;
  }

  template class BoundaryConditions<2>;
  template class BoundaryConditions<3>;
} // namespace dieflow
