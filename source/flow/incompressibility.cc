// The incompressibility forms behind one interface: plain penalty, augmented Lagrangian and the mixed form.
#include <dieflow/flow/incompressibility.h>
#include <dieflow/flow/pressure_projection.h>
#include <dieflow/mesh/whole_mesh.h>
#include <dieflow/solvers/rigid_body_modes.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace dieflow
{
  namespace
  {
    /**
     * The mixed form's ||q / lambda|| / ||grad v|| at which the pressure
     * equation counts as solved: its residual M q / lambda perturbs P div v
     * by q / lambda, and the velocity (inf-sup stability) by about as much
     * relative to grad v.
     */
    constexpr double mixed_pressure_tolerance = 1e-10;
  } // namespace



  template <int dim>
  Incompressibility<dim>::Incompressibility(const Material &             material,
                                            const CoordinateSystem<dim> &coordinates,
                                            const DoFHandler<dim> &      dof_handler,
                                            LinearSolver &               linear_solver,
                                            std::ostream &               log)
    : material(material)
    , coordinates(coordinates)
    , dof_handler(dof_handler)
    , linear_solver(linear_solver)
    , log(log)
  {}



  template <int dim>
  double
  Incompressibility<dim>::factor() const
  {
    return current_form == Form::augmented_lagrangian && krylov ? linear_solver.parameters.augmentation :
                                                                  material.penalty_factor;
  }



  template <int dim>
  std::string
  Incompressibility<dim>::form_name() const
  {
    return current_form == Form::penalty ? "penalty" :
           current_form == Form::mixed   ? "mixed" :
                                           "augmented Lagrangian";
  }



  template <int dim>
  std::string
  Incompressibility<dim>::name() const
  {
    return current_form == Form::augmented_lagrangian ? "augmented-Lagrangian penalty r" : "penalty lambda";
  }



  template <int dim>
  void
  Incompressibility<dim>::set_viscosity_scale(const double eta, const Material *law)
  {
    eta_m          = eta;
    stage_law      = law;
    largest_lambda = process_rate > 0 ? Material::largest_penalty_factor * (law != nullptr ? *law : material).evaluate(process_rate).eta :
                                        std::numeric_limits<double>::infinity();
    lambda         = std::min(factor() * eta_m, largest_lambda);
  }



  template <int dim>
  void
  Incompressibility<dim>::reinit(const AffineConstraints<double> &hanging_node_constraints,
                                 const Vector<double> &           velocity,
                                 const SparseMatrix<double> &     matrix)
  {
    const auto &       fe      = dof_handler.get_fe();
    const unsigned int n_cells = dof_handler.get_triangulation().n_active_cells();
    linear_solver.reset(matrix);
    bool iterative = linear_solver.parameters.iterative_for(dim, fe.degree, dof_handler.n_dofs());
    if (!iterative && linear_solver.parameters.method == LinearSolverParameters::Method::automatic &&
        !linear_solver.direct_fits(dim, matrix))
      {
        iterative = true;
        log << "  Linear solver/Method = auto: a direct factorisation of " << dof_handler.n_dofs()
            << " unknowns would not fit in the memory free; iterative on this mesh" << std::endl;
      }
    krylov        = iterative;
    stalled_steps = 0;
    if (!krylov)
      last_divergence_ratio = 0;
    current_form = !iterative       ? (augmented_direct ? Form::augmented_lagrangian : Form::penalty) :
                   fe.degree == 1   ? Form::augmented_lagrangian :
                                      Form::mixed;
    if (current_form == Form::mixed)
      {
        blocks.reinit(dof_handler, hanging_node_constraints, PressureProjection<dim>::n_modes_for(fe));
        if (!saddle_point_solver)
          saddle_point_solver = std::make_unique<SaddlePointSolver<dim>>();
        saddle_point_solver->reinit();
        saddle_point_solver->set_rigid_body_modes(rigid_body_modes(dof_handler));
        if (linear_solver.parameters.p_multigrid)
          saddle_point_solver->use_p_multigrid(dof_handler);
        last_mixed_tolerance                 = 0;
        last_mixed_residual                  = 0;
        last_mixed_update                    = 1;
        saddle_point_solver->inner_tolerance = linear_solver.parameters.inner_tolerance;
        // The previous mesh's cell stress gives the first pressure (cell
        // means). Without one the pressure starts at zero, at the first
        // assembly: q = -lambda P div v there (a velocity that only meets
        // the boundary conditions has a divergence of order its speed over
        // a cell, whose pressure lambda P div v would swamp the residual).
        Vector<double> pressure(blocks.n_pressure());
        pressure_unset = !(carried_stress.size() == n_cells && velocity.size() == dof_handler.n_dofs());
        if (pressure_unset)
          multiplier = pressure;
        else
          {
            for (unsigned int c = 0; c < n_cells; ++c)
              pressure[c * blocks.n_modes] = carried_stress[c];
            multiplier = multiplier_for(pressure, velocity);
          }
        accepted_multiplier = multiplier;
        multiplier_update.reinit(multiplier.size());
      }
    else if (current_form == Form::augmented_lagrangian)
      {
        if (krylov)
          {
            linear_solver.set_constant_modes(whole_mesh::constant_modes(dof_handler));
          }
        // The previous mesh's cell stress is the best first multiplier.
        // Only the cell means go from mesh to mesh (the first coefficient).
        const unsigned int n_modes = PressureProjection<dim>::n_modes_for(fe);
        const bool         carried = carried_stress.size() == n_cells;
        multiplier.reinit(n_cells * n_modes);
        if (carried)
          for (unsigned int c = 0; c < n_cells; ++c)
            multiplier[c * n_modes] = carried_stress[c];
        if (velocity.size() == dof_handler.n_dofs())
          update_cell_penalty(velocity);
        else
          cell_penalty.reinit(n_cells);
      }
    else
      multiplier.reinit(0);
    if (eta_m > 0)
      lambda = std::min(factor() * eta_m, largest_lambda);
  }



  template <int dim>
  FlowTerms<dim>
  Incompressibility<dim>::terms()
  {
    FlowTerms<dim> terms;
    terms.penalty      = lambda;
    terms.multiplier   = current_form != Form::penalty ? &multiplier : nullptr;
    terms.cell_penalty = current_form == Form::augmented_lagrangian ? &cell_penalty : nullptr;
    terms.mixed        = current_form == Form::mixed ? &blocks : nullptr;
    return terms;
  }



  template <int dim>
  void
  Incompressibility<dim>::before_state_update(const Vector<double> &v)
  {
    if (current_form != Form::augmented_lagrangian || v.linfty_norm() == 0)
      return;
    // q_h <- q_h + r P div v, each cell's coefficients with the cell's r.
    const Vector<double> divergence = cell_divergence(coordinates, dof_handler, v);
    const unsigned int   n_modes    = PressureProjection<dim>::n_modes_for(dof_handler.get_fe());
    for (unsigned int i = 0; i < divergence.size(); ++i)
      multiplier[i] += cell_penalty[i / n_modes] * divergence[i];
    const double previous_ratio = last_divergence_ratio;
    last_divergence_ratio       = divergence_ratio(coordinates, dof_handler, v);
    stalled_steps =
      !krylov && previous_ratio > 0 && last_divergence_ratio > 0.5 * previous_ratio ? stalled_steps + 1 : 0;
    update_cell_penalty(v);
  }



  template <int dim>
  void
  Incompressibility<dim>::after_projection(const Vector<double> &before, const Vector<double> &v)
  {
    if (current_form != Form::mixed || pressure_unset || before.size() != v.size() || before == v)
      return;
    Vector<double> move = v;
    move -= before;
    accepted_multiplier.add(-lambda, PressureProjection<dim>::project_all(dof_handler, move, coordinates));
    multiplier = accepted_multiplier;
  }



  template <int dim>
  void
  Incompressibility<dim>::prepare_assembly(const Vector<double> &v, const Linearization linearization)
  {
    if (current_form != Form::mixed)
      return;
    if (pressure_unset)
      accepted_multiplier = multiplier_for(Vector<double>(blocks.n_pressure()), v);
    pressure_unset          = false;
    multiplier              = accepted_multiplier;
    assembled_iterate       = v;
    assembled_linearization = linearization;
  }



  template <int dim>
  void
  Incompressibility<dim>::solve(SparseMatrix<double> &           matrix,
                                const bool                       symmetric,
                                Vector<double> &                 rhs,
                                const AffineConstraints<double> &update_constraints,
                                Vector<double> &                 update,
                                const double                     relative_residual,
                                const double                     residual_floor,
                                const Vector<double> &           velocity,
                                const Reassembly &               reassemble)
  {
    update.reinit(dof_handler.n_dofs());
    if (current_form == Form::mixed)
      solve_mixed(matrix, symmetric, rhs, update_constraints, update,
                  mixed_solve_tolerance(relative_residual, residual_floor, velocity), reassemble);
    else if (current_form == Form::augmented_lagrangian && krylov)
      linear_solver.solve_iteratively(dim, matrix, symmetric, rhs, update);
    else
      {
        // A reused factorisation's GMRES solves J du = -R to a tenth of
        // the residual's round-off floor (relative to the reactions, as
        // the residual is), no looser than 1e-6 of -R: what is left of
        // the linear residual then stays below what Newton's own residual
        // can resolve.
        const double tolerance =
          relative_residual > 0 ? std::clamp(0.1 * residual_floor / relative_residual, 1e-12, 1e-6) : 1e-6;
        linear_solver.solve_step(matrix, symmetric, rhs, update, tolerance);
      }
  }



  template <int dim>
  void
  Incompressibility<dim>::set_trial_step(const double step)
  {
    if (current_form != Form::mixed)
      return;
    multiplier = accepted_multiplier;
    multiplier.add(step, multiplier_update);
  }



  template <int dim>
  void
  Incompressibility<dim>::accept(const double step)
  {
    if (current_form != Form::mixed)
      return;
    accepted_multiplier.add(step, multiplier_update);
    multiplier        = accepted_multiplier;
    multiplier_update = 0;
  }



  template <int dim>
  bool
  Incompressibility<dim>::settled(const Vector<double> &velocity) const
  {
    if (current_form == Form::mixed)
      return pressure_residual_ratio(velocity) <= mixed_pressure_tolerance;
    return current_form != Form::augmented_lagrangian ||
           last_divergence_ratio <= linear_solver.parameters.divergence_tolerance || uzawa_stalled();
  }



  template <int dim>
  double
  Incompressibility<dim>::cancellation_floor() const
  {
    return 6e-17 * factor() * std::sqrt(static_cast<double>(dof_handler.n_dofs()));
  }



  template <int dim>
  double
  Incompressibility<dim>::mixed_solve_tolerance(const double          relative_residual,
                                                const double          residual_floor,
                                                const Vector<double> &velocity)
  {
    // Without the tightening, Newton's residual reached its floor while
    // the ratio stalled near its bound, each solve at the tightest
    // tolerance leaving about as much of q as it removed. The ratio costs
    // a pass of gradients over the mesh: only at the floor.
    double tolerance =
      linear_solver.parameters.forcing_tolerance(relative_residual, factor(), last_mixed_tolerance, last_mixed_residual);
    const double previous_residual = last_mixed_residual;
    last_mixed_residual            = relative_residual;
    // At the floor also where the residual stopped falling while the
    // velocity stopped moving: residual_floor() is a fit, and a larger
    // mesh at a large penalty can stall above it (doc/benchmarks.md,
    // "Figures behind the code's rules").
    const bool stalled = relative_residual > 0.5 * previous_residual && last_mixed_update <= 1e-8;
    if (last_mixed_tolerance > 0 && (relative_residual <= residual_floor || stalled))
      {
        const double ratio = pressure_residual_ratio(velocity);
        if (ratio > mixed_pressure_tolerance)
          tolerance = std::max({1e-10, 1e-2 * tolerance,
                                std::min(tolerance, 0.1 * mixed_pressure_tolerance / ratio * last_mixed_tolerance)});
      }
    last_mixed_tolerance = tolerance;
    return tolerance;
  }



  template <int dim>
  void
  Incompressibility<dim>::solve_mixed(SparseMatrix<double> &           matrix,
                                      const bool                       symmetric,
                                      Vector<double> &                 rhs,
                                      const AffineConstraints<double> &update_constraints,
                                      Vector<double> &                 update,
                                      const double                     tolerance,
                                      const Reassembly &               reassemble)
  {
    // b_p = -R_p = M q / lambda.
    Vector<double> inverse_penalty(blocks.n_cells), rhs_pressure, dp;
    for (unsigned int c = 0; c < blocks.n_cells; ++c)
      inverse_penalty[c] = 1. / blocks.penalty[c];
    blocks.mass_vmult(rhs_pressure, accepted_multiplier, inverse_penalty);
    const auto info = saddle_point_solver->solve(matrix, update_constraints,
                                                 material.is_newtonian() ? nullptr : &assembled_iterate, blocks, rhs,
                                                 rhs_pressure, update, dp, symmetric, tolerance,
                                                 linear_solver.parameters.max_block_iterations);
    // A solve that stopped at its iteration limit having reduced its
    // residual tenfold is still a descent step of an inexact Newton method
    // (forcing term 0.1); where the direct fallback would not fit, taking it
    // beats stopping (doc/benchmarks.md, "Figures behind the code's rules").
    const bool partial_step = !info.converged && info.residual_reduction <= 0.1 &&
                              !linear_solver.direct_fallback_fits(dim, matrix, symmetric);
    linear_solver.counts.add_block_solve(info.iterations, info.inner_iterations, info.residual_reduction, partial_step);
    linear_solver.counts.setup_seconds += info.setup_seconds;
    std::ostringstream line;
    line << "           GMRES " << info.iterations << " iterations, residual " << std::scientific << std::setprecision(1)
         << info.residual_reduction << " of its start (asked " << tolerance << ")"
         << (info.converged ? "" : partial_step ? ": stopped short, taken as a partial step" : ": stopped short");
    log << line.str() << std::endl;
    if (info.converged || partial_step)
      {
        last_mixed_update = update.l2_norm() / std::max(assembled_iterate.l2_norm(), 1e-300);
        // dq = dp - lambda M^-1 B du.
        Vector<double> divergence(blocks.n_pressure());
        blocks.divergence.vmult(divergence, update);
        blocks.inverse_mass_vmult(multiplier_update, divergence, blocks.penalty);
        multiplier_update.sadd(-1., 1., dp);
        return;
      }
    // The direct solver on the penalty form gives the mixed step exactly:
    // eliminating dp = lambda M^-1 B du - q leaves J du = -R_v + B^T q,
    // which is -R(v) assembled with q = 0. The carried pressure's update is
    // then dq = dp - lambda M^-1 B du = -q. Keeping q and its update (not
    // setting q = 0 at once) matters when the step is shortened: a trial
    // step s then carries (1 - s) q, where q = 0 left lambda P div of the
    // contact projections' moves in the pressure, a residual some 1e9 too
    // large that turned the line search and the Picard step that followed
    // into a divergence (doc/benchmarks.md, "Figures behind the code's rules").
    // LU's room: the penalty form's symmetry is known after its assembly.
    linear_solver.require_direct_fallback_fits(dim, matrix, false);
    ++linear_solver.counts.direct_fallbacks;
    FlowTerms<dim> penalty_form;
    penalty_form.penalty = lambda;
    const bool penalty_form_symmetric = reassemble(assembled_iterate, assembled_linearization, penalty_form);
    multiplier_update = accepted_multiplier;
    multiplier_update *= -1.;
    linear_solver.factorize(matrix, penalty_form_symmetric, LinearSolver::FactorisationFor::fallback);
    linear_solver.solve(rhs, update);
  }



  template <int dim>
  Vector<double>
  Incompressibility<dim>::multiplier_for(const Vector<double> &p, const Vector<double> &v) const
  {
    const Vector<double> divergence = PressureProjection<dim>::project_all(dof_handler, v, coordinates);
    Vector<double>       q          = p;
    q.add(-lambda, divergence);
    return q;
  }



  template <int dim>
  double
  Incompressibility<dim>::pressure_residual_ratio(const Vector<double> &velocity) const
  {
    if (accepted_multiplier.size() == 0 || velocity.size() != dof_handler.n_dofs())
      return 0;
    Vector<double> ones(blocks.n_cells), Mq;
    ones = 1.;
    blocks.mass_vmult(Mq, accepted_multiplier, ones);
    const auto &                             fe = dof_handler.get_fe();
    const dealii::FEValuesExtractors::Vector velocities(0);
    dealii::FEValues<dim>                    gauss(fe,
                                dealii::QGauss<dim>(fe.degree + 1),
                                dealii::update_gradients | dealii::update_JxW_values | dealii::update_quadrature_points);
    std::vector<dealii::Tensor<2, dim>> grad(gauss.n_quadrature_points);
    double                              grad_squared = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        gauss.reinit(cell);
        gauss[velocities].get_function_gradients(velocity, grad);
        for (const unsigned int q : gauss.quadrature_point_indices())
          grad_squared += grad[q].norm_square() * gauss.JxW(q) * coordinates.weight(gauss.quadrature_point(q));
      }
    const double q_norm = std::sqrt(accepted_multiplier * Mq);
    return grad_squared > 0 ? q_norm / (lambda * std::sqrt(grad_squared)) : q_norm;
  }



  template <int dim>
  void
  Incompressibility<dim>::update_cell_penalty(const Vector<double> &v)
  {
    // r per cell in proportion to its viscosity: the multiplier then
    // converges as fast in the stiff plug of the container as in the
    // deforming zone (with one r for all, 1e3 times the mean viscosity is
    // nothing where eta is 1e4 times the mean).
    dealii::FEValues<dim>        centre(dof_handler.get_fe(), dealii::QGauss<dim>(1),
                                 dealii::update_gradients | coordinates.flags());
    std::vector<StrainRate<dim>> D(1);
    cell_penalty.reinit(dof_handler.get_triangulation().n_active_cells());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        centre.reinit(cell);
        coordinates.strain_rates(centre, v, D);
        cell_penalty[cell->active_cell_index()] =
          (stage_law != nullptr ? *stage_law : material).evaluate(std::sqrt(2. / 3. * (D[0] * D[0]))).eta;
      }
    cell_penalty *= factor();
  }



  template <int dim>
  void
  Incompressibility<dim>::augment(const Vector<double> &v)
  {
    if (current_form != Form::penalty)
      return;
    current_form     = Form::augmented_lagrangian;
    augmented_direct = true;
    restart_multiplier(v);
  }



  template <int dim>
  void
  Incompressibility<dim>::restart_multiplier(const Vector<double> &v)
  {
    if (current_form != Form::augmented_lagrangian)
      return;
    update_cell_penalty(v);
    // q = (lambda - r) P div v per cell: the pressure stays -lambda P div v.
    multiplier             = cell_divergence(coordinates, dof_handler, v);
    const unsigned int n_modes = multiplier.size() / cell_penalty.size();
    for (unsigned int i = 0; i < multiplier.size(); ++i)
      multiplier[i] *= lambda - cell_penalty[i / n_modes];
    last_divergence_ratio = divergence_ratio(coordinates, dof_handler, v);
    stalled_steps         = 0;
  }



  template <int dim>
  void
  Incompressibility<dim>::uniform_cell_penalty(const double r)
  {
    if (current_form != Form::augmented_lagrangian)
      return;
    cell_penalty.reinit(dof_handler.get_triangulation().n_active_cells());
    cell_penalty.add(r);
  }



  template <int dim>
  Vector<double>
  Incompressibility<dim>::cell_pressures(const Vector<double> &velocity) const
  {
    return cell_pressure(coordinates,
                         dof_handler,
                         velocity,
                         lambda,
                         current_form != Form::penalty ? &multiplier : nullptr,
                         current_form == Form::augmented_lagrangian ? &cell_penalty : nullptr);
  }



  template <int dim>
  FlowTerms<dim>
  Incompressibility<dim>::start_terms(const double start_penalty, const Vector<double> &velocity)
  {
    FlowTerms<dim> terms;
    terms.penalty = start_penalty;
    if (current_form == Form::mixed)
      {
        // p = 0 to start with (see reinit()), with the start's lambda.
        accepted_multiplier = PressureProjection<dim>::project_all(dof_handler, velocity, coordinates);
        accepted_multiplier *= -start_penalty;
        multiplier       = accepted_multiplier;
        pressure_unset   = false;
        terms.multiplier = &multiplier;
        terms.mixed      = &blocks;
      }
    return terms;
  }



  template <int dim>
  void
  Incompressibility<dim>::finish_start(const double start_penalty, const double eta, const Vector<double> &velocity)
  {
    // The start's pressure, p = q + lambda P div v with its own lambda.
    Vector<double> start_pressure;
    if (current_form == Form::mixed)
      {
        start_pressure = accepted_multiplier;
        start_pressure.add(1., multiplier_update);
        start_pressure.add(start_penalty, PressureProjection<dim>::project_all(dof_handler, velocity, coordinates));
      }
    // The first Uzawa step uses the r this solve had.
    uniform_cell_penalty(start_penalty);
    set_viscosity_scale(eta);
    if (current_form == Form::mixed)
      {
        // As the penalty form's p = lambda P div v does when lambda changes
        // (the same Newton path as the direct solver's).
        start_pressure *= lambda / start_penalty;
        accepted_multiplier = multiplier_for(start_pressure, velocity);
        multiplier          = accepted_multiplier;
        multiplier_update   = 0;
      }
  }

  template class Incompressibility<2>;
  template class Incompressibility<3>;
} // namespace dieflow
