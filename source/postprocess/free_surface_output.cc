// The steady free surface's files: free-surface.dat (gnuplot) and free-surface.vtp (ParaView), the polylines of the last solve, and each cycle's polyline for solution.pvd.
#include <dieflow/base/atomic_file.h>
#include <dieflow/postprocess/free_surface_output.h>

#include <iomanip>

namespace dieflow
{
  namespace
  {
    /// The free stretches of @p record as a VTK PolyData file @p path.
    void
    write_polylines(const FreeSurfaceRecord &record, const std::string &path)
    {
      AtomicFile    file(path);
      std::ostream &out = file.stream();
      unsigned int  n   = 0;
      for (const FreeSurfaceLine &line : record.lines)
        n += line.points.size();
      out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          << "<PolyData>\n<Piece NumberOfPoints=\"" << n << "\" NumberOfLines=\"" << record.lines.size() << "\">\n"
          << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      for (const FreeSurfaceLine &line : record.lines)
        for (const auto &p : line.points)
          out << std::setprecision(10) << p[0] << ' ' << p[1] << " 0\n";
      out << "</DataArray>\n</Points>\n<Lines>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
      for (unsigned int i = 0; i < n; ++i)
        out << i << (i + 1 < n ? ' ' : '\n');
      out << "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
      unsigned int offset = 0;
      for (const FreeSurfaceLine &line : record.lines)
        out << (offset += line.points.size()) << '\n';
      out << "</DataArray>\n</Lines>\n<CellData>\n<DataArray type=\"Int32\" Name=\"leaves_id\" format=\"ascii\">\n";
      for (const FreeSurfaceLine &line : record.lines)
        out << static_cast<int>(line.leaves) << '\n';
      out << "</DataArray>\n</CellData>\n</Piece>\n</PolyData>\n</VTKFile>\n";
      file.commit();
    }
  } // namespace



  void
  write_free_surface(const FreeSurfaceRecord &record, const std::string &directory, const std::string &cycle_file)
  {
    {
      AtomicFile    file(directory + "/free-surface.dat");
      std::ostream &out = file.stream();
      out << "# the steady free surface: each stretch from where the metal leaves the part before it (its boundary "
             "id), downstream\n# x(mm) y(mm)\n";
      for (const FreeSurfaceLine &line : record.lines)
        {
          out << "# leaves id " << line.leaves << ", ends on id " << line.ends << "\n";
          for (const auto &p : line.points)
            out << std::setprecision(10) << p[0] << ' ' << p[1] << '\n';
          out << '\n';
        }
      file.commit();
    }
    for (const std::string &name : {std::string("free-surface.vtp"), cycle_file})
      if (!name.empty())
        write_polylines(record, directory + "/" + name);
  }
} // namespace dieflow
