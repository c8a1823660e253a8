// A rigid die read on its own: its facets, the search for a node's master facet, and the wall nodes' directions taken from it.
#include <dieflow/base/serialization.h>
#include <dieflow/contact/die_surface.h>
#include <dieflow/mesh/geometry.h>

#include <deal.II/grid/tria.h>

#include <boost/geometry/index/rtree.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace dieflow
{
  namespace
  {
    template <int dim>
    Tensor<1, dim>
    facet_normal(const std::array<Point<dim>, dim> &x)
    {
      Tensor<1, dim> n;
      if constexpr (dim == 2)
        {
          n[0] = x[1][1] - x[0][1];
          n[1] = x[0][0] - x[1][0];
        }
      else
        n = dealii::cross_product_3d(x[1] - x[0], x[2] - x[0]);
      return n;
    }

    /// Facet measure: length (2D), area (3D).
    template <int dim>
    double
    facet_measure(const std::array<Point<dim>, dim> &x)
    {
      return dim == 2 ? facet_normal<dim>(x).norm() : 0.5 * facet_normal<dim>(x).norm();
    }

    /**
     * The smallest barycentric coordinate of the projection of @p p onto
     * the facet's plane (line): >= 0 inside, negative outside by about the
     * distance over the facet size.
     */
    template <int dim>
    double
    insideness(const std::array<Point<dim>, dim> &x, const Point<dim> &p)
    {
      if constexpr (dim == 2)
        {
          const Tensor<1, 2> t  = x[1] - x[0];
          const double       xi = (p - x[0]) * t / (t * t);
          return std::min(xi, 1 - xi);
        }
      else
        {
          // Barycentric coordinates by the Gram system of the edges.
          const Tensor<1, 3> e1 = x[1] - x[0], e2 = x[2] - x[0], d = p - x[0];
          const double       a = e1 * e1, b = e1 * e2, c = e2 * e2, r1 = d * e1, r2 = d * e2;
          const double       det = a * c - b * b;
          const double       l1 = (c * r1 - b * r2) / det, l2 = (a * r2 - b * r1) / det;
          return std::min({1 - l1 - l2, l1, l2});
        }
    }

    /// Whether @p x lies over the facet @p vertices (outside it by at most
    /// @p tolerance, a length).
    template <int dim>
    bool
    over(const std::array<Point<dim>, dim> &vertices, const Point<dim> &x, const double tolerance)
    {
      return insideness<dim>(vertices, x) * std::sqrt(facet_measure<dim>(vertices)) >= -tolerance;
    }

    /// A direction of @p node off its die (@p off_die) joins a direction of
    /// the same die that is on it, if the node has one: the metal's corner
    /// that slid past the die's corner lies on one wall now.
    template <int dim>
    void
    join_directions_off_the_die(const std::vector<bool> &off_die, WallNode<dim> &node)
    {
      std::vector<bool> joined(node.directions.size(), false);
      for (unsigned int k = 0; k < node.directions.size(); ++k)
        for (unsigned int j = 0; j < node.directions.size() && off_die[k] && !joined[k]; ++j)
          if (!off_die[j] && node.directions[j].id == node.directions[k].id)
            {
              node.directions[j].weight += node.directions[k].weight;
              node.directions[j].length += node.directions[k].length;
              joined[k] = true;
            }
      std::vector<WallDirection<dim>> kept;
      for (unsigned int k = 0; k < node.directions.size(); ++k)
        if (!joined[k])
          kept.push_back(node.directions[k]);
      node.directions = kept;
    }
  } // namespace



  template <int dim>
  std::vector<const typename DieSurface<dim>::Facet *>
  DieSurface<dim>::facets_near(const dealii::BoundingBox<dim> &box) const
  {
    std::vector<Box> hits;
    tree.query(boost::geometry::index::intersects(box), std::back_inserter(hits));
    std::vector<const Facet *> near;
    for (const auto &hit : hits)
      near.push_back(&facets[hit.second]);
    return near;
  }



  template <int dim>
  void
  DieSurface<dim>::read(const std::string &file_name, const std::string &base_directory, const std::string &entry)
  {
    dealii::Triangulation<dim - 1, dim> surface;
    read_msh_file(file_name,
                  base_directory,
                  entry,
                  dim == 2 ? "a Gmsh surface mesh of lines" : "a Gmsh surface mesh of triangles or quadrilaterals",
                  surface);

    std::vector<Facet> read_facets;
    for (const auto &cell : surface.active_cell_iterators())
      for (const Facet &f : facets_of(*cell))
        read_facets.push_back(f);
    require(!read_facets.empty(), entry, "'" + file_name + "' contains no facets");
    set_facets(read_facets);
  }



  namespace
  {
    /// Saves or loads @p facets (their vertices and normals) with @p ar.
    template <class Archive, typename Facet>
    void
    serialize_facets(Archive &ar, std::vector<Facet> &facets)
    {
      serialize_each(ar, facets, [&](Facet &facet) {
        for (auto &vertex : facet.vertices)
          ar &vertex;
        ar &facet.normal;
      });
    }
  } // namespace



  template <int dim>
  void
  DieSurface<dim>::save(OutputArchive &ar) const
  {
    std::vector<Facet> kept = facets;
    serialize_facets(ar, kept);
  }



  template <int dim>
  void
  DieSurface<dim>::load(InputArchive &ar)
  {
    std::vector<Facet> read_facets;
    serialize_facets(ar, read_facets);
    set_facets(read_facets);
  }



  template <int dim>
  void
  save_dies(OutputArchive &ar, const std::map<BoundaryId, DieSurface<dim>> &dies)
  {
    std::size_t n = dies.size();
    ar << n;
    for (const auto &[id, surface] : dies)
      {
        BoundaryId copy = id;
        ar << copy;
        surface.save(ar);
      }
  }



  template <int dim>
  void
  load_dies(InputArchive &ar, std::map<BoundaryId, DieSurface<dim>> &dies)
  {
    dies.clear();
    std::size_t n = 0;
    ar >> n;
    for (std::size_t i = 0; i < n; ++i)
      {
        BoundaryId id = 0;
        ar >> id;
        dies[id].load(ar);
      }
  }



  template <int dim>
  void
  DieSurface<dim>::set_facets(const std::vector<Facet> &new_facets)
  {
    facets.clear();
    std::vector<Box> boxes;
    for (const auto &f : new_facets)
      {
        Facet                facet  = f;
        const Tensor<1, dim> normal = facet_normal<dim>(facet.vertices);
        const double         length = normal.norm();
        require(length > 0 && std::isfinite(length), "Contact/Die surfaces", "a facet of the die surface is degenerate");
        facet.normal = normal / length;
        facets.push_back(facet);
        const std::vector<Point<dim>> points(facet.vertices.begin(), facet.vertices.end());
        boxes.emplace_back(dealii::BoundingBox<dim>(points), facets.size() - 1);
      }
    dealii::BoundingBox<dim> all = boxes.front().first;
    for (const auto &b : boxes)
      all.merge_with(b.first);
    size = all.vertex(0).distance(all.vertex((1 << dim) - 1));
    // Widened by the search tolerance (attach_die_surfaces: 1e-6 of the
    // diameter), so that a node off the plane by round-off still hits.
    for (auto &b : boxes)
      b.first.extend(1e-6 * size);
    tree = dealii::pack_rtree(boxes);
  }



  template <int dim>
  void
  DieSurface<dim>::translate(const Tensor<1, dim> &shift)
  {
    std::vector<Facet> moved = facets;
    for (auto &facet : moved)
      for (auto &x : facet.vertices)
        x += shift;
    set_facets(moved);
  }



  template <int dim>
  std::optional<typename DieSurface<dim>::Match>
  DieSurface<dim>::find(const Point<dim> &position, const Tensor<1, dim> &metal_normal, const double tolerance,
                        const double cos_corner) const
  {
    std::optional<Match> best;
    double               best_insideness = -std::numeric_limits<double>::max();
    // The node may lie on an edge or vertex of the die, shared by facets of
    // different normals (a faceted cone): its normal is their mean, by
    // measure, as the mesh's walls do (WallNode).
    Tensor<1, dim> mean_normal;
    for (const Facet *facet : facets_near(dealii::BoundingBox<dim>(std::make_pair(position, position))))
      {
        const Facet &f         = *facet;
        const double alignment = f.normal * metal_normal;
        if (std::abs(alignment) < cos_corner)
          continue;
        const double distance = std::abs((position - f.vertices[0]) * f.normal);
        // Outside the facet by at most the tolerance, too (a node at a
        // facet's edge, written with fewer digits).
        if (distance > tolerance || !over<dim>(f.vertices, position, tolerance))
          continue;
        const double         inside   = insideness<dim>(f.vertices, position);
        const Tensor<1, dim> oriented = alignment > 0 ? f.normal : -f.normal;
        mean_normal += facet_measure<dim>(f.vertices) * oriented;
        if (inside > best_insideness)
          {
            best_insideness = inside;
            best            = Match{{f.vertices, oriented}, distance};
          }
      }
    if (best)
      best->facet.normal = mean_normal / mean_normal.norm();
    return best;
  }



  template <int dim>
  std::optional<typename DieSurface<dim>::Projection>
  DieSurface<dim>::project(const Point<dim> &x, const double radius, const double tolerance) const
  {
    dealii::BoundingBox<dim> around(std::make_pair(x, x));
    around.extend(radius);
    std::optional<Projection> nearest;
    for (const Facet *facet : facets_near(around))
      {
        const Facet &f        = *facet;
        const double distance = (x - f.vertices[0]) * f.normal;
        if (std::abs(distance) > radius || !over<dim>(f.vertices, x, tolerance))
          continue;
        if (!nearest || std::abs(distance) < nearest->distance)
          nearest = Projection{x - distance * f.normal, std::abs(distance), f};
      }
    return nearest;
  }



  template <int dim>
  std::optional<typename DieSurface<dim>::Projection>
  DieSurface<dim>::crossing(const Point<dim> &from, const Point<dim> &to, const double tolerance) const
  {
    dealii::BoundingBox<dim> path(std::vector<Point<dim>>{from, to});
    path.extend(tolerance);
    std::optional<Projection> deepest;
    for (const Facet *facet : facets_near(path))
      {
        const Facet &f      = *facet;
        const double before = (from - f.vertices[0]) * f.normal;
        const double after  = (to - f.vertices[0]) * f.normal;
        const bool   went_through = before * after < 0 && std::abs(before) > tolerance;
        if (!(went_through || std::abs(after) <= tolerance) || !over<dim>(f.vertices, to, tolerance))
          continue;
        const double depth = went_through ? std::abs(after) : 0.;
        if (!deepest || depth > deepest->distance)
          deepest = Projection{to - after * f.normal, depth, f};
      }
    return deepest;
  }



  template <int dim>
  void
  attach_die_surfaces(const std::map<BoundaryId, DieSurface<dim>> &surfaces,
                      const double                                 corner_angle_degrees,
                      const bool                                   in_time,
                      std::vector<WallNode<dim>> &                 wall_nodes)
  {
    const double cos_corner = std::cos(corner_angle_degrees * dealii::numbers::PI / 180.);
    for (auto &node : wall_nodes)
      {
        std::vector<bool> off_die(node.directions.size(), false);
        for (unsigned int k = 0; k < node.directions.size(); ++k)
          {
            auto &     direction = node.directions[k];
            const auto surface   = surfaces.find(direction.id);
            if (surface == surfaces.end())
              continue;
            const double tolerance = 1e-6 * surface->second.diameter();
            const auto   match     = surface->second.find(node.position, direction.normal, tolerance, cos_corner);
            if (match)
              {
                direction.facet  = match->facet.vertices;
                direction.normal = match->facet.normal;
                continue;
              }
            if (in_time)
              {
                off_die[k] = true;
                continue;
              }
            std::ostringstream message;
            message.precision(6);
            message << "the metal's wall node at (" << node.position << ") of boundary id " << direction.id
                    << " lies on no facet of its die surface with a normal within " << corner_angle_degrees
                    << " degrees of the wall's (tolerance " << tolerance
                    << " mm): in a steady run the metal's die boundary must lie on the die surface";
            throw InputError("Contact/Die surfaces: " + message.str());
          }
        join_directions_off_the_die(off_die, node);
        join_directions_of_one_wall(node);
      }
  }



  template <int dim>
  void
  join_directions_of_one_wall(WallNode<dim> &node)
  {
    std::vector<WallDirection<dim>> kept;
    for (const auto &direction : node.directions)
      {
        const auto same = std::find_if(kept.begin(), kept.end(), [&](const WallDirection<dim> &k) {
          return k.id == direction.id && k.normal * direction.normal > 1 - 1e-12;
        });
        if (same == kept.end())
          kept.push_back(direction);
        else
          {
            same->weight += direction.weight;
            same->length += direction.length;
          }
      }
    node.directions = kept;
  }



  template class DieSurface<2>;
  template class DieSurface<3>;
  template void
  join_directions_of_one_wall<2>(WallNode<2> &);
  template void
  join_directions_of_one_wall<3>(WallNode<3> &);
  template void
  attach_die_surfaces<2>(const std::map<BoundaryId, DieSurface<2>> &, const double, const bool, std::vector<WallNode<2>> &);
  template void
  attach_die_surfaces<3>(const std::map<BoundaryId, DieSurface<3>> &, const double, const bool, std::vector<WallNode<3>> &);
  template void
  save_dies(OutputArchive &, const std::map<BoundaryId, DieSurface<2>> &);
  template void
  save_dies(OutputArchive &, const std::map<BoundaryId, DieSurface<3>> &);
  template void
  load_dies(InputArchive &, std::map<BoundaryId, DieSurface<2>> &);
  template void
  load_dies(InputArchive &, std::map<BoundaryId, DieSurface<3>> &);
} // namespace dieflow
