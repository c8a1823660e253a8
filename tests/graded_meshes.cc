// Mesh/Die2d/Grading exponent q on the three structured die meshes (die2d,
// round bar quarter, rectangular bar quarter):
//  - valid: the Jacobian is positive at every vertex of every cell (q up
//    to 3, the coarse and a finer mesh);
//  - the same domain: the graded mesh's area (volume) equals the uniform
//    one's to round-off. Grading moves vertices along the straight block
//    lines of the bilinear blocks (2D), and in 3D keeps the section's
//    boundary vertices on their rays and the block ends at C and D, so the
//    polygonal walls (planar facets between slices) bound the same solid;
//  - graded as stated: the land's wall face at the die exit D is
//    (1/n_l)^q of the land's wall for its n_l faces (2D);
//  - and what the grading is for: the axisymmetric round bar
//    (parameters/roundbar-held-land.prm without corner refinement, one cycle) at 8
//    cells across is 7.9 % above the converged mean axial stress (998.6
//    MPa, 1,132,536 +- 147 N, the round bar's reference in
//    doc/axisymmetric.md: an independent Kelly-refined degree-2 study on
//    the corner-refined mesh family) uniform, and within 1 % graded with
//    q = 2.5 (the 3D target; measured 0.83 %); at 16 across
//    graded within 0.3 % (measured 0.23 %), so the
//    error falls by more than half per halving of the cells.
#include <dieflow/mesh/geometry.h>
#include <dieflow/problem/run.h>

#include "report.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <iostream>
#include <limits>

using namespace dieflow;

namespace
{
  struct MeshMeasures
  {
    double       volume       = 0;
    double       smallest_jxw = std::numeric_limits<double>::max();
    unsigned int cells        = 0;
  };

  template <int dim>
  MeshMeasures
  measure(const Triangulation<dim> &tria)
  {
    // The trapezoidal rule's points are the vertices: JxW there is the
    // Jacobian at each vertex times a positive weight.
    const dealii::FE_Q<dim>   fe(1);
    dealii::FEValues<dim>     corners(fe, dealii::QTrapezoid<dim>(), dealii::update_JxW_values);
    dealii::FEValues<dim>     interior(fe, dealii::QGauss<dim>(2), dealii::update_JxW_values);
    dealii::DoFHandler<dim>   dofs(tria);
    MeshMeasures              m;
    dofs.distribute_dofs(fe);
    for (const auto &cell : dofs.active_cell_iterators())
      {
        corners.reinit(cell);
        interior.reinit(cell);
        for (const unsigned int q : corners.quadrature_point_indices())
          m.smallest_jxw = std::min(m.smallest_jxw, corners.JxW(q));
        for (const unsigned int q : interior.quadrature_point_indices())
          m.volume += interior.JxW(q);
        ++m.cells;
      }
    return m;
  }

  template <int dim>
  MeshMeasures
  mesh(const std::string &source, const double q, const unsigned int across)
  {
    MeshParameters parameters;
    parameters.source                  = MeshParameters::source_named(source);
    parameters.die2d.grading_exponent  = q;
    parameters.die2d.cells_across      = across;
    parameters.die2d.cells_in_depth    = across / 2;
    Triangulation<dim> tria;
    make_mesh(parameters, tria);
    return measure(tria);
  }

  template <int dim>
  void
  check_source(const std::string &source)
  {
    for (const unsigned int across : {4u, 16u})
      {
        const MeshMeasures uniform = mesh<dim>(source, 1, across);
        bool               valid = true, same_volume = true;
        for (const double q : {2., 2.5, 3.})
          {
            const MeshMeasures graded = mesh<dim>(source, q, across);
            valid                     = valid && graded.smallest_jxw > 0;
            same_volume = same_volume && std::abs(graded.volume - uniform.volume) < 1e-12 * uniform.volume;
          }
        const std::string name = source + ", " + std::to_string(across) + " across, q = 2, 2.5, 3";
        report(name + ": every cell's Jacobian positive at its vertices", valid);
        report(name + ": the uniform mesh's " + (dim == 2 ? "area" : "volume") + " to 1e-12", same_volume);
      }
  }

  /// The land's wall faces (die id, beyond the die exit D) in order from D.
  void
  check_grading_at_die_exit()
  {
    for (const double q : {1., 2., 2.5})
      {
        MeshParameters parameters;
        parameters.die2d.grading_exponent = q;
        parameters.die2d.cells_across     = 8;
        Triangulation<2> tria;
        make_mesh(parameters, tria);
        const Die2dGeometry &g = parameters.die2d;
        const Point<2>       D = g.corner('D');
        unsigned int         n_l = 0;
        double               at_D = 0;
        for (const auto &face : tria.active_face_iterators())
          if (face->at_boundary() && face->boundary_id() == Die2dGeometry::die_id &&
              face->center()[0] > D[0])
            {
              ++n_l;
              if (face->vertex(0).distance(D) < 1e-9 || face->vertex(1).distance(D) < 1e-9)
                at_D = face->measure();
            }
        const double expected = g.land_length * std::pow(1. / n_l, q);
        report("die2d, q = " + std::to_string(q).substr(0, 3) + ": the land's wall face at D is (1/n_l)^q of the land",
               std::abs(at_D - expected) < 1e-12 * g.land_length);
      }
  }

  /// The mean axial stress of the axisymmetric round bar, MPa.
  double
  round_bar_stress(const unsigned int across, const double q)
  {
    const RunSummary s = run_deck_text(
      "set Geometry = axisymmetric\n"
      "subsection Mesh\n subsection Die2d\n  set Cells across = " +
      std::to_string(across) + "\n  set Grading exponent = " + std::to_string(q) +
      "\n end\nend\n"
      "subsection Material\n set Law = Newtonian\n set Viscosity = 0.278\n set Penalty factor = 1e7\nend\n"
      "subsection Boundary conditions\n set Symmetry ids = 5\n set Prescribed velocity ids = 1\n"
      " set Traction free ids = 2\n subsection Prescribed velocity 1\n  set Velocity = 190; 0\n end\nend\n"
      "subsection Contact\n set Die ids = 3, 4\n set Friction law = Coulomb\n"
      " set Friction coefficients = 3: 0.001, 4: 0.1\nend\n"
      "subsection Discretisation\n set Velocity degree = 2\nend\n");
    return s.cycles.back().boundary_force.at(1)[0] / (dealii::numbers::PI * 19 * 19);
  }
} // namespace

int
main()
{
  check_source<2>("die2d");
  check_source<3>("round bar quarter");
  check_source<3>("rectangular bar quarter");
  check_grading_at_die_exit();

  const double converged = 1132536.2 / (dealii::numbers::PI * 19 * 19);
  const double uniform_8 = round_bar_stress(8, 1) / converged - 1;
  const double graded_8  = round_bar_stress(8, 2.5) / converged - 1;
  const double graded_16 = round_bar_stress(16, 2.5) / converged - 1;
  report("axisymmetric round bar, 8 across, uniform: more than 5 % above the converged stress", uniform_8 > 0.05);
  report("graded q = 2.5, 8 across: within 1 % of it", std::abs(graded_8) < 0.01);
  report("graded q = 2.5, 16 across: within 0.3 % of it", std::abs(graded_16) < 0.003);
  report("graded: the error falls by more than half from 8 to 16 across",
         std::abs(graded_16) < 0.5 * std::abs(graded_8));
}
