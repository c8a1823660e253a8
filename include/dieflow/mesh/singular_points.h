// The corners of the walls, where the velocity is singular, and the geometric grading of the mesh towards them.
#ifndef dieflow_singular_points_h
#define dieflow_singular_points_h

#include <dieflow/base/parameters.h>

#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include <set>
#include <vector>

namespace dieflow
{
  /**
   * The corners of the walls: boundary vertices where a wall part (a die id
   * or a slip wall) turns by more than @p angle_degrees, or meets another
   * boundary part. In die2d these are B (inlet / container), C (die entry),
   * D (die exit) and E (land / outlet). Near such a corner of interior angle
   * omega the velocity behaves as r^lambda with lambda < 1 where omega > 180
   * degrees (D, the re-entrant die exit) and wherever the boundary condition
   * changes type, so the error of a uniform mesh is dominated there.
   */
  template <int dim>
  std::vector<dealii::Point<dim>>
  wall_corners(const dealii::Triangulation<dim> &triangulation,
               const std::set<BoundaryId> &      wall_ids,
               double                            angle_degrees = 5);

  /**
   * Geometric grading towards @p points: @p levels rounds, each refining
   * every active cell whose centre lies within (1/2 + @p width) of its
   * diameter from a point. A cell at distance r from a point is then about
   * max(h 2^-levels, r / (1/2 + width)) in size: the geometric mesh
   * (ratio 1/2 per layer) of Babuska and Guo for corner singularities, whose
   * error decays like that of a smooth solution until h 2^-levels is
   * reached.
   */
  template <int dim>
  void
  grade_towards(const std::vector<dealii::Point<dim>> &points,
                unsigned int                           levels,
                double                                 width,
                dealii::Triangulation<dim> &           triangulation);
} // namespace dieflow

#endif
