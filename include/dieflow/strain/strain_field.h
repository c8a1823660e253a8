// The metal's equivalent strain as a steady field on the flow's mesh: v.grad eps = epsdot_eq, for strain hardening in steady runs.
#ifndef dieflow_strain_field_h
#define dieflow_strain_field_h

#include <dieflow/base/parameters.h>
#include <dieflow/flow/material.h>
#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/mesh/scalar_field.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/solution_transfer.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dieflow
{
  /// The deck's Equivalent strain subsection.
  struct StrainParameters
  {
    /// Whether the field is asked for; a steady run whose law hardens solves it anyway (ProblemParameters::steady_strain()).
    bool requested = false;
    /// The strain the metal brings where it enters (an earlier pass).
    double inlet_strain = 0;
    /// For tests: the exact eps (an expression, or empty), against which the errors are reported.
    std::string exact_strain;
    /// The most strain solves per cycle (each followed by the flow at the new hardening), and when they have settled.
    unsigned int coupling_iterations = 20;
    double       coupling_tolerance  = 3e-3;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /// What the strain field of a cycle reports (summary.json "strain").
  struct StrainRecord
  {
    /// Strain solves made, and whether the last changed eps by less than the Coupling tolerance.
    unsigned int solves  = 0;
    bool         settled = false;
    /// The last solve's change of eps, root mean square over the metal.
    double last_change = 0;
    /// The largest eps over the metal (nodal), and where the metal leaves:
    /// its mean weighted by the outflow v.n > 0 and its range over the faces
    /// that carry the outflow (mean v.n above half their mean speed).
    double eps_max = 0, eps_exit = 0, eps_exit_min = 0, eps_exit_max = 0;
    /// The hardening factor (eps_0 + eps)^n over the flow's points (1 without hardening).
    double hardening_min = 1, hardening_max = 1;
    /// Against Equivalent strain/Exact strain: ||eps_h - eps||_L2 (2 pi r in the axisymmetric geometry) and the largest nodal error.
    std::optional<double> l2_error, nodal_error;
    /// eps at the mesh's vertices (for the VTU).
    std::vector<double> vertex_strain;
  };

  /**
   * The equivalent strain of the metal in a steady flow (Eulerian): along
   * each streamline eps grows at the equivalent strain rate of the paper's
   * eq. (4), so that
   *   v.grad eps = epsdot_eq = sqrt(2/3 D:D),     eps = eps_in where v.n < 0,
   * a first-order hyperbolic problem. Continuous Q_k elements (k the
   * velocity's degree); SUPG (Brooks, Hughes 1982) with tau = h/(2|v|), the
   * limit of HeatEquation's tau without diffusion; the inflow condition
   * weakly, int_{v.n<0} |v.n| (eps - eps_in) w ds, which with the advection
   * term makes the form coercive (its symmetric part is the boundary's
   * 1/2 int |v.n| eps^2 for div v = 0). Exact along straight streamlines:
   * the sink flow of a conical die has eps = 2 ln(rho_0/rho) (spherical, the
   * axisymmetric die) and 2/sqrt(3) ln(rho_0/rho) (plane strain). The flow
   * reads the hardening factor (eps_0 + eps)^n at its quadrature points
   * (flow_hardening(), Material::hardening()).
   */
  template <int dim>
  class StrainField
  {
  public:
    StrainField(const StrainParameters &          parameters,
                const Material &                  material,
                const CoordinateSystem<dim> &     coordinates,
                const dealii::Triangulation<dim> &triangulation,
                const unsigned int                velocity_degree);

    /// The dofs and the matrix of the current mesh; eps = eps_in on the first.
    void
    setup();
    /// Carries eps through a refinement of the mesh: before and after execute_coarsening_and_refinement().
    void
    prepare_refinement();
    void
    finish_refinement();

    /**
     * Solves for eps with the flow's @p velocity; returns the change of eps
     * (its root mean square over the metal: the largest nodal change sits
     * at a corner's singular strain and jitters there). With @p relax (the coupling's later solves on one
     * mesh) the new eps is the last one plus omega times the change, omega
     * by Aitken's rule (Irons, Tuck 1969; Kuttler, Wall 2008) from the last
     * two changes: the fixed point of flow and hardening, which oscillates
     * about its limit, is reached in fewer flow solves. The change
     * returned is the unrelaxed one (the fixed point's residual).
     */
    double
    solve(const dealii::DoFHandler<dim> &flow_dofs, const dealii::Vector<double> &velocity, const bool relax = false);

    /// The hardening factor at the flow's quadrature points (QGauss(velocity degree + 1), per active cell) from the current eps,
    /// at the temperatures there (set_flow_temperatures(); Material/Temperature without them).
    void
    update_flow_hardening();
    /// The temperatures at the flow's quadrature points that the hardening factor reads (HeatEquation::flow_temperatures()).
    void
    set_flow_temperatures(const std::vector<double> *temperatures)
    {
      flow_temperatures = temperatures;
    }
    /// What the flow assembly reads (FlowTerms::point_hardening).
    const std::vector<double> *
    flow_hardening() const
    {
      return &point_hardening;
    }
    /// sqrt(int f^2 dx / int dx) over the metal (2 pi r dx in the axisymmetric geometry).
    double
    root_mean_square(const dealii::Vector<double> &field) const;
    /// eps's own root mean square over the metal: what the coupling's change is measured against.
    double
    root_mean_square() const
    {
      return root_mean_square(strain);
    }

    const StrainRecord &
    record() const
    {
      return last;
    }
    StrainRecord &
    record()
    {
      return last;
    }
    unsigned int
    n_dofs() const
    {
      return dof_handler.n_dofs();
    }
    /// The hardening factor at QGauss(@p points_per_direction)'s points of each active cell (indexed as
    /// values_at_points()) from the current eps, at @p temperatures there (Material/Temperature when null or of another size).
    std::vector<double>
    hardening_at(const unsigned int points_per_direction, const std::vector<double> *temperatures) const;

  private:
    /// The exit, the extremes, the errors and the vertex values of the solution just found.
    void
    make_record(const dealii::DoFHandler<dim> &flow_dofs, const dealii::Vector<double> &velocity);

    const StrainParameters &                     parameters;
    const Material &                             material;
    const CoordinateSystem<dim>                  coordinates;
    const dealii::Triangulation<dim> &           triangulation;
    const unsigned int                           flow_quadrature;
    const dealii::FE_Q<dim>                      fe;
    dealii::DoFHandler<dim>                      dof_handler;
    std::unique_ptr<dealii::FunctionParser<dim>> exact;
    dealii::AffineConstraints<double>            constraints;
    dealii::SparsityPattern                      sparsity;
    dealii::SparseMatrix<double>                 matrix;
    dealii::Vector<double>                       rhs;
    dealii::Vector<double>                       strain;
    std::vector<double>                          point_hardening;
    const std::vector<double> *                  flow_temperatures = nullptr;
    std::unique_ptr<dealii::SolutionTransfer<dim, dealii::Vector<double>>> transfer;
    StrainRecord                                 last;
    /// The last solve's change G(eps) - eps and its relaxation factor (Aitken), for relaxed solves.
    dealii::Vector<double> last_residual;
    double                 omega = 1;
  };
} // namespace dieflow

#endif
