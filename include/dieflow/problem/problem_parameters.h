// The deck's parameters in one structure: each piece's subsection, and the checks of entries against each other.
#ifndef dieflow_problem_parameters_h
#define dieflow_problem_parameters_h

#include <dieflow/base/parameters.h>
#include <dieflow/contact/contact_parameters.h>
#include <dieflow/flow/boundary_conditions.h>
#include <dieflow/flow/material.h>
#include <dieflow/free_surface/free_surface.h>
#include <dieflow/heat/heat_parameters.h>
#include <dieflow/strain/strain_field.h>
#include <dieflow/incremental/checkpoint.h>
#include <dieflow/incremental/remeshing.h>
#include <dieflow/incremental/time_stepping.h>
#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/mesh/geometry.h>
#include <dieflow/mesh/refinement.h>
#include <dieflow/solvers/linear_solver.h>
#include <dieflow/solvers/nonlinear_solver.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/point.h>

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>

namespace dieflow
{
  /**
   * Top-level entries of the deck: what runs and where the results go.
   */
  struct RunParameters
  {
    unsigned int dimension        = 2;
    Geometry     geometry         = Geometry::plane_strain;
    std::string  output_directory = "output/die2d";
    bool         write_vtu        = true;
    bool         write_mesh_svg   = false;
    bool         write_gnuplot    = false;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /// What the second reading of a deck declares beyond the fixed entries.
  struct DeckLayout
  {
    unsigned int         dimension = 2;
    std::set<BoundaryId> velocity_ids{1};
  };

  /**
   * The deck, read once: every piece's subsection (each piece declares and
   * parses its own), the entries that belong to the run as a whole (the
   * velocity degree, the probe point, the exact velocity), and the checks
   * of entries against each other in one place (check_entries(); those
   * that need the mesh in check_mesh()). The pieces of the problem keep
   * references to these, not copies.
   */
  template <int dim>
  struct ProblemParameters
  {
    static void
    declare_parameters(ParameterHandler &prm, const DeckLayout &layout);

    /// Reads the deck (relative files are relative to @p deck_directory) and checks it.
    ProblemParameters(ParameterHandler &prm, const std::string &deck_directory);

    /// The checks of the mesh as Mesh makes it: every boundary part has
    /// one condition and the mesh has the parts the deck names; the
    /// axisymmetric mesh's axis.
    void
    check_mesh(const dealii::Triangulation<dim> &triangulation) const;

    /**
     * After the mesh is graded, before the first cycle: the prescribed
     * fluxes; a warning on @p log where the pressure level is free (no
     * traction-free part) and Coulomb friction then moves with the
     * penalty; then the entries checked against each other after the mesh
     * (the target quantity, the dual-weighted estimate's limits, something
     * that drives the flow).
     */
    void
    check_graded_mesh(const dealii::Triangulation<dim> &triangulation, std::ostream &log) const;

    /**
     * The prescribed-velocity part whose force F_x the dual-weighted
     * indicator and the ram stroke aim at: the Target quantity's, if it is
     * such a force, else the first part (or, driven by a moving die alone,
     * that die).
     */
    BoundaryId
    goal_part() const;

    /// The walls the mesh is graded towards and the wall nodes lie on: dies, slip walls, symmetry lines.
    std::set<BoundaryId>
    wall_ids() const;

    RunParameters           run;
    unsigned int            velocity_degree = 1;
    CoordinateSystem<dim>   coordinates;
    MeshParameters          mesh;
    Material                material;
    BoundaryConditions<dim> boundary_conditions;
    NonlinearSolver         nonlinear_solver;
    LinearSolverParameters  linear_solver;
    RefinementParameters    refinement;
    TimeStepping            time_stepping;
    RemeshingParameters     remeshing;
    CheckpointParameters    checkpoint;
    ContactParameters       contact;
    FreeSurfaceParameters   free_surface;
    HeatParameters          heat;
    StrainParameters        strain;
    /// Whether a steady run solves the equivalent strain as a field (asked for, or the law hardens).
    bool
    steady_strain() const
    {
      return !time_stepping.incremental && (strain.requested || material.hardens());
    }
    /// Where the velocity is reported as a quantity of interest (if any).
    std::optional<dealii::Point<dim>> probe;
    /// Verification/Exact velocity (if any).
    std::unique_ptr<dealii::FunctionParser<dim>> exact_velocity;

  private:
    /// The checks of entries against each other that need no mesh.
    void
    check_entries() const;
  };
} // namespace dieflow

#endif
