// The corners of the walls, where the velocity is singular, and the geometric grading of the mesh towards them.
#include <dieflow/mesh/singular_points.h>
#include <dieflow/mesh/wall_nodes.h>

#include <cmath>
#include <map>

namespace dieflow
{
  namespace
  {
    /// One layer of grade_towards(): refine flags on the cells near @p points.
    template <int dim>
    void
    flag_cells_near(const std::vector<dealii::Point<dim>> &points,
                    const double                           width,
                    dealii::Triangulation<dim> &           triangulation)
    {
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto &p : points)
          if (cell->center().distance(p) <= (0.5 + width) * cell->diameter())
            {
              cell->clear_coarsen_flag();
              cell->set_refine_flag();
              break;
            }
    }
  } // namespace



  template <int dim>
  std::vector<dealii::Point<dim>>
  wall_corners(const dealii::Triangulation<dim> &triangulation,
               const std::set<BoundaryId> &      wall_ids,
               const double                      angle_degrees)
  {
    struct Side
    {
      BoundaryId             id;
      dealii::Tensor<1, dim> normal;
    };
    std::map<unsigned int, std::vector<Side>> sides;
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            const Side side{cell->face(f)->boundary_id(), outward_unit_normal<dim>(cell, f)};
            for (const unsigned int v : cell->face(f)->vertex_indices())
              sides[cell->face(f)->vertex_index(v)].push_back(side);
          }

    const double                    cos_angle = std::cos(angle_degrees * dealii::numbers::PI / 180);
    std::vector<dealii::Point<dim>> corners;
    for (const auto &[vertex, at] : sides)
      {
        bool on_wall = false, corner = false;
        for (const auto &a : at)
          {
            on_wall |= wall_ids.count(a.id) > 0;
            for (const auto &b : at)
              corner |= a.id != b.id || a.normal * b.normal < cos_angle;
          }
        if (on_wall && corner)
          corners.push_back(triangulation.get_vertices()[vertex]);
      }
    return corners;
  }



  template <int dim>
  void
  grade_towards(const std::vector<dealii::Point<dim>> &points,
                const unsigned int                     levels,
                const double                           width,
                dealii::Triangulation<dim> &           triangulation)
  {
    for (unsigned int level = 0; level < levels && !points.empty(); ++level)
      {
        flag_cells_near(points, width, triangulation);
        triangulation.execute_coarsening_and_refinement();
      }
  }



  template std::vector<dealii::Point<2>>
  wall_corners<2>(const dealii::Triangulation<2> &, const std::set<BoundaryId> &, double);
  template std::vector<dealii::Point<3>>
  wall_corners<3>(const dealii::Triangulation<3> &, const std::set<BoundaryId> &, double);
  template void
  grade_towards<2>(const std::vector<dealii::Point<2>> &, unsigned int, double, dealii::Triangulation<2> &);
  template void
  grade_towards<3>(const std::vector<dealii::Point<3>> &, unsigned int, double, dealii::Triangulation<3> &);
} // namespace dieflow
