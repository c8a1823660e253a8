// A rigid die read on its own: its facets, the search for a node's master facet, and the wall nodes' directions taken from it.
#ifndef dieflow_die_surface_h
#define dieflow_die_surface_h

#include <dieflow/base/archive.h>
#include <dieflow/base/parameters.h>

#include <dieflow/mesh/wall_nodes.h>

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/numerics/rtree.h>

#include <array>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dieflow
{
  using dealii::Point;

  /**
   * A rigid die given on its own, apart from the metal's mesh: a surface of
   * facets (segments in 2D, triangles in 3D; a quadrilateral is split into
   * two triangles along its diagonal 0-3) read from a Gmsh file, and the
   * node-to-facet search that gives a node of the metal's wall its master
   * facet, the segment 1-2 or triangle 1-2-3 of the paper's contact
   * element, and its normal n = (x2 - x1) x (x3 - x1) / |.| (in 2D the
   * segment's normal), oriented out of the metal.
   *
   * The search: the facets whose bounding boxes (widened by the tolerance)
   * hold the node (an R-tree, so O(log N) per node), and among them those
   * whose plane lies within the tolerance of the node, whose normal is
   * within the corner angle of the metal's normal there (a node at a die
   * corner finds one facet per wall direction), and that contain the node's
   * projection (outside it by at most the tolerance); of these the one that
   * holds it most inside.
   */
  template <int dim>
  class DieSurface
  {
  public:
    struct Facet
    {
      std::array<Point<dim>, dim> vertices;
      /// Unit normal, in the orientation of the file (the search orients it).
      Tensor<1, dim>              normal;
    };

    /**
     * Reads a Gmsh file (format 2 or 4) of lines (2D) or triangles and
     * quadrilaterals (3D); @p entry names the deck entry in messages, a
     * relative path is relative to @p base_directory.
     */
    void
    read(const std::string &file_name, const std::string &base_directory, const std::string &entry);

    /// The facets of a surface given directly (tests; a moving die later).
    void
    set_facets(const std::vector<Facet> &facets);

    /// Its facets into a checkpoint, and back (load() rebuilds the search tree).
    void
    save(OutputArchive &ar) const;
    void
    load(InputArchive &ar);

    /// The facets, where they are now (a checkpoint's).
    const std::vector<Facet> &
    all_facets() const
    {
      return facets;
    }

    struct Match
    {
      Facet  facet;
      /// |(x - x_1).n|: the node's distance from the facet's plane.
      double distance;
    };

    /**
     * The master facet of the node at @p position whose wall has the
     * metal's outward normal @p metal_normal, oriented like it, or none
     * within @p tolerance (distance) and @p cos_corner (angle).
     */
    std::optional<Match>
    find(const Point<dim> &position, const Tensor<1, dim> &metal_normal, const double tolerance,
         const double cos_corner) const;

    /// A point of the surface and how far it is from the point it stands for.
    struct Projection
    {
      Point<dim> point;
      double     distance;
      /// The facet projected onto.
      Facet facet;
    };

    /**
     * The nearest projection of @p x onto the plane of a facet that holds
     * it (outside by at most @p tolerance), among the facets within
     * @p radius of @p x; none if there is none.
     */
    std::optional<Projection>
    project(const Point<dim> &x, const double radius, const double tolerance) const;

    /**
     * Whether a node moving straight from @p from to @p to went through a
     * facet (its distance to the plane changed sign, or it ended within
     * @p tolerance of it) and ended over it: then the end's projection onto
     * that plane and the depth it went through (the largest such facet's).
     * Orientation-free, so that a die needs no inside.
     */
    std::optional<Projection>
    crossing(const Point<dim> &from, const Point<dim> &to, const double tolerance) const;

    /**
     * The facets of one cell of a surface mesh or one boundary face of the
     * metal's mesh (either accessor): a segment or triangle as it is, a
     * quadrilateral (lexicographic vertices) split on its diagonal 0-3.
     */
    template <typename Accessor>
    static std::vector<Facet>
    facets_of(const Accessor &cell)
    {
      std::vector<std::array<unsigned int, dim>> pieces(1);
      for (unsigned int v = 0; v < dim; ++v)
        pieces[0][v] = v;
      if constexpr (dim == 3)
        if (cell.n_vertices() == 4)
          pieces = {{{0, 1, 3}}, {{0, 3, 2}}};
      std::vector<Facet> result(pieces.size());
      for (unsigned int p = 0; p < pieces.size(); ++p)
        for (unsigned int v = 0; v < dim; ++v)
          result[p].vertices[v] = cell.vertex(pieces[p][v]);
      return result;
    }

    /// Moves the whole surface by @p shift (a die's rigid step).
    void
    translate(const Tensor<1, dim> &shift);

    unsigned int
    n_facets() const
    {
      return facets.size();
    }

    /// Diagonal of the bounding box of all facets.
    double
    diameter() const
    {
      return size;
    }

  private:
    /// The facets whose (widened) bounding boxes meet @p box: the R-tree's
    /// candidates for the searches above.
    std::vector<const Facet *>
    facets_near(const dealii::BoundingBox<dim> &box) const;

    std::vector<Facet> facets;
    double             size = 0;
    using Box = std::pair<dealii::BoundingBox<dim>, unsigned int>;
    dealii::RTree<Box> tree;
  };

  /// Dies by boundary id (each with its facets) into a checkpoint, and back.
  template <int dim>
  void
  save_dies(OutputArchive &ar, const std::map<BoundaryId, DieSurface<dim>> &dies);
  template <int dim>
  void
  load_dies(InputArchive &ar, std::map<BoundaryId, DieSurface<dim>> &dies);



  /**
   * Joins the directions of @p node that are one wall of one die (the same
   * id and normal, to round-off), their weights and lengths added. The
   * node's two faces may meet at an angle where the die has none (a new
   * mesh's node near a die corner, off the die, both of whose directions
   * take the facet under it: ContactGaps::close_gaps()); held twice along
   * one normal the node would count as held by two walls, at rest and
   * "sticking", while it slides
   * (doc/benchmarks.md, "Figures behind the code's rules").
   */
  template <int dim>
  void
  join_directions_of_one_wall(WallNode<dim> &node);

  /**
   * Die surfaces read on their own (Contact/Die surfaces): for every
   * direction of a wall node whose id has a surface, its master facet and
   * normal become the surface's, found by DieSurface::find(). In a steady
   * run the metal's die boundary must lie on the die: a node farther from
   * every facet of matching normal than 1e-6 of the surface's diameter is
   * an input error that names the node and the distance.
   *
   * In time (@p in_time) the metal moves over the die, and a node of a die
   * face may be off it: a corner node of the metal that slid past a corner
   * of the die (the exit D) lies on one of its walls only, so its other
   * direction joins the one on the die (weights and lengths added: the
   * node is on one wall now); a node off every facet (it separated, or slid
   * past the die's end) keeps the facet and normal of the metal's own face,
   * as a die made of the metal's faces does, and ContactGaps decides when
   * its face leaves the die.
   */
  template <int dim>
  void
  attach_die_surfaces(const std::map<BoundaryId, DieSurface<dim>> &surfaces,
                      const double                                 corner_angle_degrees,
                      const bool                                   in_time,
                      std::vector<WallNode<dim>> &                 wall_nodes);

} // namespace dieflow

#endif
