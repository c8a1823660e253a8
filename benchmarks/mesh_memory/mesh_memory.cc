// What the replicated mesh and matrix cost per cell: triangulation, DoFHandler (velocity Q_k^dim), sparsity pattern and matrix values (8 bytes per entry).
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <iostream>
#include <cstdlib>

using namespace dealii;

template <int dim>
void
measure(const unsigned int n, const unsigned int degree)
{
  Triangulation<dim> tria;
  std::vector<unsigned int> reps(dim, n);
  Point<dim> p0, p1;
  for (unsigned int d = 0; d < dim; ++d)
    p1[d] = 1;
  GridGenerator::subdivided_hyper_rectangle(tria, reps, p0, p1);
  FESystem<dim>   fe(FE_Q<dim>(degree), dim);
  DoFHandler<dim> dof(tria);
  dof.distribute_dofs(fe);
  AffineConstraints<double> constraints;
  DoFTools::make_hanging_node_constraints(dof, constraints);
  constraints.close();
  DynamicSparsityPattern dsp(dof.n_dofs());
  DoFTools::make_sparsity_pattern(dof, dsp, constraints, false);
  SparsityPattern sp;
  sp.copy_from(dsp);
  const double cells = tria.n_active_cells();
  std::cout << dim << "D degree " << degree << ": " << tria.n_active_cells() << " cells, " << dof.n_dofs()
            << " dofs; bytes per cell: triangulation " << tria.memory_consumption() / cells << ", DoFHandler "
            << dof.memory_consumption() / cells << ", sparsity " << sp.memory_consumption() / cells << ", matrix values "
            << 8. * sp.n_nonzero_elements() / cells << std::endl;
}

int
main(int argc, char **argv)
{
  const unsigned int n2 = argc > 1 ? std::atoi(argv[1]) : 200, n3 = argc > 2 ? std::atoi(argv[2]) : 30;
  for (unsigned int degree = 1; degree <= 2; ++degree)
    {
      measure<2>(n2, degree);
      measure<3>(n3, degree);
    }
}
