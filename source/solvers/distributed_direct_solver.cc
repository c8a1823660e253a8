// The direct solve of the Newton system across MPI processes: MUMPS through PETSc, each process owning a block of rows.
#include <dieflow/base/processes.h>
#include <dieflow/solvers/distributed_direct_solver.h>
#include <dieflow/solvers/linear_solver.h>

#include <deal.II/base/mpi.h>

#include <petscmat.h>

#include <algorithm>
#include <exception>
#include <iomanip>
#include <sstream>
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
    Mat      matrix = nullptr;
    /// MUMPS's LU of the matrix (PETSc's factor matrix).
    Mat      factor    = nullptr;
    PetscInt first_row = 0, last_row = 0, size = 0;
    bool     factorised = false;
    /// From the analysis (DistributedDirectSolver::memory_ratio(), memory_need()).
    double      memory_ratio = 0;
    std::string memory_need;

    ~Petsc()
    {
      // Destroying MUMPS's instance is collective: while an exception
      // unwinds one process, the others may wait elsewhere (the process is
      // ended by MPI_Abort, run.cc).
      if (std::uncaught_exceptions() > 0)
        return;
      if (factor != nullptr)
        MatDestroy(&factor);
      if (matrix != nullptr)
        MatDestroy(&matrix);
    }

    /// The PETSc matrix of @p a's pattern, this process's rows preallocated
    /// exactly, and MUMPS's factor of it.
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
      check(MatGetFactor(matrix, MATSOLVERMUMPS, MAT_FACTOR_LU, &factor), "MatGetFactor");
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

    /// The worst of the processes' factorisation errors (every process must
    /// agree: a zero pivot is met by one), as MatFactorError.
    MatFactorError
    worst_error() const
    {
      MatFactorError error = MAT_FACTOR_NOERROR;
      check(MatFactorGetError(factor, &error), "MatFactorGetError");
      return static_cast<MatFactorError>(dealii::Utilities::MPI::max(static_cast<int>(error), processes::communicator()));
    }
  };



  namespace
  {
    /// The message of a factorisation's @p error.
    std::string
    failure(const MatFactorError error)
    {
      return std::string("MUMPS could not factorise the Newton system (") +
             (error == MAT_FACTOR_OUTMEMORY ? "out of memory, or its workspace estimate too small: run on more processes "
                                              "or machines, or set Linear solver/Method = iterative)" :
              error == MAT_FACTOR_OTHER     ? "MUMPS's error)" :
                                              "singular)");
    }
  } // namespace



  DistributedDirectSolver::DistributedDirectSolver() = default;
  DistributedDirectSolver::~DistributedDirectSolver() = default;



  void
  DistributedDirectSolver::reset()
  {
    petsc.reset();
  }



  bool
  DistributedDirectSolver::analyse(const dealii::SparseMatrix<double> &matrix)
  {
    if (petsc != nullptr && petsc->size == static_cast<PetscInt>(matrix.m()))
      return false;
    petsc = std::make_unique<Petsc>();
    petsc->create(matrix);
    // MUMPS's analysis (ordering, symbolic factorisation) reads the values
    // too: it scales and permutes by them (ICNTL(6), ICNTL(8)).
    petsc->copy_rows(matrix);
    MatFactorInfo info;
    check(MatFactorInfoInitialize(&info), "MatFactorInfoInitialize");
    // MUMPS orders the matrix itself: PETSc's row and column orderings are not asked for.
    check(MatLUFactorSymbolic(petsc->factor, petsc->matrix, nullptr, nullptr, &info), "MatLUFactorSymbolic");
    if (const MatFactorError error = petsc->worst_error(); error != MAT_FACTOR_NOERROR)
      {
        petsc.reset();
        throw SolverFailure(failure(error));
      }
    weigh_memory();
    return true;
  }



  void
  DistributedDirectSolver::weigh_memory()
  {
    // INFO(15): the MB (of 10^6 bytes) MUMPS's analysis says this process's
    // factorisation and solves take in core; negative in millions of MB.
    PetscInt megabytes = 0;
    check(MatMumpsGetInfo(petsc->factor, 15, &megabytes), "MatMumpsGetInfo");
    const double own = megabytes >= 0 ? 1e6 * static_cast<double>(megabytes) : -1e12 * static_cast<double>(megabytes);

    // The processes on a machine share its free memory; each has its own
    // address space's limit.
    const MPI_Comm world   = processes::communicator();
    MPI_Comm       machine = MPI_COMM_NULL;
    MPI_Comm_split_type(world, MPI_COMM_TYPE_SHARED, static_cast<int>(processes::rank()), MPI_INFO_NULL, &machine);
    const double on_machine      = dealii::Utilities::MPI::sum(own, machine);
    const double largest         = dealii::Utilities::MPI::max(own, machine);
    const double free_there      = dealii::Utilities::MPI::min(LinearSolver::machine_memory(), machine);
    const int    processes_there = static_cast<int>(dealii::Utilities::MPI::n_mpi_processes(machine));
    MPI_Comm_free(&machine);
    const double room = LinearSolver::address_space_room();

    const double machine_ratio = free_there > 0 ? on_machine / free_there : 0.;
    const double own_ratio     = room > 0 ? own / room : 0.;
    std::ostringstream text;
    text << std::fixed << std::setprecision(2) << "MUMPS's factorisation of " << petsc->size << " unknowns needs about ";
    if (machine_ratio >= own_ratio)
      text << on_machine / 1e9 << " GB on a machine of " << processes_there << " of the " << processes::n()
           << " processes (from its analysis; " << largest / 1e9 << " GB on the largest), more than the " << free_there / 1e9
           << " GB free there";
    else
      text << own / 1e9 << " GB on MPI process " << processes::rank() << " (from its analysis), more than the " << room / 1e9
           << " GB its address space may still take (ulimit -v)";

    // Every process must take the same decisions: the worst ratio, told by
    // the process that found it.
    struct
    {
      double ratio;
      int    rank;
    } worst{std::max(machine_ratio, own_ratio), static_cast<int>(processes::rank())};
    MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
    petsc->memory_ratio = worst.ratio;
    std::string  told   = text.str();
    unsigned int length = static_cast<unsigned int>(told.size());
    MPI_Bcast(&length, 1, MPI_UNSIGNED, worst.rank, world);
    told.resize(length);
    MPI_Bcast(told.data(), static_cast<int>(length), MPI_CHAR, worst.rank, world);
    petsc->memory_need = told;
  }



  double
  DistributedDirectSolver::memory_ratio() const
  {
    Assert(petsc != nullptr, dealii::ExcMessage("memory_ratio() before analyse()"));
    return petsc->memory_ratio;
  }



  const std::string &
  DistributedDirectSolver::memory_need() const
  {
    Assert(petsc != nullptr, dealii::ExcMessage("memory_need() before analyse()"));
    return petsc->memory_need;
  }



  void
  DistributedDirectSolver::factorize(const dealii::SparseMatrix<double> &matrix)
  {
    if (!analyse(matrix))
      petsc->copy_rows(matrix);
    petsc->factorised = false;
    MatFactorInfo info;
    check(MatFactorInfoInitialize(&info), "MatFactorInfoInitialize");
    // The same pattern: MUMPS's analysis is kept, the factorisation made anew.
    check(MatLUFactorNumeric(petsc->factor, petsc->matrix, &info), "MatLUFactorNumeric");
    if (const MatFactorError error = petsc->worst_error(); error != MAT_FACTOR_NOERROR)
      {
        // MUMPS keeps a failed factorisation's error for the pattern: the
        // next factorisation starts afresh.
        petsc.reset();
        throw SolverFailure(failure(error));
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
    check(transpose ? MatSolveTranspose(petsc->factor, b, x) : MatSolve(petsc->factor, b, x), "MatSolve");
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
