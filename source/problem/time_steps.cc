// The die-flow problem's steps in time: the mesh moved with the metal, meshed anew where cells degrade, the free surface coming onto the dies, the load-stroke table.
#include <dieflow/base/atomic_file.h>
#include <dieflow/incremental/mesh_transfer.h>
#include <dieflow/incremental/remeshing.h>
#include <dieflow/mesh/mesh_motion.h>
#include <dieflow/problem/problem.h>

#include <cmath>
#include <iomanip>
#include <sstream>

namespace dieflow
{
  template <int dim>
  void
  DieFlowProblem<dim>::advance_configuration(const unsigned int n)
  {
    if (parameters.heat.model == HeatParameters::Model::transient)
      step_heat(n);
    dealii::TimerOutput::Scope scope(timer, "mesh motion");
    const auto [a, b]           = incremental.move_weights(n, dof_handler.n_dofs());
    Vector<double> displacement = velocity;
    displacement *= a;
    if (b != 0)
      displacement.add(b, incremental.previous_velocity);
    incremental.advance_strain(a, b, dof_handler, velocity);

    const std::vector<dealii::Point<dim>> old_vertices = triangulation.get_vertices();
    std::vector<bool>                     in_contact(triangulation.n_vertices(), false);
    if (!contact.empty())
      {
        const auto status = contact.vertex_status(dof_handler);
        for (unsigned int i = 0; i < status.size(); ++i)
          in_contact[i] = status[i] > static_cast<double>(ContactStatus::separated);
        // Put back only where every die direction holds the node: a corner
        // of the metal that leaves one wall of a die corner (past the exit
        // D, along the die face) is not to be pulled onto the other wall
        // (the land), which would cut the corner through the die.
        for (const auto &r : contact.results(velocity))
          if (r.vertex != dealii::numbers::invalid_unsigned_int && r.status == ContactStatus::separated)
            in_contact[r.vertex] = false;
      }
    move_vertices(dof_handler, displacement, triangulation);
    incremental.fixed_walls.keep(triangulation);
    const double dt = parameters.time_stepping.time(n + 1) - parameters.time_stepping.time(n);
    for (const auto &[id, components] : parameters.contact.die_velocities)
      {
        const Tensor<1, dim> shift = dt * contact.velocity_of(id);
        if (die_surfaces.count(id))
          die_surfaces.at(id).translate(shift);
        incremental.gaps.translate(id, shift);
      }
    incremental.last_gap_update =
      incremental.gaps.update(old_vertices,
                              in_contact,
                              triangulation,
                              std::cos(parameters.boundary_conditions.corner_angle * dealii::numbers::PI / 180.));
  }



  template <int dim>
  void
  DieFlowProblem<dim>::remesh(const unsigned int n, const double jacobian_before)
  {
    dealii::TimerOutput::Scope scope(timer, "remeshing");
    RemeshRecord               record;
    record.step                   = n;
    record.cells_before           = triangulation.n_active_cells();
    record.jacobian_before        = jacobian_before;
    const double     volume_before = domain_volume(parameters.coordinates, triangulation);
    const Point<dim> worst_before  = worst_cell_centre(triangulation);
    dealii::Triangulation<dim> fresh;
    // A die face's edge that cuts a die's corner (from the die face to the
    // land past the exit D) lies in the die: pieces of it would be nodes in
    // the die. Such an edge (its midpoint beyond the die's surface, seen
    // from the metal: a, b go round the domain counter-clockwise) stays
    // whole; dies given as a surface.
    const EdgeFilter<dim> edge_out_of_its_die = [this](const Point<dim> &a, const Point<dim> &b, const BoundaryId id) {
      const auto die = die_surfaces.find(id);
      if constexpr (dim == 2)
        if (die != die_surfaces.end())
          {
            const double         tolerance = 1e-6 * die->second.diameter();
            const Point<dim>     middle    = 0.5 * (a + b);
            const Tensor<1, dim> outward({b[1] - a[1], a[0] - b[0]});
            if (const auto on = die->second.project(middle, a.distance(b), tolerance))
              return (middle - on->point) * (on->facet.normal * outward > 0 ? on->facet.normal : -on->facet.normal) <=
                     tolerance;
          }
      return true;
    };
    const NewMesh new_mesh = remesh_domain(triangulation,
                                           fresh,
                                           parameters.remeshing.boundary_edge_length,
                                           edge_out_of_its_die,
                                           "Incremental/Remesh below Jacobian");

    // The velocity (the next solve's first iterate) and the strain go over
    // to the new mesh: fields on the moved mesh, so the value at a new node
    // is that of the material point there, as the Lagrangian move needs.
    dealii::DoFHandler<dim> fresh_dofs(fresh);
    fresh_dofs.distribute_dofs(fe);
    const MeshTransfer<dim> transfer(dof_handler, fresh_dofs, "before step " + std::to_string(n));
    const Vector<double>    fresh_velocity = transfer.nodal(velocity);
    Vector<double>          fresh_previous_velocity = transfer.nodal(incremental.previous_velocity);
    Vector<double>          fresh_strain            = transfer.per_cell(incremental.equivalent_strain);
    Vector<double>          fresh_previous_rate     = transfer.per_cell(incremental.previous_strain_rate);
    const double            ram_displacement        = incremental.ram_displacement(triangulation);
    // T goes over as the velocity does (nodal), its heat content measured on both meshes.
    const bool             heat_in_time = parameters.heat.model == HeatParameters::Model::transient;
    const auto             heat_before  = heat_in_time ? heat.integrals() : typename HeatEquation<dim>::Integrals();
    dealii::Vector<double> fresh_temperature;
    double                 interpolated = 0, shift = 0;
    if (heat_in_time)
      fresh_temperature = heat.on_new_mesh(fresh, "before step " + std::to_string(n));

    // The same cells in the same order: distribute_dofs() numbers the copy
    // as it numbered fresh_dofs.
    triangulation.clear();
    triangulation.copy_triangulation(fresh);
    dof_handler.reinit(triangulation);
    dof_handler.distribute_dofs(fe);
    velocity = fresh_velocity;
    incompressibility.carry(Vector<double>());
    if (heat_in_time)
      {
        heat.take_new_mesh(std::move(fresh_temperature));
        auto after   = heat.integrals();
        interpolated = after.content / heat_before.content - 1;
        // The heat content per volume kept: metal the new boundary leaves out (or takes in) carries its share.
        if (parameters.heat.conservative_transfer)
          {
            shift = heat.restore_content(heat_before.content * after.volume / heat_before.volume);
            after = heat.integrals();
          }
        record.heat_content_change     = after.content / heat_before.content - 1;
        record.mean_temperature_change = after.temperature / after.volume - heat_before.temperature / heat_before.volume;
      }

    record.cells_after      = triangulation.n_active_cells();
    record.jacobian_after   = smallest_scaled_jacobian(triangulation);
    record.volume_change    = domain_volume(parameters.coordinates, triangulation) / volume_before - 1;
    record.split_edges      = new_mesh.split_edges;
    record.dropped_vertices = new_mesh.dropped_vertices;
    incremental.new_mesh(ram_displacement,
                         triangulation,
                         parameters.goal_part(),
                         parameters.boundary_conditions.wall_ids(),
                         new_mesh.boundary_face_of_old,
                         std::move(fresh_previous_velocity),
                         std::move(fresh_strain),
                         std::move(fresh_previous_rate),
                         record);
    log << "  new mesh before step " << n << " (t = " << std::setprecision(6) << parameters.time_stepping.time(n)
        << " s): smallest scaled Jacobian " << std::setprecision(3) << record.jacobian_before << " (the cell at "
        << worst_before << ") -> " << record.jacobian_after << ", " << record.cells_before << " -> "
        << record.cells_after << " cells, volume change " << std::setprecision(2) << record.volume_change
        << std::setprecision(6);
    if (record.dropped_vertices > 0)
      log << ", " << record.dropped_vertices << " crowding boundary vertices dropped";
    if (heat_in_time)
      log << ", heat content change " << record.heat_content_change << " (mean T " << std::showpos
          << record.mean_temperature_change << std::noshowpos << " K"
          << (parameters.heat.conservative_transfer ? ", the interpolation's " + deck_number(interpolated) +
                                                        " undone by a uniform shift of " + deck_number(shift) + " K)" :
                                                      std::string(")"));
    if (!new_mesh.attempt.empty())
      log << ", Gmsh's first attempt failed, made with " << new_mesh.attempt;
    if (transfer.n_in_folds() > 0)
      log << ", " << transfer.n_in_folds() << " new nodes or cell centres in folded cells (the nearest cell's values)";
    log << std::endl;
  }



  template <int dim>
  std::vector<WallNode<dim>>
  DieFlowProblem<dim>::approaching_nodes() const
  {
    const auto [reach, gap_rate] = gap_closing();
    if (reach < 0)
      return {};
    const auto &bc = parameters.boundary_conditions;
    // Nodes of a die face are the die's already; one on a symmetry plane or
    // slip wall keeps that wall (ContactSet: a fixed normal).
    std::set<GlobalDof>                        on_die;
    std::map<GlobalDof, const WallNode<dim> *> on_wall;
    for (const auto &node : wall_nodes)
      {
        on_wall[node.dofs[0]] = &node;
        for (const auto &wall : node.directions)
          if (parameters.contact.die_ids.count(wall.id))
            on_die.insert(node.dofs[0]);
      }
    std::vector<WallNode<dim>> free_nodes;
    for (auto &node : collect_wall_nodes(
           parameters.coordinates, dof_handler, bc.traction_free_ids, hanging_node_constraints, bc.corner_angle))
      if (!on_die.count(node.dofs[0]))
        free_nodes.push_back(std::move(node));
    std::vector<WallNode<dim>> approaching = incremental.gaps.approaching(free_nodes, reach, gap_rate);
    for (auto &node : approaching)
      if (const auto wall = on_wall.find(node.dofs[0]); wall != on_wall.end())
        node.directions.insert(node.directions.end(), wall->second->directions.begin(), wall->second->directions.end());
    return approaching;
  }



  template <int dim>
  std::pair<double, typename ContactGaps<dim>::GapRate>
  DieFlowProblem<dim>::gap_closing() const
  {
    const TimeStepping &time_stepping = parameters.time_stepping;
    const unsigned int  n             = incremental.current_step;
    if (!time_stepping.incremental || !time_stepping.contact_within_step || incremental.gaps.empty() ||
        n >= time_stepping.n_steps())
      return {-1., {}};
    const double dt = time_stepping.time(n + 1) - time_stepping.time(n);
    // Reach: twice the largest travel of the step (the previous step's
    // speed, the dies'); a node farther off cannot arrive, and the after-
    // the-move rule of ContactGaps::update() still catches one that does.
    const bool have_velocity = velocity.size() == dof_handler.n_dofs();
    double     speed         = have_velocity ? velocity.linfty_norm() : 0.;
    for (const auto &[id, components] : parameters.contact.die_velocities)
      speed = std::max(speed, contact.velocity_of(id).norm());
    // The move will be x += a v_n + b v_{n-1} (advance_configuration()): the
    // node lands on the die where a (v_n - V).n + b (v_{n-1} - V).n = g,
    // i.e. (v_n - V).n = (g - b (v_{n-1} - V).n) / a (a + b = dt).
    const auto [a, b]   = incremental.move_weights(n, dof_handler.n_dofs());
    const auto gap_rate = [this, a = a, b = b](const WallNode<dim> &node, const WallDirection<dim> &direction, const double gap) {
      double previous_rate = 0;
      if (b != 0)
        for (unsigned int d = 0; d < dim; ++d)
          previous_rate +=
            (incremental.previous_velocity[node.dofs[d]] - contact.velocity_of(direction.id)[d]) * direction.normal[d];
      return (gap - b * previous_rate) / a;
    };
    return {2 * speed * dt, gap_rate};
  }



  template <int dim>
  double
  DieFlowProblem<dim>::ram_stroke(const double time) const
  {
    if (parameters.boundary_conditions.velocity_ids.empty())
      return contact.velocity_of(parameters.goal_part()).norm() * time;
    return std::abs(incremental.ram_displacement(triangulation));
  }



  template <int dim>
  void
  DieFlowProblem<dim>::write_load_stroke(const RunSummary &summary) const
  {
    AtomicFile    file(parameters.run.output_directory + "/load-stroke.txt");
    std::ostream &out = file.stream();
    out << "# Problem = incremental: one row per step (summary.json has the same per cycle).\n"
        << "# stroke: "
        << (parameters.boundary_conditions.velocity_ids.empty() ? "the travel of die " :
                                                                  "mean x displacement of the vertices of boundary part ")
        << parameters.goal_part() << " (mm); forces as in summary.json (plane strain N/mm, else N);\n"
        << "# volume_change: (V - V_0) / V_0; min_scaled_jacobian: 1 for rectangles, <= 0 inverted;\n"
        << "# faces_entered / faces_left: boundary faces that came onto a die / left it with the move to this step;\n"
        << "# penetration: the deepest a free node went through a die in that move, before it was put back (mm);\n"
        << "# mean_strain: the equivalent strain the metal has taken, its mean over the volume;\n"
        << "# new_mesh: 1 where the domain was meshed anew before the step's solve (Incremental/Remesh below Jacobian).\n"
        << "# step time stroke";
    const auto &names = summary.cycles.front().quantities;
    for (const auto &[name, value] : names)
      out << ' ' << name;
    out << " volume_change min_scaled_jacobian faces_entered faces_left penetration mean_strain new_mesh converged\n";
    out << incremental.earlier_load_stroke << load_stroke_rows(summary);
    file.commit();
  }



  template <int dim>
  std::string
  DieFlowProblem<dim>::load_stroke_rows(const RunSummary &summary) const
  {
    std::ostringstream out;
    for (const auto &cycle : summary.cycles)
      {
        const StepRecord &step = *cycle.step;
        out << step.step << ' ' << std::setprecision(8) << step.time << ' ' << step.stroke;
        for (const auto &[name, value] : cycle.quantities)
          out << ' ' << value;
        out << ' ' << std::setprecision(4) << step.volume_change << ' ' << step.smallest_scaled_jacobian << ' '
            << step.faces_entered << ' ' << step.faces_left << ' ' << step.penetration << ' ' << step.mean_strain
            << ' ' << (step.remesh ? 1 : 0) << ' ' << (cycle.converged ? 1 : 0) << '\n';
      }
    return out.str();
  }

#define DIEFLOW_INSTANTIATE(dim)                                                                                       \
  template void                       DieFlowProblem<dim>::advance_configuration(const unsigned int);                  \
  template void                       DieFlowProblem<dim>::remesh(const unsigned int, const double);                   \
  template std::vector<WallNode<dim>> DieFlowProblem<dim>::approaching_nodes() const;                                  \
  template std::pair<double, typename ContactGaps<dim>::GapRate> DieFlowProblem<dim>::gap_closing() const;             \
  template double      DieFlowProblem<dim>::ram_stroke(const double) const;                                            \
  template void        DieFlowProblem<dim>::write_load_stroke(const RunSummary &) const;                               \
  template std::string DieFlowProblem<dim>::load_stroke_rows(const RunSummary &) const;

  DIEFLOW_INSTANTIATE(2)
  DIEFLOW_INSTANTIATE(3)
#undef DIEFLOW_INSTANTIATE
} // namespace dieflow
