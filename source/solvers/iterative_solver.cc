// Krylov solves (CG or GMRES) preconditioned by Trilinos ML's algebraic multigrid, for the augmented-Lagrangian form, on one process or across several; MPI on first use.
#include <dieflow/solvers/iterative_solver.h>

#include <dieflow/base/processes.h>

#include <deal.II/base/timer.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/trilinos_vector.h>

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



  namespace
  {
    /// CG (@p symmetric) or GMRES on @p matrix x = @p rhs from x = 0, to |r| <= @p target.
    template <typename Matrix, typename VectorType>
    IterativeSolveInfo
    krylov(const Matrix &                                   matrix,
           const bool                                       symmetric,
           const VectorType &                               rhs,
           VectorType &                                     solution,
           const dealii::TrilinosWrappers::PreconditionAMG &preconditioner,
           const double                                     target,
           const unsigned int                               max_iterations)
    {
      IterativeSolveInfo    info;
      dealii::SolverControl control(max_iterations, target, false, false);
      try
        {
          if (symmetric)
            dealii::SolverCG<VectorType>(control).solve(matrix, solution, rhs, preconditioner);
          else
            {
              // Restarts every 50 vectors: enough for AMG-preconditioned
              // systems, and 50 vectors of 500,000 dofs are 200 MB.
              typename dealii::SolverGMRES<VectorType>::AdditionalData gmres(50, true);
              dealii::SolverGMRES<VectorType>(control, gmres).solve(matrix, solution, rhs, preconditioner);
            }
          info.converged = true;
        }
      catch (const dealii::SolverControl::NoConvergence &)
        {}
      info.iterations = control.last_step();
      return info;
    }
  } // namespace



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

    if (processes::n() > 1)
      return solve_across_processes(matrix, symmetric, rhs, solution, target, max_iterations);
    const dealii::Timer setup;
    preconditioner.initialize(matrix, velocity_amg_data(constant_modes, false));
    const double setup_seconds = setup.wall_time();
    info                       = krylov(matrix, symmetric, rhs, solution, preconditioner, target, max_iterations);
    info.setup_seconds         = setup_seconds;
    return info;
  }



  IterativeSolveInfo
  IterativeSolver::solve_across_processes(const dealii::SparseMatrix<double> &matrix,
                                          const bool                          symmetric,
                                          const dealii::Vector<double> &      rhs,
                                          dealii::Vector<double> &            solution,
                                          const double                        target,
                                          const unsigned int                  max_iterations)
  {
    const dealii::IndexSet rows = processes::owned_rows(matrix.m());
    // The operator as it is (no entry dropped: the Krylov method multiplies
    // with it), its pattern made afresh: on a pattern it knows, Trilinos's
    // copy would keep the old value where the new one is zero.
    const dealii::Timer setup;
    preconditioner.clear();
    distributed_matrix.clear();
    distributed_matrix.reinit(rows, rows, matrix, processes::communicator(), 0.);
    preconditioner.initialize(distributed_matrix, velocity_amg_data(constant_modes, false));
    const double setup_seconds = setup.wall_time();
    dealii::TrilinosWrappers::MPI::Vector b(rows, processes::communicator()), x(b);
    for (const auto row : rows)
      b[row] = rhs[row];
    b.compress(dealii::VectorOperation::insert);
    IterativeSolveInfo info = krylov(distributed_matrix, symmetric, b, x, preconditioner, target, max_iterations);
    info.setup_seconds      = setup_seconds;
    for (const auto row : rows)
      solution[row] = x[row];
    processes::gather(solution);
    return info;
  }
} // namespace dieflow
