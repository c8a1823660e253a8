// The flow's cell terms: the residual and the Jacobian (standard or primal-dual Newton) of the penalised velocity problem, with its loads.
#ifndef dieflow_flow_assembler_h
#define dieflow_flow_assembler_h

#include <dieflow/base/processes.h>
#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/flow/material.h>
#include <dieflow/solvers/linearization.h>
#include <dieflow/solvers/mixed_penalty.h>

#include <deal.II/base/function.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <set>
#include <unordered_map>

namespace dieflow
{
  using dealii::AffineConstraints;
  using dealii::DoFHandler;
  using dealii::SparseMatrix;
  using dealii::Vector;

  /**
   * Row transformations of nodes' equations, keyed by the node's first
   * (x-velocity) dof: the node's rows of the flow residual and Jacobian are
   * replaced by T times them (the friction of a slipping contact node
   * depends on its normal reaction, see ContactSet).
   */
  using RowTransforms = std::unordered_map<dealii::types::global_dof_index, dealii::FullMatrix<double>>;

  /**
   * What one assembly of the flow terms reads besides the velocity, and
   * where the mixed form's blocks go: the state of the incompressibility
   * form (Incompressibility::terms()) and the strain hardening of a run in
   * time (IncrementalState). Passed with each call: the assembler keeps no
   * pointer into the problem's state.
   */
  template <int dim>
  struct FlowTerms
  {
    /// lambda of the penalty term (r of the augmented Lagrangian where there is no cell_penalty).
    double penalty = 0;
    /**
     * The augmented-Lagrangian form and the mixed form: a multiplier q_h in
     * the pressure space (PressureProjection::n_modes() coefficients per
     * active cell) joins the penalty pressure, sigma = 2 eta D + (q_h + r P
     * div v) I, so the residual gains int q_h div w and the Jacobian is
     * unchanged; null: the plain penalty method.
     */
    const Vector<double> *multiplier = nullptr;
    /// A penalty per active cell (replacing penalty there), or null.
    const Vector<double> *cell_penalty = nullptr;
    /// A factor of the viscosity per active cell (strain hardening,
    /// Material::hardening()), or null: eta and its rate derivative scale
    /// alike, so the Newton tangent stays consistent.
    const Vector<double> *hardening = nullptr;
    /// A factor of the viscosity at the viscous term's quadrature points
    /// (indexed as temperature; the steady strain field, StrainField), or null.
    const std::vector<double> *point_hardening = nullptr;
    /// The temperature at the viscous term's quadrature points (QGauss(degree
    /// + 1), index active cell x points + point; HeatEquation), or null: the
    /// law at Material/Temperature (Material::evaluate(rate, T)).
    const std::vector<double> *temperature = nullptr;
    /// The mixed form (velocity degree 2, with a matrix only): the penalty's
    /// matrix term lambda B^T M^-1 B stays out of the matrix, which is then
    /// the velocity block A, and its blocks go here.
    MixedPenalty<dim> *mixed = nullptr;
  };



  /**
   * The cell terms of the penalised velocity problem (7)-(9) of the paper:
   *   R(v; w) = int 2 eta(epsdot(v)) D(v):D(w) dx        (Gauss, degree + 1 points)
   *           + int lambda (P div v)(P div w) dx
   *           - int f.w dx - int_Gamma_t t.w ds,
   * i.e. sigma = 2 eta D + lambda (P div v) I, p = -lambda P div v, with P
   * the projection of PressureProjection: for velocity degree 1 div v at
   * the cell centre (selective reduced integration, the paper's Q1-P0
   * element; full integration locks), for degree 2 the L2 projection onto
   * linear functions per cell (the stable Q2-P1disc pair).
   *
   * Newton tangent, with epsdot_reg = sqrt(2/3 D:D + epsdot_min^2):
   *   dR[dv](w) = int 2 eta D(dv):D(w)
   *             + (4/3) (d eta/d epsdot) / epsdot_reg (D(v):D(dv)) (D(v):D(w))
   *             + lambda div dv div w,
   * symmetric (the problem minimises a convex dissipation potential).
   *
   * In the axisymmetric geometry (set_coordinate_system()) D is the
   * StrainRate with the hoop rate v_r/r, div v gains v_r/r, and dx, ds
   * carry the factor 2 pi r (CoordinateSystem), so R is the virtual power
   * of the body of revolution.
   */
  template <int dim>
  class FlowAssembler
  {
  public:
    /// The Newton tangent's form.
    enum class Tangent
    {
      /// the consistent tangent of R
      standard,
      /**
       * Primal-dual Newton (Isaac, Stadler, Ghattas, SIAM J. Sci. Comput.
       * 37 (2015) B804): the normalised strain rate S = D/r becomes an
       * independent unknown at the quadrature points, linearised with v;
       * after eliminating dS the tangent reads
       *   2 eta D(dv):D(w) + (4/3) eta' r sym[(S^:D(dv)) (S:D(w))],
       * and S is updated by its Newton step S + dS = (D + D(dv) - S dr)/r,
       * scaled to |S| = sqrt(2/3 S:S) <= 1.
       * Same solution, far fewer iterations for strongly shear-thinning
       * laws (m << 1), whose standard tangent is too soft where r is small.
       */
      primal_dual
    };

    void
    set_tangent(const Tangent t)
    {
      tangent = t;
    }

    /**
     * Primal-dual state: reset S = D(v)/r(v) (@p update null, or a new mesh),
     * or advance it by the linearised update for the step v -> v + step*update.
     */
    void
    update_dual(const DoFHandler<dim> &dof_handler,
                const Vector<double> & velocity,
                const Vector<double> * update,
                const double           step);

    FlowAssembler(const Material &material, const dealii::Function<dim> *body_force);
    /// Assembles with @p material's law from now on (a continuation's stage);
    /// kept by reference.
    void
    set_material(const Material &material)
    {
      this->material = &material;
    }

    void
    set_coordinate_system(const CoordinateSystem<dim> &c)
    {
      coordinates = c;
    }
    const CoordinateSystem<dim> &
    coordinate_system() const
    {
      return coordinates;
    }

    void
    set_body_force(const dealii::Function<dim> *f)
    {
      body_force = f;
    }
    /// The prescribed traction t on the faces with the given ids: the
    /// load -int t.w ds joins the residual (a dead load: no Jacobian term).
    void
    set_traction(const dealii::Function<dim> *t, const std::set<dealii::types::boundary_id> &ids)
    {
      traction     = t;
      traction_ids = ids;
    }
    /// Copies the loads (body force, traction) and the coordinate system of @p other.
    void
    copy_loads(const FlowAssembler &other)
    {
      coordinates  = other.coordinates;
      body_force   = other.body_force;
      traction     = other.traction;
      traction_ids = other.traction_ids;
    }

    /**
     * The Jacobian and the right-hand side -R(v) of the update equation,
     * condensed with the homogeneous @p update_constraints, and the raw
     * (unconstrained) residual R(v) whose entries at constrained dofs are
     * the reaction forces; @p transforms (if any) apply to the condensed
     * system, not to the raw residual. @p terms: the penalty's state and
     * the hardening; with terms.mixed (velocity degree 2 only), @p matrix
     * is the velocity block A and the penalty's blocks go to terms.mixed
     * (the residual is unchanged). On P > 1 processes the matrix is summed
     * by @p row_sums where given (each process's own rows; its pattern
     * that of RowSums::reinit()), else in every row (a pattern of all).
     */
    void
    assemble_system(const DoFHandler<dim> &           dof_handler,
                    const Vector<double> &            velocity,
                    const FlowTerms<dim> &            terms,
                    const AffineConstraints<double> & update_constraints,
                    const Linearization               linearization,
                    SparseMatrix<double> &            matrix,
                    Vector<double> &                  rhs,
                    Vector<double> &                  raw_residual,
                    const RowTransforms *             transforms = nullptr,
                    const processes::RowSums *        row_sums   = nullptr) const;

    /// As assemble_system() without the matrix: rhs = -R(v) condensed, and the raw R(v).
    void
    assemble_residual(const DoFHandler<dim> &          dof_handler,
                      const Vector<double> &           velocity,
                      const FlowTerms<dim> &           terms,
                      const AffineConstraints<double> &update_constraints,
                      Vector<double> &                 rhs,
                      Vector<double> &                 raw_residual,
                      const RowTransforms *            transforms = nullptr) const;

    /// Volume average of eta(epsdot(v)) (2x2 Gauss points).
    double
    mean_viscosity(const DoFHandler<dim> &dof_handler, const Vector<double> &velocity) const;

  private:
    void
    assemble(const DoFHandler<dim> &           dof_handler,
             const Vector<double> &            velocity,
             const FlowTerms<dim> &            terms,
             const AffineConstraints<double> & update_constraints,
             const Linearization               linearization,
             SparseMatrix<double> *            matrix,
             Vector<double> &                  rhs,
             Vector<double> &                  raw_residual,
             const RowTransforms *             transforms,
             const processes::RowSums *        row_sums) const;

    unsigned int
    n_dual_points(const DoFHandler<dim> &dof_handler) const;

    const Material *             material;
    CoordinateSystem<dim>        coordinates;
    Tangent                      tangent = Tangent::primal_dual;
    std::vector<StrainRate<dim>> dual;
    const dealii::Function<dim> *body_force;
    const dealii::Function<dim> *traction = nullptr;
    std::set<dealii::types::boundary_id> traction_ids;
  };
} // namespace dieflow

#endif
