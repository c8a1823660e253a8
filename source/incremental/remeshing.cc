// Meshing a run's domain anew: when (the deck's remeshing entries), and how (Gmsh's quadrilaterals inside the same boundary).
#include <dieflow/incremental/remeshing.h>

#include <dieflow/incremental/time_stepping.h>
#include <dieflow/mesh/boundary_loops.h>

#include <deal.II/grid/grid_tools.h>

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

namespace dieflow
{
  void
  RemeshingParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Remesh below Jacobian",
                      "0",
                      dealii::Patterns::Double(0, 1),
                      "Mesh the domain anew (2D, Gmsh) before a step whose moved mesh has a "
                      "cell corner whose scaled Jacobian (the sine of its angle; 1 for "
                      "rectangles) is below this; 0: never. About 0.2-0.3 keeps the cells "
                      "fit for the solve. The boundary nodes stay, so the volume is kept; "
                      "the velocity and the equivalent strain go over to the new mesh "
                      "(doc/incremental.md).");
    prm.declare_entry("Remesh interval",
                      "0",
                      dealii::Patterns::Integer(0),
                      "Also mesh the domain anew every this many steps since the last "
                      "new mesh; 0: only by Remesh below Jacobian.");
    prm.declare_entry("Remesh boundary edge length",
                      "0",
                      dealii::Patterns::Double(0),
                      "In a new mesh, cut every boundary edge longer than this (mm) into "
                      "equal pieces on it, no longer than it; 0: the boundary's edges as "
                      "they are. Where metal flows out of a die its surface stretches by "
                      "the reduction (an extrudate's edges grow 4x through die2d), and the "
                      "new mesh's cells take their size from the boundary's edges.");
  }



  void
  RemeshingParameters::parse_parameters(ParameterHandler &prm)
  {
    jacobian_threshold = prm.get_double("Remesh below Jacobian");
    interval             = prm.get_integer("Remesh interval");
    boundary_edge_length = prm.get_double("Remesh boundary edge length");
  }



    namespace
  {
    std::pair<unsigned int, unsigned int>
    edge_key(const unsigned int a, const unsigned int b)
    {
      return {std::min(a, b), std::max(a, b)};
    }

    /// Twice the signed area of @p loop (positive: counter-clockwise).
    double
    signed_area(const std::vector<dealii::Point<2>> &x, const std::vector<BoundaryEdge> &loop)
    {
      double area = 0;
      for (const auto &e : loop)
        area += x[e.a][0] * x[e.b][1] - x[e.b][0] * x[e.a][1];
      return area;
    }

    /// Gmsh's API is global state and sets its own signal handlers: one
    /// session at a time, and dieflow's handlers (interrupt.h) back after it.
    class GmshSession
    {
    public:
      GmshSession()
      {
        for (unsigned int i = 0; i < signals.size(); ++i)
          sigaction(signals[i], nullptr, &saved[i]);
        gmsh::initialize(0, nullptr, false);
        gmsh::option::setNumber("General.Terminal", 0);
      }
      ~GmshSession()
      {
        // Also when Gmsh's error unwinds through here: a second throw would end the program.
        try
          {
            gmsh::finalize();
          }
        catch (...)
          {}
        for (unsigned int i = 0; i < signals.size(); ++i)
          sigaction(signals[i], &saved[i], nullptr);
      }

    private:
      const std::array<int, 4>             signals{{SIGINT, SIGTERM, SIGSEGV, SIGFPE}};
      std::array<struct sigaction, 4>      saved;
    };

    /**
     * A stretch of a boundary loop that becomes one Gmsh line: two old
     * edges a-m-b (the line's midpoint node, which Gmsh's subdivision
     * makes, goes to m), or one edge a-b (the midpoint stays: the edge is
     * split, on itself).
     */
    struct BoundaryGroup
    {
      std::vector<BoundaryEdge> edges;
      /// Gmsh's segments on the line (more than one: a long edge cut).
      unsigned int              segments = 1;
      unsigned int
      first() const
      {
        return edges.front().a;
      }
      unsigned int
      last() const
      {
        return edges.back().b;
      }
    };

    /// Pairs the edges of @p loop where their middle vertex is near the
    /// chord's midpoint (within a tenth of the chord), both have one id and
    /// neither is longer than @p longest_edge (0: no limit); an edge longer
    /// than that gets as many Gmsh segments as, halved, make it no longer.
    std::vector<BoundaryGroup>
    group_edges(const std::vector<dealii::Point<2>> &x,
                const std::vector<BoundaryEdge> &    loop,
                const double                         longest_edge,
                const EdgeFilter<2> &                may_cut,
                const bool                           pair)
    {
      const auto too_long = [&](const BoundaryEdge &e) {
        return longest_edge > 0 && x[e.a].distance(x[e.b]) > longest_edge && may_cut(x[e.a], x[e.b], e.id);
      };
      const unsigned int n = loop.size();
      // Start where the id changes (a pair never straddles it), if anywhere.
      unsigned int start = 0;
      for (unsigned int k = 0; k < n; ++k)
        if (loop[k].id != loop[(k + n - 1) % n].id)
          {
            start = k;
            break;
          }
      std::vector<BoundaryGroup> groups;
      for (unsigned int j = 0; j < n;)
        {
          const BoundaryEdge &e = loop[(start + j) % n];
          if (j + 1 < n)
            {
              const BoundaryEdge &f     = loop[(start + j + 1) % n];
              const double        chord = x[e.a].distance(x[f.b]);
              if (pair && e.id == f.id && !too_long(e) && !too_long(f) &&
                  x[e.b].distance(0.5 * (x[e.a] + x[f.b])) <= 0.1 * chord)
                {
                  groups.push_back({{e, f}});
                  j += 2;
                  continue;
                }
            }
          const unsigned int segments =
            too_long(e) ? static_cast<unsigned int>(std::ceil(x[e.a].distance(x[e.b]) / (2 * longest_edge))) : 1;
          groups.push_back({{e}, segments});
          ++j;
        }
      return groups;
    }

    /**
     * Drops the boundary vertices that crowd their neighbours from @p loop:
     * while an edge is shorter than a quarter of the longer of its two
     * neighbours, or than a tenth of @p longest_edge (if not 0), one of its
     * ends goes, the one whose triangle with its two neighbours is the
     * smaller (a vertex on a straight wall before a corner: the polygon
     * stays the same), joining two edges of one id; never a reflex corner
     * (the chord would leave the domain). Nodes that flow into a
     * corner where the metal stands (the die entry, where a sticking die
     * face meets the wall) or that the dies put back onto one corner crowd
     * to a millionth of a millimetre: a new mesh that kept them all would
     * have cells of that size and corners of no angle at all. Returns the
     * number of vertices dropped.
     */
    unsigned int
    drop_crowding_vertices(const std::vector<dealii::Point<2>> &x,
                           std::vector<BoundaryEdge> &          loop,
                           const double                         longest_edge)
    {
      const auto length = [&](const BoundaryEdge &e) { return x[e.a].distance(x[e.b]); };
      // The triangle a vertex q cuts off with its neighbours p and r, when
      // the domain keeps the chord p-r: q is no reflex corner (the loops
      // have the domain on their left), else the new mesh would reach
      // beyond the old one, into a die; and q stands no higher over the
      // chord than a twentieth of it: a vertex crowded into a corner stands
      // a millionth over it, the corner of a fold (the ring's free side
      // folding onto the platen) a tenth or more, and the fold is the shape
      // of the metal, not a crowding (dropped, it took some of the ring's
      // volume and the run stopped at the next contact update;
      // doc/benchmarks.md).
      const auto cost = [&](const unsigned int p, const unsigned int q, const unsigned int r) {
        const dealii::Tensor<1, 2> u = x[q] - x[p], w = x[r] - x[q];
        const double               turn  = u[0] * w[1] - u[1] * w[0];
        const double               chord = (u + w).norm();
        const bool                 flat  = 0.5 * turn <= 0.025 * chord * chord; // height <= chord / 20
        return turn >= -1e-12 * u.norm() * w.norm() && flat ? 0.5 * turn : std::numeric_limits<double>::infinity();
      };
      unsigned int dropped = 0;
      std::set<std::pair<unsigned int, unsigned int>> stuck; // crowded edges neither of whose ends can go
      while (loop.size() > 4)
        {
          const unsigned int n        = loop.size();
          unsigned int       shortest = n;
          double             worst    = 1;
          for (unsigned int k = 0; k < n; ++k)
            {
              const double l          = length(loop[k]);
              const double neighbours = std::max(length(loop[(k + n - 1) % n]), length(loop[(k + 1) % n]));
              const double crowding   = std::min(l / (0.25 * neighbours), longest_edge > 0 ? l / (0.1 * longest_edge) : 1.);
              if (crowding < worst && stuck.count({loop[k].a, loop[k].b}) == 0)
                {
                  worst    = crowding;
                  shortest = k;
                }
            }
          if (shortest == n)
            break;
          const unsigned int  k    = shortest;
          const BoundaryEdge &e    = loop[k];
          const BoundaryEdge &prev = loop[(k + n - 1) % n];
          const BoundaryEdge &next = loop[(k + 1) % n];
          const double cost_a = prev.id == e.id ? cost(prev.a, e.a, e.b) : std::numeric_limits<double>::infinity();
          const double cost_b = next.id == e.id ? cost(e.a, e.b, next.b) : std::numeric_limits<double>::infinity();
          if (std::isinf(cost_a) && std::isinf(cost_b))
            {
              stuck.insert({e.a, e.b});
              continue;
            }
          if (cost_a <= cost_b)
            {
              loop[(k + n - 1) % n] = {prev.a, e.b, e.id, dealii::numbers::invalid_unsigned_int};
              loop.erase(loop.begin() + k);
            }
          else
            {
              loop[k] = {e.a, next.b, e.id, dealii::numbers::invalid_unsigned_int};
              loop.erase(loop.begin() + (k + 1) % n);
            }
          ++dropped;
        }
      return dropped;
    }

    /// Whether the cell of @p points with lexicographic @p vertices has a
    /// corner whose Jacobian is not positive.
    bool
    tangled(const std::vector<dealii::Point<2>> &points, const dealii::CellData<2> &cell)
    {
      return scaled_jacobian<2>({{points[cell.vertices[0]], points[cell.vertices[1]], points[cell.vertices[2]],
                                  points[cell.vertices[3]]}}) <= 0;
    }

    /// How Gmsh is asked for a new mesh: its triangulation algorithm
    /// (Mesh.Algorithm), and whether the boundary goes to it in pairs a-m-b.
    struct MeshingAttempt
    {
      int         algorithm;
      bool        pair;
      const char *name;
    };

    /// The new mesh (with pairs a-m-b if @p attempt says so), or none if
    /// Gmsh's cells came out tangled.
    std::optional<NewMesh>
    remesh_polygon(const dealii::Triangulation<2> &old,
                   dealii::Triangulation<2> &      fresh,
                   const double                    longest_edge,
                   const EdgeFilter<2> &           may_cut,
                   const MeshingAttempt &          attempt,
                   const std::string &             entry)
    {
      const bool pair = attempt.pair;
      const std::vector<dealii::Point<2>>    x     = old.get_vertices();
      std::vector<std::vector<BoundaryEdge>> loops = boundary_loops(old, entry);
      // The outer loop first (the largest counter-clockwise one), then the holes.
      std::sort(loops.begin(), loops.end(), [&](const auto &l, const auto &m) {
        return signed_area(x, l) > signed_area(x, m);
      });
      for (unsigned int l = 1; l < loops.size(); ++l)
        require(signed_area(x, loops[l]) < 0, entry, "cannot mesh the domain anew: it has more than one piece");

      NewMesh     result;
      GmshSession session;
      gmsh::model::add("dieflow-remesh");
      std::map<int, unsigned int>  vertex_of_point; // Gmsh point tag -> old vertex
      std::map<int, BoundaryGroup> group_of_line;
      std::map<int, std::pair<int, int>> ends_of_line;
      std::vector<int>             wires;
      for (const auto &loop : loops)
        {
          std::vector<BoundaryEdge> kept_loop = loop;
          result.dropped_vertices += drop_crowding_vertices(x, kept_loop, longest_edge);
          const std::vector<BoundaryGroup> groups = group_edges(x, kept_loop, longest_edge, may_cut, pair);
          const unsigned int               n      = groups.size();
          // Gmsh's cell size at a point: the mean length of its two lines'
          // segments, a single edge's counted twice (its halves are the
          // mesh's edges); a long edge cut: its segments.
          const auto size = [&](const BoundaryGroup &g) {
            const double length = x[g.first()].distance(x[g.last()]);
            return g.segments > 1 ? length / g.segments : length * (g.edges.size() == 1 ? 2. : 1.);
          };
          std::vector<int> points(n), lines(n);
          for (unsigned int k = 0; k < n; ++k)
            {
              const double h = 0.5 * (size(groups[(k + n - 1) % n]) + size(groups[k]));
              points[k]      = gmsh::model::geo::addPoint(x[groups[k].first()][0], x[groups[k].first()][1], 0, h);
              vertex_of_point[points[k]] = groups[k].first();
            }
          for (unsigned int k = 0; k < n; ++k)
            {
              lines[k]                = gmsh::model::geo::addLine(points[k], points[(k + 1) % n]);
              group_of_line[lines[k]] = groups[k];
              ends_of_line[lines[k]]  = {points[k], points[(k + 1) % n]};
            }
          wires.push_back(gmsh::model::geo::addCurveLoop(lines));
        }
      const int surface = gmsh::model::geo::addPlaneSurface(wires);
      gmsh::model::geo::synchronize();
      for (const auto &[line, group] : group_of_line)
        gmsh::model::mesh::setTransfiniteCurve(line, group.segments + 1);
      gmsh::model::mesh::setRecombine(2, surface);
      gmsh::option::setNumber("Mesh.Algorithm", attempt.algorithm);
      gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 1); // Blossom
      // Blossom may leave triangles; splitting every cell (a quadrilateral
      // into 4, a triangle into 3) leaves none, and halves every line.
      gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 1);
      // Gmsh meshes in an OpenMP region, out of which its exception (the
      // API's default, "General.AbortOnError" = 2) cannot be caught: it
      // would end the program. Abort the meshing instead, and ask.
      gmsh::option::setNumber("General.AbortOnError", 1);
      gmsh::model::mesh::generate(2);
      std::string gmsh_error;
      gmsh::logger::getLastError(gmsh_error);
      if (!gmsh_error.empty())
        throw gmsh_error;

      // Gmsh's nodes -> new vertices. The midpoint of a line of two old
      // edges goes to their middle vertex: the boundary is the old one.
      std::vector<dealii::Point<2>>       points;
      std::map<std::size_t, unsigned int> vertex_of_node;
      std::vector<std::size_t>            tags;
      std::vector<double>                 coordinates, parametric;
      gmsh::model::mesh::getNodes(tags, coordinates, parametric, -1, -1, true, false);
      for (unsigned int i = 0; i < tags.size(); ++i)
        if (vertex_of_node.emplace(tags[i], points.size()).second)
          points.emplace_back(coordinates[3 * i], coordinates[3 * i + 1]);
      // The nodes inside a point (one) or a line, in order along @p direction.
      const auto nodes_on = [&](const int dim, const int tag, const std::size_t expected,
                                const dealii::Tensor<1, 2> &direction = {}) {
        std::vector<std::size_t> on;
        std::vector<double>      c, p;
        gmsh::model::mesh::getNodes(on, c, p, dim, tag, false, false);
        require(on.size() == expected, entry, "Gmsh's mesh does not have the old boundary");
        std::vector<std::pair<double, unsigned int>> ordered;
        for (unsigned int i = 0; i < on.size(); ++i)
          ordered.emplace_back(c[3 * i] * direction[0] + c[3 * i + 1] * direction[1], vertex_of_node.at(on[i]));
        std::sort(ordered.begin(), ordered.end());
        std::vector<unsigned int> vertices;
        for (const auto &o : ordered)
          vertices.push_back(o.second);
        return vertices;
      };
      const auto node_on = [&](const int dim, const int tag) { return nodes_on(dim, tag, 1)[0]; };
      std::map<int, unsigned int> new_vertex_of_point;
      for (const auto &[point, vertex] : vertex_of_point)
        {
          new_vertex_of_point[point] = node_on(0, point);
          points[new_vertex_of_point[point]] = x[vertex]; // exactly
        }

      dealii::SubCellData                                           boundary;
      std::map<std::pair<unsigned int, unsigned int>, unsigned int> old_face_of_edge;
      const auto add_face = [&](const unsigned int a, const unsigned int b, const BoundaryId id, const unsigned int face) {
        dealii::CellData<1> line;
        line.vertices    = {a, b};
        line.boundary_id = id;
        boundary.boundary_lines.push_back(line);
        old_face_of_edge[edge_key(a, b)] = face;
      };
      for (const auto &[line, group] : group_of_line)
        {
          const unsigned int a = new_vertex_of_point.at(ends_of_line.at(line).first);
          const unsigned int b = new_vertex_of_point.at(ends_of_line.at(line).second);
          if (group.segments > 1)
            {
              // Gmsh's segments are equal, and so its halves: the nodes go exactly onto the edge.
              std::vector<unsigned int> chain =
                nodes_on(1, line, 2 * group.segments - 1, x[group.last()] - x[group.first()]);
              for (unsigned int i = 0; i < chain.size(); ++i)
                points[chain[i]] = x[group.first()] + (i + 1.) / (chain.size() + 1.) * (x[group.last()] - x[group.first()]);
              chain.insert(chain.begin(), a);
              chain.push_back(b);
              for (unsigned int i = 0; i + 1 < chain.size(); ++i)
                add_face(chain[i], chain[i + 1], group.edges[0].id, dealii::numbers::invalid_unsigned_int);
              ++result.split_edges;
              continue;
            }
          const unsigned int mid = node_on(1, line);
          if (group.edges.size() == 2)
            {
              points[mid] = x[group.edges[0].b];
              add_face(a, mid, group.edges[0].id, group.edges[0].face);
              add_face(mid, b, group.edges[1].id, group.edges[1].face);
            }
          else
            {
              add_face(a, mid, group.edges[0].id, dealii::numbers::invalid_unsigned_int);
              add_face(mid, b, group.edges[0].id, dealii::numbers::invalid_unsigned_int);
              ++result.split_edges;
            }
        }

      std::vector<std::size_t> quads, quad_nodes;
      gmsh::model::mesh::getElementsByType(3, quads, quad_nodes);
      require(!quads.empty(), entry, "Gmsh made no quadrilaterals");
      std::vector<dealii::CellData<2>> cells(quads.size());
      for (unsigned int c = 0; c < quads.size(); ++c)
        {
          // Gmsh's quadrilateral goes round; deal.II's vertices are lexicographic.
          static constexpr unsigned int lexicographic[4] = {0, 1, 3, 2};
          for (unsigned int v = 0; v < 4; ++v)
            cells[c].vertices[v] = vertex_of_node.at(quad_nodes[4 * c + lexicographic[v]]);
          cells[c].material_id = old.begin_active()->material_id();
        }
      // Gmsh goes round one way; a cell gone round the other was inverted
      // (deal.II's inversion throws when some are and some are not).
      const auto inverted = [&](const dealii::CellData<2> &cell) {
        const auto diagonal = points[cell.vertices[3]] - points[cell.vertices[0]];
        const auto other    = points[cell.vertices[2]] - points[cell.vertices[1]];
        return diagonal[0] * other[1] - diagonal[1] * other[0] < 0;
      };
      const auto n_inverted = std::count_if(cells.begin(), cells.end(), inverted);
      if (n_inverted > 0 && n_inverted < static_cast<long>(cells.size()))
        return std::nullopt;
      dealii::GridTools::invert_all_negative_measure_cells(points, cells);
      if (std::any_of(cells.begin(), cells.end(), [&](const auto &cell) { return tangled(points, cell); }))
        return std::nullopt;
      dealii::GridTools::consistently_order_cells(cells);
      fresh.clear();
      fresh.create_triangulation(points, cells, boundary);

      // The same boundary: as many boundary faces as edges, each an old one or a half.
      unsigned int n_boundary_faces = 0;
      for (const auto &cell : fresh.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              ++n_boundary_faces;
              const auto it = old_face_of_edge.find(edge_key(face->vertex_index(0), face->vertex_index(1)));
              require(it != old_face_of_edge.end(), entry, "Gmsh's mesh does not have the old boundary");
              if (it->second != dealii::numbers::invalid_unsigned_int)
                result.boundary_face_of_old[it->second] = face->index();
            }
      require(n_boundary_faces == old_face_of_edge.size(), entry, "Gmsh's mesh does not have the old boundary");
      return result;
    }
  } // namespace



  template <int dim>
  NewMesh
  remesh_domain(const dealii::Triangulation<dim> &old,
                dealii::Triangulation<dim> &      fresh,
                const double                      longest_edge,
                const EdgeFilter<dim> &           may_cut,
                const std::string &               entry)
  {
    if constexpr (dim == 2)
      {
        // Gmsh's cells can come out tangled (a few gone round the other
        // way; doc/benchmarks.md), or Gmsh can fail to recover a boundary
        // edge: then Gmsh meshes again, with another algorithm, and last with
        // every boundary edge a line of its own, split at its midpoint (which
        // keeps the boundary twice as fine: four times the cells).
        static constexpr MeshingAttempt attempts[] = {{6, true, "Frontal-Delaunay"},
                                                      {5, true, "Delaunay"},
                                                      {8, true, "Frontal-Delaunay for quads"},
                                                      {6, false, "every boundary edge a line of its own"}};
        std::string first_error;
        for (const MeshingAttempt &attempt : attempts)
          try
            {
              if (auto made = remesh_polygon(old, fresh, longest_edge, may_cut, attempt, entry))
                {
                  made->attempt = &attempt == attempts ? "" : attempt.name;
                  return *made;
                }
            }
          catch (const std::string &gmsh_error)
            {
              if (first_error.empty())
                first_error = gmsh_error;
            }
        throw InputError(entry + ": Gmsh could not make a new mesh of the domain" +
                         (first_error.empty() ? std::string(": its cells came out tangled (a corner of the boundary too "
                                                            "sharp for its cells)") :
                                                ": " + first_error) +
                         "; lower Incremental/Time step, or raise Remesh below Jacobian");
      }
    else
      {
        (void)old;
        (void)fresh;
        (void)longest_edge;
        (void)may_cut;
        throw InputError(entry + ": meshing the domain anew is available in 2D only (plane strain, axisymmetric)");
      }
  }

  template NewMesh
  remesh_domain(const dealii::Triangulation<2> &, dealii::Triangulation<2> &, const double, const EdgeFilter<2> &,
                const std::string &);
  template NewMesh
  remesh_domain(const dealii::Triangulation<3> &, dealii::Triangulation<3> &, const double, const EdgeFilter<3> &,
                const std::string &);
} // namespace dieflow
