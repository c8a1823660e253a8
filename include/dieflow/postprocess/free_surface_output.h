// The steady free surface's files: free-surface.dat (gnuplot) and free-surface.vtp (ParaView), the polylines of the last solve.
#ifndef dieflow_free_surface_output_h
#define dieflow_free_surface_output_h

#include <dieflow/postprocess/summary.h>

#include <string>

namespace dieflow
{
  /**
   * Writes the free stretches of @p record into @p directory:
   * free-surface.dat (x y per node from where the metal leaves the part
   * before it, a blank line between stretches) and free-surface.vtp (a VTK
   * PolyData file of the same polylines, to open in ParaView with the
   * fields' VTU), and the PolyData also as @p cycle_file if it is not empty
   * (the cycle's own, which solution.pvd lists with the cycle's VTU).
   */
  void
  write_free_surface(const FreeSurfaceRecord &record, const std::string &directory, const std::string &cycle_file = "");
} // namespace dieflow

#endif
