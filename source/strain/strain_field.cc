// The metal's equivalent strain in a steady run: the deck's entries, the SUPG assembly with the weak inflow condition, the solve, the flow's hardening factors and the record.
#include <dieflow/base/expressions.h>
#include <dieflow/mesh/scalar_field.h>
#include <dieflow/mesh/whole_mesh.h>
#include <dieflow/strain/strain_field.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace dieflow
{
  void
  StrainParameters::declare_parameters(ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Equivalent strain");
    {
      prm.declare_entry("Steady field",
                        "false",
                        Bool(),
                        "Problem = steady: solve the metal's equivalent strain as a field, "
                        "v.grad eps = epsdot_eq with eps = Inlet strain where the metal "
                        "enters (doc/strain.md), and report it (summary.json \"strain\", the "
                        "VTU). A steady run whose law hardens (Material/Hardening exponent "
                        "n > 0) solves it whatever this says: the flow takes the hardening "
                        "factor (eps_0 + eps)^n from it.");
      prm.declare_entry("Inlet strain",
                        "0",
                        Double(),
                        "The equivalent strain the metal brings where it enters (v.n < 0): "
                        "0 for annealed stock, the strain of the earlier passes otherwise.");
      prm.declare_entry("Exact strain",
                        "",
                        Anything(),
                        "For verification: the exact eps as an expression in x, y[, z]; the "
                        "L2 and largest nodal errors of eps are reported (summary.json). "
                        "Empty: none.");
      prm.declare_entry("Coupling iterations",
                        "20",
                        Integer(1, 100),
                        "With hardening: the most strain solves per cycle, each followed by "
                        "the flow's Newton iteration at the new hardening.");
      prm.declare_entry("Coupling tolerance",
                        "3e-3",
                        Double(0),
                        "Strain and flow have settled when a strain solve changes eps, in "
                        "the root mean square over the metal, by less than this part of "
                        "eps's own root mean square (or 1e-9 where it vanishes). With "
                        "contact the changes stall at 1e-3 to 3e-3 of eps (the contact "
                        "states' flips); the flow stress moves by n times the change.");
    }
    prm.leave_subsection();
  }



  void
  StrainParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Equivalent strain");
    requested    = prm.get_bool("Steady field");
    inlet_strain = prm.get_double("Inlet strain");
    require(std::isfinite(inlet_strain) && inlet_strain >= 0,
            "Equivalent strain/Inlet strain",
            "must not be negative, got " + prm.get("Inlet strain"));
    exact_strain        = prm.get("Exact strain");
    coupling_iterations = prm.get_integer("Coupling iterations");
    coupling_tolerance  = prm.get_double("Coupling tolerance");
    require(std::isfinite(coupling_tolerance) && coupling_tolerance > 0,
            "Equivalent strain/Coupling tolerance",
            "must be positive");
    prm.leave_subsection();
  }



  template <int dim>
  StrainField<dim>::StrainField(const StrainParameters &          parameters,
                                const Material &                  material,
                                const CoordinateSystem<dim> &     coordinates,
                                const dealii::Triangulation<dim> &triangulation,
                                const unsigned int                velocity_degree)
    : parameters(parameters)
    , material(material)
    , coordinates(coordinates)
    , triangulation(triangulation)
    , flow_quadrature(velocity_degree + 1)
    , fe(velocity_degree)
    , dof_handler(triangulation)
  {
    if (!parameters.exact_strain.empty())
      exact = parse_vector_expression<dim>("Equivalent strain/Exact strain", parameters.exact_strain, "", 1);
  }



  template <int dim>
  void
  StrainField<dim>::setup()
  {
    dof_handler.distribute_dofs(fe);
    if (strain.size() == 0)
      {
        // The first mesh: the metal as it enters, everywhere.
        strain.reinit(dof_handler.n_dofs());
        strain = parameters.inlet_strain;
      }
    AssertDimension(strain.size(), dof_handler.n_dofs());
    constraints.clear();
    dealii::DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    constraints.close();
    dealii::DynamicSparsityPattern dsp(dof_handler.n_dofs());
    whole_mesh::make_sparsity_pattern(dof_handler, dsp, constraints);
    sparsity.copy_from(dsp);
    matrix.reinit(sparsity);
    rhs.reinit(dof_handler.n_dofs());
    update_flow_hardening();
  }



  template <int dim>
  void
  StrainField<dim>::prepare_refinement()
  {
    transfer = std::make_unique<dealii::SolutionTransfer<dim, dealii::Vector<double>>>(dof_handler);
    transfer->prepare_for_coarsening_and_refinement(strain);
  }



  template <int dim>
  void
  StrainField<dim>::finish_refinement()
  {
    dof_handler.distribute_dofs(fe);
    dealii::Vector<double> carried(dof_handler.n_dofs());
    transfer->interpolate(strain, carried);
    strain = carried;
    transfer.reset();
    // A new mesh: the relaxation starts afresh. (A mesh the free surface
    // only moved keeps it: the surface's moves are part of the flow's
    // response to the hardening, and starting afresh after each made every
    // strain solve an unrelaxed one.)
    last_residual.reinit(0);
    omega = 1;
  }



  template <int dim>
  double
  StrainField<dim>::solve(const dealii::DoFHandler<dim> &flow_dofs,
                          const dealii::Vector<double> & velocity,
                          const bool                     relax)
  {
    const dealii::QGauss<dim>     quadrature(fe.degree + 1);
    const dealii::QGauss<dim - 1> face_quadrature(fe.degree + 1);
    dealii::FEValues<dim>         fe_values(fe,
                                    quadrature,
                                    dealii::update_values | dealii::update_gradients | dealii::update_quadrature_points |
                                      dealii::update_JxW_values);
    dealii::FEValues<dim>     flow_values(flow_dofs.get_fe(),
                                      quadrature,
                                      dealii::update_values | dealii::update_gradients | coordinates.flags());
    dealii::FEFaceValues<dim> face_values(fe,
                                          face_quadrature,
                                          dealii::update_values | dealii::update_quadrature_points |
                                            dealii::update_JxW_values | dealii::update_normal_vectors);
    dealii::FEFaceValues<dim> flow_face_values(flow_dofs.get_fe(), face_quadrature, dealii::update_values);
    const dealii::FEValuesExtractors::Vector     velocities(0);
    const unsigned int                           n = fe.n_dofs_per_cell(), n_q = quadrature.size();
    dealii::FullMatrix<double>                   cell_matrix(n, n);
    dealii::Vector<double>                       cell_rhs(n);
    std::vector<dealii::types::global_dof_index> dofs(n);
    std::vector<dealii::Tensor<1, dim>>          v(n_q), v_face(face_quadrature.size());
    std::vector<StrainRate<dim>>                 D(n_q);
    std::vector<double>                          advection(n);

    matrix = 0;
    rhs    = 0;
    // Where the metal stands still (v = 0 on whole cells) the equation says
    // nothing: a reaction 1e-10 V/h eps (V the largest nodal speed) makes
    // eps = 0 there and changes it by 1e-10 of itself elsewhere.
    const double speed_scale = velocity.linfty_norm();
    auto         flow_cell   = flow_dofs.begin_active();
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        flow_values.reinit(flow_cell);
        flow_values[velocities].get_function_values(velocity, v);
        coordinates.strain_rates(flow_values, velocity, D);
        cell_matrix = 0;
        cell_rhs    = 0;
        const double h = cell->diameter() / std::sqrt(double(dim)) / fe.degree;
        for (unsigned int q = 0; q < n_q; ++q)
          {
            const double dx    = fe_values.JxW(q) * coordinates.weight(fe_values.quadrature_point(q));
            const double rate  = std::sqrt(2. / 3. * (D[q] * D[q]));
            const double speed = v[q].norm();
            // SUPG without diffusion: tau = h / (2 |v|) (HeatEquation's at infinite Peclet number).
            const double tau = speed > 0 ? h / (2. * speed) : 0.;
            for (unsigned int j = 0; j < n; ++j)
              advection[j] = v[q] * fe_values.shape_grad(j, q);
            const double reaction = 1e-10 * speed_scale / h;
            for (unsigned int i = 0; i < n; ++i)
              {
                const double test = fe_values.shape_value(i, q) + tau * advection[i];
                for (unsigned int j = 0; j < n; ++j)
                  cell_matrix(i, j) += (test * advection[j] + reaction * fe_values.shape_value(i, q) * fe_values.shape_value(j, q)) * dx;
                cell_rhs(i) += test * rate * dx;
              }
          }
        // Where the metal enters: |v.n| (eps - eps_in) weakly.
        for (const unsigned int f : cell->face_indices())
          {
            if (!cell->face(f)->at_boundary())
              continue;
            face_values.reinit(cell, f);
            flow_face_values.reinit(flow_cell, f);
            flow_face_values[velocities].get_function_values(velocity, v_face);
            for (unsigned int q = 0; q < face_quadrature.size(); ++q)
              {
                const double vn = v_face[q] * face_values.normal_vector(q);
                if (vn >= 0)
                  continue;
                const double ds = face_values.JxW(q) * coordinates.weight(face_values.quadrature_point(q));
                for (unsigned int i = 0; i < n; ++i)
                  {
                    for (unsigned int j = 0; j < n; ++j)
                      cell_matrix(i, j) -= vn * face_values.shape_value(i, q) * face_values.shape_value(j, q) * ds;
                    cell_rhs(i) -= vn * parameters.inlet_strain * face_values.shape_value(i, q) * ds;
                  }
              }
          }
        cell->get_dof_indices(dofs);
        constraints.distribute_local_to_global(cell_matrix, cell_rhs, dofs, matrix, rhs);
        ++flow_cell;
      }

    dealii::Vector<double>      previous = strain;
    dealii::SparseDirectUMFPACK solver;
    solver.initialize(matrix);
    solver.vmult(strain, rhs);
    constraints.distribute(strain);
    // The fixed point's residual r = G(eps) - eps; relaxed: eps + omega r,
    // omega = -omega_last r_last.(r - r_last)/|r - r_last|^2, within [0.1, 1.5]
    // and within a factor 2 of omega_last: unguarded, the factor cycled with
    // period 3 (0.1, 0.8, 0.7) on the 12 degree wire at n = 0.5, which did
    // not settle; guarded, that wire and the cold extrusion with the land
    // held settle too (doc/strain.md).
    dealii::Vector<double> residual = strain;
    residual -= previous;
    last.last_change = root_mean_square(residual);
    if (relax && last_residual.size() == residual.size())
      {
        dealii::Vector<double> difference = residual;
        difference -= last_residual;
        const double squared = difference.norm_sqr();
        if (squared > 0)
          omega = std::clamp(std::clamp(-omega * (last_residual * difference) / squared, 0.5 * omega, 2. * omega),
                             0.1,
                             1.5);
        strain = previous;
        strain.add(omega, residual);
      }
    else
      omega = 1;
    last_residual = residual;
    make_record(flow_dofs, velocity);
    return last.last_change;
  }



  template <int dim>
  double
  StrainField<dim>::root_mean_square(const dealii::Vector<double> &field) const
  {
    const dealii::QGauss<dim> quadrature(fe.degree + 1);
    dealii::FEValues<dim>     fe_values(fe, quadrature, dealii::update_values | dealii::update_quadrature_points | dealii::update_JxW_values);
    std::vector<double>       values(quadrature.size());
    double                    squared = 0, volume = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        fe_values.get_function_values(field, values);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            const double dx = fe_values.JxW(q) * coordinates.weight(fe_values.quadrature_point(q));
            squared += values[q] * values[q] * dx;
            volume += dx;
          }
      }
    return std::sqrt(squared / volume);
  }



  template <int dim>
  void
  StrainField<dim>::update_flow_hardening()
  {
    point_hardening    = hardening_at(flow_quadrature, flow_temperatures);
    last.hardening_min = std::numeric_limits<double>::max();
    last.hardening_max = 0;
    for (const double value : point_hardening)
      {
        last.hardening_min = std::min(last.hardening_min, value);
        last.hardening_max = std::max(last.hardening_max, value);
      }
  }



  template <int dim>
  std::vector<double>
  StrainField<dim>::hardening_at(const unsigned int points_per_direction, const std::vector<double> *temperatures) const
  {
    std::vector<double> factors = values_at_points(dof_handler, strain, points_per_direction);
    // A new mesh's temperatures are those of its points once the heat is set up on it.
    const bool with_temperature = temperatures != nullptr && temperatures->size() == factors.size();
    for (std::size_t i = 0; i < factors.size(); ++i)
      // eps_h may dip below 0 by a little near a steep rise (no maximum principle with SUPG).
      factors[i] = material.hardening(std::max(factors[i], 0.), with_temperature ? (*temperatures)[i] : material.temperature);
    return factors;
  }



  template <int dim>
  void
  StrainField<dim>::make_record(const dealii::DoFHandler<dim> &flow_dofs, const dealii::Vector<double> &velocity)
  {
    const dealii::QGauss<dim - 1>            face_quadrature(fe.degree + 1);
    const dealii::FEValuesExtractors::Vector velocities(0);
    dealii::FEFaceValues<dim>                face_values(fe,
                                          face_quadrature,
                                          dealii::update_values | dealii::update_quadrature_points |
                                            dealii::update_JxW_values | dealii::update_normal_vectors);
    dealii::FEFaceValues<dim> flow_face_values(flow_dofs.get_fe(), face_quadrature, dealii::update_values);
    std::vector<dealii::Tensor<1, dim>> v_face(face_quadrature.size());
    std::vector<double>                 eps_face(face_quadrature.size());
    // Where the metal leaves: eps_exit the mixed-cup mean over all the
    // outflow (int eps v.n / int v.n over v.n > 0: a die's small v.n weighs
    // little); the range, as HeatRecord's, over the faces whose mean v.n is
    // above half their mean speed (not a die's values).
    double exit_flux = 0, exit_strain = 0;
    last.eps_exit_min = std::numeric_limits<double>::max();
    last.eps_exit_max = std::numeric_limits<double>::lowest();
    auto flow_cell    = flow_dofs.begin_active();
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        for (const unsigned int f : cell->face_indices())
          {
            if (!cell->face(f)->at_boundary())
              continue;
            face_values.reinit(cell, f);
            flow_face_values.reinit(flow_cell, f);
            face_values.get_function_values(strain, eps_face);
            flow_face_values[velocities].get_function_values(velocity, v_face);
            double face_flux = 0, face_speed = 0;
            for (unsigned int q = 0; q < face_quadrature.size(); ++q)
              {
                const double ds = face_values.JxW(q) * coordinates.weight(face_values.quadrature_point(q));
                const double vn = v_face[q] * face_values.normal_vector(q);
                face_flux += vn * ds;
                face_speed += v_face[q].norm() * ds;
                if (vn > 0)
                  exit_flux += vn * ds, exit_strain += vn * eps_face[q] * ds;
              }
            if (face_flux > 0.5 * face_speed && face_flux > 0)
              {
                for (const double eps : eps_face)
                  {
                    last.eps_exit_min = std::min(last.eps_exit_min, eps);
                    last.eps_exit_max = std::max(last.eps_exit_max, eps);
                  }
              }
          }
        ++flow_cell;
      }
    last.eps_exit = exit_flux > 0 ? exit_strain / exit_flux : 0;
    if (!(exit_flux > 0))
      last.eps_exit_min = last.eps_exit_max = 0;
    last.eps_max = strain.linfty_norm();

    if (exact)
      std::tie(last.l2_error, last.nodal_error) = errors_against(coordinates, dof_handler, strain, *exact);
    last.vertex_strain = vertex_values(dof_handler, strain);
  }



  template class StrainField<2>;
  template class StrainField<3>;
} // namespace dieflow
