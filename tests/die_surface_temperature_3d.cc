// 3D die surfaces with a temperature field: each contact node's row of die-surface-ID.dat carries the metal's T there, checked against the T prescribed on the die faces.
//
// The 3D Couette layer of couette3d_edge_stick.prm (a 4 x 1 x 1 box, u =
// 0.5 y z, dies 3 (y = 0) and 5 (z = 0) with mu = 1: every die node
// sticks), velocity and temperature of degree 2 (contact nodes between
// the vertices too, whose T the file finds in the mesh rather than at a
// vertex), with a steady temperature field whose value on the dies and
// the inlet is prescribed, T = 300 + x + 2 y + 3 z: every die node's
// temperature column must be that expression at the node's position (to
// 1e-9: the prescribed values are interpolated exactly at the nodes), and
// its heat-flux column 0 (no transfer coefficient on a prescribed part).
// A row taking another node's T, or the column missing, fails.
#include "fuzz.h"

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace
{
  const char *deck =
    "set Dimension = 3\nset Output directory = surface\nset Write VTU = false\n"
    "subsection Mesh\n  set Source = box\n  subsection Box\n    set Lower corner = 0, 0, 0\n"
    "    set Upper corner = 4, 1, 1\n    set Subdivisions = 4, 2, 2\n  end\nend\n"
    "subsection Material\n  set Law = Newtonian\n  set Viscosity = 1\n  set Activation energy Q = 0\n"
    "  set Temperature = 300\nend\n"
    "subsection Boundary conditions\n  set Prescribed velocity ids = 1, 2\n  set Symmetry ids =\n"
    "  set Slip wall ids =\n  set Traction free ids =\n  set Traction ids = 4, 6\n"
    "  set Traction = 0.5*(y*(z>0.999) + z*(y>0.999)); -(y>0.999); -(z>0.999)\n"
    "  subsection Prescribed velocity 1\n    set Velocity = 0.5*y*z; 0; 0\n  end\n"
    "  subsection Prescribed velocity 2\n    set Velocity = 0.5*y*z; 0; 0\n  end\nend\n"
    "subsection Contact\n  set Die ids = 3, 5\n  set Friction coefficients = 3: 1, 5: 1\nend\n"
    "subsection Discretisation\n  set Velocity degree = 2\nend\n"
    "subsection Heat\n  set Model = steady\n  set Prescribed temperature ids = 1, 3, 5\n"
    "  set Prescribed temperature = 300 + x + 2*y + 3*z\nend\n";
} // namespace

int
main()
{
  const fuzz::Outcome outcome = fuzz::run("surface.prm", deck);
  std::cout << "exit status " << outcome.status << std::endl;
  unsigned int rows = 0, wrong = 0, between = 0;
  bool         header = true;
  for (const int id : {3, 5})
    {
      std::ifstream file("surface/die-surface-" + std::to_string(id) + ".dat");
      std::string   line;
      bool          columns = false;
      while (std::getline(file, line))
        {
          if (line.rfind('#', 0) == 0)
            {
              columns |= line.find("temperature(K) heat_flux") != std::string::npos;
              continue;
            }
          std::istringstream in(line);
          std::vector<double> v;
          for (double x; in >> x;)
            v.push_back(x);
          // x y z p f_x f_y f_z |f| v_n s_x s_y s_z status T flux
          if (v.size() != 15)
            {
              ++wrong;
              continue;
            }
          ++rows;
          const double x = v[0], y = v[1], z = v[2];
          between += std::abs(x - std::round(x)) > 1e-9 || std::abs(2 * y - std::round(2 * y)) > 1e-9 ||
                     std::abs(2 * z - std::round(2 * z)) > 1e-9;
          if (std::abs(v[13] - (300 + x + 2 * y + 3 * z)) > 1e-9 || v[14] != 0)
            ++wrong;
        }
      header &= columns;
    }
  const auto verdict = [](const bool ok) { return ok ? "yes" : "NO"; };
  std::cout << "converged: " << verdict(outcome.status == 0) << std::endl
            << "both files have the temperature and heat-flux columns: " << verdict(header) << std::endl
            << "die nodes listed: " << rows << ", of which between vertices (degree 2): " << between << std::endl
            << "every node's T is the prescribed 300 + x + 2 y + 3 z, its flux 0: " << verdict(rows > 0 && wrong == 0)
            << std::endl;
  return 0;
}
