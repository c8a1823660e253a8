// The direct solve of the Newton system across MPI processes: MUMPS through PETSc, each process owning a block of rows.
#include <dieflow/base/processes.h>
#include <dieflow/solvers/distributed_direct_solver.h>
#include <dieflow/solvers/linear_solver.h>

#include <deal.II/base/mpi.h>

#include <petscksp.h>

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dieflow
{
  namespace
  {
    /// A PETSc call that failed, perhaps on this process alone while the
    /// others wait in a collective: not a SolverFailure (which a process
    /// would handle by itself, the others waiting for ever) but an internal
    /// error, which ends the run on every process (MPI_Abort, run.cc).
    void
    check(const PetscErrorCode error, const char *what)
    {
      if (error != 0)
        {
          const char *text = nullptr;
          PetscErrorMessage(error, &text, nullptr);
          throw std::runtime_error(std::string("PETSc ") + what + " failed in the distributed direct solve: " +
                                   (text != nullptr ? text : "error " + std::to_string(error)));
        }
    }
  } // namespace



  struct DistributedDirectSolver::Petsc
  {
    Mat      matrix    = nullptr;
    KSP      ksp       = nullptr;
    PetscInt first_row = 0, last_row = 0, size = 0;
    bool     factorised = false;

    ~Petsc()
    {
      // Destroying MUMPS's instance is collective: while an exception
      // unwinds one process, the others may wait elsewhere (the process is
      // ended by MPI_Abort, run.cc).
      if (std::uncaught_exceptions() > 0)
        return;
      if (ksp != nullptr)
        KSPDestroy(&ksp);
      if (matrix != nullptr)
        MatDestroy(&matrix);
    }

    /// The PETSc matrix of @p a's pattern, this process's rows preallocated exactly.
    void
    create(const dealii::SparseMatrix<double> &a)
    {
      // The rows the matrix's sums are in (processes::RowSums).
      size      = static_cast<PetscInt>(a.m());
      first_row = static_cast<PetscInt>(processes::first_owned_row(a.m(), 1, processes::rank()));
      last_row  = static_cast<PetscInt>(processes::first_owned_row(a.m(), 1, processes::rank() + 1));
      std::vector<PetscInt> diagonal(last_row - first_row), off_diagonal(last_row - first_row);
      for (PetscInt row = first_row; row < last_row; ++row)
        for (auto entry = a.begin(row); entry != a.end(row); ++entry)
          {
            const auto column = static_cast<PetscInt>(entry->column());
            ++(column >= first_row && column < last_row ? diagonal : off_diagonal)[row - first_row];
          }
      const PetscInt local = last_row - first_row;
      check(MatCreateAIJ(processes::communicator(), local, local, size, size, 0, diagonal.data(), 0, off_diagonal.data(), &matrix),
            "MatCreateAIJ");
      check(MatSetOption(matrix, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption");
      check(KSPCreate(processes::communicator(), &ksp), "KSPCreate");
      check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
      PC pc = nullptr;
      check(KSPGetPC(ksp, &pc), "KSPGetPC");
      check(PCSetType(pc, PCLU), "PCSetType");
      check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    }

    /// This process's rows of @p a into the PETSc matrix.
    void
    copy_rows(const dealii::SparseMatrix<double> &a)
    {
      std::vector<PetscInt>    columns;
      std::vector<PetscScalar> values;
      for (PetscInt row = first_row; row < last_row; ++row)
        {
          columns.clear();
          values.clear();
          for (auto entry = a.begin(row); entry != a.end(row); ++entry)
            {
              columns.push_back(static_cast<PetscInt>(entry->column()));
              values.push_back(entry->value());
            }
          check(MatSetValues(matrix, 1, &row, static_cast<PetscInt>(columns.size()), columns.data(), values.data(), INSERT_VALUES),
                "MatSetValues");
        }
      check(MatAssemblyBegin(matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
      check(MatAssemblyEnd(matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    }
  };



  DistributedDirectSolver::DistributedDirectSolver() = default;
  DistributedDirectSolver::~DistributedDirectSolver() = default;



  void
  DistributedDirectSolver::reset()
  {
    petsc.reset();
  }



  void
  DistributedDirectSolver::factorize(const dealii::SparseMatrix<double> &matrix)
  {
    if (petsc == nullptr || petsc->size != static_cast<PetscInt>(matrix.m()))
      {
        petsc = std::make_unique<Petsc>();
        petsc->create(matrix);
      }
    petsc->factorised = false;
    petsc->copy_rows(matrix);
    // The same pattern: PETSc's LU keeps MUMPS's analysis and factorises anew.
    check(KSPSetOperators(petsc->ksp, petsc->matrix, petsc->matrix), "KSPSetOperators");
    check(KSPSetUp(petsc->ksp), "KSPSetUp");
    PC pc = nullptr;
    check(KSPGetPC(petsc->ksp, &pc), "KSPGetPC");
    PCFailedReason reason = PC_NOERROR;
    check(PCGetFailedReason(pc, &reason), "PCGetFailedReason");
    // Every process must agree on the failure (a zero pivot is met by one):
    // the worst reason of any (the set-up error, -1, taken as the worst).
    const int worst = dealii::Utilities::MPI::max(
      reason == PC_NOERROR ? 0 : reason == PC_SETUP_ERROR ? 100 : static_cast<int>(reason), processes::communicator());
    if (worst != 0)
      {
        // MUMPS keeps a failed factorisation's error for the pattern: the
        // next factorisation starts afresh.
        petsc.reset();
        throw SolverFailure(std::string("MUMPS could not factorise the Newton system (") +
                            (worst == 100 ? "SETUP_ERROR" : PCFailedReasons[worst]) +
                            (worst == PC_FACTOR_OUTMEMORY ?
                               "): out of memory, or its workspace estimate too small: run on more processes or machines" :
                               "): singular"));
      }
    petsc->factorised = true;
  }



  void
  DistributedDirectSolver::solve(const dealii::Vector<double> &rhs, dealii::Vector<double> &solution, const bool transpose)
  {
    Assert(has_factorisation(), dealii::ExcMessage("solve() before factorize()"));
    Vec b = nullptr, x = nullptr, all = nullptr;
    check(MatCreateVecs(petsc->matrix, &x, &b), "MatCreateVecs");
    PetscScalar *entries = nullptr;
    check(VecGetArray(b, &entries), "VecGetArray");
    std::copy(rhs.begin() + petsc->first_row, rhs.begin() + petsc->last_row, entries);
    check(VecRestoreArray(b, &entries), "VecRestoreArray");
    check(transpose ? KSPSolveTranspose(petsc->ksp, b, x) : KSPSolve(petsc->ksp, b, x), "KSPSolve");
    // Onto every process, the same bits.
    VecScatter to_all = nullptr;
    check(VecScatterCreateToAll(x, &to_all, &all), "VecScatterCreateToAll");
    check(VecScatterBegin(to_all, x, all, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
    check(VecScatterEnd(to_all, x, all, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
    const PetscScalar *gathered = nullptr;
    check(VecGetArrayRead(all, &gathered), "VecGetArrayRead");
    solution.reinit(rhs.size(), true);
    std::copy(gathered, gathered + rhs.size(), solution.begin());
    check(VecRestoreArrayRead(all, &gathered), "VecRestoreArrayRead");
    VecScatterDestroy(&to_all);
    VecDestroy(&all);
    VecDestroy(&x);
    VecDestroy(&b);
  }



  bool
  DistributedDirectSolver::has_factorisation() const
  {
    return petsc != nullptr && petsc->factorised;
  }
} // namespace dieflow
