// The deck's Refinement subsection, the error indicators per cell (Kelly's, the die criterion, both), and the marking of cells.
#include <dieflow/mesh/refinement.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>
#include <deal.II/fe/fe.h>
#include <deal.II/grid/grid_refinement.h>
#include <deal.II/numerics/error_estimator.h>

#include <cmath>
#include <map>

namespace dieflow
{
  void
  RefinementParameters::declare_parameters(ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Refinement");
    prm.declare_entry("Cycles",
                      "1",
                      Integer(1, 40),
                      "Number of solve-refine cycles; each cycle starts from the "
                      "previous solution transferred to the new mesh, and the study "
                      "table has a row per cycle.");
    prm.declare_entry("Strategy",
                      "global",
                      Selection("global|adaptive"),
                      "global: refine every cell between cycles. adaptive: refine "
                      "(and coarsen) the cells the indicator marks.");
    prm.declare_entry("Indicator",
                      "combined",
                      Selection("kelly|die|combined|dual weighted"),
                      "kelly: deal.II's Kelly estimator of the velocity. die: cells "
                      "at the die (touching the contact ids or within the die band), "
                      "twice as strongly at its corners and where stick turns to "
                      "slip or contact opens, largest first. combined: Kelly "
                      "weighted up at the die by (1 + die weight x die criterion). "
                      "dual weighted: goal-oriented, aimed at the force F_x of the "
                      "Target quantity's part (else of the first prescribed-velocity "
                      "part): Kelly's indicator of the velocity times Kelly's "
                      "indicator of the dual solution of that force (the adjoint of "
                      "the converged linearised problem with the contact states "
                      "frozen: one more solve with the last factorisation; see also "
                      "Dual-weighted estimate). Use it with Marking = "
                      "fixed fraction and Refine fraction = 0.9, or fixed number and "
                      "0.15: the product is concentrated in few cells.");
    prm.declare_entry("Marking",
                      "fixed fraction",
                      Selection("fixed fraction|fixed number"),
                      "fixed fraction: refine the cells that carry the Refine "
                      "fraction of the total indicator (coarsen those that carry the "
                      "Coarsen fraction). fixed number: refine that fraction of the "
                      "cells (coarsen that fraction), largest indicators first.");
    prm.declare_entry("Refine fraction",
                      "0.3",
                      Double(0, 1),
                      "Fraction for the marking (see Marking).");
    prm.declare_entry("Coarsen fraction",
                      "0",
                      Double(0, 1),
                      "Fraction for coarsening (0: none).");
    prm.declare_entry("Die band",
                      "0",
                      Double(0),
                      "Width (mm) of the band along the die whose cells the die "
                      "criterion marks; 0: the cells touching the die.");
    prm.declare_entry("Die weight",
                      "1",
                      Double(0),
                      "Weight w of the die criterion in the combined indicator.");
    prm.declare_entry("Maximum cells",
                      "0",
                      Integer(0),
                      "Stop refining beyond about this many cells (0: no limit); "
                      "with a Target error, the run stops here and says that the "
                      "target was not reached.");
    prm.declare_entry("Target error",
                      "0",
                      Double(0, 1),
                      "Relative error (0.001 = 0.1 %) at which the cycles stop: "
                      "after each cycle from the third on, the estimated error of "
                      "the Target quantity (from the changes over the last cycles, "
                      "see the study table) is compared with it. Cycles is then the "
                      "most cycles to run. 0: run all Cycles.");
    prm.declare_entry("Target quantity",
                      "F_x[1]",
                      Anything(),
                      "The quantity of interest the Target error applies to: "
                      "F_x[id] (the force along x on a prescribed-velocity part; "
                      "F_x[1] is die2d's ram force), F_n[id] or F_t[id] (the "
                      "normal or friction force on a die id), or v_x(probe).");
    prm.declare_entry("Dual-weighted estimate",
                      "false",
                      Bool(),
                      "Also estimate the error of the force F_x of the Target "
                      "quantity's part (else of the first prescribed-velocity part) "
                      "by the dual-weighted residual (deal.II step-14): the adjoint "
                      "problem with the contact states frozen, solved with velocity "
                      "degree + 1 on the same mesh. The log and summary.json "
                      "(dual_weighted_error) give it; the +- of the results stays "
                      "the estimate from the cycles, which doc/benchmarks.md found "
                      "the more honest on die2d. Costs about three Newton iterations.");
    prm.leave_subsection();
  }



  void
  RefinementParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Refinement");
    cycles           = prm.get_integer("Cycles");
    strategy         = prm.get("Strategy") == "adaptive" ? Strategy::adaptive : Strategy::global;
    const std::string indicator_name = prm.get("Indicator");
    indicator        = indicator_name == "kelly"         ? Indicator::kelly :
                       indicator_name == "die"           ? Indicator::die :
                       indicator_name == "dual weighted" ? Indicator::dual_weighted :
                                                           Indicator::combined;
    marking          = prm.get("Marking") == "fixed number" ? Marking::fixed_number : Marking::fixed_fraction;
    refine_fraction  = prm.get_double("Refine fraction");
    coarsen_fraction = prm.get_double("Coarsen fraction");
    die_band         = prm.get_double("Die band");
    die_weight       = prm.get_double("Die weight");
    maximum_cells    = prm.get_integer("Maximum cells");
    target_error     = prm.get_double("Target error");
    target_quantity  = dealii::Utilities::trim(prm.get("Target quantity"));
    dual_weighted_estimate = prm.get_bool("Dual-weighted estimate");
    require(target_error == 0 || cycles >= 3,
            "Refinement/Cycles",
            "must be at least 3 with a Target error (the estimate needs three cycles); it is the most "
            "cycles the run may take");
    require(refine_fraction + coarsen_fraction <= 1,
            "Refinement/Coarsen fraction",
            "and Refine fraction together exceed 1");
    prm.leave_subsection();
  }



  template <int dim>
  dealii::Vector<float>
  kelly_indicators(const dealii::DoFHandler<dim> &dof_handler, const dealii::Vector<double> &field)
  {
    dealii::Vector<float> eta(dof_handler.get_triangulation().n_active_cells());
    dealii::KellyErrorEstimator<dim>::estimate(dof_handler, dealii::QGauss<dim - 1>(dof_handler.get_fe().degree + 1), {}, field, eta);
    return eta;
  }



  template <int dim>
  double
  kelly_estimate(const dealii::DoFHandler<dim> &dof_handler, const dealii::Vector<double> &velocity)
  {
    return kelly_indicators(dof_handler, velocity).l2_norm();
  }



  namespace
  {
    /// chi_K of the die criterion.
    template <int dim>
    dealii::Vector<float>
    die_criterion(const RefinementParameters &   parameters,
                  const dealii::Triangulation<dim> &triangulation,
                  const DieFeatures<dim> &       die)
    {
      dealii::Vector<float> chi(triangulation.n_active_cells());
      if (die.ids.empty())
        return chi;

      // Vertices of the die faces, for the band test.
      std::vector<dealii::Point<dim>> die_points;
      for (const auto &face : triangulation.active_face_iterators())
        if (face->at_boundary() && die.ids.count(face->boundary_id()))
          die_points.push_back(face->center());

      for (const auto &cell : triangulation.active_cell_iterators())
        {
          float value = 0;
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary() && die.ids.count(cell->face(f)->boundary_id()))
              value = 1;
          if (value == 0 && parameters.die_band > 0)
            for (const auto &p : die_points)
              if (cell->center().distance(p) <= parameters.die_band)
                {
                  value = 1;
                  break;
                }
          for (const unsigned int v : cell->vertex_indices())
            for (const auto &hot : die.hot_points)
              if (cell->vertex(v).distance(hot) < 1e-9 * cell->diameter())
                value = 2;
          chi[cell->active_cell_index()] = value;
        }
      return chi;
    }
  } // namespace



  template <int dim>
  dealii::Vector<float>
  refinement_indicators(const RefinementParameters &   parameters,
                        const dealii::DoFHandler<dim> &dof_handler,
                        const dealii::Vector<double> & velocity,
                        const DieFeatures<dim> &       die)
  {
    const auto &          triangulation = dof_handler.get_triangulation();
    dealii::Vector<float> indicator(triangulation.n_active_cells());
    const auto            chi = die_criterion(parameters, triangulation, die);
    if (parameters.indicator == RefinementParameters::Indicator::die)
      {
        for (const auto &cell : triangulation.active_cell_iterators())
          indicator[cell->active_cell_index()] = chi[cell->active_cell_index()] * cell->measure();
        return indicator;
      }
    indicator = kelly_indicators(dof_handler, velocity);
    if (parameters.indicator == RefinementParameters::Indicator::combined)
      for (unsigned int i = 0; i < indicator.size(); ++i)
        indicator[i] *= 1 + parameters.die_weight * chi[i];
    return indicator;
  }



  template <int dim>
  void
  mark_cells(const RefinementParameters & parameters,
             const dealii::Vector<float> &indicators,
             dealii::Triangulation<dim> & triangulation)
  {
    const unsigned int max_cells =
      parameters.maximum_cells > 0 ? parameters.maximum_cells : std::numeric_limits<unsigned int>::max();
    if (parameters.marking == RefinementParameters::Marking::fixed_fraction)
      dealii::GridRefinement::refine_and_coarsen_fixed_fraction(
        triangulation, indicators, parameters.refine_fraction, parameters.coarsen_fraction, max_cells);
    else
      dealii::GridRefinement::refine_and_coarsen_fixed_number(
        triangulation, indicators, parameters.refine_fraction, parameters.coarsen_fraction, max_cells);
    // A cell the indicator does not point at at all is not refined (the die
    // criterion is zero away from the die, and a fixed number of cells would
    // otherwise take such cells too).
    for (const auto &cell : triangulation.active_cell_iterators())
      if (indicators[cell->active_cell_index()] == 0)
        cell->clear_refine_flag();
  }



  template <int dim>
  double
  share_of_cells_at(const dealii::Triangulation<dim> &triangulation, const std::set<BoundaryId> &ids)
  {
    unsigned int at = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() && ids.count(cell->face(f)->boundary_id()))
          {
            ++at;
            break;
          }
    return static_cast<double>(at) / triangulation.n_active_cells();
  }

  template struct DieFeatures<2>;
  template dealii::Vector<float>
  refinement_indicators<2>(const RefinementParameters &, const dealii::DoFHandler<2> &,
                           const dealii::Vector<double> &, const DieFeatures<2> &);
  template dealii::Vector<float>
  kelly_indicators<2>(const dealii::DoFHandler<2> &, const dealii::Vector<double> &);
  template double
  kelly_estimate<2>(const dealii::DoFHandler<2> &, const dealii::Vector<double> &);
  template void
  mark_cells<2>(const RefinementParameters &, const dealii::Vector<float> &, dealii::Triangulation<2> &);
  template double
  share_of_cells_at<2>(const dealii::Triangulation<2> &, const std::set<BoundaryId> &);
  template struct DieFeatures<3>;
  template dealii::Vector<float>
  refinement_indicators<3>(const RefinementParameters &, const dealii::DoFHandler<3> &,
                           const dealii::Vector<double> &, const DieFeatures<3> &);
  template dealii::Vector<float>
  kelly_indicators<3>(const dealii::DoFHandler<3> &, const dealii::Vector<double> &);
  template double
  kelly_estimate<3>(const dealii::DoFHandler<3> &, const dealii::Vector<double> &);
  template void
  mark_cells<3>(const RefinementParameters &, const dealii::Vector<float> &, dealii::Triangulation<3> &);
  template double
  share_of_cells_at<3>(const dealii::Triangulation<3> &, const std::set<BoundaryId> &);
} // namespace dieflow
