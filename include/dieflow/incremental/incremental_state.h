// What a run in time carries from step to step: the previous velocity, the strain, the ram, the gaps to the dies, the fixed walls.
#ifndef dieflow_incremental_state_h
#define dieflow_incremental_state_h

#include <dieflow/base/archive.h>
#include <dieflow/base/parameters.h>
#include <dieflow/contact/die_surface.h>
#include <dieflow/flow/material.h>
#include <dieflow/incremental/contact_gaps.h>
#include <dieflow/incremental/step_record.h>
#include <dieflow/incremental/time_stepping.h>
#include <dieflow/mesh/coordinate_system.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>

namespace dieflow
{
  /**
   * The state of Problem = incremental between steps (the paper's
   * incremental approach, TimeStepping): the mesh is Lagrangian, so what
   * the metal has been through lives on it.
   *  - v_{n-1} at the same nodes, for Adams-Bashforth 2's move
   *    x_{n+1} = x_n + a v_n + b v_{n-1} (move_weights());
   *  - per active cell the equivalent strain eps, integrated by the same
   *    rule eps += a epsdot_n + b epsdot_{n-1}, its previous rate, and the
   *    hardening factor (eps_0 + eps)^n of the law (Material::hardening());
   *  - the ram: its vertices' start positions, whose mean x displacement
   *    is the stroke (plus what it had travelled before a new mesh);
   *  - the volume at t = 0;
   *  - the dies' surfaces for the free surface's gaps (ContactGaps) and the
   *    last move's contact events; the fixed walls (FixedWalls);
   *  - the new meshes: steps since the last, its record;
   *  - the load-stroke rows of the run a checkpoint came from.
   * It saves and loads itself (checkpoints).
   */
  template <int dim>
  class IncrementalState
  {
  public:
    IncrementalState(const TimeStepping &time_stepping, const CoordinateSystem<dim> &coordinates, const Material &material);

    /**
     * The state at t = 0 of @p triangulation: its volume, the ram part
     * @p ram_part's vertices, the planes of @p wall_ids, zero strain; with
     * contact (@p die_ids not empty), the dies' surfaces for the gaps (the
     * faces of @p die_ids, or @p given_surfaces) and the free ids.
     */
    void
    initialize(const dealii::Triangulation<dim> &            triangulation,
               const BoundaryId                              ram_part,
               const std::set<BoundaryId> &                  wall_ids,
               const std::set<BoundaryId> &                  die_ids,
               const std::map<BoundaryId, DieSurface<dim>> & given_surfaces,
               const std::set<BoundaryId> &                  free_ids);

    /**
     * The weights (a, b) of the move x += a v_n + b v_{n-1} of step @p n:
     * TimeStepping's; forward Euler after a change of contact (Adams-
     * Bashforth 2 assumes v smooth in time; when faces came onto a die or
     * left it with the last move, v_{n-1} belongs to another contact
     * state) or without v_{n-1} at @p n_dofs nodes.
     */
    std::pair<double, double>
    move_weights(const unsigned int n, const std::size_t n_dofs) const;

    /// eps += a epsdot_n + b epsdot_{n-1} per cell from @p velocity on the
    /// configuration x_n, and the hardening factors that follow; v_{n-1} = @p velocity.
    void
    advance_strain(const double                   a,
                   const double                   b,
                   const dealii::DoFHandler<dim> &dof_handler,
                   const dealii::Vector<double> & velocity);

    /// The hardening factor per active cell for the assembly (FlowTerms), or null when the law does not harden.
    const dealii::Vector<double> *
    hardening() const
    {
      return material.hardens() ? &cell_hardening : nullptr;
    }

    /// The signed mean x displacement of the ram's vertices since t = 0.
    double
    ram_displacement(const dealii::Triangulation<dim> &triangulation) const;
    /// ram_start: the vertices of @p ram_part where they are now.
    void
    record_ram_start(const dealii::Triangulation<dim> &triangulation, const BoundaryId ram_part);

    /// Time, stroke (@p stroke), volume, cell shape, contact events and strain of step @p n on @p triangulation.
    StepRecord
    step_record(const unsigned int n, const double stroke, const dealii::Triangulation<dim> &triangulation) const;

    /**
     * After the domain was meshed anew (@p triangulation): the fields of
     * the old mesh carried to the new one (@p previous_velocity, @p strain,
     * @p previous_rate, by MeshTransfer), the ram's stroke going on from
     * where it was (@p stroke_before: ram_displacement() on the old mesh), the fixed walls
     * and the faces' ids before they came onto a die renumbered, the
     * record of the new mesh.
     */
    void
    new_mesh(const double                                stroke_before,
             const dealii::Triangulation<dim> &          triangulation,
             const BoundaryId                            ram_part,
             const std::set<BoundaryId> &                wall_ids,
             const std::map<unsigned int, unsigned int> &new_face_of_old,
             dealii::Vector<double>                      previous_velocity,
             dealii::Vector<double>                      strain,
             dealii::Vector<double>                      previous_rate,
             const RemeshRecord &                        record);

    /// Into a checkpoint, and back.
    void
    save(OutputArchive &ar, const dealii::Triangulation<dim> &triangulation) const;
    void
    load(InputArchive &ar);

    /// v_{n-1} at the same nodes (empty before the first step).
    dealii::Vector<double> previous_velocity;
    /// Per active cell: the equivalent strain and its rate at the previous step.
    dealii::Vector<double> equivalent_strain, previous_strain_rate;
    /// The volume at t = 0.
    double initial_volume = 0;
    /// The step being solved.
    unsigned int current_step = 0;
    /// The dies' surfaces for the free surface's gaps, and the last move's events.
    ContactGaps<dim> gaps;
    GapUpdate        last_gap_update;
    FixedWalls<dim>  fixed_walls;
    /// New meshes: steps since the last, and its record.
    unsigned int                steps_since_remesh = 0;
    std::optional<RemeshRecord> last_remesh;
    /// load-stroke.txt's rows of the run a checkpoint came from.
    std::string earlier_load_stroke;

    /// The hardening factor (Material::hardening()) of every active cell, at
    /// the mean of the temperatures of its points (set_flow_temperatures(); Material/Temperature without them).
    void
    update_hardening();
    /// The temperatures at the flow's quadrature points, per active cell (HeatEquation::flow_temperatures()).
    void
    set_flow_temperatures(const std::vector<double> *temperatures)
    {
      flow_temperatures = temperatures;
    }

  private:

    const TimeStepping &         time_stepping;
    const CoordinateSystem<dim> &coordinates;
    const Material &             material;
    dealii::Vector<double>       cell_hardening;
    const std::vector<double> *  flow_temperatures = nullptr;
    /// The ram part's vertices with their positions at the start (or at the last new mesh).
    std::map<unsigned int, dealii::Point<dim>> ram_start;
    /// The ram's mean displacement before the last new mesh (ram_start's base).
    double ram_offset = 0;
  };
} // namespace dieflow

#endif
