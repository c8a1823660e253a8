// Contact/Die surfaces: the die read on its own (a Gmsh surface mesh) and
// found by the node-to-facet search gives the same contact element (master
// facet in the die's plane, the same normal) as the die taken from the
// metal mesh's boundary faces, so the same discrete problem: forces, flux
// and contact zones agree to the solver tolerance (1e-7 relative) for
//  1. die2d in 2D (Q2, Coulomb): the die as the mesh's own boundary lines
//     (GridGenerator::extract_boundary_mesh, written with GridOut), and as
//     three segments written by hand (container B-C, die face C-D, land
//     D-E), coarser than the mesh, so nodes find facets they do not share
//     vertices with, and the die corners C and D lie on two facets each;
//  2. the rectangular bar quarter in 3D (Q1, Coulomb): its four die walls
//     as the mesh's boundary quadrilaterals, split into triangles by the
//     reader, and the two die walls (die face + land, ids 4 and 7) as
//     coarse triangles of their planes; and as Gmsh meshes of triangles
//     (tests/meshes/rectbar-die-walls.geo, format 4.1) that reach 5 mm
//     beyond the bar, frictionless and with Coulomb friction (each node's
//     master triangle sets its own tangent basis: the answer must not
//     depend on it);
// and a die surface 0.1 mm off the metal's wall, a missing file and a
// surface for an id that is not a die are refused with a message that names
// the entry.
#include <dieflow/problem/run.h>

#include "report.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_out.h>
#include <deal.II/grid/tria.h>

#include <dieflow/mesh/geometry.h>

#include <cmath>
#include <fstream>
#include <iostream>

using namespace dieflow;

namespace
{
  double
  gap(const double a, const double b)
  {
    return std::abs(a - b) / std::max(std::abs(b), 1e-300);
  }

  /// The largest relative difference over ram force, die forces, flux and contact lengths.
  double
  difference(const CycleSummary &a, const CycleSummary &b)
  {
    double d = gap(a.boundary_force.at(1)[0], b.boundary_force.at(1)[0]);
    for (const auto &[id, f] : b.die_normal_force)
      d = std::max(d, gap(a.die_normal_force.at(id), f));
    for (const auto &[id, f] : b.die_friction_force)
      d = std::max(d, std::abs(a.die_friction_force.at(id) - f) / std::abs(b.boundary_force.at(1)[0]));
    d = std::max(d, gap(a.flux.at(2), b.flux.at(2)));
    for (const auto &[id, l] : b.contact_length)
      for (unsigned int k = 0; k < 3; ++k)
        d = std::max(d, std::abs(a.contact_length.at(id)[k] - l[k]) / (l[0] + l[1] + l[2]));
    return d;
  }

  /// Claims that the run with the die surfaces @p surfaces is @p reference's.
  template <typename Run>
  void
  report_same(const std::string &claim, const Run &run, const std::string &surfaces, const CycleSummary &reference)
  {
    const CycleSummary s = run(surfaces);
    report(claim + ": the same forces, flux, contact zones (1e-7)", s.converged && difference(s, reference) < 1e-7);
  }

  /// The boundary faces of @p ids as a Gmsh surface mesh.
  template <int dim>
  void
  write_boundary(const Triangulation<dim> &tria, const std::set<BoundaryId> &ids, const std::string &file)
  {
    dealii::Triangulation<dim - 1, dim> surface;
    dealii::GridGenerator::extract_boundary_mesh(tria, surface, ids);
    std::ofstream out(file);
    out.precision(17);
    dealii::GridOut().write_msh(surface, out);
  }

  /// Gmsh 2.2 file of lines (2D) or triangles (3D) through the given points.
  template <int dim>
  void
  write_facets(const std::vector<std::array<Point<dim>, dim>> &facets, const std::string &file)
  {
    std::ofstream out(file);
    out.precision(17);
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << dim * facets.size() << "\n";
    unsigned int node = 0;
    for (const auto &f : facets)
      for (const auto &x : f)
        out << ++node << " " << x[0] << " " << x[1] << " " << (dim == 3 ? x[dim - 1] : 0.) << "\n";
    out << "$EndNodes\n$Elements\n" << facets.size() << "\n";
    for (unsigned int e = 0; e < facets.size(); ++e)
      {
        out << e + 1 << (dim == 2 ? " 1" : " 2") << " 2 1 1";
        for (unsigned int v = 0; v < dim; ++v)
          out << " " << dim * e + v + 1;
        out << "\n";
      }
    out << "$EndElements\n";
  }

  const std::string die2d_deck =
    "subsection Material\n set Law = Newtonian\n set Viscosity = 0.278\nend\n"
    "subsection Mesh\n subsection Die2d\n  set Cells across = 4\n end\nend\n"
    "subsection Discretisation\n set Velocity degree = 2\nend\n"
    "subsection Boundary conditions\n set Symmetry ids = 5\n set Prescribed velocity ids = 1\n"
    " set Traction free ids = 2\n subsection Prescribed velocity 1\n  set Velocity = 190; 0\n end\nend\n";

  CycleSummary
  die2d(const std::string &surfaces)
  {
    return run_deck_text(die2d_deck + "subsection Contact\n set Die ids = 3, 4\n set Die surfaces = " + surfaces +
                         "\nend\n")
      .cycles.back();
  }

  const std::string rectbar_deck =
    "set Dimension = 3\n"
    "subsection Material\n set Law = Newtonian\n set Viscosity = 0.278\nend\n"
    "subsection Mesh\n set Source = rectangular bar quarter\n subsection Die2d\n  set Cells across = 4\n"
    "  set Cells in depth = 2\n end\nend\n"
    "subsection Boundary conditions\n set Symmetry ids = 5\n set Prescribed velocity ids = 1\n"
    " set Traction free ids = 2\n subsection Prescribed velocity 1\n  set Velocity = 190; 0; 0\n end\nend\n";

  CycleSummary
  rectbar(const std::string &surfaces, const std::string &friction = "3: 0.001, 4: 0.1, 6: 0.001, 7: 0.1")
  {
    return run_deck_text(rectbar_deck + "subsection Contact\n set Die ids = 3, 4, 6, 7\n set Friction coefficients = " +
                         friction + "\n set Die surfaces = " + surfaces + "\nend\n")
      .cycles.back();
  }
} // namespace

int
main()
{
  {
    MeshParameters parameters;
    parameters.die2d.cells_across = 4;
    Triangulation<2> tria;
    make_mesh(parameters, tria);
    write_boundary(tria, {3}, "container.msh");
    write_boundary(tria, {4}, "die.msh");
    const Die2dGeometry &g = parameters.die2d;
    write_facets<2>({{{g.corner('B'), g.corner('C')}}}, "container-line.msh");
    write_facets<2>({{{g.corner('C'), g.corner('D')}}, {{g.corner('D'), g.corner('E')}}}, "die-lines.msh");
    // The die face and land 0.1 mm into the metal.
    const dealii::Tensor<1, 2> down({0, -0.1});
    write_facets<2>({{{g.corner('C') + down, g.corner('D') + down}}, {{g.corner('D') + down, g.corner('E') + down}}},
                    "die-off.msh");

    const CycleSummary mesh_faces = die2d("");
    report("die2d: converged with the mesh's faces", mesh_faces.converged);
    report_same("die2d, the die as the mesh's boundary lines read back", die2d, "3: container.msh, 4: die.msh",
                mesh_faces);
    report_same("die2d, the die as three segments B-C, C-D, D-E", die2d, "3: container-line.msh, 4: die-lines.msh",
                mesh_faces);
    for (const auto &[surfaces, what] : std::vector<std::pair<std::string, std::string>>{
           {"4: die-off.msh", "a die surface 0.1 mm off the wall"},
           {"4: missing.msh", "a die surface file that does not exist"},
           {"2: die.msh", "a die surface for an id that is not a die"}})
      try
        {
          die2d(surfaces);
          report(what + " is refused", false);
        }
      catch (const InputError &e)
        {
          report(what + " is refused, naming Contact/Die surfaces",
                 std::string(e.what()).find("Contact/Die surfaces") != std::string::npos);
        }
  }
  {
    MeshParameters parameters;
    parameters.source               = MeshParameters::Source::rectangular_bar_quarter;
    parameters.die2d.cells_across   = 4;
    parameters.die2d.cells_in_depth = 2;
    Triangulation<3> tria;
    make_mesh(parameters, tria);
    for (const BoundaryId id : {3, 4, 6, 7})
      write_boundary(tria, {static_cast<BoundaryId>(id)}, "wall-" + std::to_string(id) + ".msh");
    // The die face and land of each direction as two triangles per plane
    // piece, far coarser than the mesh.
    const Die2dGeometry &g   = parameters.die2d;
    const double         x_d = g.die_exit_x(), x_e = x_d + g.land_length;
    const double h_i = g.inlet_half_height, h_o = g.outlet_half_height;
    const double w_i = g.inlet_half_width, w_o = g.outlet_half_width;
    using P = Point<3>;
    // y walls y = h(x), z in [0, w(x)]; z walls z = w(x), y in [0, h(x)].
    write_facets<3>({{{P(0, h_i, 0), P(x_d, h_o, 0), P(x_d, h_o, w_o)}},
                     {{P(0, h_i, 0), P(x_d, h_o, w_o), P(0, h_i, w_i)}},
                     {{P(x_d, h_o, 0), P(x_e, h_o, 0), P(x_e, h_o, w_o)}},
                     {{P(x_d, h_o, 0), P(x_e, h_o, w_o), P(x_d, h_o, w_o)}}},
                    "die-y.msh");
    write_facets<3>({{{P(0, 0, w_i), P(x_d, 0, w_o), P(x_d, h_o, w_o)}},
                     {{P(0, 0, w_i), P(x_d, h_o, w_o), P(0, h_i, w_i)}},
                     {{P(x_d, 0, w_o), P(x_e, 0, w_o), P(x_e, h_o, w_o)}},
                     {{P(x_d, 0, w_o), P(x_e, h_o, w_o), P(x_d, h_o, w_o)}}},
                    "die-z.msh");

    const CycleSummary mesh_faces = rectbar("");
    report("rectangular bar: converged with the mesh's faces", mesh_faces.converged);
    const auto coulomb = [](const std::string &surfaces) { return rectbar(surfaces); };
    report_same("rectangular bar, the walls as the mesh's quadrilaterals read back", coulomb,
                "3: wall-3.msh, 4: wall-4.msh, 6: wall-6.msh, 7: wall-7.msh", mesh_faces);
    report_same("rectangular bar, the die walls as coarse triangles", coulomb, "4: die-y.msh, 7: die-z.msh",
                mesh_faces);
    // Gmsh's triangles give each node its own master triangle, so its own
    // tangent basis (t_1 along the edge 1-2): with Coulomb friction the
    // stick/slip split and the friction resultants must not depend on it.
    // Before the edge-node fix (d428aed) they did: the y die wall's F_t
    // differed by 13 % (doc/three-dimensional.md).
    const std::string  meshes = std::string(SOURCE_DIR) + "/meshes/";
    const std::string  walls  = "4: " + meshes + "rectbar-die-y.msh, 7: " + meshes + "rectbar-die-z.msh";
    const auto frictionless = [](const std::string &surfaces) { return rectbar(surfaces, ""); };
    report_same("rectangular bar, frictionless, the die walls meshed by Gmsh (format 4.1, 5 mm beyond the bar)",
                frictionless, walls, frictionless(""));
    report_same("rectangular bar, Coulomb, the die walls meshed by Gmsh", coulomb, walls, mesh_faces);
  }
}
