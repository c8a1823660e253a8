// The free surface of a steady flow and the deck's Free surface subsection: moves onto the streamlines of a solution, the dies keeping it out.
#include <dieflow/free_surface/free_surface.h>

#include <dieflow/mesh/mesh_motion.h>
#include <dieflow/mesh/boundary_loops.h>
#include <dieflow/mesh/whole_mesh.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
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
                      "1e-5",
                      dealii::Patterns::Double(0),
                      "The free surface has settled when no node of it would move more "
                      "than this part of the free surface's length (its own scale, not "
                      "the mesh's) and no face of it would go to or from a die.");
    prm.declare_entry("Relaxation",
                      "Aitken",
                      dealii::Patterns::Selection("Aitken|none"),
                      "Aitken: each move is the march's times a factor in [0.25, 2] from the "
                      "last two moves (Irons and Tuck's form of Aitken's delta-squared), "
                      "which damps the first moves' overshoot onto the dies (a uniform "
                      "32-across die2d mesh with friction settles in 6 moves, not 40; "
                      "doc/incremental.md); started anew where faces come onto a die. "
                      "none: the march's own move.");
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
    relaxation = prm.get("Relaxation") == "none" ? Relaxation::none : Relaxation::aitken;
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
                          const FreeSurfaceParameters &free_surface_parameters,
                          const CoordinateSystem<2> &  coordinate_system)
  {
    parameters  = free_surface_parameters;
    coordinates = coordinate_system;
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



  dealii::Point<2>
  FreeSurface::onto_die(dealii::Point<2> out, dealii::Point<2> in) const
  {
    for (unsigned int bisection = 0; bisection < 60 && out.distance(in) > on_die; ++bisection)
      {
        const dealii::Point<2> middle = out + 0.5 * (in - out);
        (nearest_die(middle).depth > 0 ? in : out) = middle;
      }
    return out;
  }



  void
  FreeSurface::relax(std::map<unsigned int, dealii::Point<2>> &placed, const std::vector<dealii::Point<2>> &x)
  {
    if (parameters.relaxation == FreeSurfaceParameters::Relaxation::none)
      return;
    // Faces came onto a die: the map from surface to surface changed, and
    // the last move says nothing of the next (the sequence starts anew).
    if (restart)
      {
        last_residual.clear();
        relaxation = 1;
      }
    std::map<unsigned int, Tensor<1, 2>> residual;
    for (const auto &[vertex, p] : placed)
      residual[vertex] = p - x[vertex];
    if (!last_residual.empty())
      {
        // omega_k = -omega_k-1 r_k-1.(r_k - r_k-1) / |r_k - r_k-1|^2 over
        // the nodes of either move (a node in one only moved 0 in the other).
        double product = 0, change = 0;
        for (const auto &[vertex, r] : residual)
          {
            const auto         last   = last_residual.find(vertex);
            const Tensor<1, 2> before = last == last_residual.end() ? Tensor<1, 2>() : last->second;
            product += before * (r - before);
            change += (r - before).norm_square();
          }
        for (const auto &[vertex, before] : last_residual)
          if (!residual.count(vertex))
            {
              product -= before.norm_square();
              change += before.norm_square();
            }
        if (change > 0)
          relaxation = std::clamp(-relaxation * product / change, smallest_relaxation, largest_relaxation);
      }
    last_residual = residual;
    // A node the relaxed move puts into a die goes onto it on the way.
    for (auto &[vertex, p] : placed)
      {
        const dealii::Point<2> relaxed = x[vertex] + relaxation * residual[vertex];
        p = nearest_die(relaxed).depth > on_die ? onto_die(x[vertex], relaxed) : relaxed;
      }
  }



  namespace
  {
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

    /**
     * The mean of the velocity over each boundary face, weighted as
     * @p coordinates weights ds (2 pi r in axisymmetric runs): a straight
     * face along it has no flux, int v.n w ds = n . int v w ds = 0,
     * whatever the velocity degree.
     */
    std::map<unsigned int, Tensor<1, 2>>
    face_mean_velocities(const dealii::DoFHandler<2> &dof_handler, const dealii::Vector<double> &velocity,
                         const CoordinateSystem<2> &coordinates)
    {
      const dealii::QGauss<1>       quadrature(dof_handler.get_fe().degree + 1);
      dealii::FEFaceValues<2>       fe_face(dof_handler.get_fe(), quadrature,
                                      dealii::update_values | dealii::update_quadrature_points | dealii::update_JxW_values);
      const dealii::FEValuesExtractors::Vector v(0);
      std::vector<Tensor<1, 2>>     values(quadrature.size());
      std::map<unsigned int, Tensor<1, 2>> mean;
      for (const auto &cell : dof_handler.active_cell_iterators())
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            {
              fe_face.reinit(cell, f);
              fe_face[v].get_function_values(velocity, values);
              Tensor<1, 2> sum;
              double       weight = 0;
              for (unsigned int q = 0; q < quadrature.size(); ++q)
                {
                  const double w = fe_face.JxW(q) * coordinates.weight(fe_face.quadrature_point(q));
                  sum += w * values[q];
                  weight += w;
                }
              mean[cell->face(f)->index()] = weight > 0 ? sum / weight : sum;
            }
      return mean;
    }

    Tensor<1, 2>
    outward_normal(const dealii::Point<2> &a, const dealii::Point<2> &b)
    {
      const Tensor<1, 2> along = b - a;
      return Tensor<1, 2>({along[1], -along[0]}) / along.norm();
    }

    double
    cross(const Tensor<1, 2> &a, const Tensor<1, 2> &b)
    {
      return a[0] * b[1] - a[1] * b[0];
    }

    /// Puts every vertex of @p mesh at @p x (undoing a move).
    void
    set_vertices(dealii::Triangulation<2> &mesh, const std::vector<dealii::Point<2>> &x)
    {
      for (const auto &cell : mesh.cell_iterators())
        for (const unsigned int i : cell->vertex_indices())
          cell->vertex(i) = x[cell->vertex_index(i)];
    }
  } // namespace



  FreeSurfaceMove
  FreeSurface::move(dealii::Triangulation<2> &mesh, const dealii::DoFHandler<2> &dof_handler,
                    const dealii::Vector<double> &velocity, const std::vector<ContactNodeResult<2>> &results,
                    const bool apply)
  {
    const std::vector<dealii::Point<2>> x = mesh.get_vertices();
    const std::vector<Tensor<1, 2>>     v = vertex_velocities(dof_handler, velocity);
    const auto mean_velocity = face_mean_velocities(dof_handler, velocity, coordinates);
    // The least rate at which the metal must move away from a die for a
    // face to leave it: 1e-3 of the speed, a streamline at 0.06 degrees to
    // the die (the jets of die2d N0-N3 leave the land at 1-10 degrees).
    constexpr double leaving_rate = 1e-3;
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
    double                                   surface_length = 0;

    for (const auto &loop : boundary_loops(mesh, "Free surface/Iterations"))
      {
        const unsigned int n = loop.size();
        std::vector<bool>  is_free(n);
        for (unsigned int k = 0; k < n; ++k)
          {
            const BoundaryEdge &e      = loop[k];
            const Tensor<1, 2>  normal = outward_normal(x[e.a], x[e.b]);
            // A die face the contact lets go at both ends is free where the
            // metal moves away from the die: a separation the flow does
            // not make (the metal sliding along the die, as at the corner
            // C, where the contact can leave a node or two separated on a
            // fine mesh) would start a stretch that the march carries along
            // the die at its first offset, parallel to the flow.
            const auto flow = mean_velocity.find(e.face);
            const bool leaves =
              flow == mean_velocity.end() || flow->second * normal < -leaving_rate * flow->second.norm();
            is_free[k] = is_free_id(e.id) ||
                         (die_ids.count(e.id) && !held(e.a, e.id, normal) && !held(e.b, e.id, normal) && leaves);
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
            // Die faces let go next to a corner where a die turns into the
            // metal (the domain on the edges' left turns left by more than a
            // degree: the corner C of die2d) are no free stretch: the metal
            // runs into that die at once, and the march, which moves each
            // node along its spine, would put the corner into the metal and
            // carry that offset down the die parallel to the flow (die2d N0
            // on its seventh cycle). The contact decides there.
            const auto turns_into_die = [&](const unsigned int from, const unsigned int to) {
              const Tensor<1, 2> a = x[loop[from].b] - x[loop[from].a], b = x[loop[to].b] - x[loop[to].a];
              return cross(a, b) > std::sin(dealii::numbers::PI / 180) * a.norm() * b.norm();
            };
            const unsigned int before_stretch = (edges.front() + n - 1) % n, after_stretch = (edges.back() + 1) % n;
            if (std::none_of(edges.begin(), edges.end(), [&](const unsigned int i) { return is_free_id(loop[i].id); }) &&
                ((die_ids.count(loop[before_stretch].id) && turns_into_die(before_stretch, edges.front())) ||
                 (die_ids.count(loop[after_stretch].id) && turns_into_die(edges.back(), after_stretch))))
              continue;
            // March from the end where the flow comes in.
            std::vector<unsigned int> nodes{loop[edges.front()].a};
            for (const unsigned int i : edges)
              nodes.push_back(loop[i].b);
            const auto   into = [&](const unsigned int end, const unsigned int next) {
              return v[nodes[end]] * (x[nodes[next]] - x[nodes[end]]) / x[nodes[next]].distance(x[nodes[end]]);
            };
            const unsigned int m = nodes.size() - 1;
            const bool         reversed = into(m, m - 1) > into(0, 1);
            // The free stretch as it lies now, from where it leaves the part before it.
            FreeSurfaceLine line_now;
            line_now.leaves = loop[reversed ? (k + edges.size()) % n : (k + n - 1) % n].id;
            line_now.ends   = loop[reversed ? (k + n - 1) % n : (k + edges.size()) % n].id;
            for (unsigned int i = 0; i <= m; ++i)
              line_now.points.push_back(x[nodes[reversed ? m - i : i]]);
            result.lines.push_back(line_now);
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
            const unsigned int free_edges = edges.size();
            while (die_ids.count(loop[after].id) && !is_free[after] && edges.size() < n)
              {
                nodes.push_back(reversed ? loop[after].a : loop[after].b);
                edges.push_back(after);
                after = downstream(after);
              }
            const bool         end_moves = edges.size() < n && !is_free[after];
            const unsigned int end       = nodes.back();
            // The straight boundary after the stretch (the outlet): its
            // nodes, and its direction, the spine of the stretch's end.
            std::vector<unsigned int> line;
            const Tensor<1, 2> first = reversed ? x[loop[after].a] - x[end] : x[loop[after].b] - x[end];
            if (end_moves)
              for (unsigned int i = after, count = 0; !is_free[i] && count < n; i = downstream(i), ++count)
                {
                  const unsigned int far = reversed ? loop[i].a : loop[i].b;
                  const Tensor<1, 2> to  = x[far] - x[end];
                  if (loop[i].id != loop[after].id || std::abs(cross(first, to)) > 1e-9 * first.norm() * to.norm())
                    break;
                  line.push_back(far);
                }
            // Each node moves along its spine: the outward normal of the
            // surface where the node first took part in a move on this mesh
            // (the outlet's line for the end), not along the surface.
            for (unsigned int i = 1; i < nodes.size(); ++i)
              if (!spines.count(nodes[i]))
                {
                  const Tensor<1, 2> before = outward_normal(x[nodes[i - 1]], x[nodes[i]]) * (reversed ? -1. : 1.);
                  const Tensor<1, 2> next =
                    i + 1 < nodes.size() ? outward_normal(x[nodes[i]], x[nodes[i + 1]]) * (reversed ? -1. : 1.) : before;
                  spines[nodes[i]] = (before + next) / (before + next).norm();
                }
            double length = 0;
            for (unsigned int i = 0; i + 1 < nodes.size(); ++i)
              length += x[nodes[i]].distance(x[nodes[i + 1]]);
            surface_length += length;

            // The march: node i + 1 goes onto its spine where the edge from
            // the moved node i lies along the mean velocity of the edge
            // (its flux then vanishes).
            dealii::Point<2> here        = x[nodes[0]];
            bool             back_on_die = false;
            for (unsigned int i = 0; i + 1 < nodes.size(); ++i)
              {
                const unsigned int a = nodes[i], b = nodes[i + 1];
                if (i + 2 == nodes.size() && !end_moves)
                  break;
                const Tensor<1, 2> old_edge = x[b] - x[a];
                const unsigned int face     = loop[edges[i]].face;
                const Tensor<1, 2> flow = mean_velocity.count(face) ? mean_velocity.at(face) : v[a] + v[b];
                const Tensor<1, 2> spine = (b == end && !line.empty()) ? first / first.norm() : spines.at(b);
                dealii::Point<2>   next  = here + old_edge;
                if (flow.norm() > 0 && std::abs(cross(flow, spine)) > 0.1 * flow.norm())
                  {
                    const double h = -cross(flow, x[b] - here) / cross(flow, spine);
                    if ((x[b] + h * spine - here) * flow > 0)
                      next = x[b] + h * spine;
                  }
                else if (flow.norm() > 0 && old_edge * flow > 0)
                  next = here + ((old_edge * flow) / flow.norm_square()) * flow;
                // Into a die: onto it along the spine (where the spine
                // meets it; a node on the die then stays: no creep along it).
                const Nearest die = nearest_die(next);
                // Past the free stretch, a node a die holds stays from where
                // the streamline meets the die on: the contact decides there
                // (the metal came onto the die again).
                const BoundaryEdge &e = loop[edges[i]];
                if (i >= free_edges && held(b, e.id, outward_normal(x[e.a], x[e.b])) &&
                    (back_on_die || die.depth > -on_die || given_back.count(e.face)))
                  {
                    placed[b]   = x[b];
                    here        = x[b];
                    back_on_die = true;
                    continue;
                  }
                if (die.depth > on_die)
                  next = nearest_die(x[b]).depth <= on_die ? onto_die(x[b], next) : die.point;
                placed[b] = next;
                here      = next;
              }
            for (const unsigned int i : edges)
              surface.push_back(loop[i]);
            if (line.empty())
              continue;
            // The straight boundary after the stretch (the outlet) stretches to its moved end.
            const dealii::Point<2> corner = x[line.back()];
            const double           span   = x[end].distance(corner);
            for (unsigned int i = 0; i + 1 < line.size(); ++i)
              placed[line[i]] = corner + x[line[i]].distance(corner) / span * (placed[end] - corner);
          }
      }
    // The largest move, over the free surface's length (its own scale).
    for (const auto &[vertex, p] : placed)
      result.largest = std::max(result.largest, p.distance(x[vertex]) / surface_length);
    if (apply && result.largest > parameters.tolerance)
      {
        relax(placed, x);
        result.relaxation = relaxation;
      }

    // A face the dies let go on the mesh before stays free on this one
    // (its free id; were it given back, the solve would pull it away again).
    // Both ends of a face on the same die (within on_die of it).
    const auto on_one_die = [&](const Nearest &a, const Nearest &b) {
      return a.id != dealii::numbers::invalid_boundary_id && a.id == b.id && std::abs(a.depth) <= on_die &&
             std::abs(b.depth) <= on_die;
    };
    if (carry_let_go && apply)
      for (const BoundaryEdge &e : surface)
        if (is_free_id(e.id) && on_one_die(nearest_die(x[e.a]), nearest_die(x[e.b])))
          let_go.insert(e.face);
    carry_let_go = false;
    const auto at = [&](const unsigned int vertex) { return placed.count(vertex) ? placed.at(vertex) : x[vertex]; };
    std::vector<bool> on(surface.size());
    for (unsigned int i = 0; i < surface.size(); ++i)
      {
        const BoundaryEdge &e = surface[i];
        const Nearest       a = nearest_die(at(e.a)), b = nearest_die(at(e.b));
        const bool          lies_on_die = on_one_die(a, b);
        on[i]                           = lies_on_die && !let_go.count(e.face);
        face_ids[e.face]                = on[i] ? a.id : is_free_id(e.id) ? e.id : parameters.ids.front();
        result.free_faces += on[i] ? 0 : 1;
        // Free, lying on a die: the push into it that no pressure answers.
        // (The weight is linear in r, so its integral over the straight
        // face is the length times its value at the midpoint.)
        if (!on[i] && lies_on_die && mean_velocity.count(e.face))
          {
            ++result.grazing_faces;
            result.grazing_flux += mean_velocity.at(e.face) * outward_normal(x[e.a], x[e.b]) * x[e.a].distance(x[e.b]) *
                                   coordinates.weight(x[e.a] + 0.5 * (x[e.b] - x[e.a]));
          }
        result.let_go += (!on[i] && die_ids.count(e.id)) ? 1 : 0;
        result.reattached += (on[i] && !die_ids.count(e.id)) ? 1 : 0;
      }
    // Settled only where no node would move and no face would change
    // hands: a surface within the tolerance of a die that the flow pushes
    // into is given back to it and solved again.
    if (!apply || !result.changes(parameters.tolerance))
      return result;
    restart = result.reattached > 0;
    // A face the march gives back to a die and the solve lets go again
    // stays free on this mesh (grazing: held, the metal pulls away; free,
    // it pushes in): no cycle of two.
    for (unsigned int i = 0; i < surface.size(); ++i)
      {
        if (!on[i] && die_ids.count(surface[i].id) && given_back.count(surface[i].face))
          let_go.insert(surface[i].face);
        if (on[i] && !die_ids.count(surface[i].id))
          given_back.insert(surface[i].face);
      }
    // The whole move, halved while it would spoil the cells (the interior
    // follows by deal.II's Laplace transform, hanging vertices onto their
    // parents): the first streamlines of a domain the metal does not fill
    // can be far off.
    const double before = smallest_scaled_jacobian(mesh);
    std::map<unsigned int, dealii::Point<2>> boundary = dealii::GridTools::get_all_vertices_at_boundary(mesh);
    for (double step = 1; step > 1e-3; step /= 2)
      {
        for (const auto &[vertex, p] : placed)
          boundary[vertex] = x[vertex] + step * (p - x[vertex]);
        whole_mesh::laplace_transform(boundary, mesh);
        place_hanging_vertices(mesh);
        result.step = step;
        if (smallest_scaled_jacobian(mesh) >= std::min(0.25, 0.5 * before))
          break;
        set_vertices(mesh, x);
        result.step = 0;
      }
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face_ids.count(face->index()))
          face->set_boundary_id(face_ids.at(face->index()));
    return result;
  }
} // namespace dieflow
