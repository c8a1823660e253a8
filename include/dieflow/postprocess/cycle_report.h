// The report of a converged cycle: forces, fluxes, checks, errors, quantities of interest and the output files, from a read-only view of the solution.
#ifndef dieflow_cycle_report_h
#define dieflow_cycle_report_h

#include <dieflow/base/archive.h>
#include <dieflow/contact/contact_set.h>
#include <dieflow/flow/boundary_conditions.h>
#include <dieflow/flow/flow_assembler.h>
#include <dieflow/flow/incompressibility.h>
#include <dieflow/flow/material.h>
#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/mesh/wall_nodes.h>
#include <dieflow/postprocess/summary.h>

#include <deal.II/base/function.h>
#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace dieflow
{
  /// What the report of a cycle reads: the converged solution and what gives it meaning, all read-only.
  template <int dim>
  struct SolutionView
  {
    const CoordinateSystem<dim> &     coordinates;
    const Material &                  material;
    const BoundaryConditions<dim> &   boundary_conditions;
    const DoFHandler<dim> &           dof_handler;
    const AffineConstraints<double> & hanging_node_constraints;
    const AffineConstraints<double> & update_constraints;
    const std::vector<WallNode<dim>> &wall_nodes;
    const Vector<double> &            velocity;
    /// The flow terms and what they read (the reactions are their residual).
    const FlowAssembler<dim> &        flow;
    const FlowTerms<dim>              terms;
    const Incompressibility<dim> &    incompressibility;
    const ContactSet<dim> &           contact;
    /// A run in time: the equivalent strain per active cell (else null).
    const Vector<double> *            equivalent_strain;
    /// The temperature's record (Heat/Model), or null: isothermal.
    const HeatRecord *                heat;
    /// The temperature field (for the die profiles), or null: isothermal.
    const HeatEquation<dim> *         temperature;
    /// The steady equivalent strain field's record, or null.
    const StrainRecord *              strain;
    /// The steady equivalent strain field (for the dual-weighted estimate's stresses), or null.
    const StrainField<dim> *          strain_field;
  };

  /// How a run reports: where its files go, which, and its quantities of interest.
  template <int dim>
  struct ReportSettings
  {
    std::string output_directory;
    bool        write_vtu      = true;
    bool        write_gnuplot  = false;
    bool        write_mesh_svg = false;
    /// Refinement/Dual-weighted estimate, of the force F_x on goal_part.
    bool       dual_weighted_estimate = false;
    BoundaryId goal_part              = 1;
    /// Verification/Exact velocity (null: none) and Refinement/Probe point.
    const dealii::Function<dim> *     exact_velocity = nullptr;
    std::optional<dealii::Point<dim>> probe;
  };

  /**
   * The report of a converged cycle (interface.md's summary.json): cells
   * and dofs; the fluxes and each part's area; the forces on the boundary
   * parts from the reactions (boundary_forces()), with the dies' shares of
   * the nodes they share with prescribed-velocity parts; the divergence
   * ratio and the mass balance; the penalty and its viscosity; Kelly's
   * estimate and, if asked, the dual-weighted estimate of the ram force;
   * the errors against an exact velocity; the contact's forces, lengths
   * and checks (summarise_contact()) and its die profiles; the quantities
   * of interest; and the fields (VTU, gnuplot) and the mesh (SVG).
   * It reads the solution through a SolutionView and writes into the
   * summary and the output directory only; the PVD index of the fields
   * written so far is its own state (saved and loaded with checkpoints).
   */
  template <int dim>
  class CycleReport
  {
  public:
    CycleReport(const ReportSettings<dim> &settings, std::ostream &log);

    /**
     * Fills @p summary (whose cycle number is set) from @p view; writes the
     * fields where @p write_fields, indexed at @p record_time (the cycle,
     * or the time of a step).
     */
    void
    report(const SolutionView<dim> &view, const bool write_fields, const double record_time, CycleSummary &summary);

    /// The PVD index into a checkpoint, and back.
    void
    save(OutputArchive &ar) const;
    void
    load(InputArchive &ar);

  private:
    const ReportSettings<dim>                   settings;
    std::ostream &                              log;
    std::vector<std::pair<double, std::string>> pvd_records;
  };
} // namespace dieflow

#endif
