// Krylov solves (CG or GMRES) preconditioned by Trilinos ML's algebraic multigrid, for the augmented-Lagrangian form; MPI on first use.
#include <dieflow/solvers/iterative_solver.h>

#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>

#include <mpi.h>

#include <cstdlib>

namespace dieflow
{
  MpiOnFirstUse::MpiOnFirstUse()
  {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (initialised)
      return;
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    std::atexit([]() {
      int finalised = 0;
      MPI_Finalized(&finalised);
      if (!finalised)
        MPI_Finalize();
    });
  }



  dealii::TrilinosWrappers::PreconditionAMG::AdditionalData
  velocity_amg_data(const std::vector<std::vector<bool>> &constant_modes, const bool higher_order)
  {
    dealii::TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic              = true;
    data.higher_order_elements = higher_order;
    data.smoother_sweeps       = 2;
    data.aggregation_threshold = 0.02;
    data.constant_modes        = constant_modes;
    return data;
  }



  void
  IterativeSolver::set_constant_modes(const std::vector<std::vector<bool>> &modes)
  {
    constant_modes = modes;
  }



  IterativeSolveInfo
  IterativeSolver::solve(const dealii::SparseMatrix<double> &matrix,
                         const bool                          symmetric,
                         const dealii::Vector<double> &      rhs,
                         dealii::Vector<double> &            solution,
                         const double                        tolerance,
                         const unsigned int                  max_iterations)
  {
    IterativeSolveInfo info;
    solution.reinit(rhs.size());
    const double target = tolerance * rhs.l2_norm();
    if (target == 0)
      {
        info.converged = true;
        return info;
      }

    preconditioner.initialize(matrix, velocity_amg_data(constant_modes, false));

    dealii::SolverControl control(max_iterations, target, false, false);
    try
      {
        if (symmetric)
          dealii::SolverCG<dealii::Vector<double>>(control).solve(matrix, solution, rhs, preconditioner);
        else
          {
            // Restarts every 50 vectors: enough for AMG-preconditioned
            // systems, and 50 vectors of 500,000 dofs are 200 MB.
            dealii::SolverGMRES<dealii::Vector<double>>::AdditionalData gmres(50, true);
            dealii::SolverGMRES<dealii::Vector<double>>(control, gmres).solve(matrix, solution, rhs, preconditioner);
          }
        info.converged = true;
      }
    catch (const dealii::SolverControl::NoConvergence &)
      {}
    info.iterations = control.last_step();
    return info;
  }
} // namespace dieflow
