// The goal-oriented estimate of a force's error: the force's dual problem, its dual-weighted residual, and the refinement indicators it gives.
#ifndef dieflow_goal_estimate_h
#define dieflow_goal_estimate_h

#include <dieflow/flow/boundary_conditions.h>
#include <dieflow/contact/contact_set.h>
#include <dieflow/flow/flow_assembler.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <functional>
#include <utility>
#include <vector>

namespace dieflow
{
  /// The temperature and the hardening factor at QGauss(@p n)'s points of each active cell, indexed as
  /// FlowTerms' (an empty vector: isothermal, no steady hardening): what the flow reads, on the dual's quadratures.
  using PointFields = std::function<std::pair<std::vector<double>, std::vector<double>>(const unsigned int n)>;

  /// What dual_weighted_force_error() returns.
  struct GoalEstimate
  {
    /// The estimate of F - F_h (the exact force minus the computed one).
    double error = 0;
    /// Its velocity part, sum_K int_K sigma_h : D(z - I_h z).
    double velocity_part = 0;
    /// Its pressure part, sum_K int_K (z_p - P z_p) div v_h.
    double pressure_part = 0;
    /// Unknowns of the dual problem (velocity degree + 1).
    unsigned int dual_dofs = 0;
  };

  /**
   * psi: the lifting of the force F_x on the part @p part_id, 1 at the
   * x-components of its nodes (hanging nodes distributed), so that the
   * force is the reaction F_h = R_h(v_h; psi).
   */
  template <int dim>
  Vector<double>
  force_direction(const DoFHandler<dim> &dof_handler, const AffineConstraints<double> &hanging_node_constraints, const BoundaryId part_id);

  /**
   * The dual solution z of the force with lifting @p psi, in the space of
   * @p dof_handler, with the contact states of @p contact frozen:
   *   z = psi + T^T C y,  J_c^T y = -C^T J_flow^T psi,
   * J_c the condensed Jacobian (with the friction row transforms T and
   * the constraints C of @p constraints, homogeneous) that
   * @p solve_transposed solves with, J_flow the flow Jacobian condensed
   * with the hanging nodes only (its rows at the part are dF/dv). So
   * R_h(v_h; z) = F_h, and z weights each equation by how much its
   * residual moves the force.
   */
  template <int dim>
  Vector<double>
  force_dual(const DoFHandler<dim> &                       dof_handler,
             const AffineConstraints<double> &             hanging_node_constraints,
             const AffineConstraints<double> &             constraints,
             const dealii::SparsityPattern &               pattern,
             const Vector<double> &                        velocity,
             const FlowAssembler<dim> &                    assembler,
             const FlowTerms<dim> &                        terms,
             const ContactSet<dim> &                       contact,
             const Vector<double> &                        psi,
             const std::function<void(Vector<double> &)> & solve_transposed);

  /**
   * The goal-oriented refinement indicator eta_K(v_h) eta_K(z): the Kelly
   * indicators of the solution and of the dual solution @p dual of the
   * same space multiplied (Mommer and Stevenson, SIAM J. Numer. Anal. 47
   * (2009) 861). The cell terms of the dual-weighted estimate below would
   * localise it too, but they carry large contributions of either sign
   * that cancel between neighbours (the weak form's face terms): marking
   * by them refined cells that did not change the force (measured).
   */
  template <int dim>
  dealii::Vector<float>
  goal_indicators(const DoFHandler<dim> &dof_handler, const Vector<double> &velocity, const Vector<double> &dual);

  /**
   * A goal-oriented (dual-weighted residual) estimate of the error of the
   * force F_x on the prescribed-velocity part @p part_id, after Becker and
   * Rannacher (Acta Numerica 2001) and deal.II's step-14.
   *
   * The force is the reaction F_h = R_h(v_h; psi), psi = e_x at the part's
   * nodes. With the contact states of the converged solution frozen (active
   * contact: v.n = 0; sticking: v = 0; slipping: the friction row transform
   * T = I + b n^T of ContactSet, so that the test functions w satisfy
   * w.n = b.w at slipping nodes and the friction traction does no work),
   * the dual solution z in psi + W solves the adjoint of the linearised
   * problem, J(v_h)^T z = 0 on every admissible variation, and
   *   F - F_h = R(v_h; z - I_h z) + (higher order)
   *           = sum_K int_K sigma_h : D(z - I_h z) dx
   *             - sum_K int_K (z_p - P z_p) div v_h dx,
   * sigma_h = 2 eta(v_h) D(v_h) - p_h I, p_h = -lambda P div v_h, and z_p =
   * -lambda P div z the dual pressure. z is computed on the same mesh with
   * the velocity degree raised by one (step-14's choice), which needs no
   * patch structure of the mesh; I_h interpolates onto the velocity element
   * of v_h, P projects onto its pressure space. The dual takes one
   * factorisation of the degree + 1 Jacobian.
   *
   * Measured (doc/benchmarks.md, "Two estimates of the ram force's
   * error"): exact where the solution is (Couette, Poiseuille, hanging
   * nodes included); on a problem linear once the contact states are
   * fixed it is F_h(degree p + 1) - F_h(degree p) on the same mesh, as it
   * must be, so its effectivity is the share of the error that the higher
   * degree removes: most of it on die2d with frictionless dies, less for
   * degree 2 than for degree 1 (the die exit's singularity), and near zero
   * with Coulomb friction, whose error is mostly that of the contact
   * states themselves (where stick turns to slip, where the metal
   * separates), outside a frozen-state linearisation.
   *
   * Only the flow part of the residual enters: for exact Coulomb slip the
   * contact terms vanish on the test space above (regularised laws, the
   * contact penalty and the augmented Lagrangian are not covered), and
   * there is no body force or prescribed traction (die scenes).
   */
  template <int dim>
  GoalEstimate
  dual_weighted_force_error(const DoFHandler<dim> &          dof_handler,
                            const AffineConstraints<double> &hanging_node_constraints,
                            const Vector<double> &           velocity,
                            const FlowAssembler<dim> &       assembler,
                            const FlowTerms<dim> &           terms,
                            const Material &                 material,
                            const ContactSet<dim> &          contact,
                            const BoundaryConditions<dim> &  boundary_conditions,
                            const std::set<BoundaryId> &     die_ids,
                            const BoundaryId                 part_id,
                            const PointFields &              fields = {});
} // namespace dieflow

#endif
