// The free surface of a steady flow and the deck's Free surface subsection: moves onto the streamlines of a solution, the dies keeping it out.
#include <dieflow/free_surface/free_surface.h>

#include <dieflow/mesh/mesh_motion.h>
#include <dieflow/mesh/boundary_loops.h>

#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace dieflow
{
  void
  FreeSurfaceParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Free surface");
    prm.declare_entry("Iterations",
                      "0",
                      dealii::Patterns::Integer(0, 200),
                      "Steady runs (2D): the most moves of the free surface per cycle, "
                      "each followed by a solve, until it is a streamline of the flow "
                      "(v.n = 0; doc/incremental.md). The free surface: the faces of the "
                      "Free surface ids, and the die faces the metal leaves (separated). "
                      "0: the domain stays as meshed, and the metal leaves a die in "
                      "velocity only (the mass-balance warning of a die's flux).");
    prm.declare_entry("Tolerance",
                      "1e-3",
                      dealii::Patterns::Double(0),
                      "The free surface has settled when no node of it would move more "
                      "than this part of the shorter of its two boundary edges.");
    prm.declare_entry("Free surface ids",
                      "",
                      dealii::Patterns::List(dealii::Patterns::Integer(0, 255)),
                      "Ids of Boundary conditions/Traction free ids whose faces are free "
                      "surfaces of the metal (not an outlet, where it flows out). The die "
                      "faces the metal leaves take the first (it need not be in the mesh); "
                      "needed when Iterations > 0.");
    prm.leave_subsection();
  }



  void
  FreeSurfaceParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Free surface");
    iterations = prm.get_integer("Iterations");
    tolerance  = prm.get_double("Tolerance");
    ids.clear();
    for (const std::string &id : dealii::Utilities::split_string_list(prm.get("Free surface ids")))
      ids.push_back(static_cast<BoundaryId>(dealii::Utilities::string_to_int(id)));
    prm.leave_subsection();
    require(iterations == 0 || !ids.empty(),
            "Free surface/Free surface ids",
            "is empty: a traction-free id is needed for the die faces the metal leaves (Iterations > 0)");
  }



  void
  FreeSurface::initialize(const dealii::Triangulation<2> &mesh, const std::set<BoundaryId> &die_ids,
                          const FreeSurfaceParameters &free_surface_parameters)
  {
    parameters = free_surface_parameters;
    dies.clear();
    const auto &x = mesh.get_vertices();
    for (const auto &loop : boundary_loops(mesh, "Free surface/Iterations"))
      for (const BoundaryEdge &e : loop)
        if (die_ids.count(e.id))
          {
            // The domain is on the edge's left: out of it is to the right.
            const Tensor<1, 2> along = x[e.b] - x[e.a];
            dies.push_back({x[e.a], x[e.b], Tensor<1, 2>({along[1], -along[0]}) / along.norm(), e.id});
          }
    on_die = 1e-9 * dealii::GridTools::diameter(mesh);
  }



  FreeSurface::Nearest
  FreeSurface::nearest_die(const dealii::Point<2> &x) const
  {
    Nearest nearest{0, x, dealii::numbers::invalid_boundary_id};
    double  best = std::numeric_limits<double>::max();
    for (const Segment &s : dies)
      {
        const Tensor<1, 2> along = s.b - s.a;
        const double       t     = std::clamp((x - s.a) * along / along.norm_square(), 0., 1.);
        const auto         point = s.a + t * along;
        const double       d     = x.distance(point);
        const double       side  = (x - point) * s.normal;
        if (d < best - on_die)
          {
            best    = d;
            nearest = {side, point, s.id};
          }
        else if (d <= best + on_die)
          nearest.depth += side;
      }
    if (nearest.id != dealii::numbers::invalid_boundary_id)
      nearest.depth = nearest.depth > 0 ? best : -best;
    return nearest;
  }



  namespace
  {
    /// The largest move of a node per move(), over its edge's length.
    constexpr double largest_step = 0.25;

    /// The velocity at every vertex of the mesh.
    std::vector<Tensor<1, 2>>
    vertex_velocities(const dealii::DoFHandler<2> &dof_handler, const dealii::Vector<double> &velocity)
    {
      std::vector<Tensor<1, 2>> v(dof_handler.get_triangulation().n_vertices());
      for (const auto &cell : dof_handler.active_cell_iterators())
        for (const unsigned int i : cell->vertex_indices())
          for (unsigned int d = 0; d < 2; ++d)
            v[cell->vertex_index(i)][d] = velocity[cell->vertex_dof_index(i, d)];
      return v;
    }

    Tensor<1, 2>
    outward_normal(const dealii::Point<2> &a, const dealii::Point<2> &b)
    {
      const Tensor<1, 2> along = b - a;
      return Tensor<1, 2>({along[1], -along[0]}) / along.norm();
    }
  } // namespace



  FreeSurfaceMove
  FreeSurface::move(dealii::Triangulation<2> &mesh, const dealii::DoFHandler<2> &dof_handler,
                    const dealii::Vector<double> &velocity, const std::vector<ContactNodeResult<2>> &results,
                    const bool apply)
  {
    const std::vector<dealii::Point<2>> x = mesh.get_vertices();
    const std::vector<Tensor<1, 2>>     v = vertex_velocities(dof_handler, velocity);
    // A die face is held where a node's direction of that die, of the face's normal, is not separated.
    const auto held = [&](const unsigned int vertex, const BoundaryId id, const Tensor<1, 2> &normal) {
      for (const auto &r : results)
        if (r.vertex == vertex && r.id == id && r.status != ContactStatus::separated && r.normal * normal > 0.9)
          return true;
      return false;
    };
    const auto is_free_id = [&](const BoundaryId id) {
      return std::find(parameters.ids.begin(), parameters.ids.end(), id) != parameters.ids.end();
    };
    std::set<BoundaryId> die_ids;
    for (const Segment &s : dies)
      die_ids.insert(s.id);

    std::map<unsigned int, dealii::Point<2>> placed;
    std::map<unsigned int, BoundaryId>       face_ids;
    std::vector<BoundaryEdge>                surface;
    FreeSurfaceMove                          result;
    const auto place = [&](const unsigned int vertex, const dealii::Point<2> &p, const double edge) {
      placed[vertex]  = p;
      result.largest = std::max(result.largest, p.distance(x[vertex]) / edge);
    };

    for (const auto &loop : boundary_loops(mesh, "Free surface/Iterations"))
      {
        const unsigned int n = loop.size();
        std::vector<bool>  is_free(n);
        for (unsigned int k = 0; k < n; ++k)
          {
            const BoundaryEdge &e      = loop[k];
            const Tensor<1, 2>  normal = outward_normal(x[e.a], x[e.b]);
            is_free[k] = is_free_id(e.id) || (die_ids.count(e.id) && !held(e.a, e.id, normal) && !held(e.b, e.id, normal));
          }
        const auto first_held = std::find(is_free.begin(), is_free.end(), false);
        if (first_held == is_free.end())
          continue;
        // Each stretch of free edges, from the edge after a held one.
        for (unsigned int j = 0, start = first_held - is_free.begin(); j < n; ++j)
          {
            const unsigned int k = (start + j) % n;
            if (!is_free[k] || is_free[(k + n - 1) % n])
              continue;
            std::vector<unsigned int> edges;
            for (unsigned int i = k; is_free[i]; i = (i + 1) % n)
              edges.push_back(i);
            // March from the end where the flow comes in.
            std::vector<unsigned int> nodes{loop[edges.front()].a};
            for (const unsigned int i : edges)
              nodes.push_back(loop[i].b);
            const auto   into = [&](const unsigned int end, const unsigned int next) {
              return v[nodes[end]] * (x[nodes[next]] - x[nodes[end]]) / x[nodes[next]].distance(x[nodes[end]]);
            };
            const unsigned int m = nodes.size() - 1;
            const bool         reversed = into(m, m - 1) > into(0, 1);
            unsigned int       after    = (edges.back() + 1) % n;
            if (reversed)
              {
                std::reverse(nodes.begin(), nodes.end());
                std::reverse(edges.begin(), edges.end());
                after = (edges.back() + n - 1) % n;
              }
            // On over the die faces that follow (the metal may come onto the
            // die again there, or leave it: the march puts their nodes back
            // onto it where the flow goes into it), to the next other part.
            const auto downstream = [&](const unsigned int i) { return reversed ? (i + n - 1) % n : (i + 1) % n; };
            while (die_ids.count(loop[after].id) && !is_free[after] && edges.size() < n)
              {
                nodes.push_back(reversed ? loop[after].a : loop[after].b);
                edges.push_back(after);
                after = downstream(after);
              }
            const bool       end_moves = edges.size() < n && !is_free[after];
            dealii::Point<2> here      = x[nodes[0]];
            for (unsigned int i = 0; i + 1 < nodes.size(); ++i)
              {
                const unsigned int a = nodes[i], b = nodes[i + 1];
                const Tensor<1, 2> old_edge = x[b] - x[a];
                const double       length   = old_edge.norm();
                if (i + 2 == nodes.size() && !end_moves)
                  break;
                const Tensor<1, 2> flow = v[a] + v[b];
                const Tensor<1, 2> along = flow / flow.norm();
                // Against the flow or across it (a stagnation point): the edge as it was.
                const Tensor<1, 2> edge = old_edge * along > 0 ? Tensor<1, 2>((old_edge * along) * along) : old_edge;
                dealii::Point<2>   next = here + edge;
                const Nearest      die  = nearest_die(next);
                if (die.depth > on_die)
                  next = die.point;
                place(b, next, length);
                here = next;
              }
            for (const unsigned int i : edges)
              surface.push_back(loop[i]);
            if (!end_moves)
              continue;
            // The straight boundary after the stretch (the outlet) stretches to its moved end.
            const unsigned int end = nodes.back();
            std::vector<unsigned int> line;
            const Tensor<1, 2>        first = reversed ? x[loop[after].a] - x[end] : x[loop[after].b] - x[end];
            for (unsigned int i = after, count = 0; !is_free[i] && count < n; i = downstream(i), ++count)
              {
                const unsigned int far = reversed ? loop[i].a : loop[i].b;
                const Tensor<1, 2> to  = x[far] - x[end];
                if (loop[i].id != loop[after].id || std::abs(first[0] * to[1] - first[1] * to[0]) > 1e-9 * first.norm() * to.norm())
                  break;
                line.push_back(far);
              }
            if (line.empty())
              continue;
            const dealii::Point<2> corner = x[line.back()];
            const double           span   = x[end].distance(corner);
            for (unsigned int i = 0; i + 1 < line.size(); ++i)
              placed[line[i]] = corner + x[line[i]].distance(corner) / span * (placed[end] - corner);
          }
      }

    // A damped fixed point: the first streamlines of a domain the metal
    // does not fill can be edges away from the last, and the interior's
    // move must not turn cells inside out.
    if (result.largest > largest_step)
      for (auto &[vertex, p] : placed)
        p = x[vertex] + largest_step / result.largest * (p - x[vertex]);
    const auto at = [&](const unsigned int vertex) { return placed.count(vertex) ? placed.at(vertex) : x[vertex]; };
    for (const BoundaryEdge &e : surface)
      {
        const Nearest a = nearest_die(at(e.a)), b = nearest_die(at(e.b));
        const bool    on = a.id != dealii::numbers::invalid_boundary_id && a.id == b.id && std::abs(a.depth) <= on_die &&
                        std::abs(b.depth) <= on_die && !let_go.count(e.face);
        if (!on && die_ids.count(e.id) && apply && result.largest > parameters.tolerance)
          let_go.insert(e.face);
        face_ids[e.face] = on ? a.id : is_free_id(e.id) ? e.id : parameters.ids.front();
        result.free_faces += on ? 0 : 1;
        result.let_go += (!on && die_ids.count(e.id)) ? 1 : 0;
        result.reattached += (on && !die_ids.count(e.id)) ? 1 : 0;
      }
    if (!apply || result.largest <= parameters.tolerance)
      return result;
    std::map<unsigned int, dealii::Point<2>> boundary = dealii::GridTools::get_all_vertices_at_boundary(mesh);
    for (const auto &[vertex, p] : placed)
      boundary[vertex] = p;
    dealii::GridTools::laplace_transform(boundary, mesh);
    place_hanging_vertices(mesh);
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face_ids.count(face->index()))
          face->set_boundary_id(face_ids.at(face->index()));
    return result;
  }
} // namespace dieflow
