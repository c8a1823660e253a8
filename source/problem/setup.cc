// The die-flow problem's set-up: the deck and the mesh, and for each mesh its dofs, constraints and system.
#include <dieflow/base/processes.h>
#include <dieflow/mesh/singular_points.h>
#include <dieflow/problem/problem.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <cmath>
#include <sstream>

namespace dieflow
{
  namespace
  {
    template <int dim>
    ReportSettings<dim>
    report_settings(const ProblemParameters<dim> &parameters)
    {
      ReportSettings<dim> settings;
      settings.output_directory       = parameters.run.output_directory;
      settings.write_vtu              = parameters.run.write_vtu;
      settings.write_gnuplot          = parameters.run.write_gnuplot;
      settings.write_mesh_svg         = parameters.run.write_mesh_svg;
      settings.dual_weighted_estimate = parameters.refinement.dual_weighted_estimate;
      settings.exact_velocity         = parameters.exact_velocity.get();
      settings.probe                  = parameters.probe;
      // A deck without any prescribed velocity has no goal part unless a
      // die drives it (the checks after the mesh refuse the rest).
      if (!parameters.boundary_conditions.velocity_ids.empty() || !parameters.contact.die_velocities.empty())
        settings.goal_part = parameters.goal_part();
      return settings;
    }

    /// Refuses, on more than one process, what is not yet distributed (doc/parallel.md).
    template <int dim>
    void
    check_processes(const ProblemParameters<dim> &parameters, const dealii::Triangulation<dim> &triangulation)
    {
      const std::string processes_started = std::to_string(processes::n()) + " MPI processes";
      require(!parameters.time_stepping.incremental,
              "Problem",
              "incremental runs are not yet distributed (the remeshing, the transfer of fields and the checkpoint): "
              "run this deck on one process, without mpirun (started as " + processes_started + ", doc/parallel.md)");
      require(triangulation.n_active_cells() >= 2 * processes::n(),
              "Mesh",
              std::to_string(triangulation.n_active_cells()) + " cells for " + processes_started +
                ": each process needs at least two cells to assemble; run on fewer processes or refine the mesh");
    }
  } // namespace



  template <int dim>
  void
  DieFlowProblem<dim>::declare_parameters(ParameterHandler &prm, const DeckLayout &layout)
  {
    ProblemParameters<dim>::declare_parameters(prm, layout);
  }



  template <int dim>
  DieFlowProblem<dim>::DieFlowProblem(ParameterHandler &prm, const std::string &deck_directory, std::ostream &log)
    : parameters(prm, deck_directory)
    , log(log)
    , timer(log, dealii::TimerOutput::never, dealii::TimerOutput::wall_times)
    , assembler(parameters.material, nullptr)
    , linear_solver(parameters.linear_solver)
    , mesh(processes::new_triangulation<dim>())
    , triangulation(*mesh)
    , fe(dealii::FE_Q<dim>(parameters.velocity_degree), dim)
    , dof_handler(triangulation)
    , incompressibility(parameters.material, parameters.coordinates, dof_handler, linear_solver, log)
    , system(dof_handler, update_constraints, assembler, contact, &row_sums)
    , incremental(parameters.time_stepping, parameters.coordinates, parameters.material)
    , heat(parameters.heat, parameters.material, parameters.coordinates, triangulation, parameters.velocity_degree)
    , strain(parameters.strain, parameters.material, parameters.coordinates, triangulation, parameters.velocity_degree)
    , report(report_settings(parameters), log)
  {
    contact.initialize(parameters.contact);
    for (const auto &[id, file] : parameters.contact.die_surface_files)
      die_surfaces[id].read(file, deck_directory, "Contact/Die surfaces");

    const auto &bc = parameters.boundary_conditions;
    assembler.set_coordinate_system(parameters.coordinates);
    assembler.set_tangent(parameters.nonlinear_solver.newton_tangent == NonlinearSolver::NewtonTangent::standard ?
                            FlowAssembler<dim>::Tangent::standard :
                            FlowAssembler<dim>::Tangent::primal_dual);
    if (bc.has_body_force)
      assembler.set_body_force(bc.body_force.get());
    if (!bc.traction_ids.empty())
      assembler.set_traction(bc.traction.get(), bc.traction_ids);

    // On P > 1 the mesh is made and checked as a plain one, then copied
    // (with its manifolds) into the shared one, which partitions it: the
    // mesh makers need not know the shared mesh, and a mesh of fewer cells
    // than processes is refused before METIS would be asked to divide it.
    dealii::Triangulation<dim>  plain;
    dealii::Triangulation<dim> &made = processes::n() > 1 ? plain : triangulation;
    make_mesh(parameters.mesh, made);
    parameters.check_mesh(made);
    if (parameters.mesh.corner_refinements > 0)
      {
        std::set<BoundaryId> walls = parameters.contact.die_ids;
        walls.insert(bc.slip_wall_ids.begin(), bc.slip_wall_ids.end());
        grade_towards(wall_corners(made, walls), parameters.mesh.corner_refinements, parameters.mesh.corner_width, made);
      }
    parameters.check_graded_mesh(made, log);
    if (processes::n() > 1)
      {
        check_processes(parameters, made);
        triangulation.copy_triangulation(made);
      }
  }



  template <int dim>
  void
  DieFlowProblem<dim>::setup_system()
  {
    dealii::TimerOutput::Scope scope(timer, "setup");
    const auto &               bc = parameters.boundary_conditions;
    // Which cells this process assembles (all of them on one), and its rows.
    processes::distribute_dofs(dof_handler, fe);

    hanging_node_constraints.clear();
    dealii::DoFTools::make_hanging_node_constraints(dof_handler, hanging_node_constraints);
    hanging_node_constraints.close();

    const bool in_time = parameters.time_stepping.incremental;
    wall_nodes = collect_wall_nodes(parameters.coordinates, dof_handler, parameters.wall_ids(), hanging_node_constraints,
                                    bc.corner_angle);
    attach_die_surfaces(die_surfaces, bc.corner_angle, in_time, wall_nodes);
    if (in_time && !die_surfaces.empty() && !incremental.gaps.empty())
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
        incremental.gaps.close_gaps(
          wall_nodes, given, reach, std::cos(bc.corner_angle * dealii::numbers::PI / 180.), gap_rate);
      }
    if (!in_time)
      check_steady_die_motion();
    if (!contact.empty())
      {
        bc.make_prescribed_constraints(dof_handler, prescribed_constraints);
        contact.setup(wall_nodes, prescribed_constraints, dof_handler.n_dofs() > 0 && contact_states_valid,
                      approaching_nodes());
      }
    make_constraints();

    // Wall and Dirichlet constraints only couple the components of one node,
    // which the pattern couples anyway: the hanging-node pattern serves all.
    // On P > 1 each process's cells' entries, to which RowSums adds the
    // other processes' in its own rows.
    {
      dealii::DynamicSparsityPattern dsp(dof_handler.n_dofs());
      dealii::DoFTools::make_sparsity_pattern(dof_handler, dsp, hanging_node_constraints, false,
                                              processes::n() > 1 ? processes::rank() :
                                                                   dealii::numbers::invalid_subdomain_id);
      row_sums.reinit(dsp, sparsity_pattern);
    }
    system_matrix.reinit(sparsity_pattern);
    incompressibility.reinit(hanging_node_constraints, velocity, system_matrix);
    system_rhs.reinit(dof_handler.n_dofs());
    if (parameters.heat.enabled())
      {
        // The hardening (Hansel-Spittel's (1 + eps)^(m5 T)) reads T where the flow does.
        strain.set_flow_temperatures(heat.flow_temperatures());
        incremental.set_flow_temperatures(heat.flow_temperatures());
        heat.setup();
      }
    if (parameters.steady_strain())
      strain.setup();
  }



  template <int dim>
  void
  DieFlowProblem<dim>::make_constraints()
  {
    const auto &bc = parameters.boundary_conditions;
    bc.make_constraints(dof_handler, hanging_node_constraints, wall_nodes, false, constraints);
    contact.add_constraints(constraints, false);
    constraints.close();
    bc.make_constraints(dof_handler, hanging_node_constraints, wall_nodes, true, update_constraints);
    contact.add_constraints(update_constraints, true);
    update_constraints.close();
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
  FlowTerms<dim>
  DieFlowProblem<dim>::flow_terms()
  {
    FlowTerms<dim> terms = incompressibility.terms();
    terms.hardening      = parameters.time_stepping.incremental ? incremental.hardening() : nullptr;
    if (parameters.heat.enabled())
      terms.temperature = heat.flow_temperatures();
    if (parameters.steady_strain() && parameters.material.hardens())
      terms.point_hardening = strain.flow_hardening();
    return terms;
  }



  template <int dim>
  SolutionView<dim>
  DieFlowProblem<dim>::solution_view()
  {
    return SolutionView<dim>{parameters.coordinates,
                             parameters.material,
                             parameters.boundary_conditions,
                             dof_handler,
                             hanging_node_constraints,
                             update_constraints,
                             wall_nodes,
                             velocity,
                             assembler,
                             flow_terms(),
                             incompressibility,
                             contact,
                             parameters.time_stepping.incremental ? &incremental.equivalent_strain : nullptr,
                             parameters.heat.enabled() ? &heat.record() : nullptr,
                             parameters.heat.enabled() ? &heat : nullptr,
                             parameters.steady_strain() ? &strain.record() : nullptr,
                             parameters.steady_strain() ? &strain : nullptr};
  }

  template class DieFlowProblem<2>;
  template class DieFlowProblem<3>;
} // namespace dieflow
