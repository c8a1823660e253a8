// The Refinement entries no deck test sets, each against a count or a ratio
// worked out apart. On a box of 8 x 4 unit cells whose bottom (id 2) is the
// die: Die band = 1.6 (mm) makes the die criterion chi = 1 on the cells
// whose centre lies within 1.6 of a die face's centre, the two bottom rows
// (centres at y = 0.5 and 1.5; the third row's at 2.5), 16 cells, each with
// the die indicator chi |K| = 1; the default (0) only the row touching the
// die, 8. Die weight = 3 scales Kelly's indicator by 1 + 3 chi in the
// combined indicator: by exactly 4 on those 16 cells, 1 elsewhere (Kelly's
// indicator of a quadratic field, nonzero on every cell). Coarsen fraction
// = 0.5 with Marking = fixed number and the indicator y_K on the box refined
// once from 4 x 2 cells: the 16 cells of the two bottom rows (the 4
// children of each bottom parent) are flagged and coarsened, 32 -> 20
// cells; the default (0) coarsens nothing.
#include <dieflow/mesh/refinement.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/numerics/vector_tools.h>

#include "report.h"

#include <cmath>

using namespace dieflow;

namespace
{
  RefinementParameters
  parsed(const std::string &entries)
  {
    ParameterHandler prm;
    RefinementParameters::declare_parameters(prm);
    prm.parse_input_from_string("subsection Refinement\n" + entries + "end\n");
    RefinementParameters parameters;
    parameters.parse_parameters(prm);
    return parameters;
  }

  class Quadratic : public dealii::Function<2>
  {
  public:
    Quadratic()
      : dealii::Function<2>(2)
    {}
    double
    value(const dealii::Point<2> &p, const unsigned int component) const override
    {
      return component == 0 ? p[0] * p[0] + p[1] * p[1] : p[0] * p[1] + p[1] * p[1];
    }
  };
} // namespace

int
main()
{
  dealii::Triangulation<2> box;
  dealii::GridGenerator::subdivided_hyper_rectangle(box, {8, 4}, dealii::Point<2>(0, 0), dealii::Point<2>(8, 4), true);
  const dealii::FESystem<2> fe(dealii::FE_Q<2>(1), 2);
  dealii::DoFHandler<2>     dofs(box);
  dofs.distribute_dofs(fe);
  dealii::Vector<double> velocity(dofs.n_dofs());
  dealii::VectorTools::interpolate(dofs, Quadratic(), velocity);
  DieFeatures<2> die;
  die.ids = {2};

  // Die band.
  const auto   count_die_cells = [&](const RefinementParameters &p, double &largest) {
    const auto   chi   = refinement_indicators(p, dofs, velocity, die);
    unsigned int count = 0;
    largest            = 0;
    for (const auto &cell : box.active_cell_iterators())
      if (chi[cell->active_cell_index()] != 0)
        {
          ++count;
          largest = std::max(largest, std::abs(chi[cell->active_cell_index()] - cell->measure()));
        }
    return count;
  };
  double             off      = 0;
  const unsigned int in_band  = count_die_cells(parsed("set Indicator = die\nset Die band = 1.6\n"), off);
  report("Die band = 1.6: the die criterion on the 16 cells of the two bottom rows, chi |K| = 1 each",
         in_band == 16 && off == 0);
  const unsigned int touching = count_die_cells(parsed("set Indicator = die\n"), off);
  report("Die band = 0 (default): on the 8 cells touching the die", touching == 8 && off == 0);

  // Die weight.
  const auto kelly    = refinement_indicators(parsed("set Indicator = kelly\n"), dofs, velocity, die);
  const auto combined = refinement_indicators(parsed("set Indicator = combined\nset Die band = 1.6\nset Die weight = 3\n"),
                                              dofs, velocity, die);
  bool ratios = true, positive = true;
  for (const auto &cell : box.active_cell_iterators())
    {
      const unsigned int i = cell->active_cell_index();
      positive &= kelly[i] > 0;
      ratios &= std::abs(combined[i] / kelly[i] - (cell->center()[1] < 1.6 ? 4. : 1.)) < 1e-6;
    }
  report("Die weight = 3: the combined indicator is Kelly's times 4 in the band and Kelly's elsewhere",
         positive && ratios);

  // Coarsen fraction.
  const auto cells_after = [](const std::string &entries) {
    dealii::Triangulation<2> tria;
    dealii::GridGenerator::subdivided_hyper_rectangle(tria, {4, 2}, dealii::Point<2>(0, 0), dealii::Point<2>(8, 4));
    tria.refine_global(1);
    dealii::Vector<float> indicators(tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      indicators[cell->active_cell_index()] = cell->center()[1];
    mark_cells(parsed("set Strategy = adaptive\nset Marking = fixed number\nset Refine fraction = 0\n" + entries),
               indicators,
               tria);
    tria.execute_coarsening_and_refinement();
    return tria.n_active_cells();
  };
  report("Coarsen fraction = 0.5: the two bottom rows' 4 parents coarsened, 32 -> 20 cells",
         cells_after("set Coarsen fraction = 0.5\n") == 20);
  report("Coarsen fraction = 0 (default): nothing coarsened, 32 cells", cells_after("") == 32);
}
