// The closed loops of a 2D mesh's boundary edges, each counter-clockwise about the domain, read from the cells' topology.
#include <dieflow/mesh/boundary_loops.h>

#include <map>

namespace dieflow
{
  std::vector<std::vector<BoundaryEdge>>
  boundary_loops(const dealii::Triangulation<2> &old, const std::string &entry)
  {
    // Each face's cell vertices in counter-clockwise order about the
    // cell (deal.II's lexicographic quadrilateral): from the cell's
    // topology, not its shape, so that a cell the move tangled (the
    // reason for a new mesh) still gives its face the right way round.
    static constexpr unsigned int counter_clockwise[4][2] = {{2, 0}, {1, 3}, {0, 1}, {3, 2}};
    std::map<unsigned int, BoundaryEdge> leaving;
    for (const auto &cell : old.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            const auto   face = cell->face(f);
            BoundaryEdge e{cell->vertex_index(counter_clockwise[f][0]),
                           cell->vertex_index(counter_clockwise[f][1]),
                           face->boundary_id(),
                           static_cast<unsigned int>(face->index())};
            require(leaving.emplace(e.a, e).second,
                    entry,
                    "the domain's boundary touches itself at (" +
                      deck_number(old.get_vertices()[e.a][0]) + ", " + deck_number(old.get_vertices()[e.a][1]) + ")");
          }
    std::vector<std::vector<BoundaryEdge>> loops;
    while (!leaving.empty())
      {
        std::vector<BoundaryEdge> loop;
        auto                      it = leaving.begin();
        while (it != leaving.end())
          {
            loop.push_back(it->second);
            leaving.erase(it);
            it = leaving.find(loop.back().b);
          }
        require(loop.back().b == loop.front().a, entry, "a loop of the domain's boundary does not close");
        loops.push_back(loop);
      }
    return loops;
  }
} // namespace dieflow
