// What a run in time carries from step to step: the previous velocity, the strain, the ram, the gaps to the dies, the fixed walls.
#include <dieflow/base/serialization.h>
#include <dieflow/incremental/incremental_state.h>
#include <dieflow/mesh/mesh_motion.h>

#include <numeric>

namespace dieflow
{
  template <int dim>
  IncrementalState<dim>::IncrementalState(const TimeStepping &         time_stepping,
                                          const CoordinateSystem<dim> &coordinates,
                                          const Material &             material)
    : time_stepping(time_stepping)
    , coordinates(coordinates)
    , material(material)
  {}



  template <int dim>
  void
  IncrementalState<dim>::initialize(const dealii::Triangulation<dim> &           triangulation,
                                    const BoundaryId                             ram_part,
                                    const std::set<BoundaryId> &                 wall_ids,
                                    const std::set<BoundaryId> &                 die_ids,
                                    const std::map<BoundaryId, DieSurface<dim>> &given_surfaces,
                                    const std::set<BoundaryId> &                 free_ids)
  {
    initial_volume = domain_volume(coordinates, triangulation);
    record_ram_start(triangulation, ram_part);
    fixed_walls.initialize(triangulation, wall_ids);
    equivalent_strain.reinit(triangulation.n_active_cells());
    update_hardening();
    if (!die_ids.empty())
      gaps.initialize(triangulation, die_ids, given_surfaces, free_ids);
  }



  template <int dim>
  std::pair<double, double>
  IncrementalState<dim>::move_weights(const unsigned int n, const std::size_t n_dofs) const
  {
    const bool contact_changed = last_gap_update.entered + last_gap_update.left > 0;
    const bool have_previous   = previous_velocity.size() == n_dofs;
    return time_stepping.weights(n, contact_changed || !have_previous);
  }



  template <int dim>
  void
  IncrementalState<dim>::advance_strain(const double                   a,
                                        const double                   b,
                                        const dealii::DoFHandler<dim> &dof_handler,
                                        const dealii::Vector<double> & velocity)
  {
    previous_velocity = velocity;
    // The positions' rule, from the rates on the configuration x_n.
    const dealii::Vector<double> rate = cell_strain_rates(coordinates, dof_handler, velocity);
    equivalent_strain.add(a, rate);
    if (b != 0)
      equivalent_strain.add(b, previous_strain_rate);
    previous_strain_rate = rate;
    update_hardening();
  }



  template <int dim>
  void
  IncrementalState<dim>::update_hardening()
  {
    if (!material.hardens())
      return;
    const std::size_t n_cells = equivalent_strain.size();
    cell_hardening.reinit(n_cells);
    // A new mesh's temperatures are those of its points once the heat is on it.
    const std::size_t n_points = (flow_temperatures != nullptr && n_cells > 0 && flow_temperatures->size() % n_cells == 0) ?
                                   flow_temperatures->size() / n_cells :
                                   0;
    for (unsigned int c = 0; c < n_cells; ++c)
      {
        double T = material.temperature;
        if (n_points > 0)
          {
            T = 0;
            for (std::size_t q = 0; q < n_points; ++q)
              T += (*flow_temperatures)[c * n_points + q] / n_points;
          }
        cell_hardening[c] = material.hardening(equivalent_strain[c], T);
      }
  }



  template <int dim>
  double
  IncrementalState<dim>::ram_displacement(const dealii::Triangulation<dim> &triangulation) const
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
  IncrementalState<dim>::record_ram_start(const dealii::Triangulation<dim> &triangulation, const BoundaryId ram_part)
  {
    ram_start.clear();
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face->boundary_id() == ram_part)
          for (const unsigned int v : face->vertex_indices())
            ram_start.emplace(face->vertex_index(v), face->vertex(v));
  }



  template <int dim>
  StepRecord
  IncrementalState<dim>::step_record(const unsigned int                n,
                                     const double                      stroke,
                                     const dealii::Triangulation<dim> &triangulation) const
  {
    StepRecord record;
    record.step                     = n;
    record.time                     = time_stepping.time(n);
    record.stroke                   = stroke;
    const dealii::Vector<double> volumes = cell_volumes(coordinates, triangulation);
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
  IncrementalState<dim>::new_mesh(const double                                stroke_before,
                                  const dealii::Triangulation<dim> &          triangulation,
                                  const BoundaryId                            ram_part,
                                  const std::set<BoundaryId> &                wall_ids,
                                  const std::map<unsigned int, unsigned int> &new_face_of_old,
                                  dealii::Vector<double>                      carried_previous_velocity,
                                  dealii::Vector<double>                      strain,
                                  dealii::Vector<double>                      previous_rate,
                                  const RemeshRecord &                        record)
  {
    // The ram's stroke goes on from where it is.
    ram_offset           = stroke_before;
    previous_velocity    = std::move(carried_previous_velocity);
    equivalent_strain    = std::move(strain);
    previous_strain_rate = std::move(previous_rate);
    update_hardening();
    record_ram_start(triangulation, ram_part);
    fixed_walls.initialize(triangulation, wall_ids);
    gaps.renumber_faces(new_face_of_old);
    last_remesh        = record;
    steps_since_remesh = 0;
  }



  template <int dim>
  void
  IncrementalState<dim>::save(OutputArchive &ar, const dealii::Triangulation<dim> &triangulation) const
  {
    double displacement = ram_displacement(triangulation);
    ar << previous_velocity << equivalent_strain << previous_strain_rate << initial_volume << displacement;
    ar << last_gap_update.entered << last_gap_update.left << last_gap_update.penetration << steps_since_remesh;
    StepRecord last;
    last.remesh = last_remesh;
    ar << last;
    gaps.save(ar);
    fixed_walls.save(ar);
  }



  template <int dim>
  void
  IncrementalState<dim>::load(InputArchive &ar)
  {
    ar >> previous_velocity >> equivalent_strain >> previous_strain_rate >> initial_volume >> ram_offset;
    ar >> last_gap_update.entered >> last_gap_update.left >> last_gap_update.penetration >> steps_since_remesh;
    StepRecord last;
    ar >> last;
    last_remesh = last.remesh;
    gaps.load(ar);
    fixed_walls.load(ar);
    update_hardening();
  }

  template class IncrementalState<2>;
  template class IncrementalState<3>;
} // namespace dieflow
