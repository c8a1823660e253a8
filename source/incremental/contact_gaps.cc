// Contact in a run in time by the gap in positions: nodes put back onto the dies, faces that come onto and leave them, gaps closed within a step.
#include <dieflow/base/serialization.h>
#include <dieflow/incremental/contact_gaps.h>
#include <dieflow/incremental/time_stepping.h>

#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <limits>
#include <optional>

namespace dieflow
{
  namespace
  {
    /// Calls @p act(id, vertex index, vertex) once for each vertex of the
    /// boundary faces whose id satisfies @p selected (the first such face's id).
    template <int dim, typename Selected, typename Act>
    void
    for_each_vertex_of(dealii::Triangulation<dim> &triangulation, const Selected &selected, const Act &act)
    {
      std::vector<bool> done(triangulation.n_vertices(), false);
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && selected(face->boundary_id()))
            for (const unsigned int v : face->vertex_indices())
              if (!done[face->vertex_index(v)])
                {
                  done[face->vertex_index(v)] = true;
                  act(face->boundary_id(), face->vertex_index(v), face->vertex(v));
                }
    }

    /// The vertices where two facets of @p die meet at an angle whose
    /// cosine is below @p cos_corner (shared vertices are the same point:
    /// one Gmsh node, or one mesh vertex, translated alike).
    std::vector<dealii::Point<2>>
    corners_of(const DieSurface<2> &die, const double cos_corner)
    {
      std::map<std::pair<double, double>, std::vector<dealii::Tensor<1, 2>>> tangents_at;
      for (const auto &facet : die.all_facets())
        for (unsigned int k = 0; k < 2; ++k)
          {
            const auto along = facet.vertices[1 - k] - facet.vertices[k];
            tangents_at[{facet.vertices[k][0], facet.vertices[k][1]}].push_back(along / along.norm());
          }
      std::vector<dealii::Point<2>> corners;
      for (const auto &[x, tangents] : tangents_at)
        // Both tangents point away from the vertex: a straight wall has -1.
        if (tangents.size() == 2 && -(tangents[0] * tangents[1]) < cos_corner)
          corners.emplace_back(x.first, x.second);
      return corners;
    }

    /// Each boundary vertex's two neighbours along the boundary (2D).
    std::map<unsigned int, std::vector<unsigned int>>
    boundary_neighbours(const dealii::Triangulation<2> &triangulation)
    {
      std::map<unsigned int, std::vector<unsigned int>> neighbours;
      for (const auto &face : triangulation.active_face_iterators())
        if (face->at_boundary())
          {
            neighbours[face->vertex_index(0)].push_back(face->vertex_index(1));
            neighbours[face->vertex_index(1)].push_back(face->vertex_index(0));
          }
      return neighbours;
    }

    /// The area the domain gains or loses when boundary vertex @p v moves to
    /// @p to: the triangle its two boundary neighbours span with the move.
    double
    area_changed(const dealii::Triangulation<2> &                         triangulation,
                 const std::map<unsigned int, std::vector<unsigned int>> &neighbours,
                 const unsigned int                                       v,
                 const dealii::Point<2> &                                 to)
    {
      const auto around = neighbours.find(v);
      if (around == neighbours.end() || around->second.size() != 2)
        return std::numeric_limits<double>::max();
      const auto &x    = triangulation.get_vertices();
      const auto  span = x[around->second[1]] - x[around->second[0]], move = to - x[v];
      return 0.5 * std::abs(span[0] * move[1] - span[1] * move[0]);
    }

    /// Whether the cells around vertex @p v stay uninverted with it at @p to.
    bool
    keeps_cells_valid(dealii::Triangulation<2> &triangulation, const unsigned int v, const dealii::Point<2> &to)
    {
      std::vector<dealii::Triangulation<2>::active_cell_iterator> around;
      dealii::Point<2> *                                           position = nullptr;
      // (Cells with v as a hanging vertex are left out: moving v moves only
      // the cells whose corner it is.)
      for (const auto &cell : dealii::GridTools::find_cells_adjacent_to_vertex(triangulation, v))
        for (const unsigned int k : cell->vertex_indices())
          if (cell->vertex_index(k) == v)
            {
              around.push_back(cell);
              position = &cell->vertex(k);
            }
      if (position == nullptr)
        return false;
      const dealii::Point<2> from = *position;
      *position                   = to;
      const bool valid =
        std::all_of(around.begin(), around.end(), [](const auto &cell) { return scaled_jacobian<2>(cell) > 0; });
      *position = from;
      return valid;
    }

    /// The boundary edge (of an id that @p selected) that passes deepest
    /// on the metal's side of @p corner, over the edge's interior and within
    /// its length, and how deep; none within @p tolerance.
    template <typename Selected>
    std::optional<std::pair<dealii::Triangulation<2>::face_iterator, double>>
    edge_over(const dealii::Triangulation<2> &triangulation,
              const dealii::Point<2> &        corner,
              const Selected &                selected,
              const double                    tolerance)
    {
      std::optional<std::pair<dealii::Triangulation<2>::face_iterator, double>> over;
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          {
            if (!face->at_boundary() || !selected(face->boundary_id()))
              continue;
            const auto             a = face->vertex(0);
            const auto             along  = face->vertex(1) - a;
            const double           length = along.norm();
            dealii::Tensor<1, 2>   outward({along[1] / length, -along[0] / length});
            if ((face->center() - cell->center()) * outward < 0)
              outward = -outward;
            const double s = (corner - a) * along / (length * length);
            const double depth = (a - corner) * outward;
            if (s > 0 && s < 1 && depth > std::max(tolerance, over ? over->second : 0.) && depth < length)
              over = std::make_pair(face, depth);
          }
      return over;
    }

    /**
     * The facets of a die from the mesh, going on straight past its edges by
     * @p reach: in 2D each end segment (a vertex of one facet only) is
     * lengthened; in 3D a flat die (every facet in one plane: a platen)
     * gains a square of its plane, of half side @p reach about its centre.
     * A curved 3D die keeps its facets.
     */
    template <int dim>
    std::vector<typename DieSurface<dim>::Facet>
    extended(std::vector<typename DieSurface<dim>::Facet> facets, const double reach)
    {
      if constexpr (dim == 2)
        {
          std::map<std::pair<double, double>, unsigned int> ends;
          for (const auto &f : facets)
            for (const auto &x : f.vertices)
              ++ends[{x[0], x[1]}];
          for (auto &f : facets)
            for (unsigned int k = 0; k < 2; ++k)
              if (ends[{f.vertices[k][0], f.vertices[k][1]}] == 1)
                {
                  const auto along = f.vertices[k] - f.vertices[1 - k];
                  f.vertices[k] += reach / along.norm() * along;
                }
        }
      else
        {
          const auto normal_of = [](const typename DieSurface<dim>::Facet &f) {
            const dealii::Tensor<1, dim> n = dealii::cross_product_3d(f.vertices[1] - f.vertices[0], f.vertices[2] - f.vertices[0]);
            return n / n.norm();
          };
          const dealii::Tensor<1, dim> n      = normal_of(facets.front());
          dealii::Point<dim>           centre;
          double                       extent = 0;
          for (const auto &f : facets)
            for (const auto &x : f.vertices)
              centre += x / (3. * facets.size());
          bool flat = true;
          for (const auto &f : facets)
            {
              flat &= std::abs(normal_of(f) * n) > 1 - 1e-12;
              for (const auto &x : f.vertices)
                extent = std::max(extent, x.distance(centre));
            }
          for (const auto &f : facets)
            for (const auto &x : f.vertices)
              flat &= std::abs((x - centre) * n) <= 1e-12 * extent;
          if (flat)
            {
              // Two in-plane directions, and the square's corners.
              dealii::Tensor<1, dim> t1 = facets.front().vertices[1] - facets.front().vertices[0];
              t1 /= t1.norm();
              const dealii::Tensor<1, dim> t2 = dealii::cross_product_3d(n, t1);
              const dealii::Point<dim>     a  = centre - reach * t1 - reach * t2, b = centre + reach * t1 - reach * t2,
                                       c      = centre + reach * t1 + reach * t2, d = centre - reach * t1 + reach * t2;
              typename DieSurface<dim>::Facet first, second;
              first.vertices  = {{a, b, c}};
              second.vertices = {{a, c, d}};
              facets.push_back(first);
              facets.push_back(second);
            }
        }
      return facets;
    }
  } // namespace



  template <int dim>
  void
  ContactGaps<dim>::initialize(const dealii::Triangulation<dim> &          triangulation,
                               const std::set<BoundaryId> &                 die_ids,
                               const std::map<BoundaryId, DieSurface<dim>> &given_surfaces,
                               const std::set<BoundaryId> &                 free)
  {
    free_ids = free;
    dies.clear();
    std::map<BoundaryId, std::vector<typename DieSurface<dim>::Facet>> faces;
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && die_ids.count(face->boundary_id()) && !given_surfaces.count(face->boundary_id()))
          for (const auto &facet : DieSurface<dim>::facets_of(*face))
            faces[face->boundary_id()].push_back(facet);
    // A die from the mesh goes on straight past its edges: a platen is
    // larger than the block it presses, whose contact grows as the block
    // spreads. The searches' tolerance is that of the die extended by the
    // mesh's size; the die itself is extended as far as the metal may ever
    // spread (a thousand times the mesh's size): a die whose edge the metal
    // may flow past (a land's exit) is given as a surface (Contact/Die
    // surfaces). Ending the die at the mesh's size let the spreading block
    // slide off the platen's end, which then pressed on less and less
    // metal (plane-strain upsetting past 56 % reduction, doc/incremental.md).
    const double mesh_size = dealii::GridTools::diameter(triangulation);
    tolerance              = 0;
    for (auto &[id, facets] : faces)
      {
        DieSurface<dim> near;
        near.set_facets(extended<dim>(facets, mesh_size));
        tolerance = std::max(tolerance, 1e-6 * near.diameter());
        dies[id].set_facets(extended<dim>(facets, 1e3 * mesh_size));
      }
    for (const auto &[id, surface] : given_surfaces)
      {
        dies[id]  = surface;
        tolerance = std::max(tolerance, 1e-6 * surface.diameter());
      }
  }



  template <int dim>
  std::vector<WallNode<dim>>
  ContactGaps<dim>::approaching(const std::vector<WallNode<dim>> &free_nodes,
                                const double                      reach,
                                const GapRate &                   gap_rate) const
  {
    std::vector<WallNode<dim>> result;
    for (const auto &free_node : free_nodes)
      {
        WallNode<dim> node = free_node;
        node.directions.clear();
        Tensor<1, dim> outward;
        double         weight = 0, length = 0;
        for (const auto &direction : free_node.directions)
          {
            outward += direction.normal;
            weight += direction.weight;
            length += direction.length;
          }
        for (const auto &[id, surface] : dies)
          if (const auto on = surface.project(free_node.position, reach, tolerance))
            {
              // Towards the die; a node already on its plane (put back there
              // by update()) faces it with its free surface.
              Tensor<1, dim> normal = on->facet.normal;
              if (on->distance > tolerance)
                normal = (on->point - free_node.position) / on->distance;
              else if (normal * outward < 0)
                normal = -normal;
              WallDirection<dim> direction{normal, id, weight, length, on->facet.vertices};
              direction.gap_rate = gap_rate(free_node, direction, on->distance);
              node.directions.push_back(direction);
            }
        if (!node.directions.empty())
          result.push_back(node);
      }
    return result;
  }



  template <int dim>
  void
  ContactGaps<dim>::close_gaps(std::vector<WallNode<dim>> &wall_nodes,
                               const std::set<BoundaryId> &ids,
                               const double                reach,
                               const double                cos_corner,
                               const GapRate &             gap_rate) const
  {
    std::vector<WallNode<dim>> kept;
    for (auto &node : wall_nodes)
      {
        std::vector<WallDirection<dim>> directions;
        for (auto &direction : node.directions)
          {
            const auto die = dies.find(direction.id);
            if (!ids.count(direction.id) || die == dies.end())
              {
                directions.push_back(direction);
                continue;
              }
            const auto on = die->second.project(node.position, std::max(reach, tolerance), tolerance);
            if (on && on->distance <= tolerance)
              {
                directions.push_back(direction); // on the die (attach_die_surfaces)
                continue;
              }
            // No facet of the die faces this wall within reach: the wall is
            // no wall here (its own face would be a phantom die, the die
            // face's plane extended past the die's edge).
            if (!on || std::abs(on->facet.normal * direction.normal) < cos_corner)
              continue;
            const Tensor<1, dim> normal = on->facet.normal * direction.normal > 0 ? on->facet.normal : -on->facet.normal;
            direction.normal            = normal;
            direction.facet             = on->facet.vertices;
            direction.gap_rate          = gap_rate(node, direction, (on->point - node.position) * normal);
            directions.push_back(direction);
          }
        node.directions = directions;
        join_directions_of_one_wall(node);
        if (!node.directions.empty())
          kept.push_back(node);
      }
    wall_nodes = kept;
  }



  template <int dim>
  void
  ContactGaps<dim>::renumber_faces(const std::map<unsigned int, unsigned int> &new_face_of_old)
  {
    std::map<unsigned int, BoundaryId> renumbered;
    for (const auto &[face, id] : id_before)
      if (const auto it = new_face_of_old.find(face); it != new_face_of_old.end())
        renumbered[it->second] = id;
    id_before = renumbered;
  }



  template <int dim>
  void
  ContactGaps<dim>::save(OutputArchive &ar) const
  {
    save_dies(ar, dies);
    ar << id_before << free_ids << tolerance;
  }



  template <int dim>
  void
  ContactGaps<dim>::load(InputArchive &ar)
  {
    load_dies(ar, dies);
    ar >> id_before >> free_ids >> tolerance;
    shifts.clear();
  }



  template <int dim>
  void
  ContactGaps<dim>::translate(const BoundaryId id, const dealii::Tensor<1, dim> &shift)
  {
    if (const auto it = dies.find(id); it != dies.end())
      {
        it->second.translate(shift);
        shifts[id] += shift;
      }
  }



  template <int dim>
  template <typename FaceIterator>
  unsigned int
  ContactGaps<dim>::vertices_on(const FaceIterator &face, const BoundaryId die) const
  {
    unsigned int on = 0;
    for (const unsigned int v : face->vertex_indices())
      on += dies.at(die).project(face->vertex(v), tolerance, tolerance).has_value();
    return on;
  }



  template <int dim>
  GapUpdate
  ContactGaps<dim>::update(const std::vector<dealii::Point<dim>> &old_vertices,
                           const std::vector<bool> &              in_contact,
                           dealii::Triangulation<dim> &           triangulation,
                           const double                           cos_corner)
  {
    GapUpdate update;
    if (dies.empty())
      return update;

    // The nodes in contact stay on their die: the step's velocity keeps
    // them on its plane to first order, Adams-Bashforth 2's v_{n-1} of a
    // node that just came onto it did not, and a curved die turns away
    // from the plane.
    for_each_vertex_of(triangulation,
                       [&](const BoundaryId id) { return dies.count(id) > 0; },
                       [&](const BoundaryId id, const unsigned int index, dealii::Point<dim> &x) {
                         if (!in_contact[index])
                           return;
                         const double moved = x.distance(old_vertices[index]);
                         if (const auto on = dies.at(id).project(x, moved + tolerance, tolerance))
                           x = on->point;
                       });

    // The nodes that no die held, of the free surface and of die faces
    // (separated, or off a die given as a surface: close_gaps()), that went
    // through a die go back onto it.
    for_each_vertex_of(triangulation,
                       [&](const BoundaryId id) { return free_ids.count(id) > 0 || dies.count(id) > 0; },
                       [&](const BoundaryId, const unsigned int index, dealii::Point<dim> &x) {
                         if (in_contact[index])
                           return;
                         // In the frame of a moving die, the node started
                         // at its old position plus the die's shift.
                         for (const auto &[id, surface] : dies)
                           if (const auto crossing = surface.crossing(old_vertices[index] + shifts[id], x, tolerance))
                             {
                               update.penetration = std::max(update.penetration, crossing->distance);
                               x                  = crossing->point;
                             }
                       });
    update.penetration = std::max(update.penetration, put_nodes_on_die_corners(triangulation, cos_corner));

    // Faces onto and off the dies.
    const BoundaryId first_free = free_ids.empty() ? dealii::numbers::invalid_boundary_id : *free_ids.begin();
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        {
          if (!face->at_boundary())
            continue;
          const BoundaryId id = face->boundary_id();
          if (free_ids.count(id))
            {
              for (const auto &[die, surface] : dies)
                if (vertices_on(face, die) == face->n_vertices())
                  {
                    id_before[face->index()] = id;
                    face->set_boundary_id(die);
                    ++update.entered;
                    break;
                  }
            }
          else if (dies.count(id) && first_free != dealii::numbers::invalid_boundary_id && vertices_on(face, id) == 0)
            {
              const auto before = id_before.find(face->index());
              face->set_boundary_id(before == id_before.end() ? first_free : before->second);

              ++update.left;
            }
        }
    shifts.clear();
    return update;
  }

  template <int dim>
  double
  ContactGaps<dim>::put_nodes_on_die_corners(dealii::Triangulation<dim> &triangulation, const double cos_corner) const
  {
    double deepest = 0;
    if constexpr (dim == 2)
      {
        const auto neighbours = boundary_neighbours(triangulation);
        const auto movable    = [&](const BoundaryId id) { return free_ids.count(id) > 0 || dies.count(id) > 0; };
        for (const auto &[die, surface] : dies)
          for (const auto &corner : corners_of(surface, cos_corner))
            if (const auto over = edge_over(triangulation, corner, movable, tolerance))
              {
                // The end whose move changes the area least, of those whose
                // cells it leaves uninverted (a node on the die face a cell
                // back from the corner would fold its cell over).
                double             least = std::numeric_limits<double>::max();
                const unsigned int none  = 2;
                unsigned int       end   = none;
                for (unsigned int k = 0; k < 2; ++k)
                  {
                    const unsigned int v    = over->first->vertex_index(k);
                    const double       area = area_changed(triangulation, neighbours, v, corner);
                    if (area < least && keeps_cells_valid(triangulation, v, corner))
                      {
                        least = area;
                        end   = k;
                      }
                  }
                if (end != none)
                  {
                    over->first->vertex(end) = corner;
                    deepest                  = std::max(deepest, over->second);
                  }
              }
      }
    (void)triangulation;
    (void)cos_corner;
    return deepest;
  }

  template class ContactGaps<2>;
  template class ContactGaps<3>;
} // namespace dieflow
