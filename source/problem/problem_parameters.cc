// The deck's parameters in one structure: each piece's subsection, and the checks of entries against each other.
#include <dieflow/base/expressions.h>
#include <dieflow/problem/problem_parameters.h>

#include <deal.II/base/utilities.h>

#include <algorithm>

namespace dieflow
{
  void
  RunParameters::declare_parameters(ParameterHandler &prm)
  {
    using dealii::Patterns::Bool;
    using dealii::Patterns::Anything;
    using dealii::Patterns::Integer;
    prm.declare_entry("Dimension",
                      "2",
                      Integer(2, 3),
                      "Space dimension of the problem: 2 (plane strain or "
                      "axisymmetric, see Geometry) or 3.");
    prm.declare_entry("Geometry",
                      "plane strain",
                      dealii::Patterns::Selection("plane strain|axisymmetric"),
                      "What the 2D mesh is a section of. plane strain: a body of "
                      "unit depth (forces in N/mm of depth). axisymmetric: the "
                      "meridian half-plane of a body of revolution about the x "
                      "axis, y the radius (y >= 0 everywhere on the mesh): round "
                      "bars, wires, tubes, cylinders. The strain rate gains the "
                      "hoop rate v_y/y, every integral the factor 2 pi y, and "
                      "forces are the whole body's, in N. Boundary parts on the "
                      "axis y = 0 must be Symmetry ids (v_y = 0 there). With "
                      "Dimension = 3 the mesh is the body itself: leave it at "
                      "plane strain (summary.json says 3d; forces in N).");
    prm.declare_entry("Output directory",
                      "output/die2d",
                      Anything(),
                      "Directory for summary.json, the study table, the die-wall "
                      "profiles and the VTU/PVD files. Created if it does not "
                      "exist; relative paths are relative to the working "
                      "directory.");
    prm.declare_entry("Write VTU",
                      "true",
                      Bool(),
                      "Write the solution of every cycle as VTU with a PVD index "
                      "for ParaView (velocity, pressure, equivalent strain rate "
                      "and stress, viscosity). summary.json is always written.");
    prm.declare_entry("Write gnuplot",
                      "false",
                      Bool(),
                      "Also write the fields of every cycle as solution-CYCLE.gnuplot "
                      "(columns x, y, velocity, derived fields, pressure; one "
                      "block per cell) for gnuplot's pm3d, without ParaView.");
    prm.declare_entry("Write mesh SVG",
                      "false",
                      Bool(),
                      "Write the mesh of every cycle as mesh-CYCLE.svg, to see "
                      "the refinement without ParaView.");
  }



  void
  RunParameters::parse_parameters(ParameterHandler &prm)
  {
    dimension        = prm.get_integer("Dimension");
    geometry         = prm.get("Geometry") == "axisymmetric" ? Geometry::axisymmetric : Geometry::plane_strain;
    output_directory = prm.get("Output directory");
    write_vtu        = prm.get_bool("Write VTU");
    write_mesh_svg   = prm.get_bool("Write mesh SVG");
    write_gnuplot    = prm.get_bool("Write gnuplot");
    require(dimension == 2 || geometry == Geometry::plane_strain,
            "Geometry",
            "axisymmetric is the meridian half-plane of a 2D mesh; with Dimension = 3 the mesh is the "
            "body itself (leave Geometry at plane strain, or set Dimension = 2)");
    require(dimension == 2 || !write_mesh_svg,
            "Write mesh SVG",
            "draws a 2D mesh only; set it false with Dimension = 3 (the VTU shows the 3D mesh)");
    require(!output_directory.empty(),
            "Output directory",
            "must not be empty (use . for the working directory)");
    check_output_directory(output_directory);
  }






  template <int dim>
  void
  ProblemParameters<dim>::declare_parameters(ParameterHandler &prm, const DeckLayout &layout)
  {
    RunParameters::declare_parameters(prm);
    MeshParameters::declare_parameters(prm);
    Material::declare_parameters(prm);
    BoundaryConditions<dim>::declare_parameters(prm, layout.velocity_ids);
    NonlinearSolver::declare_parameters(prm);
    LinearSolverParameters::declare_parameters(prm);
    RefinementParameters::declare_parameters(prm);
    TimeStepping::declare_parameters(prm);
    prm.enter_subsection("Incremental");
    RemeshingParameters::declare_parameters(prm);
    CheckpointParameters::declare_parameters(prm);
    prm.leave_subsection();
    ContactParameters::declare_parameters(prm);
    FreeSurfaceParameters::declare_parameters(prm);
    HeatParameters::declare_parameters(prm);
    StrainParameters::declare_parameters(prm);
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
  ProblemParameters<dim>::ProblemParameters(ParameterHandler &prm, const std::string &deck_directory)
  {
    run.parse_parameters(prm);
    prm.enter_subsection("Discretisation");
    velocity_degree = prm.get_integer("Velocity degree");
    prm.leave_subsection();
    coordinates = CoordinateSystem<dim>(run.geometry);
    mesh.parse_parameters(prm);
    mesh.base_directory = deck_directory;
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
    free_surface.parse_parameters(prm);
    heat.parse_parameters(prm);
    strain.parse_parameters(prm);
    check_entries();

    prm.enter_subsection("Refinement");
    const std::string probe_text = prm.get("Probe point");
    prm.leave_subsection();
    if (probe_text == "auto")
      {
        if (mesh.source == MeshParameters::Source::die2d)
          {
            const auto E = mesh.die2d.corner('E');
            // In the land also when it is shorter than 2 mm.
            const double before = std::min(1., 0.5 * mesh.die2d.land_length);
            probe               = dealii::Point<dim>();
            (*probe)[0]         = E[0] - before;
            (*probe)[1]         = 0.5 * E[1];
            if constexpr (dim == 3)
              (*probe)[2] = 0.5 * mesh.die2d.depth;
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
    contact.parse_parameters(prm);
    for (const auto &[id, components] : contact.die_velocities)
      require(components.size() == dim,
              "Contact/Die velocities",
              "id " + std::to_string(id) + ": " + std::to_string(components.size()) + " velocity component(s) given, " +
                std::to_string(dim) + " needed (write 'id: vx vy" + (dim == 3 ? " vz'" : "'") + ")");

    prm.enter_subsection("Verification");
    if (!prm.get("Exact velocity").empty())
      exact_velocity = parse_vector_expression<dim>("Verification/Exact velocity",
                                                    prm.get("Exact velocity"),
                                                    prm.get("Constants"));
    prm.leave_subsection();
  }



  template <int dim>
  void
  ProblemParameters<dim>::check_entries() const
  {
    require(!free_surface.enabled() || (dim == 2 && !time_stepping.incremental),
            "Free surface/Iterations",
            "a free surface is found for steady runs in 2D (plane strain, axisymmetric); an incremental "
            "run moves its free surface with the metal: set 0");
    for (const BoundaryId id : free_surface.ids)
      require(boundary_conditions.traction_free_ids.count(id),
              "Free surface/Free surface ids",
              "id " + std::to_string(id) + " is not one of Boundary conditions/Traction free ids: a free surface is traction free");
    require(!remeshing.enabled() || dim == 2 || !time_stepping.incremental,
            "Incremental/Remesh below Jacobian",
            "meshing the domain anew is available in 2D only (plane strain, axisymmetric); set 0 and "
            "Remesh interval = 0 for Dimension = 3");
    require(heat.model != HeatParameters::Model::steady || !time_stepping.incremental,
            "Heat/Model",
            "steady solves the steady heat equation, for Problem = steady; a run in time (Problem = "
            "incremental) takes transient");
    require(heat.model != HeatParameters::Model::transient || time_stepping.incremental,
            "Heat/Model",
            "transient steps the heat equation in time, for Problem = incremental; a steady run takes steady");
    require(!material.hardens() || time_stepping.incremental || heat.model != HeatParameters::Model::steady ||
              heat.degree == 0 || heat.degree == velocity_degree,
            "Heat/Degree",
            "a steady run with a hardening law takes the temperature's degree of the velocity (0 or " +
              std::to_string(velocity_degree) + "): the heat of deformation reads the hardening at the flow's points");
    require(!strain.requested || !time_stepping.incremental,
            "Equivalent strain/Steady field",
            "is for Problem = steady: a run in time carries the strain with the metal (set false)");
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
  }



  template <int dim>
  void
  ProblemParameters<dim>::check_mesh(const dealii::Triangulation<dim> &triangulation) const
  {
    auto assigned = boundary_conditions.assigned_ids();
    for (const BoundaryId id : contact.die_ids)
      {
        const auto [it, inserted] = assigned.emplace(id, "Contact/Die ids");
        require(inserted,
                "Contact/Die ids",
                "boundary id " + std::to_string(id) + " is already listed under " + it->second +
                  "; a boundary part has one condition (Die ids defaults to die2d's 3, 4: "
                  "'set Die ids =' for no contact)");
      }
    // In time, a die given as a surface may have no face of the metal on it
    // yet: the metal comes onto it.
    auto                           in_mesh  = assigned;
    const std::vector<BoundaryId> &mesh_ids = triangulation.get_boundary_ids();
    if (time_stepping.incremental)
      for (const auto &[id, file] : contact.die_surface_files)
        if (std::find(mesh_ids.begin(), mesh_ids.end(), id) == mesh_ids.end())
          in_mesh.erase(id);
    // The die faces the metal leaves take the first free-surface id.
    if (!free_surface.ids.empty() &&
        std::find(mesh_ids.begin(), mesh_ids.end(), free_surface.ids[0]) == mesh_ids.end())
      in_mesh.erase(free_surface.ids[0]);
    check_boundary_ids(triangulation, in_mesh);
    if (heat.enabled())
      {
        // The parts the heat equation names: in the mesh (or the free surface the dies' faces become).
        const auto known = [&](const BoundaryId id) {
          return std::find(mesh_ids.begin(), mesh_ids.end(), id) != mesh_ids.end() ||
                 std::find(free_surface.ids.begin(), free_surface.ids.end(), id) != free_surface.ids.end();
        };
        for (const BoundaryId id : heat.prescribed_ids)
          require(known(id), "Heat/Prescribed temperature ids", "id " + std::to_string(id) + " is not in the mesh");
        for (const auto &[id, h] : heat.transfer_coefficient)
          require(known(id), "Heat/Heat transfer coefficients", "id " + std::to_string(id) + " is not in the mesh");
        for (const auto &[id, e] : heat.emissivity)
          require(known(id), "Heat/Emissivities", "id " + std::to_string(id) + " is not in the mesh");
        for (const auto &[id, e] : heat.die_effusivity)
          require(contact.die_ids.count(id),
                  "Heat/Die effusivities",
                  "id " + std::to_string(id) + " is not one of Contact/Die ids");
      }
    // A free surface needs faces to start from: its own, or a die's to leave.
    if (free_surface.enabled() && contact.die_ids.empty())
      {
        bool has_free_faces = false;
        for (const BoundaryId id : free_surface.ids)
          has_free_faces |= std::find(mesh_ids.begin(), mesh_ids.end(), id) != mesh_ids.end();
        require(has_free_faces,
                "Free surface/Free surface ids",
                "no face of the mesh has these ids and Contact/Die ids is empty: there is no surface for the metal to "
                "leave; give the die ids, or set Free surface/Iterations = 0");
      }
    if (coordinates.axisymmetric())
      check_axisymmetric_mesh(triangulation, boundary_conditions.symmetry_ids);
  }



  template <int dim>
  void
  ProblemParameters<dim>::check_graded_mesh(const dealii::Triangulation<dim> &triangulation, std::ostream &log) const
  {
    const bool contact_present = !contact.die_ids.empty();
    boundary_conditions.check_prescribed_fluxes(triangulation, contact_present);
    bool pressure_level_free =
      boundary_conditions.traction_free_ids.empty() && boundary_conditions.traction_ids.empty();
    for (const auto &[id, mask] : boundary_conditions.velocity_components)
      pressure_level_free &= (mask.n_selected_components() == dim);
    if (contact_present && pressure_level_free)
      {
        bool coulomb = false;
        for (const auto &[id, mu] : contact.friction_coefficient)
          coulomb |= mu > 0 && contact.law != FrictionLaw::Kind::tresca;
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
        for (const BoundaryId id : contact.die_ids)
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
    if (refinement.solves_dual())
      {
        require(!contact.uses_penalty(),
                "Refinement/Indicator",
                "'dual weighted' needs Contact/Normal enforcement = active set (its dual freezes the "
                "contact constraints; the penalty contact is not covered)");
        require(!coordinates.axisymmetric(),
                "Refinement/Indicator",
                "'dual weighted' is not available with Geometry = axisymmetric yet (its dual problem "
                "is assembled in plane strain); use Kelly");
        require(linear_solver.method == LinearSolverParameters::Method::direct,
                "Refinement/Indicator",
                "'dual weighted' needs Linear solver/Method = direct (the augmented Lagrangian of the "
                "iterative method is not covered)");
        require(contact.die_surface_files.empty(),
                "Refinement/Indicator",
                "'dual weighted' does not take Contact/Die surfaces yet (its dual problem finds the die "
                "facets from the mesh); use Kelly");
        require(contact.die_velocities.empty(),
                "Refinement/Indicator",
                "'dual weighted' does not take Contact/Die velocities yet (its dual problem holds the "
                "dies at rest); use Kelly");
      }
    require(!boundary_conditions.velocity_ids.empty() || (time_stepping.incremental && !contact.die_velocities.empty()),
            "Boundary conditions/Prescribed velocity ids",
            "is empty: without a prescribed velocity (or, in Problem = incremental, a die that "
            "moves: Contact/Die velocities) nothing drives the flow and rigid motions are free");
  }



  template <int dim>
  BoundaryId
  ProblemParameters<dim>::goal_part() const
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
      return contact.die_velocities.begin()->first;
    return *boundary_conditions.velocity_ids.begin();
  }



  template <int dim>
  std::set<BoundaryId>
  ProblemParameters<dim>::wall_ids() const
  {
    std::set<BoundaryId> walls = boundary_conditions.wall_ids();
    walls.insert(contact.die_ids.begin(), contact.die_ids.end());
    return walls;
  }

  template struct ProblemParameters<2>;
  template struct ProblemParameters<3>;
} // namespace dieflow
