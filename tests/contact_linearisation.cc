// The assembled Newton system of flow and contact against finite
// differences of the assembled residual, on die2d (4 cells across) with a
// Norton-Hoff law and the paper's Coulomb friction, for both normal
// enforcements. The contact states (active directions, stick, slip) are
// decided once from a velocity field and then frozen, as in one Newton
// iteration; then J w must equal (R(v + e w) - R(v - e w)) / 2e for any w
// that respects the constraints. This checks the row transformation of the
// slipping nodes (the friction force follows the normal reaction n.R_flow),
// the stick penalty, the penalty normal force, and the condensation; for
// velocity degree 1 and 2 (contact at the edge midpoints too); and in 3D on
// the rectangular bar quarter (4 cells across, 2 in depth, mu = 0.5 on all
// four die faces): two tangent directions per node, the semismooth slip
// with its carried friction force and its dependence on the normal force,
// and the edges where two die faces meet. Checked by breaking: mu F_n's
// derivative in the 3D semismooth slip scaled by 0.9 fails both 3D penalty
// cases; the stick penalty's derivative scaled by 0.9 fails all four
// penalty cases.
// Step e = 1e-6 |v|/|w|: truncation ~1e-12; round-off of R (penalty
// lambda = 1e7 eta) ~1e-9 relative to R, divided by e: tolerance 1e-5.
#include <dieflow/flow/boundary_conditions.h>
#include <dieflow/contact/contact_set.h>
#include <dieflow/postprocess/contact_output.h>
#include <dieflow/system/system_assembler.h>
#include <dieflow/mesh/geometry.h>
#include <dieflow/problem/run.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_pattern.h>

#include "report.h"

#include <cmath>
#include <sstream>

using namespace dieflow;

namespace
{
  template <int dim>
  void
  check(const std::string &normal_enforcement, const unsigned int degree)
  {
    // 2D penalty: omega_t = lambda (factor 1, not 100), so that the penalty
    // stick law (omega_t |v_t| <= mu |F_n|) holds some nodes of this field.
    const std::string tangential_factor = "1";
    const std::string enforcement =
      (degree == 1 ? normal_enforcement : normal_enforcement + ", Q2") + (dim == 3 ? ", 3D" : "");
    const std::string deck_3d =
      "subsection Boundary conditions\n set Symmetry ids = 5\n set Slip wall ids =\n"
      " set Prescribed velocity ids = 1\n set Traction free ids = 2\n set Traction = 0; 0; 0\n set Body force = 0; 0; 0\n"
      " subsection Prescribed velocity 1\n  set Velocity = 190; 0; 0\n end\nend\n"
      "subsection Contact\n set Die ids = 3, 4, 6, 7\n"
      " set Friction coefficients = 3: 0.5, 4: 0.5, 6: 0.5, 7: 0.5\nend\n";
    ParameterHandler prm;
    declare_default_deck(prm);
    prm.parse_input_from_string("subsection Material\n set Law = Norton-Hoff\n set Rate sensitivity m = 0.3\nend\n"
                                "subsection Contact\n set Normal enforcement = " +
                                normal_enforcement + (dim == 2 && normal_enforcement == "penalty" ? "\n set Tangential penalty factor = " + tangential_factor : "") + "\nend\n" + (dim == 3 ? deck_3d : ""));
    Material material;
    material.parse_parameters(prm);
    BoundaryConditions<dim> bc;
    bc.parse_parameters(prm);
    ContactParameters contact_parameters;
    contact_parameters.parse_parameters(prm);

    MeshParameters mesh;
    mesh.die2d.cells_across = 4;
    if (dim == 3)
      {
        mesh.source               = MeshParameters::Source::rectangular_bar_quarter;
        mesh.die2d.cells_in_depth = 2;
      }
    dealii::Triangulation<dim> triangulation;
    make_mesh(mesh, triangulation);
    dealii::FESystem<dim> fe(dealii::FE_Q<dim>(degree), dim);
    DoFHandler<dim>       dofs(triangulation);
    dofs.distribute_dofs(fe);
    AffineConstraints<double> hanging, prescribed, constraints, update_constraints;
    hanging.close();
    const auto wall_nodes = collect_wall_nodes(CoordinateSystem<dim>(), dofs, dim == 2 ? std::set<BoundaryId>{3, 4, 5} : std::set<BoundaryId>{3, 4, 5, 6, 7}, hanging, 10.);
    bc.make_prescribed_constraints(dofs, prescribed);

    const double eta = 0.1, lambda = 1e7 * eta;
    ContactSet<dim> contact;
    contact.initialize(contact_parameters);
    contact.setup(wall_nodes, prescribed, false);
    contact.set_scales(eta, lambda, 1.);
    FlowAssembler<dim> flow(material, nullptr);
    FlowTerms<dim>     terms;
    terms.penalty = lambda;
    flow.set_tangent(FlowAssembler<dim>::Tangent::standard);

    const auto make = [&]() {
      bc.make_constraints(dofs, hanging, wall_nodes, false, constraints);
      contact.add_constraints(constraints, false);
      constraints.close();
      bc.make_constraints(dofs, hanging, wall_nodes, true, update_constraints);
      contact.add_constraints(update_constraints, true);
      update_constraints.close();
    };
    make();

    // A velocity like the die flow's, faster towards the exit, pressing on
    // the walls (v.n > 0: the active set keeps its walls, the penalty needs
    // penetration to push back).
    Vector<double>        v(dofs.n_dofs());
    std::vector<Point<dim>> support(dofs.n_dofs());
    dealii::DoFTools::map_dofs_to_support_points(dealii::MappingQ<dim>(1), dofs, support);
    std::vector<dealii::types::global_dof_index> cell_dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dofs.active_cell_iterators())
      {
        cell->get_dof_indices(cell_dofs);
        for (unsigned int i = 0; i < cell_dofs.size(); ++i)
          {
            const Point<dim> & x = support[cell_dofs[i]];
            const unsigned int c = fe.system_to_component_index(i).first;
            if (dim == 2)
              v[cell_dofs[i]] = c == 0 ? 190 + 30 * x[0] + 7 * std::sin(x[1]) : 4 * x[1] + 3 * std::cos(x[0]);
            else // slow along the walls near the symmetry planes: stick there
              v[cell_dofs[i]] = c == 0 ? 0.3 * x[0] + 0.07 * std::sin(x[1]) :
                                c == 1 ? 4 * x[1] + 0.03 * std::cos(x[0]) :
                                         3 * x[dim - 1] + 0.02 * std::cos(x[0] + x[1]);
          }
      }
    constraints.distribute(v);

    // Decide the states from v, as update_state() does, and freeze them.
    Vector<double> unused, reactions;
    flow.assemble_residual(dofs, v, terms, update_constraints, unused, reactions);
    std::ostringstream log;
    contact.update(v, reactions, log);
    make();
    constraints.distribute(v);

    dealii::DynamicSparsityPattern dsp(dofs.n_dofs());
    dealii::DoFTools::make_sparsity_pattern(dofs, dsp, hanging, false);
    dealii::SparsityPattern pattern;
    pattern.copy_from(dsp);
    dealii::SparseMatrix<double> J(pattern);
    Vector<double>               rhs(dofs.n_dofs());
    SystemAssembler<dim> system(dofs, update_constraints, flow, contact);
    system.assemble(v, terms, Linearization::newton, &J, rhs);

    CycleSummary states;
    summarise_contact(contact, contact.results(v), v.linfty_norm(), states);

    Vector<double> w(dofs.n_dofs());
    for (unsigned int i = 0; i < w.size(); ++i)
      w[i] = std::cos(0.37 * i * i + 0.2);
    update_constraints.distribute(w);
    const double   e = 1e-6 * v.l2_norm() / w.l2_norm();
    Vector<double> plus = v, minus = v, r_plus(w.size()), r_minus(w.size()), Jw(w.size());
    plus.add(e, w);
    minus.add(-e, w);
    system.assemble(plus, terms, Linearization::newton, nullptr, r_plus);
    system.assemble(minus, terms, Linearization::newton, nullptr, r_minus);
    J.vmult(Jw, w);
    double error = 0, scale = 0;
    for (unsigned int i = 0; i < w.size(); ++i)
      if (!update_constraints.is_constrained(i))
        {
          const double fd = -(r_plus[i] - r_minus[i]) / (2 * e);
          error           = std::max(error, std::abs(fd - Jw[i]));
          scale           = std::max(scale, std::abs(Jw[i]));
        }
    double asymmetry = 0;
    for (unsigned int i = 0; i < J.m(); ++i)
      for (auto entry = J.begin(i); entry != J.end(i); ++entry)
        asymmetry = std::max(asymmetry, std::abs(entry->value() - J.el(entry->column(), i)));

    // 3D penalty: every node slips after these updates (stick and slip
    // rows both tested in 3D with the active set).
    if (dim == 3 && normal_enforcement == "penalty")
      report(enforcement + ": the frozen states include slip", states.contact_nodes.slip > 0);
    else
      report(enforcement + ": the frozen states include stick and slip",
             states.contact_nodes.stick > 0 && states.contact_nodes.slip > 0);
    report(enforcement + ": assembled tangent matches finite differences (1e-5)", error < 1e-5 * scale);
    report(enforcement + ": the friction makes the tangent non-symmetric", asymmetry > 1e-6 * J.linfty_norm());
  }
} // namespace

int
main()
{
  for (const unsigned int degree : {1, 2})
    {
      check<2>("active set", degree);
      check<2>("penalty", degree);
    }
  for (const unsigned int degree : {1, 2})
    {
      check<3>("active set", degree);
      check<3>("penalty", degree);
    }
}
