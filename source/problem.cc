#include <dieflow/expressions.h>
#include <dieflow/flow/pressure_projection.h>
#include <dieflow/incremental/mesh_transfer.h>
#include <dieflow/interrupt.h>
#include <dieflow/mesh/singular_points.h>
#include <dieflow/postprocess/atomic_file.h>
#include <dieflow/postprocess/mass_balance.h>
#include <dieflow/postprocess/postprocess.h>
#include <dieflow/postprocess/vertex_stress.h>
#include <dieflow/problem.h>
#include <dieflow/postprocess/goal_estimate.h>
#include <dieflow/threads.h>

#include <algorithm>
#include <limits>

#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_out.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/grid/grid_tools_cache.h>
#include <deal.II/numerics/solution_transfer.h>
#include <deal.II/numerics/vector_tools.h>

#include <filesystem>
#include <sstream>
#include <numeric>
#include <tuple>
#include <fstream>
#include <iomanip>

namespace dieflow
{
  namespace
  {
    /**
     * The mixed form's ||q / lambda|| / ||grad v|| at which the pressure
     * equation counts as solved: its residual M q / lambda perturbs P div v
     * by q / lambda, and the velocity (inf-sup stability) by about as much
     * relative to grad v.
     */
    constexpr double mixed_pressure_tolerance = 1e-10;

    unsigned int
    velocity_degree(ParameterHandler &prm)
    {
      prm.enter_subsection("Discretisation");
      const unsigned int degree = prm.get_integer("Velocity degree");
      prm.leave_subsection();
      return degree;
    }

    /// ", N partial steps" where there were any (the log stays as it was otherwise).
    std::string
    partial_steps_text(const unsigned int n)
    {
      return n == 0 ? "" : ", " + std::to_string(n) + " partial steps";
    }
  } // namespace



  template <int dim>
  void
  DieFlowProblem<dim>::declare_parameters(ParameterHandler &prm, const DeckLayout &layout)
  {
    RunParameters::declare_parameters(prm);
    MeshParameters::declare_parameters(prm);
    Material::declare_parameters(prm);
    BoundaryConditions<dim>::declare_parameters(prm, layout.velocity_ids);
    NonlinearSolver::declare_parameters(prm);
    LinearSolver::declare_parameters(prm);
    RefinementParameters::declare_parameters(prm);
    TimeStepping::declare_parameters(prm);
    prm.enter_subsection("Incremental");
    RemeshingParameters::declare_parameters(prm);
    CheckpointParameters::declare_parameters(prm);
    prm.leave_subsection();
    ContactParameters::declare_parameters(prm);
    FreeSurfaceParameters::declare_parameters(prm);
    prm.enter_subsection("Refinement");
    prm.declare_entry("Probe point",
                      "auto",
                      dealii::Patterns::Anything(),
                      "Point 'x, y' whose velocity is a quantity of interest of the "
                      "study; auto: for the die2d scene the exit velocity at mid-height, "
                      "1 mm before the outlet (half the land, if shorter); empty: none.");
    prm.leave_subsection();

    prm.enter_subsection("Discretisation");
    prm.declare_entry("Velocity degree",
                      "1",
                      dealii::Patterns::Integer(1, 2),
                      "Polynomial degree of the continuous velocity. 1: bilinear (Q1) "
                      "with the penalty on div v at the cell centre (Q1-P0, the seed "
                      "paper's element). 2: biquadratic (Q2) with the penalty on the "
                      "L2 projection of div v onto linear functions per cell (the "
                      "inf-sup stable Q2-P1disc pair): one order more accurate, a "
                      "pressure free of checkerboard oscillation, contact at the "
                      "vertices and edge midpoints of the die.");
    prm.leave_subsection();

    prm.enter_subsection("Verification");
    prm.declare_entry("Exact velocity",
                      "",
                      dealii::Patterns::Anything(),
                      "Exact velocity, one expression in x, y[, z] per component "
                      "separated by ';', to report the L2 and H1 errors of every "
                      "cycle against. Empty: no exact solution.");
    prm.declare_entry("Constants",
                      "",
                      dealii::Patterns::Anything(),
                      "Constants for the exact velocity: 'a=1, b=2'.");
    prm.leave_subsection();
  }



  template <int dim>
  DieFlowProblem<dim>::DieFlowProblem(ParameterHandler &prm, const std::string &deck_directory, std::ostream &log)
    : log(log)
    , timer(log, dealii::TimerOutput::never, dealii::TimerOutput::wall_times)
    , fe(dealii::FE_Q<dim>(velocity_degree(prm)), dim)
    , dof_handler(triangulation)
    , assembler(material, nullptr)
  {
    run_parameters.parse_parameters(prm);
    mesh_parameters.parse_parameters(prm);
    mesh_parameters.base_directory = deck_directory;
    material.parse_parameters(prm);
    boundary_conditions.parse_parameters(prm);
    nonlinear_solver.parse_parameters(prm);
    linear_solver.parse_parameters(prm);
    refinement.parse_parameters(prm);
    time_stepping.parse_parameters(prm);
    prm.enter_subsection("Incremental");
    remeshing.parse_parameters(prm);
    checkpoint.parse_parameters(prm, deck_directory);
    prm.leave_subsection();
    free_surface_parameters.parse_parameters(prm);
    require(!free_surface_parameters.enabled() || (dim == 2 && !time_stepping.incremental),
            "Free surface/Iterations",
            "a free surface is found for steady runs in 2D (plane strain, axisymmetric); an incremental "
            "run moves its free surface with the metal: set 0");
    for (const BoundaryId id : free_surface_parameters.ids)
      require(boundary_conditions.traction_free_ids.count(id),
              "Free surface/Free surface ids",
              "id " + std::to_string(id) + " is not one of Boundary conditions/Traction free ids: a free surface is traction free");
    require(!remeshing.enabled() || dim == 2 || !time_stepping.incremental,
            "Incremental/Remesh below Jacobian",
            "meshing the domain anew is available in 2D only (plane strain, axisymmetric); set 0 and "
            "Remesh interval = 0 for Dimension = 3");
    require(!material.hardens() || time_stepping.incremental,
            "Material/Hardening exponent n",
            "needs Problem = incremental: a steady run carries no strain (set 0)");
    if (time_stepping.incremental)
      {
        require(refinement.cycles == 1,
                "Refinement/Cycles",
                "is " + std::to_string(refinement.cycles) +
                  "; with Problem = incremental the steps take the place of the cycles: set 1 "
                  "(refine the starting mesh with Mesh/Global refinements)");
        require(refinement.target_error == 0,
                "Refinement/Target error",
                "applies to refinement cycles; with Problem = incremental leave it at 0");
      }
    prm.enter_subsection("Refinement");
    const std::string probe_text = prm.get("Probe point");
    prm.leave_subsection();
    if (probe_text == "auto")
      {
        if (mesh_parameters.source == "die2d")
          {
            const auto E = mesh_parameters.die2d.corner('E');
            // In the land also when it is shorter than 2 mm.
            const double before = std::min(1., 0.5 * mesh_parameters.die2d.land_length);
            probe               = dealii::Point<dim>();
            (*probe)[0]         = E[0] - before;
            (*probe)[1]         = 0.5 * E[1];
            if constexpr (dim == 3)
              (*probe)[2] = 0.5 * mesh_parameters.die2d.depth;
          }
      }
    else if (!probe_text.empty())
      {
        const auto coordinates = dealii::Utilities::split_string_list(probe_text);
        require(coordinates.size() == dim,
                "Refinement/Probe point",
                "'" + probe_text + "' is not a point of " + std::to_string(dim) + " coordinates");
        dealii::Point<dim> p;
        for (unsigned int d = 0; d < dim; ++d)
          p[d] = dealii::Utilities::string_to_double(coordinates[d]);
        probe = p;
      }
    contact_parameters.parse_parameters(prm);
    contact.initialize(contact_parameters);
    for (const auto &[id, file] : contact_parameters.die_surface_files)
      die_surfaces[id].read(file, deck_directory, "Contact/Die surfaces");

    prm.enter_subsection("Verification");
    if (!prm.get("Exact velocity").empty())
      exact_velocity = parse_vector_expression<dim>("Verification/Exact velocity",
                                                    prm.get("Exact velocity"),
                                                    prm.get("Constants"));
    prm.leave_subsection();

    coordinates = CoordinateSystem<dim>(run_parameters.geometry);
    assembler.set_coordinate_system(coordinates);
    assembler.set_tangent(nonlinear_solver.newton_tangent == "standard" ?
                            FlowAssembler<dim>::Tangent::standard :
                            FlowAssembler<dim>::Tangent::primal_dual);
    if (boundary_conditions.has_body_force)
      assembler.set_body_force(boundary_conditions.body_force.get());
    if (!boundary_conditions.traction_ids.empty())
      assembler.set_traction(boundary_conditions.traction.get(), boundary_conditions.traction_ids);

    auto assigned = boundary_conditions.assigned_ids();
    for (const BoundaryId id : contact_parameters.die_ids)
      {
        const auto [it, inserted] = assigned.emplace(id, "Contact/Die ids");
        require(inserted,
                "Contact/Die ids",
                "boundary id " + std::to_string(id) + " is already listed under " + it->second +
                  "; a boundary part has one condition (Die ids defaults to die2d's 3, 4: "
                  "'set Die ids =' for no contact)");
      }
    make_mesh(mesh_parameters, triangulation);
    // In time, a die given as a surface may have no face of the metal on it
    // yet: the metal comes onto it.
    auto                           in_mesh  = assigned;
    const std::vector<BoundaryId> &mesh_ids = triangulation.get_boundary_ids();
    if (time_stepping.incremental)
      for (const auto &[id, file] : contact_parameters.die_surface_files)
        if (std::find(mesh_ids.begin(), mesh_ids.end(), id) == mesh_ids.end())
          in_mesh.erase(id);
    // The die faces the metal leaves take the first free-surface id.
    if (!free_surface_parameters.ids.empty() &&
        std::find(mesh_ids.begin(), mesh_ids.end(), free_surface_parameters.ids[0]) == mesh_ids.end())
      in_mesh.erase(free_surface_parameters.ids[0]);
    check_boundary_ids(triangulation, in_mesh);
    if (coordinates.axisymmetric())
      check_axisymmetric_mesh(triangulation, boundary_conditions.symmetry_ids);
    if (mesh_parameters.corner_refinements > 0)
      {
        std::set<BoundaryId> walls = contact_parameters.die_ids;
        walls.insert(boundary_conditions.slip_wall_ids.begin(), boundary_conditions.slip_wall_ids.end());
        grade_towards(wall_corners(triangulation, walls),
                      mesh_parameters.corner_refinements,
                      mesh_parameters.corner_width,
                      triangulation);
      }
    boundary_conditions.check_prescribed_fluxes(triangulation, !contact.empty());
    bool pressure_level_free =
      boundary_conditions.traction_free_ids.empty() && boundary_conditions.traction_ids.empty();
    for (const auto &[id, mask] : boundary_conditions.velocity_components)
      pressure_level_free &= (mask.n_selected_components() == dim);
    if (!contact.empty() && pressure_level_free)
      {
        bool coulomb = false;
        for (const auto &[id, mu] : contact_parameters.friction_coefficient)
          coulomb |= mu > 0 && contact_parameters.law != FrictionLaw::Kind::tresca;
        if (coulomb)
          log << "warning: no boundary part is traction free: the velocity is prescribed or "
                 "walled everywhere, so a constant added to the pressure changes no "
                 "equilibrium; only the penalty's compressibility fixes the pressure level, "
                 "and with it the Coulomb friction forces and the ram force, which will move "
                 "with the penalty factor and the mesh (doc/contact.md). Compare "
                 "velocities, not forces."
              << std::endl;
      }
    if (refinement.target_error > 0)
      {
        std::set<std::string> names;
        for (const BoundaryId id : boundary_conditions.velocity_ids)
          names.insert("F_x[" + std::to_string(id) + "]");
        for (const BoundaryId id : contact_parameters.die_ids)
          {
            names.insert("F_n[" + std::to_string(id) + "]");
            names.insert("F_t[" + std::to_string(id) + "]");
          }
        if (probe)
          names.insert("v_x(probe)");
        std::string known;
        for (const auto &name : names)
          known += (known.empty() ? "" : ", ") + name;
        require(names.count(refinement.target_quantity) == 1,
                "Refinement/Target quantity",
                "'" + refinement.target_quantity + "' is not a quantity of this deck (it has " + known + ")");
      }
    if (refinement.indicator == "dual weighted" || refinement.dual_weighted_estimate)
      {
        require(!contact.uses_penalty(),
                "Refinement/Indicator",
                "'dual weighted' needs Contact/Normal enforcement = active set (its dual freezes the "
                "contact constraints; the penalty contact is not covered)");
        require(!coordinates.axisymmetric(),
                "Refinement/Indicator",
                "'dual weighted' is not available with Geometry = axisymmetric yet (its dual problem "
                "is assembled in plane strain); use Kelly");
        require(linear_solver.method == "direct",
                "Refinement/Indicator",
                "'dual weighted' needs Linear solver/Method = direct (the augmented Lagrangian of the "
                "iterative method is not covered)");
        require(die_surfaces.empty(),
                "Refinement/Indicator",
                "'dual weighted' does not take Contact/Die surfaces yet (its dual problem finds the die "
                "facets from the mesh); use Kelly");
        require(!contact.dies_move(),
                "Refinement/Indicator",
                "'dual weighted' does not take Contact/Die velocities yet (its dual problem holds the "
                "dies at rest); use Kelly");
      }
    require(!boundary_conditions.velocity_ids.empty() || (time_stepping.incremental && contact.dies_move()),
            "Boundary conditions/Prescribed velocity ids",
            "is empty: without a prescribed velocity (or, in Problem = incremental, a die that "
            "moves: Contact/Die velocities) nothing drives the flow and rigid motions are free");
  }



  template <int dim>
  void
  DieFlowProblem<dim>::setup_system()
  {
    dealii::TimerOutput::Scope scope(timer, "setup");
    dof_handler.distribute_dofs(fe);

    hanging_node_constraints.clear();
    dealii::DoFTools::make_hanging_node_constraints(dof_handler, hanging_node_constraints);
    hanging_node_constraints.close();

    std::set<BoundaryId> walls = boundary_conditions.wall_ids();
    walls.insert(contact_parameters.die_ids.begin(), contact_parameters.die_ids.end());
    wall_nodes = collect_wall_nodes(coordinates, dof_handler, walls, hanging_node_constraints, boundary_conditions.corner_angle);
    attach_die_surfaces(die_surfaces, boundary_conditions.corner_angle, time_stepping.incremental, wall_nodes);
    if (time_stepping.incremental && !die_surfaces.empty() && !gaps.empty())
      {
        auto [reach, gap_rate] = gap_closing();
        // The last step: no move follows, a node off the die is free.
        if (reach < 0)
          {
            reach    = 0;
            gap_rate = [](const WallNode<dim> &, const WallDirection<dim> &, const double) { return 0.; };
          }
        std::set<BoundaryId> given;
        for (const auto &[id, surface] : die_surfaces)
          given.insert(id);
        gaps.close_gaps(wall_nodes, given, reach, std::cos(boundary_conditions.corner_angle * dealii::numbers::PI / 180.), gap_rate);
      }
    if (!time_stepping.incremental)
      check_steady_die_motion();
    if (!contact.empty())
      {
        boundary_conditions.make_prescribed_constraints(dof_handler, prescribed_constraints);
        contact.setup(wall_nodes, prescribed_constraints, dof_handler.n_dofs() > 0 && contact_states_valid,
                      approaching_nodes());
      }
    make_constraints();

    // Wall and Dirichlet constraints only couple the components of one node,
    // which the pattern couples anyway: the hanging-node pattern serves all.
    dealii::DynamicSparsityPattern dsp(dof_handler.n_dofs());
    dealii::DoFTools::make_sparsity_pattern(dof_handler, dsp, hanging_node_constraints, false);
    sparsity_pattern.copy_from(dsp);
    system_matrix.reinit(sparsity_pattern);
    linear_solver.reset();
    const bool iterative = linear_solver.iterative_for(dim, fe.degree, dof_handler.n_dofs());
    augmented            = iterative && fe.degree == 1;
    mixed_form           = iterative && fe.degree >= 2;
    if (mixed_form)
      {
        mixed.reinit(dof_handler, hanging_node_constraints);
        if (!saddle_point_solver)
          saddle_point_solver = std::make_unique<SaddlePointSolver<dim>>();
        saddle_point_solver->set_rigid_body_modes(rigid_body_modes(dof_handler));
        if (linear_solver.p_multigrid)
          saddle_point_solver->use_p_multigrid(dof_handler);
        last_mixed_tolerance                 = 0;
        last_mixed_residual                  = 0;
        last_mixed_update                    = 1;
        saddle_point_solver->constraints     = &update_constraints;
        saddle_point_solver->flow            = material.is_newtonian() ? nullptr : &assembled_iterate;
        saddle_point_solver->inner_tolerance = linear_solver.inner_tolerance;
        // The previous mesh's cell stress gives the first pressure (cell
        // means). Without one the pressure starts at zero, at the first
        // assembly: q = -lambda P div v there (a velocity that only meets
        // the boundary conditions has a divergence of order its speed over
        // a cell, whose pressure lambda P div v would swamp the residual).
        Vector<double> pressure(mixed.n_pressure());
        pressure_unset = !(transferred_cell_stress.size() == triangulation.n_active_cells() &&
                           velocity.size() == dof_handler.n_dofs());
        if (pressure_unset)
          multiplier = pressure;
        else
          {
            for (unsigned int c = 0; c < triangulation.n_active_cells(); ++c)
              pressure[c * mixed.n_modes] = transferred_cell_stress[c];
            multiplier = multiplier_for(pressure, velocity);
          }
        accepted_multiplier = multiplier;
        multiplier_update.reinit(multiplier.size());
      }
    else if (augmented)
      {
        std::vector<std::vector<bool>> constant_modes;
        dealii::DoFTools::extract_constant_modes(dof_handler, dealii::ComponentMask(), constant_modes);
        linear_solver.set_constant_modes(constant_modes);
        // The previous mesh's cell stress is the best first multiplier.
        // Only the cell means go from mesh to mesh (the first coefficient).
        const unsigned int n_modes = PressureProjection<dim>::n_modes_for(fe);
        const bool         carried = transferred_cell_stress.size() == triangulation.n_active_cells();
        multiplier.reinit(triangulation.n_active_cells() * n_modes);
        if (carried)
          for (unsigned int c = 0; c < triangulation.n_active_cells(); ++c)
            multiplier[c * n_modes] = transferred_cell_stress[c];
        if (velocity.size() == dof_handler.n_dofs())
          update_cell_penalty(velocity);
        else
          cell_penalty.reinit(triangulation.n_active_cells());
      }
    else
      multiplier.reinit(0);
    assembler.set_multiplier(augmented || mixed_form ? &multiplier : nullptr);
    assembler.set_cell_penalty(augmented ? &cell_penalty : nullptr);
    if (mean_viscosity > 0)
      assembler.set_penalty(penalty_factor() * mean_viscosity);
    system_rhs.reinit(dof_handler.n_dofs());
    raw_residual.reinit(dof_handler.n_dofs());
  }



  template <int dim>
  std::vector<WallNode<dim>>
  DieFlowProblem<dim>::approaching_nodes() const
  {
    const auto [reach, gap_rate] = gap_closing();
    if (reach < 0)
      return {};
    // Nodes of a die face are the die's already; one on a symmetry plane or
    // slip wall keeps that wall (ContactSet: a fixed normal).
    std::set<GlobalDof>                        on_die;
    std::map<GlobalDof, const WallNode<dim> *> on_wall;
    for (const auto &node : wall_nodes)
      {
        on_wall[node.dofs[0]] = &node;
        for (const auto &wall : node.directions)
          if (contact_parameters.die_ids.count(wall.id))
            on_die.insert(node.dofs[0]);
      }
    std::vector<WallNode<dim>> free_nodes;
    for (auto &node : collect_wall_nodes(coordinates, dof_handler, boundary_conditions.traction_free_ids,
                                         hanging_node_constraints, boundary_conditions.corner_angle))
      if (!on_die.count(node.dofs[0]))
        free_nodes.push_back(std::move(node));
    std::vector<WallNode<dim>> approaching = gaps.approaching(free_nodes, reach, gap_rate);
    for (auto &node : approaching)
      if (const auto wall = on_wall.find(node.dofs[0]); wall != on_wall.end())
        node.directions.insert(node.directions.end(), wall->second->directions.begin(), wall->second->directions.end());
    return approaching;
  }



  template <int dim>
  std::pair<double, typename ContactGaps<dim>::GapRate>
  DieFlowProblem<dim>::gap_closing() const
  {
    if (!time_stepping.incremental || !time_stepping.contact_within_step || gaps.empty() ||
        current_step >= time_stepping.n_steps())
      return {-1., {}};
    const double dt = time_stepping.time(current_step + 1) - time_stepping.time(current_step);
    // Reach: twice the largest travel of the step (the previous step's
    // speed, the dies'); a node farther off cannot arrive, and the after-
    // the-move rule of ContactGaps::update() still catches one that does.
    const bool have_velocity = velocity.size() == dof_handler.n_dofs();
    double     speed         = have_velocity ? velocity.linfty_norm() : 0.;
    for (const auto &[id, components] : contact_parameters.die_velocities)
      speed = std::max(speed, contact.velocity_of(id).norm());
    // The move will be x += a v_n + b v_{n-1} (advance_configuration()): the
    // node lands on the die where a (v_n - V).n + b (v_{n-1} - V).n = g,
    // i.e. (v_n - V).n = (g - b (v_{n-1} - V).n) / a (a + b = dt).
    const auto [a, b] = move_weights(current_step);
    const auto gap_rate = [this, a = a, b = b](const WallNode<dim> &node, const WallDirection<dim> &direction, const double gap) {
      double previous_rate = 0;
      if (b != 0)
        for (unsigned int d = 0; d < dim; ++d)
          previous_rate += (previous_velocity[node.dofs[d]] - contact.velocity_of(direction.id)[d]) * direction.normal[d];
      return (gap - b * previous_rate) / a;
    };
    return {2 * speed * dt, gap_rate};
  }



  template <int dim>
  void
  DieFlowProblem<dim>::check_steady_die_motion() const
  {
    // A steady run keeps the domain: a die may move only along itself.
    for (const auto &node : wall_nodes)
      for (const auto &wall : node.directions)
        {
          const Tensor<1, dim> V = contact.velocity_of(wall.id);
          // (A node on the axis has no area and no normal of its own.)
          if (!(std::abs(V * wall.normal) > 1e-9 * V.norm()))
            continue;
          std::ostringstream message;
          message << "die " << wall.id << " moves across its own surface (V.n = " << V * wall.normal
                  << " mm/s at the wall node (" << node.position
                  << ")); a steady run keeps the domain, so a die may move only along its surface "
                     "(a belt, a mandrel): use Problem = incremental";
          require(false, "Contact/Die velocities", message.str());
        }
  }



  template <int dim>
  void
  DieFlowProblem<dim>::make_constraints()
  {
    boundary_conditions.make_constraints(dof_handler, hanging_node_constraints, wall_nodes, false, constraints);
    contact.add_constraints(constraints, false);
    constraints.close();
    boundary_conditions.make_constraints(dof_handler, hanging_node_constraints, wall_nodes, true, update_constraints);
    contact.add_constraints(update_constraints, true);
    update_constraints.close();
  }



  template <int dim>
  void
  DieFlowProblem<dim>::assemble(const FlowAssembler<dim> &    flow,
                                const Vector<double> &        v,
                                const Linearization           linearization,
                                dealii::SparseMatrix<double> *matrix,
                                Vector<double> &              minus_residual)
  {
    const AssemblyInfo info =
      assemble_with_contact(flow, contact, dof_handler, v, update_constraints, linearization, matrix, minus_residual, raw_residual,
                            mixed_form ? &mixed : nullptr);
    contact_assemblies += info.contact ? 1 : 0;
    friction_terms += info.friction_terms;
    if (matrix != nullptr)
      matrix_symmetric = info.symmetric;
  }



  template <int dim>
  Vector<double>
  DieFlowProblem<dim>::nodal_flow_residual(const Vector<double> &v)
  {
    Vector<double> unused, reactions;
    assembler.assemble_residual(dof_handler, v, update_constraints, unused, reactions);
    hanging_node_constraints.condense(reactions);
    return reactions;
  }



  template <int dim>
  double
  DieFlowProblem<dim>::roundoff_bound(const Vector<double> &v) const
  {
    // Higham's bound for a computed residual, |fl(J v) - J v| <= eps |J| |v|
    // per row, over the free rows, relative to the reactions as
    // relative_residual() measures. The formula of residual_floor() was
    // measured for Newtonian flow; a strongly shear-thinning law puts its
    // plateau higher (Norton-Hoff m = 0.2, degree 2: 3.75e-7 at 11,546 dofs,
    // six times that formula, 0.57 times this bound).
    double free_squared = 0, reaction_squared = 0;
    // The mixed form's matrix is A alone: the penalty's |B^T| lambda |M^-1| |B| |v| joins it.
    const Vector<double> penalty_rows = mixed_form ? mixed.penalty_magnitude(v) : Vector<double>();
    for (unsigned int i = 0; i < system_matrix.m(); ++i)
      if (update_constraints.is_constrained(i))
        reaction_squared += raw_residual[i] * raw_residual[i];
      else
        {
          double row = mixed_form ? penalty_rows[i] : 0.;
          for (auto entry = system_matrix.begin(i); entry != system_matrix.end(i); ++entry)
            row += std::abs(entry->value() * v[entry->column()]);
          free_squared += row * row;
        }
    if (reaction_squared == 0)
      return 0;
    // It grows with the mesh (P1, degree 2: a plateau of 1.0e-6 at 50,372
    // dofs). Trusted up to 1e-4: beyond that the reactions themselves are
    // round-off (a stress-free plug flow: 0.7), the relative residual means
    // nothing, and the update test decides.
    return std::min(std::numeric_limits<double>::epsilon() * std::sqrt(free_squared / reaction_squared), 1e-4);
  }



  template <int dim>
  double
  DieFlowProblem<dim>::relative_residual(const Vector<double> &minus_residual) const
  {
    // The reactions: the raw residual at dofs the constraints hold.
    double reaction_squared = 0;
    for (unsigned int i = 0; i < raw_residual.size(); ++i)
      if (update_constraints.is_constrained(i))
        reaction_squared += raw_residual[i] * raw_residual[i];
    const double residual = minus_residual.l2_norm();
    if (residual == 0)
      return 0;
    return residual / std::max(std::sqrt(reaction_squared), 1e-300);
  }



  template <int dim>
  StateChanges
  DieFlowProblem<dim>::update_state(Vector<double> &v)
  {
    if (augmented && v.linfty_norm() > 0)
      update_multiplier(v);
    // The projection onto the new constraints moves v at contact nodes; the
    // mixed form's pressure p = q + lambda P div v stays (else it jumps by
    // lambda P div of that move).
    const Vector<double> before = (mixed_form && !pressure_unset) ? v : Vector<double>();
    StateChanges changes;
    // The first iterate of a refined mesh is the previous solution
    // interpolated, not in equilibrium on the new mesh: its reactions say
    // nothing about the contact states, which it keeps from the previous
    // mesh for its first solve.
    if (!contact.empty() && contact_states_valid && !states_from_previous_mesh)
      {
        dealii::TimerOutput::Scope scope(timer, "contact");
        changes = contact.update(v, nodal_flow_residual(v), log);
        // Contact and exact stick are constraints.
        if (changes.total() > 0)
          make_constraints();
      }
    states_from_previous_mesh = false;
    constraints.distribute(v);
    if (before.size() == v.size() && before != v)
      {
        Vector<double> move = v;
        move -= before;
        accepted_multiplier.add(-assembler.get_penalty(), PressureProjection<dim>::project_all(dof_handler, move, coordinates));
        multiplier = accepted_multiplier;
      }
    return changes;
  }



  template <int dim>
  double
  DieFlowProblem<dim>::assemble_system(const Vector<double> &v, const Linearization linearization)
  {
    dealii::TimerOutput::Scope scope(timer, "assembly");
    if (mixed_form)
      {
        if (pressure_unset)
          accepted_multiplier = multiplier_for(Vector<double>(mixed.n_pressure()), v);
        pressure_unset          = false;
        multiplier              = accepted_multiplier;
        assembled_iterate       = v;
        assembled_linearization = linearization;
      }
    assemble(assembler, v, linearization, &system_matrix, system_rhs);
    last_roundoff_bound = roundoff_bound(v);
    return relative_residual(system_rhs);
  }



  template <int dim>
  double
  DieFlowProblem<dim>::residual(const Vector<double> &v, Vector<double> &minus_residual)
  {
    dealii::TimerOutput::Scope scope(timer, "assembly");
    assemble(assembler, v, Linearization::picard, nullptr, minus_residual);
    return relative_residual(minus_residual);
  }



  template <int dim>
  void
  DieFlowProblem<dim>::solve(Vector<double> &update, const double relative_residual)
  {
    dealii::TimerOutput::Scope scope(timer, "linear solve");
    update.reinit(dof_handler.n_dofs());
    if (mixed_form)
      solve_mixed(update, mixed_solve_tolerance(relative_residual));
    else if (augmented)
      linear_solver.solve_iteratively(dim, system_matrix, matrix_symmetric, system_rhs, update);
    else
      {
        linear_solver.factorize(system_matrix, matrix_symmetric);
        linear_solver.solve(system_rhs, update);
      }
    update_constraints.distribute(update);
  }



  template <int dim>
  void
  DieFlowProblem<dim>::accept_step(const Vector<double> &v,
                                   const Vector<double> &update,
                                   const double          step,
                                   const Linearization   linearization)
  {
    contact_states_valid = true;
    if (mixed_form)
      {
        accepted_multiplier.add(step, multiplier_update);
        multiplier = accepted_multiplier;
        multiplier_update = 0;
      }
    if (linearization == Linearization::newton)
      assembler.update_dual(dof_handler, v, &update, step);
    else
      {
        Vector<double> next = v;
        next.add(step, update);
        assembler.update_dual(dof_handler, next, nullptr, 0);
      }
  }



  template <int dim>
  double
  DieFlowProblem<dim>::mixed_solve_tolerance(const double relative_residual)
  {
    // Without it, Newton's residual reached its floor while the ratio
    // stalled near its bound, each solve at the tightest tolerance leaving
    // about as much of q as it removed (die2d, Norton-Hoff m = 0.05, 128
    // cells across: 9 more Newton iterations of some 70 Krylov iterations
    // each, the update 1e-10 of v).
    // The ratio costs a pass of gradients over the mesh: only at the floor.
    double tolerance =
      linear_solver.forcing_tolerance(relative_residual, penalty_factor(), last_mixed_tolerance, last_mixed_residual);
    const double previous_residual = last_mixed_residual;
    last_mixed_residual            = relative_residual;
    // At the floor also where the residual stopped falling while the
    // velocity stopped moving: residual_floor() is a fit measured to 150k
    // unknowns, and die2d N1 at 683k, penalty factor 1e10, stalled at 2.7
    // times it (|R|/|F| 1.36e-3, the direct solver's plateau too, updates
    // of 1e-10): without the tighter solves the pressure ratio never met
    // its tolerance and Newton stopped after 50 iterations.
    const bool stalled = relative_residual > 0.5 * previous_residual && last_mixed_update <= 1e-8;
    if (last_mixed_tolerance > 0 && (relative_residual <= residual_floor() || stalled))
      {
        const double ratio = pressure_residual_ratio();
        if (ratio > mixed_pressure_tolerance)
          tolerance = std::max({1e-10, 1e-2 * tolerance,
                                std::min(tolerance, 0.1 * mixed_pressure_tolerance / ratio * last_mixed_tolerance)});
      }
    last_mixed_tolerance = tolerance;
    return tolerance;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::solve_mixed(Vector<double> &update, const double tolerance)
  {
    // b_p = -R_p = M q / lambda.
    Vector<double> inverse_penalty(mixed.n_cells), rhs_pressure, dp;
    for (unsigned int c = 0; c < mixed.n_cells; ++c)
      inverse_penalty[c] = 1. / mixed.penalty[c];
    mixed.mass_vmult(rhs_pressure, accepted_multiplier, inverse_penalty);
    const auto info = saddle_point_solver->solve(system_matrix, mixed, system_rhs, rhs_pressure, update, dp,
                                                 matrix_symmetric, tolerance,
                                                 linear_solver.max_block_iterations);
    ++linear_solver.counts.iterative_solves;
    linear_solver.counts.krylov_iterations += info.iterations;
    linear_solver.counts.inner_iterations += info.inner_iterations;
    if (info.residual_reduction > 0 && info.residual_reduction < 1)
      linear_solver.counts.residual_decades += -std::log10(info.residual_reduction);
    // A solve that stopped at its iteration limit having reduced its
    // residual tenfold is still a descent step of an inexact Newton method
    // (forcing term 0.1); where the direct fallback would not fit, taking it
    // beats stopping: at 4.15M unknowns (die2d, 320 cells across, a refined
    // cycle) one solve missed its tolerance, the fallback would have needed
    // 20.9 GB, and with the partial step Newton went on (4.6e-3, 3.7e-4,
    // 1.1e-4).
    const bool partial_step = !info.converged && info.residual_reduction <= 0.1 &&
                              !LinearSolver::direct_fallback_fits(dim, system_matrix.m());
    if (partial_step)
      ++linear_solver.counts.partial_steps;
    std::ostringstream line;
    line << "           GMRES " << info.iterations << " iterations, residual " << std::scientific << std::setprecision(1)
         << info.residual_reduction << " of its start (asked " << tolerance << ")"
         << (info.converged ? "" : partial_step ? ": stopped short, taken as a partial step" : ": stopped short");
    log << line.str() << std::endl;
    if (info.converged || partial_step)
      {
        last_mixed_update = update.l2_norm() / std::max(assembled_iterate.l2_norm(), 1e-300);
        // dq = dp - lambda M^-1 B du.
        Vector<double> divergence(mixed.n_pressure());
        mixed.divergence.vmult(divergence, update);
        mixed.inverse_mass_vmult(multiplier_update, divergence, mixed.penalty);
        multiplier_update.sadd(-1., 1., dp);
        return;
      }
    // The direct solver on the penalty form gives the mixed step exactly:
    // eliminating dp = lambda M^-1 B du - q leaves J du = -R_v + B^T q,
    // which is -R(v) assembled with q = 0. The carried pressure's update is
    // then dq = dp - lambda M^-1 B du = -q. Keeping q and its update (not
    // setting q = 0 at once) matters when the step is shortened: a trial
    // step s then carries (1 - s) q, where q = 0 left lambda P div of the
    // contact projections' moves in the pressure, a residual some 1e9 too
    // large that turned the line search and the Picard step that followed
    // into a divergence (die2d, Norton-Hoff m = 0.05, 64 cells across).
    LinearSolver::require_direct_fallback_fits(dim, system_matrix.m());
    ++linear_solver.counts.direct_fallbacks;
    multiplier = 0;
    mixed_form = false;
    assemble(assembler, assembled_iterate, assembled_linearization, &system_matrix, system_rhs);
    mixed_form = true;
    multiplier = accepted_multiplier;
    multiplier_update = accepted_multiplier;
    multiplier_update *= -1.;
    linear_solver.factorize(system_matrix, matrix_symmetric);
    linear_solver.solve(system_rhs, update);
  }



  template <int dim>
  Vector<double>
  DieFlowProblem<dim>::multiplier_for(const Vector<double> &p, const Vector<double> &v) const
  {
    const Vector<double> divergence = PressureProjection<dim>::project_all(dof_handler, v, coordinates);
    Vector<double>       q          = p;
    q.add(-assembler.get_penalty(), divergence);
    return q;
  }



  template <int dim>
  double
  DieFlowProblem<dim>::pressure_residual_ratio() const
  {
    if (accepted_multiplier.size() == 0 || velocity.size() != dof_handler.n_dofs())
      return 0;
    Vector<double> ones(mixed.n_cells), Mq;
    ones = 1.;
    mixed.mass_vmult(Mq, accepted_multiplier, ones);
    const dealii::FEValuesExtractors::Vector     velocities(0);
    dealii::FEValues<dim>                        gauss(fe, dealii::QGauss<dim>(fe.degree + 1), dealii::update_gradients | dealii::update_JxW_values | dealii::update_quadrature_points);
    std::vector<dealii::Tensor<2, dim>>          grad(gauss.n_quadrature_points);
    double                                       grad_squared = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        gauss.reinit(cell);
        gauss[velocities].get_function_gradients(velocity, grad);
        for (const unsigned int q : gauss.quadrature_point_indices())
          grad_squared += grad[q].norm_square() * gauss.JxW(q) * coordinates.weight(gauss.quadrature_point(q));
      }
    const double q_norm = std::sqrt(accepted_multiplier * Mq);
    return grad_squared > 0 ? q_norm / (assembler.get_penalty() * std::sqrt(grad_squared)) : q_norm;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::set_trial_step(const double step)
  {
    if (!mixed_form)
      return;
    multiplier = accepted_multiplier;
    multiplier.add(step, multiplier_update);
  }



  template <int dim>
  void
  DieFlowProblem<dim>::update_multiplier(const Vector<double> &v)
  {
    // q_h <- q_h + r P div v, each cell's coefficients with the cell's r.
    const Vector<double> divergence = cell_divergence(coordinates, dof_handler, v);
    const unsigned int   n_modes    = PressureProjection<dim>::n_modes_for(fe);
    for (unsigned int i = 0; i < divergence.size(); ++i)
      multiplier[i] += cell_penalty[i / n_modes] * divergence[i];
    last_divergence_ratio = divergence_ratio(coordinates, dof_handler, v);
    update_cell_penalty(v);
  }



  template <int dim>
  void
  DieFlowProblem<dim>::update_cell_penalty(const Vector<double> &v)
  {
    // r per cell in proportion to its viscosity: the multiplier then
    // converges as fast in the stiff plug of the container as in the
    // deforming zone (with one r for all, 1e3 times the mean viscosity is
    // nothing where eta is 1e4 times the mean).
    cell_penalty = cell_viscosity(v);
    cell_penalty *= linear_solver.augmentation;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::uniform_cell_penalty(const double r)
  {
    if (!augmented)
      return;
    cell_penalty.reinit(triangulation.n_active_cells());
    cell_penalty.add(r);
  }



  template <int dim>
  Vector<double>
  DieFlowProblem<dim>::cell_viscosity(const Vector<double> &v) const
  {
    dealii::FEValues<dim>        centre(fe, dealii::QGauss<dim>(1), dealii::update_gradients | coordinates.flags());
    std::vector<StrainRate<dim>> D(1);
    Vector<double>               eta(triangulation.n_active_cells());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        centre.reinit(cell);
        coordinates.strain_rates(centre, v, D);
        eta[cell->active_cell_index()] = material.evaluate(std::sqrt(2. / 3. * (D[0] * D[0]))).eta;
      }
    return eta;
  }



  template <int dim>
  Vector<double>
  DieFlowProblem<dim>::cell_pressures() const
  {
    ++pressure_recoveries;
    return cell_pressure(coordinates,
                         dof_handler,
                         velocity,
                         assembler.get_penalty(),
                         augmented || mixed_form ? &multiplier : nullptr,
                         augmented ? &cell_penalty : nullptr);
  }



  template <int dim>
  bool
  DieFlowProblem<dim>::constraints_settled() const
  {
    if (mixed_form)
      return pressure_residual_ratio() <= mixed_pressure_tolerance;
    return !augmented || last_divergence_ratio <= linear_solver.divergence_tolerance;
  }



  template <int dim>
  double
  DieFlowProblem<dim>::residual_floor() const
  {
    // The cancellation in lambda div v (lambda = factor x eta) leaves about
    // 1e-16 x factor per nodal force; measured on die2d from 666 to 150,000
    // dofs: 1.5e-17 to 3e-17 x factor x sqrt(dofs). Twice that is the floor,
    // or the round-off bound of the last assembly where it is larger (see
    // roundoff_bound()).
    return std::max(6e-17 * penalty_factor() * std::sqrt(static_cast<double>(dof_handler.n_dofs())),
                    last_roundoff_bound);
  }



  template <int dim>
  bool
  DieFlowProblem<dim>::is_linear() const
  {
    // The augmented Lagrangian iterates on its multiplier; the mixed form's
    // Krylov solves are inexact.
    return material.is_newtonian() && contact.empty() && !augmented && !mixed_form;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::newtonian_start()
  {
    // The velocity of a Newtonian, velocity-driven problem does not depend on
    // the viscosity's value; the law's viscosity at a typical strain rate
    // keeps forces and tractions (body force, Tresca) on the right scale.
    prescribed_speed      = boundary_conditions.largest_prescribed_speed(dof_handler);
    double reference_rate = material.reference_strain_rate;
    if (reference_rate == 0)
      {
        const double diameter = dealii::GridTools::diameter(triangulation);
        reference_rate        = prescribed_speed / diameter;
        if (reference_rate == 0)
          reference_rate = 1;
      }
    const double start_viscosity = material.evaluate(reference_rate).eta;
    velocity.reinit(dof_handler.n_dofs());
    constraints.distribute(velocity);
    if (material.is_newtonian())
      {
        // The law is the Newtonian problem: the nonlinear solver's first
        // step solves it.
        mean_viscosity = start_viscosity;
        assembler.set_penalty(penalty_factor() * mean_viscosity);
        contact.set_scales(mean_viscosity, material.penalty_factor * mean_viscosity);
        log << "  " << penalty_name() << " = " << penalty_factor() << " x viscosity " << mean_viscosity << " = "
            << assembler.get_penalty() << " MPa s" << std::endl;
        uniform_cell_penalty(assembler.get_penalty());
        return;
      }

    Material newtonian = material;
    newtonian.set_newtonian(start_viscosity);
    FlowAssembler<dim> start(newtonian, nullptr);
    start.copy_loads(assembler);
    start.set_penalty(penalty_factor() * start_viscosity);
    if (mixed_form)
      {
        // p = 0 to start with (see setup_system()), with the start's lambda.
        accepted_multiplier = PressureProjection<dim>::project_all(dof_handler, velocity, coordinates);
        accepted_multiplier *= -start.get_penalty();
        multiplier     = accepted_multiplier;
        pressure_unset = false;
        start.set_multiplier(&multiplier);
      }
    contact.set_scales(start_viscosity, material.penalty_factor * start_viscosity);
    {
      dealii::TimerOutput::Scope scope(timer, "assembly");
      assemble(start, velocity, Linearization::picard, &system_matrix, system_rhs);
    }
    Vector<double> update;
    solve(update, 0);
    velocity += update;
    ++start_solves;
    // The start's pressure, p = q + lambda P div v with its own lambda.
    Vector<double> start_pressure;
    if (mixed_form)
      {
        start_pressure = accepted_multiplier;
        start_pressure.add(1., multiplier_update);
        start_pressure.add(start.get_penalty(), PressureProjection<dim>::project_all(dof_handler, velocity, coordinates));
      }
    // The first Uzawa step uses the r this solve had.
    uniform_cell_penalty(start.get_penalty());

    mean_viscosity = assembler.mean_viscosity(dof_handler, velocity);
    assembler.set_penalty(penalty_factor() * mean_viscosity);
    if (mixed_form)
      {
        // As the penalty form's p = lambda P div v does when lambda changes
        // (the same Newton path as the direct solver's).
        start_pressure *= assembler.get_penalty() / start.get_penalty();
        accepted_multiplier = multiplier_for(start_pressure, velocity);
        multiplier          = accepted_multiplier;
        multiplier_update   = 0;
      }
    contact.set_scales(mean_viscosity, material.penalty_factor * mean_viscosity);
    contact_states_valid = true;
    log << "  Newtonian start: eta = " << std::setprecision(4) << start_viscosity
        << " MPa s; " << penalty_name() << " = " << penalty_factor() << " x mean viscosity "
        << mean_viscosity << " = " << assembler.get_penalty() << " MPa s" << std::endl;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::postprocess(CycleSummary &summary)
  {
    dealii::TimerOutput::Scope scope(timer, "postprocess");
    summary.cells = triangulation.n_active_cells();
    summary.dofs  = dof_handler.n_dofs();
    summary.flux  = boundary_fluxes(coordinates, dof_handler, velocity);
    summary.boundary_area = boundary_areas(coordinates, dof_handler);

    // Reactions of the converged state, with hanging nodes' shares moved to
    // the vertices they hang from.
    Vector<double> unused;
    assembler.assemble_residual(dof_handler, velocity, update_constraints, unused, raw_residual);
    Vector<double> reactions = raw_residual;
    hanging_node_constraints.condense(reactions);
    std::vector<WallShare<dim>> wall_shares;
    const auto                  frictionless = frictionless_walls();
    summary.boundary_force =
      boundary_forces(coordinates, dof_handler, reactions, boundary_conditions, wall_nodes, frictionless, &wall_shares);
    summary.divergence_ratio = divergence_ratio(coordinates, dof_handler, velocity);
    summary.mass_balance     = mass_balance(coordinates, dof_handler, velocity, summary.flux);
    summary.penalty          = assembler.get_penalty();
    summary.mean_viscosity   = mean_viscosity;
    summary.error_estimate = kelly_estimate(dof_handler, velocity);
    if (refinement.dual_weighted_estimate)
      {
        const auto goal = dual_weighted_force_error(dof_handler, hanging_node_constraints, velocity, assembler, material,
                                                    contact, boundary_conditions, contact_parameters.die_ids,
                                                    goal_part());
        summary.dual_weighted_error = goal.error;
        log << "  dual-weighted estimate: F_x[" << goal_part() << "] exact - computed = " << std::setprecision(3)
            << goal.error << " (velocity part " << goal.velocity_part << ", pressure part " << goal.pressure_part
            << "; dual problem " << goal.dual_dofs << " dofs)" << std::endl;
      }
    summary.die_cell_share = share_of_cells_at(triangulation, contact_parameters.die_ids);
    if (exact_velocity)
      {
        const auto errors         = velocity_errors(dof_handler, velocity, *exact_velocity);
        summary.velocity_l2_error = errors.first;
        summary.velocity_h1_error = errors.second;
      }

    summary.contact_assemblies = contact_assemblies;
    summary.friction_terms     = friction_terms;
    std::map<std::string, Vector<double>> nodal_fields, cell_fields;
    if (time_stepping.incremental)
      cell_fields["equivalent_strain"] = equivalent_strain;
    // The pressure is recovered once, for the degree-1 die profiles and the
    // fields.
    const bool     write_fields_now = (run_parameters.write_vtu || run_parameters.write_gnuplot) &&
                                  (!time_stepping.incremental || time_stepping.writes_output(summary.cycle));
    const bool     recover_profiles = !contact.empty() && fe.degree == 1;
    Vector<double> pressure;
    if (recover_profiles || write_fields_now)
      pressure = cell_pressures();
    if (!contact.empty())
      {
        contact_results    = contact.results(velocity);
        const auto &results = contact_results;
        contact.summarise(results, velocity.linfty_norm(), summary);
        add_die_shares(wall_shares, frictionless, summary);
        const auto stress = recover_profiles ? vertex_stresses(coordinates, dof_handler, velocity, material, pressure) :
                                               std::vector<dealii::SymmetricTensor<2, dim>>();
        contact.write_profiles(results, recover_profiles ? &stress : nullptr, run_parameters.output_directory);
        nodal_fields["contact_status"] = contact.vertex_status(dof_handler);
        const double throughput        = boundary_conditions_throughput(summary.flux);
        for (const BoundaryId id : contact_parameters.die_ids)
          if (std::abs(summary.flux[id]) > 1e-6 * throughput)
            log << "  flux through die id " << id << ": " << std::setprecision(4) << summary.flux[id] << " ("
                << 100. * std::abs(summary.flux[id]) / throughput << "% of the throughput): "
                << (summary.flux[id] < 0 ? "the metal leaves the wall there (separated), see doc/contact.md" :
                                           "penetration")
                << std::endl;
      }
    for (const BoundaryId id : boundary_conditions.velocity_ids)
      summary.quantities.emplace_back("F_x[" + std::to_string(id) + "]", summary.boundary_force.at(id)[0]);
    for (const BoundaryId id : contact_parameters.die_ids)
      {
        summary.quantities.emplace_back("F_n[" + std::to_string(id) + "]", summary.die_normal_force[id]);
        summary.quantities.emplace_back("F_t[" + std::to_string(id) + "]", summary.die_friction_force[id]);
      }
    if (probe)
      {
        dealii::Vector<double> value(dim);
        try
          {
            dealii::VectorTools::point_value(dof_handler, velocity, *probe, value);
          }
        catch (const std::exception &)
          {
            throw InputError("Refinement/Probe point: the point is not in the mesh");
          }
        summary.quantities.emplace_back("v_x(probe)", value[0]);
      }

    if (write_fields_now)
      write_fields(coordinates,
                   dof_handler,
                   velocity,
                   material,
                   pressure,
                   nodal_fields,
                   cell_fields,
                   run_parameters.output_directory,
                   summary.cycle,
                   time_stepping.incremental ? time_stepping.time(summary.cycle) : summary.cycle,
                   run_parameters.write_vtu,
                   run_parameters.write_gnuplot,
                   pvd_records);
    summary.pressure_recoveries = pressure_recoveries;
    if (run_parameters.write_mesh_svg)
      {
        std::ofstream       svg(run_parameters.output_directory + "/mesh-" +
                          dealii::Utilities::int_to_string(summary.cycle, 2) + ".svg");
        dealii::GridOut().write_svg(triangulation, svg);
      }
  }



  template <int dim>
  Vector<double>
  DieFlowProblem<dim>::ram_force_dual()
  {
    // One more solve with the last Newton step's factorisation (transposed),
    // or with a new one when the cycle needed no linear solve.
    if (!linear_solver.has_factorisation())
      {
        assemble(assembler, velocity, Linearization::newton, &system_matrix, system_rhs);
        linear_solver.factorize(system_matrix, matrix_symmetric);
      }
    return force_dual(dof_handler, hanging_node_constraints, update_constraints, sparsity_pattern, velocity, assembler,
                      contact, force_direction(dof_handler, hanging_node_constraints, goal_part()),
                      [this](Vector<double> &b) {
                        Vector<double> x;
                        linear_solver.solve(b, x, true);
                        b = x;
                      });
  }



  template <int dim>
  BoundaryId
  DieFlowProblem<dim>::goal_part() const
  {
    const std::string &q = refinement.target_quantity;
    if (q.rfind("F_x[", 0) == 0 && q.back() == ']')
      {
        const auto id = static_cast<BoundaryId>(dealii::Utilities::string_to_int(q.substr(4, q.size() - 5)));
        if (boundary_conditions.velocity_ids.count(id))
          return id;
      }
    // Driven by a moving die alone (Problem = incremental): the first one.
    if (boundary_conditions.velocity_ids.empty())
      return contact_parameters.die_velocities.begin()->first;
    return *boundary_conditions.velocity_ids.begin();
  }



  template <int dim>
  std::set<BoundaryId>
  DieFlowProblem<dim>::frictionless_walls() const
  {
    std::set<BoundaryId> ids = boundary_conditions.wall_ids();
    for (const BoundaryId id : contact_parameters.die_ids)
      if (contact.frictionless(id))
        ids.insert(id);
    return ids;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::add_die_shares(const std::vector<WallShare<dim>> &shares,
                                      const std::set<BoundaryId> &       frictionless,
                                      CycleSummary &                     summary) const
  {
    // The node belongs to the prescribed part, not to the contact set, but
    // the die carries its share of it: |f.n| and |f - (f.n) n|, as the
    // contact nodes' forces are counted.
    for (const auto &share : shares)
      if (contact_parameters.die_ids.count(share.id) && share.normal.norm_square() > 0)
        {
          const double normal = share.force * share.normal;
          summary.die_normal_force[share.id] += std::abs(normal);
          if (!frictionless.count(share.id))
            summary.die_friction_force[share.id] += (share.force - normal * share.normal).norm();
        }
  }



  template <int dim>
  double
  DieFlowProblem<dim>::boundary_conditions_throughput(const std::map<BoundaryId, double> &flux) const
  {
    // The larger of what flows in and out through the parts other than the
    // dies: a ram pushes it in, a drawing pull takes it out through a
    // prescribed outlet while the inlet is free.
    double inflow = 0, outflow = 0;
    for (const auto &[id, q] : flux)
      if (!contact_parameters.die_ids.count(id))
        (q < 0 ? inflow : outflow) += std::abs(q);
    return std::max(inflow, outflow);
  }



  template <int dim>
  void
  DieFlowProblem<dim>::refine_mesh()
  {
    dealii::TimerOutput::Scope scope(timer, "refinement");
    if (refinement.strategy == "global")
      triangulation.set_all_refine_flags();
    else
      {
        DieFeatures<dim> die;
        die.ids        = contact_parameters.die_ids;
        die.hot_points = contact.hot_points(contact_results);
        mark_cells(refinement,
                   refinement.indicator == "dual weighted" ?
                     goal_indicators(dof_handler, velocity, ram_force_dual()) :
                     refinement_indicators(refinement, dof_handler, velocity, die),
                   triangulation);
      }
    // The cell stress q + lambda div v (q = 0 without the augmented
    // Lagrangian) goes along as a piecewise constant: the next mesh's first
    // multiplier, if the iterative method may solve there.
    const bool                                   carry_stress = linear_solver.method != "direct";
    const dealii::FE_DGQ<dim>                    cell_fe(0);
    DoFHandler<dim>                              cell_dofs(triangulation);
    Vector<double>                               cell_values;
    std::vector<dealii::types::global_dof_index> index(1);
    if (carry_stress)
      {
        cell_dofs.distribute_dofs(cell_fe);
        cell_values.reinit(cell_dofs.n_dofs());
        const Vector<double> pressure = cell_pressures();
        const unsigned int   n_modes  = PressureProjection<dim>::n_modes_for(fe);
        for (const auto &cell : cell_dofs.active_cell_iterators())
          {
            cell->get_dof_indices(index);
            cell_values[index[0]] = -pressure[cell->active_cell_index() * n_modes];
          }
      }

    dealii::SolutionTransfer<dim, Vector<double>> transfer(dof_handler), cell_transfer(cell_dofs);
    triangulation.prepare_coarsening_and_refinement();
    transfer.prepare_for_coarsening_and_refinement(velocity);
    if (carry_stress)
      cell_transfer.prepare_for_coarsening_and_refinement(cell_values);
    triangulation.execute_coarsening_and_refinement();
    dof_handler.distribute_dofs(fe);
    Vector<double> transferred(dof_handler.n_dofs());
    transfer.interpolate(velocity, transferred);
    velocity = transferred;

    transferred_cell_stress.reinit(0);
    if (!carry_stress)
      return;
    cell_dofs.distribute_dofs(cell_fe);
    Vector<double> new_cell_values(cell_dofs.n_dofs());
    cell_transfer.interpolate(cell_values, new_cell_values);
    transferred_cell_stress.reinit(triangulation.n_active_cells());
    for (const auto &cell : cell_dofs.active_cell_iterators())
      {
        cell->get_dof_indices(index);
        transferred_cell_stress[cell->active_cell_index()] = new_cell_values[index[0]];
      }
  }



  template <int dim>
  bool
  DieFlowProblem<dim>::stop_at_target(RunSummary &summary) const
  {
    const CycleSummary &last = summary.cycles.back();
    summary.target_quantity  = refinement.target_quantity;
    summary.target_error     = refinement.target_error;
    summary.target_reached   = false;
    const double value = named_value(last.quantities, refinement.target_quantity);
    const double estimate =
      named_value(last.estimated_errors, refinement.target_quantity, std::numeric_limits<double>::infinity());
    // The estimate needs three cycles (Extrapolation::estimate).
    if (last.cycle >= 2 && estimate <= refinement.target_error * std::abs(value))
      {
        summary.target_reached = true;
        log << "  target error reached: " << refinement.target_quantity << " = " << std::setprecision(6) << value
            << " +- " << std::setprecision(2) << estimate << std::endl;
        return true;
      }
    // Near Maximum cells the marking refines fewer and fewer cells: stop
    // once a cycle has added less than a tenth.
    const bool at_limit =
      refinement.maximum_cells > 0 &&
      (last.cells >= refinement.maximum_cells ||
       (summary.cycles.size() > 1 && last.cells < 1.1 * summary.cycles[summary.cycles.size() - 2].cells));
    if (at_limit)
      {
        log << "  target error NOT reached: " << refinement.target_quantity << " = " << std::setprecision(6) << value
            << " +- " << std::setprecision(2) << estimate << " with " << triangulation.n_active_cells() << " cells, at Refinement/Maximum cells = "
            << refinement.maximum_cells << std::endl;
        return true;
      }
    if (last.cycle + 1 == refinement.cycles)
      log << "  target error NOT reached in Refinement/Cycles = " << refinement.cycles << " cycles: "
          << refinement.target_quantity << " = " << std::setprecision(6) << value << " +- " << std::setprecision(2)
          << estimate << std::endl;
    return false;
  }



  template <int dim>
  std::vector<std::string>
  DieFlowProblem<dim>::contact_changes() const
  {
    std::vector<std::string> changes = contact_parameters.settling_changes();
    changes.insert(changes.begin(), "refine the mesh at the die");
    return changes;
  }



  template <int dim>
  std::vector<std::string>
  DieFlowProblem<dim>::law_changes() const
  {
    return material.range_changes();
  }



  template <int dim>
  void
  DieFlowProblem<dim>::guard_contact(CycleSummary &cycle, NonlinearResult &result) const
  {
    if (contact.empty())
      return;
    // The inequalities the converged state must keep (contact_checks,
    // relative): the active set's dead band of 1e-6, friction within its
    // cone and opposing the slip to round-off (in 3D within its cone to
    // 1e-8: the semismooth Newton method's friction force reaches the cone
    // as Newton converges, not by construction; die2d's section extruded,
    // tests/rectangular_bar_quarter, ends 2e-11 beyond it at a residual of
    // 7e-9), sticking nodes at rest to 1e-8. A direction held in contact
    // to end a cycle of the states sits where contact gives way to
    // separation, whose exact pressure is zero: its pull is that transition
    // falling between nodes, allowed to 1e-4.
    // Penalty enforcement keeps the first and the last only approximately.
    const bool exact_normal = contact_parameters.normal_enforcement == "active set";
    const bool exact_stick  = exact_normal && contact_parameters.stick_enforcement == "exact";
    const std::vector<std::tuple<std::string, double, double, bool>> checks = {
      {"penetration", cycle.contact_penetration, 1e-6, exact_normal},
      {"pull of the die", cycle.contact_tension, cycle.held_in_contact > 0 ? 1e-4 : 1e-6, exact_normal},
      {"friction beyond its bound", cycle.friction_excess, dim == 3 ? 1e-8 : 1e-12, true},
      {"friction driving the slip", cycle.friction_power, 1e-12, true},
      {"sliding of sticking nodes", cycle.stick_slip_rate, 1e-8, exact_stick}};
    std::ostringstream broken;
    for (const auto &[name, value, bound, applies] : checks)
      if (applies && !(value <= bound))
        broken << (broken.tellp() > 0 ? ", " : "") << name << ' ' << std::setprecision(1) << value << " (above "
               << bound << ")";
    if (broken.tellp() == 0)
      return;
    std::ostringstream what;
    what << "the converged state breaks the contact conditions: " << broken.str() << " of the largest force or speed";
    if (cycle.held_in_contact > 0)
      what << ", with " << cycle.held_in_contact << " direction(s) held in contact to end a cycle of the states";
    what << "; ";
    // Round-off, not the mesh, when the penalty is beyond double precision.
    constexpr double largest_penalty = 1e10;
    if (!augmented && material.penalty_factor > largest_penalty)
      what << "lower Material/Penalty factor (it is " << deck_number(material.penalty_factor)
           << ") to 1e10: beyond it round-off breaks the constraints";
    else
      what << one_of_changes(contact_changes(), "");
    cycle.converged  = false;
    result.converged = false;
    result.failure   = what.str();
  }



  template <int dim>
  void
  DieFlowProblem<dim>::guard_mass_balance(CycleSummary &cycle, NonlinearResult &result, RunSummary &summary) const
  {
    const double tolerance = nonlinear_solver.mass_balance_tolerance;
    if (tolerance == 0)
      {
        cycle.mass_balance_status = "off";
        return;
      }
    const MassBalance &balance = cycle.mass_balance;
    cycle.mass_balance_status  = mass_balance_status(balance, tolerance);
    if (cycle.mass_balance_status == "ok")
      return;
    std::ostringstream what;
    what << "the penalty lost " << std::setprecision(2) << 100 * balance.worst()
         << " % of the flow (mass balance " << std::scientific << balance.loss << ", cells' volume change "
         << balance.volume_change << std::defaultfloat << ", against Nonlinear solver/Mass balance tolerance = "
         << tolerance << "): the forces are off by about as much; "
         << mass_balance_advice(balance, tolerance, penalty_factor(), augmented, linear_solver.divergence_tolerance);
    if (cycle.mass_balance_status == "failed")
      {
        cycle.converged  = false;
        result.converged = false;
        result.failure   = what.str();
        return;
      }
    const std::string warning = "cycle " + std::to_string(cycle.cycle) + ": " + what.str();
    summary.warnings.push_back(warning);
    log << "  warning: " << what.str() << std::endl;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::advance_strain(const double a, const double b)
  {
    // The positions' rule, from the rates on the configuration x_n.
    const Vector<double> rate = cell_strain_rates(coordinates, dof_handler, velocity);
    equivalent_strain.add(a, rate);
    if (b != 0)
      equivalent_strain.add(b, previous_strain_rate);
    previous_strain_rate = rate;
    update_hardening();
  }



  template <int dim>
  void
  DieFlowProblem<dim>::update_hardening()
  {
    if (!material.hardens())
      return;
    cell_hardening.reinit(equivalent_strain.size());
    for (unsigned int c = 0; c < cell_hardening.size(); ++c)
      cell_hardening[c] = material.hardening(equivalent_strain[c]);
    assembler.set_cell_hardening(&cell_hardening);
  }



  template <int dim>
  std::pair<double, double>
  DieFlowProblem<dim>::move_weights(const unsigned int n) const
  {
    // Adams-Bashforth 2 assumes v smooth in time; when faces came onto a die
    // or left it with the last move, v_{n-1} belongs to another contact
    // state: restart with forward Euler (as on the first step, where there
    // is no v_{n-1}, which weights() knows).
    const bool contact_changed = last_gap_update.entered + last_gap_update.left > 0;
    const bool have_previous   = previous_velocity.size() == dof_handler.n_dofs();
    return time_stepping.weights(n, contact_changed || !have_previous);
  }



  template <int dim>
  void
  DieFlowProblem<dim>::advance_configuration(const unsigned int n)
  {
    dealii::TimerOutput::Scope scope(timer, "mesh motion");
    const auto [a, b]           = move_weights(n);
    Vector<double> displacement = velocity;
    displacement *= a;
    if (b != 0)
      displacement.add(b, previous_velocity);
    previous_velocity = velocity;
    advance_strain(a, b);

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
    fixed_walls.keep(triangulation);
    const double dt = time_stepping.time(n + 1) - time_stepping.time(n);
    for (const auto &[id, components] : contact_parameters.die_velocities)
      {
        const Tensor<1, dim> shift = dt * contact.velocity_of(id);
        if (die_surfaces.count(id))
          die_surfaces.at(id).translate(shift);
        gaps.translate(id, shift);
      }
    last_gap_update = gaps.update(old_vertices, in_contact, triangulation,
                                   std::cos(boundary_conditions.corner_angle * dealii::numbers::PI / 180.));
  }



  template <int dim>
  double
  DieFlowProblem<dim>::ram_stroke(const double time) const
  {
    if (boundary_conditions.velocity_ids.empty())
      return contact.velocity_of(goal_part()).norm() * time;
    return std::abs(ram_displacement());
  }



  template <int dim>
  double
  DieFlowProblem<dim>::ram_displacement() const
  {
    if (ram_start.empty())
      return ram_offset;
    const auto &vertices = triangulation.get_vertices();
    double      sum      = 0;
    for (const auto &[index, start] : ram_start)
      sum += vertices[index][0] - start[0];
    return ram_offset + sum / ram_start.size();
  }



  template <int dim>
  void
  DieFlowProblem<dim>::record_ram_start()
  {
    ram_start.clear();
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face->boundary_id() == goal_part())
          for (const unsigned int v : face->vertex_indices())
            ram_start.emplace(face->vertex_index(v), face->vertex(v));
  }



  template <int dim>
  void
  DieFlowProblem<dim>::remesh(const unsigned int n, const double jacobian_before)
  {
    dealii::TimerOutput::Scope scope(timer, "remeshing");
    RemeshRecord record;
    record.step                     = n;
    record.cells_before             = triangulation.n_active_cells();
    record.jacobian_before          = jacobian_before;
    const double volume_before      = domain_volume(coordinates, triangulation);
    const Point<dim> worst_before   = worst_cell_centre(triangulation);
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
    const NewMesh new_mesh = remesh_domain(triangulation, fresh, remeshing.boundary_edge_length, edge_out_of_its_die, "Incremental/Remesh below Jacobian");

    // The velocity (the next solve's first iterate) and the strain go over
    // to the new mesh.
    dealii::DoFHandler<dim> fresh_dofs(fresh);
    fresh_dofs.distribute_dofs(fe);
    const MeshTransfer<dim> transfer(dof_handler, fresh_dofs, "before step " + std::to_string(n));
    const Vector<double>    fresh_velocity          = transfer.nodal(velocity);
    const Vector<double>    fresh_previous_velocity = transfer.nodal(previous_velocity);
    const Vector<double>    fresh_strain            = transfer.per_cell(equivalent_strain);
    const Vector<double>    fresh_previous_rate     = transfer.per_cell(previous_strain_rate);

    // The ram's stroke goes on from where it is.
    ram_offset = ram_displacement();
    // The same cells in the same order: distribute_dofs() numbers the copy
    // as it numbered fresh_dofs.
    triangulation.clear();
    triangulation.copy_triangulation(fresh);
    dof_handler.reinit(triangulation);
    dof_handler.distribute_dofs(fe);
    velocity             = fresh_velocity;
    previous_velocity    = fresh_previous_velocity;
    equivalent_strain    = fresh_strain;
    previous_strain_rate = fresh_previous_rate;
    update_hardening();
    transferred_cell_stress.reinit(0);
    record_ram_start();
    fixed_walls.initialize(triangulation, boundary_conditions.wall_ids());
    gaps.renumber_faces(new_mesh.boundary_face_of_old);

    record.cells_after    = triangulation.n_active_cells();
    record.jacobian_after = smallest_scaled_jacobian(triangulation);
    record.volume_change  = domain_volume(coordinates, triangulation) / volume_before - 1;
    record.split_edges    = new_mesh.split_edges;
    record.dropped_vertices = new_mesh.dropped_vertices;
    last_remesh           = record;
    steps_since_remesh    = 0;
    log << "  new mesh before step " << n << " (t = " << std::setprecision(6) << time_stepping.time(n)
        << " s): smallest scaled Jacobian " << std::setprecision(3) << record.jacobian_before << " (the cell at "
        << worst_before << ") -> "
        << record.jacobian_after << ", " << record.cells_before << " -> " << record.cells_after
        << " cells, volume change " << std::setprecision(2) << record.volume_change << std::setprecision(6);
    if (record.dropped_vertices > 0)
      log << ", " << record.dropped_vertices << " crowding boundary vertices dropped";
    if (!new_mesh.attempt.empty())
      log << ", Gmsh's first attempt failed, made with " << new_mesh.attempt;
    if (transfer.n_in_folds() > 0)
      log << ", " << transfer.n_in_folds() << " new nodes or cell centres in folded cells (the nearest cell's values)";
    log << std::endl;
  }



  template <int dim>
  StepRecord
  DieFlowProblem<dim>::step_record(const unsigned int n) const
  {
    StepRecord record;
    record.step   = n;
    record.time   = time_stepping.time(n);
    record.stroke = ram_stroke(record.time);
    const Vector<double> volumes    = cell_volumes(coordinates, triangulation);
    record.volume                   = std::accumulate(volumes.begin(), volumes.end(), 0.);
    record.volume_change            = initial_volume > 0 ? record.volume / initial_volume - 1 : 0;
    record.smallest_scaled_jacobian = smallest_scaled_jacobian(triangulation);
    record.faces_entered            = last_gap_update.entered;
    record.faces_left               = last_gap_update.left;
    record.penetration              = last_gap_update.penetration;
    record.mean_strain              = (volumes * equivalent_strain) / record.volume;
    record.max_strain               = equivalent_strain.linfty_norm();
    if (last_remesh && last_remesh->step == n)
      record.remesh = last_remesh;
    return record;
  }



  template <int dim>
  void
  DieFlowProblem<dim>::write_load_stroke(const RunSummary &summary) const
  {
    AtomicFile    file(run_parameters.output_directory + "/load-stroke.txt");
    std::ostream &out = file.stream();
    out << "# Problem = incremental: one row per step (summary.json has the same per cycle).\n"
        << "# stroke: " << (boundary_conditions.velocity_ids.empty() ? "the travel of die " : "mean x displacement of the vertices of boundary part ")
        << goal_part() << " (mm); forces as in summary.json (plane strain N/mm, else N);\n"
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
    out << earlier_load_stroke << load_stroke_rows(summary);
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



  template <int dim>
  NonlinearResult
  DieFlowProblem<dim>::settle_free_surface(NonlinearResult result, CycleSummary &cycle)
  {
    if constexpr (dim == 2)
      {
        FreeSurfaceRecord record;
        free_surface.new_mesh();
        while (result.converged)
          {
            const bool      last = record.moves == free_surface_parameters.iterations;
            FreeSurfaceMove move;
            {
              dealii::TimerOutput::Scope scope(timer, "mesh motion");
              move = free_surface.move(triangulation, dof_handler, velocity, contact.results(velocity), !last);
            }
            record.largest_move = move.largest;
            record.free_faces   = move.free_faces;
            log << "  free surface: largest move " << std::setprecision(3) << move.largest << " of an edge, "
                << move.free_faces << " free faces (" << move.let_go << " let go by the dies, " << move.reattached
                << " back on them)" << std::setprecision(6) << std::endl;
            record.settled = move.largest <= free_surface_parameters.tolerance;
            if (record.settled)
              break;
            if (last)
              {
                result.converged = false;
                result.failure   = "the free surface did not settle in " + std::to_string(record.moves) +
                                 " moves (the last would move a node " + deck_number(move.largest) +
                                 " of its edge): raise Free surface/Iterations or Tolerance";
                break;
              }
            ++record.moves;
            require(smallest_scaled_jacobian(triangulation) > 0,
                    "Free surface/Iterations",
                    "the free surface's move tangled the mesh (a cell turned inside out): refine the mesh where the metal "
                    "leaves the die, or use Problem = incremental");
            states_from_previous_mesh = true;
            setup_system();
            NonlinearResult next = nonlinear_solver.solve(*this, velocity, log);
            next.iterations += result.iterations;
            next.linear_solves += result.linear_solves;
            result = next;
          }
        cycle.free_surface = record;
      }
    return result;
  }



  template <int dim>
  RunSummary
  DieFlowProblem<dim>::run()
  {
    dealii::Timer run_timer;
    RunSummary    summary;
    summary.velocity_degree = fe.degree;
    summary.geometry        = dim == 3 ? "3d" : geometry_name(coordinates.kind());
    summary.problem         = time_stepping.incremental ? "incremental" : "steady";
    const std::string summary_file = run_parameters.output_directory + "/summary.json";
    // Steady: the refinement cycles. Incremental: a solve at t_0, ..., t_N.
    const bool         incremental = time_stepping.incremental;
    const std::string  unit        = incremental ? "step " : "cycle ";
    const unsigned int n_solves    = incremental ? time_stepping.n_steps() + 1 : refinement.cycles;
    unsigned int first_solve = 0;
    if (incremental && !checkpoint.restart_from.empty())
      first_solve = load_checkpoint(summary) + 1;
    else if (incremental)
      {
        initial_volume = domain_volume(coordinates, triangulation);
        record_ram_start();
        fixed_walls.initialize(triangulation, boundary_conditions.wall_ids());
        equivalent_strain.reinit(triangulation.n_active_cells());
        update_hardening();
        if (!contact.empty())
          gaps.initialize(triangulation, contact_parameters.die_ids, die_surfaces, boundary_conditions.traction_free_ids);
      }
    if constexpr (dim == 2)
      if (free_surface_parameters.enabled())
        free_surface.initialize(triangulation, contact_parameters.die_ids, free_surface_parameters);

    for (unsigned int cycle = first_solve; cycle < n_solves; ++cycle)
      {
        dealii::Timer cycle_timer;
        if (cycle > 0 && interrupt::requested())
          {
            // Between two steps the state is a converged step's: the place to go on from.
            if (incremental && cycle > first_solve &&
                (summary.checkpoint_file.empty() || summary.checkpoint_step + 1 != cycle))
              save_checkpoint(cycle - 1, summary);
            summary.interrupted = true;
            summary.failure     = "stopped by " + interrupt::signal_name() + " before " + unit + std::to_string(cycle);
            log << "  INTERRUPTED before " << unit << cycle << std::endl;
            break;
          }
        current_step = cycle;
        if (cycle > 0)
          {
            if (incremental)
              {
                advance_configuration(cycle - 1);
                const double jacobian = smallest_scaled_jacobian(triangulation);
                if (remeshing.enabled() &&
                    remeshing.due(jacobian, ++steps_since_remesh, last_remesh ? last_remesh->jacobian_after : 1.))
                  remesh(cycle, jacobian);
                // Without new meshes the run would go on with cells turned
                // inside out, and forces of no meaning (the extrusion start
                // without them: ram force 579-5572 N/mm, exit 0). A corner a
                // little past straight (a cell squeezed to a triangle where a
                // side folds onto a platen, a fold's round-off) leaves every
                // quadrature point's Jacobian positive: the run goes on.
                if (!remeshing.enabled() && !(jacobian > -0.1))
                  {
                    std::ostringstream where;
                    where << std::setprecision(3) << "the move to step " << cycle
                          << " turned cells inside out (smallest scaled Jacobian "
                          << jacobian << ", the cell at " << worst_cell_centre(triangulation)
                          << "); set it (about 0.2-0.3) for new meshes when cells degrade (2D), or lower "
                             "Incremental/Time step";
                    throw InputError("Incremental/Remesh below Jacobian: " + where.str());
                  }
              }
            else
              refine_mesh();
            states_from_previous_mesh = true;
          }
        setup_system();
        log << unit << cycle << ": ";
        if (incremental)
          log << "t = " << time_stepping.time(cycle) << " s, ";
        log << triangulation.n_active_cells() << " cells, " << dof_handler.n_dofs() << " dofs" << std::endl;

        CycleSummary cycle_summary;
        cycle_summary.cycle = cycle;
        start_solves        = 0;
        contact_assemblies  = 0;
        friction_terms      = 0;
        pressure_recoveries = 0;
        linear_solver.counts = LinearSolverCounts();
        NonlinearResult result;
        Vector<double>  start;
        try
          {
            if (cycle == 0)
              newtonian_start();
            assembler.update_dual(dof_handler, velocity, nullptr, 0);
            start = velocity;
            constraints.distribute(start);
            result = nonlinear_solver.solve(*this, velocity, log);
            if (free_surface_parameters.enabled() && result.converged)
              result = settle_free_surface(result, cycle_summary);
          }
        catch (const SolverFailure &failure)
          {
            result.failure = std::string(failure.what()) + " for the Newtonian start";
          }
        cycle_summary.converged            = result.converged;
        cycle_summary.nonlinear_iterations = result.iterations;
        cycle_summary.linear_solves        = result.linear_solves + start_solves;
        cycle_summary.linear_method        = augmented || mixed_form ? "iterative" : "direct";
        cycle_summary.linear_counts        = linear_solver.counts;
        cycle_summary.history              = result.history;
        if (start.size() == velocity.size() && velocity.l2_norm() > 0)
          {
            start -= velocity;
            cycle_summary.start_distance = start.l2_norm() / velocity.l2_norm();
          }

        if (incremental)
          cycle_summary.step = step_record(cycle);
        postprocess(cycle_summary);
        if (result.converged)
          guard_mass_balance(cycle_summary, result, summary);
        if (result.converged)
          guard_contact(cycle_summary, result);
        cycle_summary.wall_time = cycle_timer.wall_time();
        if (!incremental)
          {
            study.add(cycle_summary);
            if (cycle > 0)
              for (const auto &[name, e] : study.extrapolations())
                cycle_summary.estimated_errors.emplace_back(name, e.estimate);
          }
        summary.cycles.push_back(cycle_summary);
        if (incremental)
          write_load_stroke(summary);

        if (!result.converged)
          {
            summary.interrupted = result.interrupted;
            summary.failure = unit + std::to_string(cycle) + ": " + result.failure;
            log << "  NOT CONVERGED: " << result.failure << std::endl;
            break;
          }
        log << "  converged: " << result.iterations << " iterations, " << cycle_summary.linear_solves
            << " linear solves, divergence ratio " << std::scientific << std::setprecision(2)
            << cycle_summary.divergence_ratio << std::defaultfloat << std::endl;
        if (augmented || mixed_form)
          log << "  iterative linear solver: " << linear_solver.counts.iterative_solves << " solves, "
              << linear_solver.counts.krylov_iterations << " Krylov iterations, " << linear_solver.counts.direct_fallbacks
              << " direct fallbacks" << partial_steps_text(linear_solver.counts.partial_steps) << std::endl;
        if (incremental && checkpoint.due(cycle, time_stepping.n_steps()))
          save_checkpoint(cycle, summary);
        summary.wall_time = run_timer.wall_time();
        write_summary_json(summary, summary_file);
        if (refinement.target_error > 0 && stop_at_target(summary))
          break;
      }

    summary.converged = summary.failure.empty();
    summary.wall_time = run_timer.wall_time();
    for (const auto &[name, e] : study.extrapolations())
      {
        QuantityEstimate q;
        q.name                = name;
        q.extrapolated        = e.value;
        q.extrapolation_error = e.error;
        q.order               = e.order;
        q.estimate            = e.estimate;
        q.last                = named_value(summary.cycles.back().quantities, name);
        summary.extrapolated.push_back(q);
      }
    if (!incremental)
      {
        AtomicFile table(run_parameters.output_directory + "/study.txt");
        study.write(table.stream());
        table.commit();
        if (refinement.cycles > 1)
          study.write(log);
      }
    summary.stage_wall_time = timer.get_summary_data(dealii::TimerOutput::total_wall_time);
    dealii::Utilities::System::MemoryStats memory;
    dealii::Utilities::System::get_memory_stats(memory);
    summary.peak_memory_mb = memory.VmHWM / 1024.;
    summary.threads        = threads::running();
    write_summary_json(summary, summary_file);

    write_result_summary(summary, log);
    log << "wall time " << std::fixed << std::setprecision(3) << summary.wall_time << " s:";
    for (const auto &[stage, seconds] : summary.stage_wall_time)
      log << ' ' << stage << ' ' << seconds;
    log << "; peak memory " << std::setprecision(1) << summary.peak_memory_mb << " MB; " << summary.threads
        << (summary.threads == 1 ? " thread" : " threads") << std::defaultfloat << std::setprecision(6) << std::endl;
    return summary;
  }

  template class DieFlowProblem<2>;
  template class DieFlowProblem<3>;
} // namespace dieflow
