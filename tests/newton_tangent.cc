// The assembled Newton tangent against finite differences of the assembled
// residual, on a distorted mesh with a non-trivial velocity field, for the
// nonlinear laws: J w = (R(v + e w) - R(v - e w)) / (2e) + O(e^2). With
// e = 1e-5 relative the truncation error is ~1e-10 and the round-off of R
// (penalty 100 eta) ~1e-11: tolerance 1e-7. Also: the tangent is symmetric,
// and the primal-dual tangent with S = D/r is the consistent one. For
// velocity degree 1 (one-point penalty) and 2 (the P1disc-projected penalty),
// in plane strain and in the axisymmetric geometry (the hoop rate v_r/r
// inside epsdot_eq and the divergence, the 2 pi r weights; the mesh touches
// the axis y = 0, where the hoop terms are largest), and in 3D (a distorted
// 3 x 2 x 2 box: the third shear rates and the 3D penalty projection).
// Checked by breaking: the (0, 2) component of S^ = D/r zeroed in 3D fails
// the 3D finite-difference and primal-dual checks at both degrees.
#include <dieflow/flow/flow_assembler.h>
#include <dieflow/mesh/geometry.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_pattern.h>

#include "report.h"

#include <cmath>
#include <iostream>

using namespace dieflow;

namespace
{
  template <int dim>
  void
  check_law(const std::string &deck, const std::string &law_name, const unsigned int degree, const Geometry geometry)
  {
    const std::string name = (degree == 1 ? law_name : law_name + ", Q2") +
                             (geometry == Geometry::axisymmetric ? ", axisymmetric" : "") + (dim == 3 ? ", 3D" : "");
    ParameterHandler prm;
    Material::declare_parameters(prm);
    prm.parse_input_from_string(deck);
    Material material;
    material.parse_parameters(prm);

    MeshParameters mesh;
    mesh.source = MeshParameters::Source::box;
    mesh.box.lower        = std::vector<double>(dim, 0.);
    mesh.box.upper        = dim == 2 ? std::vector<double>{3, 2} : std::vector<double>{3, 2, 2};
    mesh.box.subdivisions = dim == 2 ? std::vector<unsigned int>{3, 2} : std::vector<unsigned int>{3, 2, 2};
    mesh.box.distortion = 0.25;
    dealii::Triangulation<dim> triangulation;
    make_mesh(mesh, triangulation);
    dealii::FESystem<dim> fe(dealii::FE_Q<dim>(degree), dim);
    DoFHandler<dim>       dof_handler(triangulation);
    dof_handler.distribute_dofs(fe);
    AffineConstraints<double> none;
    none.close();
    dealii::DynamicSparsityPattern dsp(dof_handler.n_dofs());
    dealii::DoFTools::make_sparsity_pattern(dof_handler, dsp);
    dealii::SparsityPattern pattern;
    pattern.copy_from(dsp);
    SparseMatrix<double> J(pattern), J_pd(pattern);

    const unsigned int n = dof_handler.n_dofs();
    Vector<double>     v(n), w(n), rhs(n), raw(n), Jw(n), fd(n), r_plus(n), r_minus(n);
    for (unsigned int i = 0; i < n; ++i)
      {
        v[i] = std::sin(1.3 * i + 0.4) + 0.5 * std::cos(0.7 * i * i);
        w[i] = std::cos(2.1 * i + 1.0);
      }

    FlowAssembler<dim> assembler(material, nullptr);
    assembler.set_coordinate_system(CoordinateSystem<dim>(geometry));
    FlowTerms<dim> terms;
    terms.penalty = 100 * material.evaluate(1.).eta;
    assembler.set_tangent(FlowAssembler<dim>::Tangent::standard);
    assembler.assemble_system(dof_handler, v, terms, none, Linearization::newton, J, rhs, raw);
    J.vmult(Jw, w);

    const double e = 1e-5 * v.l2_norm() / w.l2_norm();
    Vector<double> shifted = v;
    shifted.add(e, w);
    assembler.assemble_residual(dof_handler, shifted, terms, none, r_plus, raw);
    shifted.add(-2 * e, w);
    assembler.assemble_residual(dof_handler, shifted, terms, none, r_minus, raw);
    // rhs = -R, so J w = -(r_plus - r_minus) / 2e.
    fd = r_minus;
    fd -= r_plus;
    fd /= 2 * e;
    Vector<double> difference = fd;
    difference -= Jw;
    report(name + ": Newton tangent matches finite differences (1e-7)",
           difference.l2_norm() < 1e-7 * Jw.l2_norm());

    double asymmetry = 0;
    for (unsigned int i = 0; i < n; ++i)
      for (auto entry = J.begin(i); entry != J.end(i); ++entry)
        asymmetry = std::max(asymmetry, std::abs(entry->value() - J.el(entry->column(), i)));
    report(name + ": tangent is symmetric", asymmetry < 1e-12 * J.linfty_norm());

    assembler.set_tangent(FlowAssembler<dim>::Tangent::primal_dual);
    assembler.update_dual(dof_handler, v, nullptr, 0);
    assembler.assemble_system(dof_handler, v, terms, none, Linearization::newton, J_pd, rhs, raw);
    J_pd.add(-1., J);
    report(name + ": primal-dual tangent with S = D/r is the consistent one",
           J_pd.linfty_norm() < 1e-12 * J.linfty_norm());
  }
} // namespace

int
main()
{
  for (const Geometry geometry : {Geometry::plane_strain, Geometry::axisymmetric})
    for (const unsigned int degree : {1, 2})
      {
        check_law<2>("subsection Material\n set Law = Norton-Hoff\n set Rate sensitivity m = 0.3\n"
                  " set Minimum strain rate = 1e-3\nend\n",
                  "Norton-Hoff m = 0.3",
                  degree,
                  geometry);
        check_law<2>("subsection Material\n set Law = Sellars-Tegart\n set Minimum strain rate = 1e-3\nend\n",
                  "Sellars-Tegart",
                  degree,
                  geometry);
      }
  for (const unsigned int degree : {1, 2})
    check_law<3>("subsection Material\n set Law = Norton-Hoff\n set Rate sensitivity m = 0.3\n"
                 " set Minimum strain rate = 1e-3\nend\n",
                 "Norton-Hoff m = 0.3",
                 degree,
                 Geometry::plane_strain);
}
