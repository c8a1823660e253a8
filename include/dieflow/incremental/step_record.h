// What a step of a run in time reports: its time, stroke, volume, cell shape, contact events and new mesh.
#ifndef dieflow_step_record_h
#define dieflow_step_record_h

#include <optional>

namespace dieflow
{
  /// A new mesh of the domain (remesh_domain(), before step @p step's solve).
  struct RemeshRecord
  {
    unsigned int step = 0;
    unsigned int cells_before = 0, cells_after = 0;
    /// smallest_scaled_jacobian() of the moved mesh and of the new one.
    double jacobian_before = 0, jacobian_after = 0;
    /// (V_new - V_old) / V_old: round-off where the boundary is kept, the
    /// triangles of the dropped vertices where not.
    double volume_change = 0;
    /// Boundary edges split at their midpoints (an odd loop).
    unsigned int split_edges = 0;
    /// Boundary vertices that crowded their neighbours, dropped.
    unsigned int dropped_vertices = 0;
    /// With heat in time: the heat content int rho c T, (new - old) / old, and the change of the mean T (K) it
    /// carries (interpolation at the new nodes: the mean's change is its error, the content's holds the volume's too).
    double heat_content_change = 0, mean_temperature_change = 0;
  };

  /// What a step of Problem = incremental adds to its cycle's report.
  struct StepRecord
  {
    unsigned int step = 0;
    /// t_n in s.
    double time = 0;
    /// How far the ram has travelled since t = 0: the mean displacement
    /// along x of the vertices of the first prescribed-velocity part, or,
    /// with none, the travel |V| t of the first moving die (mm).
    double stroke = 0;
    /// The volume of the mesh (plane strain: mm^2 per mm of depth), and
    /// (V - V_0) / V_0.
    double volume        = 0;
    double volume_change = 0;
    /// smallest_scaled_jacobian() of the mesh (1: rectangles; time_stepping.h).
    double smallest_scaled_jacobian = 1;
    /// The move to this configuration (contact_gaps.h): boundary faces that
    /// came onto a die and left it, and the deepest a free node went
    /// through a die before it was put back on it (mm).
    unsigned int faces_entered = 0;
    unsigned int faces_left    = 0;
    double       penetration   = 0;
    /// The equivalent strain the metal has taken: its mean over the volume and its largest cell value.
    double mean_strain = 0;
    double max_strain  = 0;
    /// The new mesh this step was solved on, if the domain was meshed anew.
    std::optional<RemeshRecord> remesh;

    /// Saves or loads the record with @p ar (a boost archive; checkpoints).
    template <class Archive>
    void
    serialize(Archive &ar, const unsigned int /*version*/)
    {
      ar &step &time &stroke &volume &volume_change &smallest_scaled_jacobian &faces_entered &faces_left &penetration
        &mean_strain &max_strain;
      bool remeshed = remesh.has_value();
      ar &remeshed;
      if (remeshed && !remesh)
        remesh.emplace();
      if (remeshed)
        ar &remesh->step &remesh->cells_before &remesh->cells_after &remesh->jacobian_before &remesh->jacobian_after
          &remesh->volume_change &remesh->split_edges &remesh->dropped_vertices &remesh->heat_content_change
          &remesh->mean_temperature_change;
      else
        remesh.reset();
    }
  };
} // namespace dieflow

#endif
