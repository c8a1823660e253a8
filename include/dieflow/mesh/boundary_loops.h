// The closed loops of a 2D mesh's boundary edges, each counter-clockwise about the domain, read from the cells' topology.
#ifndef dieflow_boundary_loops_h
#define dieflow_boundary_loops_h

#include <dieflow/base/parameters.h>

#include <deal.II/grid/tria.h>

#include <string>
#include <vector>

namespace dieflow
{
  /// A boundary edge of a 2D mesh with the domain on its left: from vertex a to b.
  struct BoundaryEdge
  {
    unsigned int a = 0, b = 0;
    BoundaryId   id = 0;
    /// The face (invalid for the halves of an edge a new mesh splits).
    unsigned int face = dealii::numbers::invalid_unsigned_int;
  };

  /**
   * The closed loops of the boundary edges of @p mesh, each counter-clockwise
   * about the domain (holes clockwise), read from the cells' topology, not
   * their shape, so that a tangled mesh gives them the right way round. A
   * vertex with two outgoing edges (the boundary touches itself) makes the
   * domain no polygon: refused, naming @p entry.
   */
  std::vector<std::vector<BoundaryEdge>>
  boundary_loops(const dealii::Triangulation<2> &mesh, const std::string &entry);
} // namespace dieflow

#endif
