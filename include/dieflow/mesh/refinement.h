// The deck's Refinement subsection, the error indicators per cell (Kelly's, the die criterion, both), and the marking of cells.
#ifndef dieflow_refinement_h
#define dieflow_refinement_h

#include <dieflow/base/parameters.h>

#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <set>
#include <string>
#include <vector>

namespace dieflow
{
  /// The deck's "Refinement" subsection.
  struct RefinementParameters
  {
    /// global: every cell; adaptive: the cells the indicator marks.
    enum class Strategy
    {
      global,
      adaptive
    };
    /// Kelly's indicator, the die criterion alone, Kelly's weighted by it,
    /// or goal-oriented towards the ram force.
    enum class Indicator
    {
      kelly,
      die,
      combined,
      dual_weighted
    };
    enum class Marking
    {
      fixed_fraction,
      fixed_number
    };
    unsigned int cycles          = 1;
    Strategy     strategy        = Strategy::global;
    Indicator    indicator       = Indicator::combined;
    Marking      marking         = Marking::fixed_fraction;
    double       refine_fraction  = 0.3;
    double       coarsen_fraction = 0;
    double       die_band        = 0;
    double       die_weight      = 1;
    unsigned int maximum_cells   = 0;
    /// Relative error at which the cycles stop (0: run every cycle), and
    /// the quantity of interest it applies to.
    double       target_error    = 0;
    std::string  target_quantity = "F_x[1]";
    /// Print and record the dual-weighted estimate of the force's error.
    bool         dual_weighted_estimate = false;

    /// Whether the run solves the dual problem of the ram force (its
    /// indicator, or its estimate printed).
    bool
    solves_dual() const
    {
      return indicator == Indicator::dual_weighted || dual_weighted_estimate;
    }

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };

  /**
   * Where the die needs cells, for the die criterion: the die's boundary ids
   * and the points where its solution is singular or changes character (the
   * die's corners, and the nodes where stick turns to slip or contact
   * opens).
   */
  template <int dim>
  struct DieFeatures
  {
    std::set<BoundaryId>            ids;
    std::vector<dealii::Point<dim>> hot_points;
  };

  /**
   * The error indicator per cell that the marking uses:
   *  - "kelly": eta_K, deal.II's Kelly estimator of the velocity (the jump
   *    of the normal derivative over the cell's faces);
   *  - "die": chi_K |K|, with chi_K = 2 for a cell with a hot point (a die
   *    corner, a stick-slip or contact-opening node) among its vertices,
   *    1 for a cell touching the die or within the die band, 0 elsewhere;
   *    the largest such cells are refined first;
   *  - "combined": eta_K (1 + w chi_K), the Kelly estimate weighted up at
   *    the die by the die weight w.
   */
  template <int dim>
  dealii::Vector<float>
  refinement_indicators(const RefinementParameters &    parameters,
                        const dealii::DoFHandler<dim> & dof_handler,
                        const dealii::Vector<double> &  velocity,
                        const DieFeatures<dim> &        die);

  /// Kelly's indicator eta_K of @p field on every active cell.
  template <int dim>
  dealii::Vector<float>
  kelly_indicators(const dealii::DoFHandler<dim> &dof_handler, const dealii::Vector<double> &field);

  /// Kelly's global estimate, sqrt(sum_K eta_K^2).
  template <int dim>
  double
  kelly_estimate(const dealii::DoFHandler<dim> &dof_handler, const dealii::Vector<double> &velocity);

  /// Sets the refine and coarsen flags of the triangulation from @p indicators.
  template <int dim>
  void
  mark_cells(const RefinementParameters & parameters,
             const dealii::Vector<float> &indicators,
             dealii::Triangulation<dim> & triangulation);

  /// Share of the active cells that have a face on one of @p ids.
  template <int dim>
  double
  share_of_cells_at(const dealii::Triangulation<dim> &triangulation, const std::set<BoundaryId> &ids);
} // namespace dieflow

#endif
