// The metal's temperature: the steady heat equation on the flow's mesh, its sources from the flow and the dies, its balance and its outputs.
#ifndef dieflow_heat_equation_h
#define dieflow_heat_equation_h

#include <dieflow/flow/material.h>
#include <dieflow/heat/heat_parameters.h>
#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/mesh/scalar_field.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/solution_transfer.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dieflow
{
  /// A contact node's friction work -F_t.v_slip (N mm/s) at @p position on die @p die: a heat source at the die.
  template <int dim>
  struct FrictionWork
  {
    dealii::Point<dim> position;
    double             work;
    BoundaryId         die;
  };

  /**
   * What the temperature of a cycle reports (summary.json "heat"). The
   * balance in W per mm of depth (plane strain) or W (axisymmetric, 3D),
   * i.e. N mm/s / 1000: the heat made (beta sigma:D, the metal's share of
   * the friction work) against the heat carried by the metal (int rho c
   * v.grad T), lost through the parts with a heat transfer coefficient, and
   * conducted out through the parts where T is prescribed (their reaction).
   */
  struct HeatRecord
  {
    /// Heat/Model = transient: the record of a step (stored, no outlet) rather than of a steady solve.
    bool transient = false;
    /// Heat solves made, and whether the last changed T by less than the Coupling tolerance.
    unsigned int solves  = 0;
    bool         settled = false;
    /// The last solve's largest change of T (K).
    double last_change = 0;
    /// The last solve's passes with rho c, k and the radiation at the last T (tabulated properties, Emissivities; 0 when linear).
    unsigned int property_passes = 0;
    /// The plastic work int sigma:D, beta of it, and the friction work and the metal's share (N mm/s).
    double plastic_work = 0, plastic_heat = 0, friction_work = 0, friction_heat = 0;
    /// int rho c v.grad T (steady), int rho c (T - T_old)/dt (in time: what the step stores in the metal),
    /// int h (T - T_ambient) over the transfer parts, the prescribed parts' reaction (N mm/s).
    double carried = 0, stored = 0, transferred = 0, prescribed_outflow = 0;
    /// int h (T - T_ambient) over each transfer part (N mm/s): the heat each die takes from the metal.
    std::map<dealii::types::boundary_id, double> transferred_by_id;
    /// (heat made - carried - stored - transferred - prescribed outflow) / heat made.
    double balance_error = 0;
    /// The metal's mean temperature, int rho c T / int rho c (K).
    double T_mean = 0;
    /// The extremes of T over the metal (nodal values) and where the metal
    /// leaves: its flux-weighted mean and range over the faces it crosses outwards (mean v.n above half its mean speed).
    double T_min = 0, T_max = 0, T_exit = 0, T_exit_min = 0, T_exit_max = 0;
    /// The largest cell Peclet number |v| h rho c / (2 k).
    double peclet = 0;
    /// Against Heat/Exact temperature (if given): ||T_h - T||_L2 (with 2 pi r in the axisymmetric geometry) and the largest nodal error.
    std::optional<double> T_l2_error, T_nodal_error;
    /// T at the mesh's vertices (for the VTU).
    std::vector<double> vertex_temperature;
  };

  /**
   * The steady heat equation of the metal on the flow's mesh (Eulerian):
   *   rho c v.grad T - div(k grad T) = beta sigma:D,
   * sigma:D = 2 eta D:D the plastic work of the flow (eq. (3) of the paper),
   * with T = T_p on the prescribed parts, k grad T.n = h (T_ambient - T) on
   * the transfer parts (dies, free surfaces), the metal's share of the
   * friction work -F_t.v_slip of each contact node as a nodal heat source
   * (the discrete friction power of the flow's reactions), and insulated
   * elsewhere. Continuous Q_k elements; in the axisymmetric geometry dx and
   * ds carry 2 pi r (the weak form of the cylindrical Laplacian). SUPG
   * (Brooks, Hughes 1982): the test function gains tau v.grad w on each
   * cell, tau = h/(2|v|) (coth Pe - 1/Pe), Pe = |v| h rho c/(2k), h the
   * cell's size over the degree, and the strong residual keeps the second
   * derivatives of degree 2 (consistent: the exact solution satisfies it).
   * The flow reads T at its quadrature points (point_temperatures()).
   */
  template <int dim>
  class HeatEquation
  {
  public:
    HeatEquation(const HeatParameters &       parameters,
                 const Material &             material,
                 const CoordinateSystem<dim> &coordinates,
                 const dealii::Triangulation<dim> &triangulation,
                 const unsigned int           velocity_degree);

    /// The dofs, constraints and matrix of the current mesh; T at its start (Material/Temperature) on the first.
    void
    setup();

    /// Carries T through a refinement of the mesh: before and after execute_coarsening_and_refinement().
    void
    prepare_refinement();
    void
    finish_refinement();

    /**
     * Solves for T with the flow's @p velocity (its viscosity at the
     * current T) and the contact nodes' friction work @p friction, the
     * metal's share of it (HeatParameters::friction_share_at()) a source at
     * the node; returns the largest change of T
     * in K. The flow keeps its temperatures until update_flow_temperatures().
     * A hardening law's factor (eps_0 + eps)^n multiplies the viscosity of
     * the plastic work as it does the flow's: @p hardening's cell factors
     * (a run in time) and point factors (the steady strain field, at the
     * flow's quadrature points: the temperature's degree must be the
     * velocity's, ProblemParameters' check).
     */
    double
    solve(const dealii::DoFHandler<dim> &                        flow_dofs,
          const dealii::Vector<double> &                         velocity,
          const std::vector<FrictionWork<dim>> &                 friction,
          const double                                           dt        = 0,
          const dealii::Vector<double> *                         cell_hardening  = nullptr,
          const std::vector<double> *                            point_hardening = nullptr);

    /**
     * In time (Heat/Model = transient) the mesh moves with the metal
     * (updated Lagrangian, the seed paper's incremental scheme): T's nodal
     * values move with their nodes, and a step from t_n to t_n + dt is
     * solve() with @p dt > 0, backward Euler on the mesh of t_n with the
     * flow of t_n:
     *   rho c (T - T_n)/dt - div(k grad T) = beta sigma:D,
     * no advection (the mesh velocity is the metal's) and so no SUPG; the
     * balance then has the heat stored in the step in place of the heat carried.
     */

    /**
     * Heat/Step coupling = trapezoid: the step from t_n made again on the
     * moved mesh (its cells are the step's first solve's), from T_n, with
     * the sources of the trapezoid rule: half those of the flow of t_n at
     * T_n (kept cell by cell and node by node from the step's first solve())
     * and half those of @p velocity, the flow of t_n+1, at the current T:
     *   rho c (T - T_n)/dt - div(k grad T) = (S_n + S_n+1)/2,
     * second order in dt where the sources are smooth in time (the first
     * solve alone is forward Euler in them). The balance is the step's:
     * the heat made is the sources' mean. Returns the largest change of T.
     */
    double
    correct_step(const dealii::DoFHandler<dim> &         flow_dofs,
                 const dealii::Vector<double> &          velocity,
                 const std::vector<FrictionWork<dim>> &  friction,
                 const double                            dt,
                 const dealii::Vector<double> *          cell_hardening = nullptr);
    /// Whether correct_step() can go on from the step's first solve (no new mesh since: the same cells).
    bool
    can_correct() const
    {
      return step_start.size() == dof_handler.n_dofs() && step_sources.cells.size() == triangulation.n_active_cells();
    }

    /// T at the nodes of a new mesh @p fresh of the same domain (MeshTransfer), before it replaces this one.
    dealii::Vector<double>
    on_new_mesh(const dealii::Triangulation<dim> &fresh, const std::string &when) const;
    /// The mesh has become the new one: its dofs, and T from on_new_mesh().
    void
    take_new_mesh(dealii::Vector<double> &&carried);
    /// The heat content int H(T) dx, H = int_0^T rho c (N mm, per mm of depth in plane strain), the volume
    /// and int T dx, with the geometry's weight.
    struct Integrals
    {
      double content = 0, volume = 0, temperature = 0;
    };
    Integrals
    integrals() const;
    /// Shifts T uniformly so that the heat content int H(T) dx becomes @p content (Newton on the shift, exact in one
    /// step for a constant rho c); returns the shift in K. Lagrange elements and hanging-node constraints keep constants.
    double
    restore_content(const double content);
    /// The record's extremes, mean and vertex values from the current T (at t = 0, after a new mesh).
    void
    record_state();

    /// Checkpoints: T (its dofs are those of the saved mesh's distribute_dofs()).
    template <class Archive>
    void
    save(Archive &ar) const
    {
      ar << temperature;
    }
    template <class Archive>
    void
    load(Archive &ar)
    {
      ar >> temperature;
    }
    /// Whether T is set on a mesh (false before the first setup, or after a checkpoint without T).
    bool
    has_temperature() const
    {
      return temperature.size() > 0;
    }
    /// T at a point of the metal (NaN if no cell holds it): the die profiles' column.
    double
    value_at(const dealii::Point<dim> &point) const;
    /// The heat flux density h (T - T_ambient) out through part @p id at @p T (0 where insulated), N/(mm s) = mW/mm^2.
    double
    wall_flux(const dealii::types::boundary_id id, const double T) const;

    /// Whether T (a checkpoint's) has as many values as this element has dofs on the mesh.
    bool
    temperature_fits() const;

    /// T at the flow's quadrature points (QGauss(velocity degree + 1), per active cell) from the current T.
    void
    update_flow_temperatures();
    /// What the flow assembly reads (FlowTerms::temperature).
    const std::vector<double> *
    flow_temperatures() const
    {
      return &point_temperature;
    }

    /// The temperature's range over the metal (K): what the coupling's change is measured against.
    double
    range() const;

    /// The last solve's record (balance, extremes, exit), the solve counts of the cycle set by the caller.
    const HeatRecord &
    record() const
    {
      return last;
    }
    HeatRecord &
    record()
    {
      return last;
    }

    unsigned int
    n_dofs() const
    {
      return dof_handler.n_dofs();
    }
    /// T at QGauss(@p points_per_direction)'s points of each active cell (values_at_points()).
    std::vector<double>
    values_at(const unsigned int points_per_direction) const
    {
      return values_at_points(dof_handler, temperature, points_per_direction);
    }

  private:
    /// The sources of a step in time as assembled (not weighted): each
    /// cell's beta sigma:D phi_i dx, each node's friction heat, and the
    /// plastic and friction work (N mm/s).
    struct StepSources
    {
      std::vector<dealii::Vector<double>>               cells;
      std::map<dealii::types::global_dof_index, double> nodes;
      double                                            plastic_work = 0, friction_work = 0;
    };
    /// solve() and correct_step(): from @p start (T_n; null: the current T)
    /// with the sources of the flow at the current T, and half of them and
    /// half @p earlier's if given.
    double
    solve_from(const dealii::DoFHandler<dim> &        flow_dofs,
               const dealii::Vector<double> &         velocity,
               const std::vector<FrictionWork<dim>> & friction,
               const double                           dt,
               const dealii::Vector<double> *         cell_hardening,
               const std::vector<double> *            point_hardening,
               const dealii::Vector<double> *         start,
               const StepSources *                    earlier);
    /// The balance and the outputs of the solution just found.
    void
    make_record(const dealii::DoFHandler<dim> &flow_dofs,
                const dealii::Vector<double> & velocity,
                const double                   friction_heat,
                const dealii::Vector<double> & previous,
                const double                   dt);

    const HeatParameters &             parameters;
    const Material &                   material;
    const CoordinateSystem<dim>        coordinates;
    const dealii::Triangulation<dim> & triangulation;
    const unsigned int                 flow_quadrature;
    const dealii::FE_Q<dim>            fe;
    dealii::DoFHandler<dim>            dof_handler;
    std::unique_ptr<dealii::FunctionParser<dim>> prescribed, exact;
    dealii::AffineConstraints<double>  constraints;
    dealii::SparsityPattern            sparsity;
    dealii::SparseMatrix<double>       matrix;
    dealii::Vector<double>             rhs;
    dealii::Vector<double>             temperature;
    std::vector<double>                point_temperature;
    std::unique_ptr<dealii::SolutionTransfer<dim, dealii::Vector<double>>> transfer;
    HeatRecord                         last;
    /// The last step's start T_n and its first solve's sources (correct_step()).
    dealii::Vector<double>             step_start;
    StepSources                        step_sources;
    /// A cell's rows of prescribed T summed: sum_j columns_j T_j - load is their reaction.
    struct PrescribedRows
    {
      std::vector<dealii::types::global_dof_index> dofs;
      std::vector<double>                          columns;
      double                                       load = 0;
    };
    std::vector<PrescribedRows> prescribed_rows;
    /// How much of a dof's row belongs to prescribed rows: 1 for a prescribed dof, a hanging node's weights on prescribed parents.
    double
    prescribed_weight(const dealii::types::global_dof_index dof) const;
  };
} // namespace dieflow

#endif
