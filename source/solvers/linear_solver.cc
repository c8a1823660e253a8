// The linear solves of the Newton systems: CHOLMOD or UMFPACK reused per mesh, a step by GMRES on the last factorisation, the iterative path and its direct fallback, and their memory (the entries: linear_solver_parameters.cc).
#include <dieflow/base/processes.h>
#include <dieflow/solvers/distributed_direct_solver.h>
#include <dieflow/solvers/linear_solver.h>
#include <dieflow/solvers/suitesparse_factorisations.h>

#include <suitesparse/cholmod.h>
#include <suitesparse/umfpack.h>

#include <deal.II/base/timer.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>

#include <malloc.h>
#include <sys/resource.h>

#include <thread>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>

namespace dieflow
{
  double
  mapped_memory()
  {
    std::ifstream status("/proc/self/status");
    std::string   line;
    while (std::getline(status, line))
      if (line.rfind("VmSize:", 0) == 0)
        return 1024. * std::stod(line.substr(7));
    return 0;
  }



  namespace
  {
    /// Whether a factorisation has run in this process: the BLAS it calls
    /// has then mapped its work buffers (it keeps them to the end).
    bool blas_buffers_mapped = false;

    /// OpenBLAS's work buffers: 128 MB per thread, mapped at its first call.
    double
    blas_buffer_bytes()
    {
      return 128. * 1024 * 1024 * std::max(1u, std::thread::hardware_concurrency());
    }

    /**
     * While it lives, the process may map at most @p room bytes more than
     * it maps now (RLIMIT_AS, what ulimit -v sets, lowered and restored;
     * never raised above a limit already set): an allocation beyond it
     * fails instead of the memory running out under the kernel.
     */
    class AddressSpaceCap
    {
    public:
      explicit AddressSpaceCap(const double room)
      {
        const double mapped = mapped_memory();
        if (room <= 0 || mapped == 0 || getrlimit(RLIMIT_AS, &saved) != 0)
          return;
        const double cap = mapped + room;
        if (saved.rlim_cur != RLIM_INFINITY && cap >= static_cast<double>(saved.rlim_cur))
          return;
        struct rlimit lowered = saved;
        lowered.rlim_cur      = static_cast<rlim_t>(cap);
        active                = setrlimit(RLIMIT_AS, &lowered) == 0;
      }

      ~AddressSpaceCap()
      {
        if (active)
          setrlimit(RLIMIT_AS, &saved);
      }

      AddressSpaceCap(const AddressSpaceCap &) = delete;
      AddressSpaceCap &
      operator=(const AddressSpaceCap &) = delete;

    private:
      struct rlimit saved;
      bool          active = false;
    };
  } // namespace



  void
  LinearSolverCounts::add_block_solve(const unsigned int iterations,
                                      const unsigned int inner,
                                      const double       residual_reduction,
                                      const bool         partial_step)
  {
    ++iterative_solves;
    krylov_iterations += iterations;
    inner_iterations += inner;
    if (residual_reduction > 0 && residual_reduction < 1)
      residual_decades += -std::log10(residual_reduction);
    if (partial_step)
      ++partial_steps;
  }



  LinearSolver::LinearSolver(const LinearSolverParameters &parameters)
    : parameters(parameters)
    , suitesparse(std::make_unique<SuiteSparse>())
  {}

  LinearSolver::~LinearSolver() = default;



  void
  LinearSolver::reset(const dealii::SparseMatrix<double> &matrix)
  {
    if (distributed)
      distributed->reset();
    // A moved mesh's factorisation is no preconditioner for its next
    // tangent: the penalty's stiff part moves with the geometry (die2d's
    // free-surface moves of 1e-5 of its length: GMRES not converged in 10
    // iterations, doc/benchmarks.md). Its ordering and symbolic
    // factorisation serve on.
    suitesparse->factorisation_current = false;
    if (processes::n() == 1 && suitesparse->same_pattern(matrix.get_sparsity_pattern()))
      return;
    suitesparse->free_factorisations();
    suitesparse->pattern_known = false;
  }



  void
  LinearSolver::factorize(const dealii::SparseMatrix<double> &matrix,
                          const bool                          symmetric,
                          const FactorisationFor              purpose)
  {
    // Counted as the solver's set-up, however the factorisation ends.
    struct SetupTime
    {
      double &            total;
      const dealii::Timer timer;
      ~SetupTime()
      {
        total += timer.wall_time();
      }
    } setup_time{counts.setup_seconds, {}};
    if (processes::n() > 1)
      {
        // Across the processes: MUMPS's LU (its memory divided among them,
        // which the serial path's estimate and cap do not describe).
        if (!distributed)
          distributed = std::make_unique<DistributedDirectSolver>();
        // Weighed once per analysis, before MUMPS allocates: later
        // factorisations of the pattern take the memory the first freed.
        if (distributed->analyse(matrix))
          {
            ++counts.symbolic_analyses;
            if (distributed->memory_ratio() > 1)
              {
                const std::string need = distributed->memory_need();
                distributed->reset();
                throw ResourceFailure(
                  purpose == FactorisationFor::fallback ?
                    "the iterative linear solver did not converge, and its direct fallback: " + need +
                      ": loosen Linear solver/Iterative tolerance, run on more machines, or solve a coarser mesh first "
                      "and refine (Refinement/Cycles)" :
                    "Linear solver/Method: " + need + ": set Method = iterative" +
                      (parameters.method == LinearSolverParameters::Method::automatic ?
                         " (auto chose the direct solver for this mesh)" :
                         " (or auto)") +
                      ", run on more machines, or solve a coarser mesh");
              }
          }
        distributed->factorize(matrix);
        ++counts.lu_factorisations;
        return;
      }
    auto &s = *suitesparse;
    s.analyse_pattern(matrix);
    s.copy_values(matrix);
    const bool cholesky = symmetric && parameters.direct_solver == LinearSolverParameters::DirectSolver::automatic;
    // The last LU factorisation's values go before the next is measured.
    if (s.numeric != nullptr)
      umfpack_dl_free_numeric(&s.numeric);
    require_factorisation_fits(cholesky);
    const double free_bytes = available_memory();
    bool         factorised = false;
    s.out_of_memory         = false;
    {
      // What the factorisation takes is known only as it runs: its
      // allocations are capped at the memory free (where known), so that
      // one beyond the estimate fails and is reported instead of the kernel
      // killing the process (doc/benchmarks.md, "Direct solves and the
      // memory left"). Until a factorisation has mapped OpenBLAS's buffers
      // the cap leaves room for them: it waits for ever where it cannot.
      const AddressSpaceCap cap(free_bytes > 0 ? free_bytes + (blas_buffers_mapped ? 0. : blas_buffer_bytes()) : 0.);
      s.last_was_cholesky = cholesky && s.cholesky();
      factorised          = s.last_was_cholesky || s.lu();
    }
    blas_buffers_mapped = blas_buffers_mapped || factorised;
    counts.symbolic_analyses += s.analyses;
    s.analyses = 0;
    if (!factorised && s.out_of_memory)
      {
        std::ostringstream message;
        message << std::fixed << std::setprecision(2) << "Linear solver/Method: the direct solver's factorisation of "
                << s.n << " unknowns ran out of the " << free_bytes / 1e9
                << " GB free: set Method = iterative"
                << (parameters.method == LinearSolverParameters::Method::automatic ? " (auto chose the direct solver for this mesh)" : " (or auto)")
                << ", or solve a coarser mesh";
        throw ResourceFailure(message.str());
      }
    if (!factorised)
      throw SolverFailure("the sparse direct solver (UMFPACK) could not factorise the "
                          "linearised system: it is singular, or memory ran out");
    ++(s.last_was_cholesky ? counts.cholesky_factorisations : counts.lu_factorisations);
    s.factorisation_current = true;
    s.last_step_reused      = false;
  }



  void
  LinearSolver::solve(const dealii::Vector<double> &rhs, dealii::Vector<double> &solution, const bool transpose)
  {
    if (processes::n() > 1)
      {
        distributed->solve(rhs, solution, transpose);
        return;
      }
    auto &s = *suitesparse;
    solution.reinit(rhs.size());
    if (s.last_was_cholesky)
      {
        s.apply_factorisation(solution, rhs);
        return;
      }
    double info[UMFPACK_INFO];
    // The stored arrays are J in compressed columns: UMFPACK_At solves J^T x = b.
    if (umfpack_dl_solve(transpose ? UMFPACK_At : UMFPACK_A, s.Ap.data(), s.Ai.data(), s.Ax.data(), solution.begin(), rhs.begin(),
                         s.numeric, s.control, info) < 0)
      throw SolverFailure("UMFPACK could not solve with its factorisation");
  }



  void
  LinearSolver::solve_step(const dealii::SparseMatrix<double> &matrix,
                           const bool                          symmetric,
                           const dealii::Vector<double> &      rhs,
                           dealii::Vector<double> &            solution,
                           const double                        tolerance)
  {
    auto &             s     = *suitesparse;
    const unsigned int limit = LinearSolverParameters::reuse_iterations;
    // Each row of J that differs from M's (by more than a tenth of its
    // norm: a contact node's changed state) is a rank-one change of M^-1 J
    // and costs GMRES about one iteration; the viscosity's change, spread
    // over every row, a few in all (die2d: 2, 7, 8 rows changed, 3, 5, 6
    // iterations; 11 and 16 rows, 9 iterations; from about 14 rows, where
    // contact nodes entered or left the dies, often no convergence in 40:
    // doc/benchmarks.md). Where more rows changed than the limit leaves
    // room for, the step is factorised without trying.
    const bool reusable = processes::n() == 1 && parameters.reuse_threshold > 0 &&
                          matrix.m() >= parameters.reuse_threshold && s.holds_current() &&
                          s.n == static_cast<long>(matrix.m()) &&
                          s.nnz == matrix.get_sparsity_pattern().n_nonzero_elements() &&
                          s.changed_rows(matrix) + 2 <= limit;
    if (reusable)
      {
        solution.reinit(rhs.size());
        dealii::SolverControl control(limit, tolerance * rhs.l2_norm(), false, false);
        // The Arnoldi basis holds every iteration: GMRES never restarts.
        dealii::SolverGMRES<dealii::Vector<double>> gmres(
          control, dealii::SolverGMRES<dealii::Vector<double>>::AdditionalData(limit + 2, true));
        // The held factorisation M as the preconditioner: vmult is x = M^-1 b.
        struct
        {
          SuiteSparse &s;
          void
          vmult(dealii::Vector<double> &x, const dealii::Vector<double> &b) const
          {
            s.apply_factorisation(x, b);
          }
        } const preconditioner{s};
        try
          {
            gmres.solve(matrix, solution, rhs, preconditioner);
            ++counts.reused_solves;
            counts.reuse_iterations += control.last_step();
            s.last_step_reused = true;
            return;
          }
        catch (const dealii::SolverControl::NoConvergence &)
          {
            ++counts.reuse_refactorised;
            counts.reuse_iterations += control.last_step();
          }
      }
    factorize(matrix, symmetric);
    solve(rhs, solution);
  }



  bool
  LinearSolver::has_factorisation() const
  {
    if (processes::n() > 1)
      return distributed && distributed->has_factorisation();
    const auto &s = *suitesparse;
    return s.holds_current() && !s.last_step_reused;
  }



  void
  LinearSolver::set_constant_modes(const std::vector<std::vector<bool>> &modes)
  {
    if (!iterative_solver)
      iterative_solver = std::make_unique<IterativeSolver>();
    iterative_solver->set_constant_modes(modes);
  }



  void
  LinearSolver::solve_iteratively(const unsigned int                  dim,
                                  const dealii::SparseMatrix<double> &matrix,
                                  const bool                          symmetric,
                                  const dealii::Vector<double> &      rhs,
                                  dealii::Vector<double> &            solution)
  {
    Assert(iterative_solver, dealii::ExcMessage("set_constant_modes() comes first"));
    const IterativeSolveInfo info =
      iterative_solver->solve(matrix, symmetric, rhs, solution, parameters.iterative_tolerance, parameters.max_augmented_iterations);
    ++counts.iterative_solves;
    counts.krylov_iterations += info.iterations;
    counts.setup_seconds += info.setup_seconds;
    if (info.converged)
      return;
    require_direct_fallback_fits(dim, matrix, symmetric);
    ++counts.direct_fallbacks;
    factorize(matrix, symmetric, FactorisationFor::fallback);
    solve(rhs, solution);
  }



  double
  LinearSolver::direct_memory_estimate(const unsigned int dim, const std::size_t n_dofs)
  {
    const double n = static_cast<double>(n_dofs);
    return dim == 2 ? 2.3e9 * n / 458000. : 1.9e9 * std::pow(n / 42315., 4. / 3.);
  }



  namespace
  {
    /// The first number in @p file (0 if none).
    double
    number_in(const std::string &file)
    {
      std::ifstream in(file);
      double        value = 0;
      return (in >> value) ? value : 0;
    }

    /// The value of @p key in a memory.stat file (0 if none).
    double
    stat_value(const std::string &file, const std::string &key)
    {
      std::ifstream in(file);
      std::string   name;
      double        value = 0;
      while (in >> name >> value)
        if (name == key)
          return value;
      return 0;
    }

  } // namespace



  namespace
  {
    /// Whether a factorisation's memory must be asked of CHOLMOD's analysis:
    /// the free memory is known and the measured estimate for @p n_dofs
    /// unknowns is not far below it (a quarter), where it is too coarse to
    /// decide (direct_fits, require_factorisation_fits, direct_fallback_bytes).
    bool
    analysis_needed(const unsigned int dim, const std::size_t n_dofs, const double available)
    {
      return available > 0 && LinearSolver::direct_memory_estimate(dim, n_dofs) >= 0.25 * available;
    }
  } // namespace



  double
  control_group_room(const std::string &process_groups, const std::string &groups_root)
  {
    std::ifstream groups(process_groups);
    double        room = 0;
    for (std::string line; std::getline(groups, line);)
      {
        // "ID:CONTROLLERS:PATH": v2 has ID 0 and no controllers.
        const auto first = line.find(':'), second = line.find(':', first + 1);
        if (first == std::string::npos || second == std::string::npos)
          continue;
        const std::string controllers = "," + line.substr(first + 1, second - first - 1) + ",";
        const bool        v2          = controllers == ",,";
        if (!v2 && controllers.find(",memory,") == std::string::npos)
          continue;
        const std::string root = v2 ? groups_root : groups_root + "/memory";
        const std::string limit_file = v2 ? "memory.max" : "memory.limit_in_bytes";
        // A v2 tree without the memory controller (hybrid mounts) has no limit files.
        for (std::filesystem::path group = line.substr(second + 1);; group = group.parent_path())
          {
            const std::string directory = root + group.string();
            std::ifstream     limit_in(directory + "/" + limit_file);
            std::string       text;
            // No limit: v2 says "max", v1 a number near 2^63.
            if (limit_in >> text && text != "max" && std::stod(text) < 1e18)
              {
                const double usage =
                  v2 ? number_in(directory + "/memory.current") -
                         stat_value(directory + "/memory.stat", "inactive_file") :
                       number_in(directory + "/memory.usage_in_bytes") -
                         stat_value(directory + "/memory.stat", "total_inactive_file");
                const double left = std::max(std::stod(text) - usage, 1.);
                room              = room == 0 ? left : std::min(room, left);
              }
            if (group == group.root_path() || group.empty())
              break;
          }
      }
    return room;
  }



  double
  LinearSolver::machine_memory()
  {
    // The machine's free memory (MemAvailable) ...
    std::ifstream meminfo("/proc/meminfo");
    std::string   key;
    double        kilobytes = 0;
    while (meminfo >> key >> kilobytes && key != "MemAvailable:")
      meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    double available = key == "MemAvailable:" && kilobytes > 0 ? 1024. * kilobytes : 0.;
    // ... and no more than the control groups' limits leave (a container's,
    // a batch job's).
    const double room = control_group_room();
    if (room > 0 && (available == 0 || room < available))
      available = room;
    return available;
  }



  double
  LinearSolver::address_space_room()
  {
    // The limit less what is mapped, plus what the allocator holds free for
    // reuse (freed memory stays mapped in its arenas).
    struct rlimit limit;
    if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY)
      return 0.;
    // OpenBLAS maps a work buffer of 128 MB per thread at its first call
    // and, where it cannot, retries for ever (seen hung in CHOLMOD's dpotrf
    // under ulimit -v): that much is kept back until a factorisation has
    // run (then the buffers are in VmSize).
    const double blas_buffers = blas_buffers_mapped ? 0. : blas_buffer_bytes();
    return std::max(static_cast<double>(limit.rlim_cur) - mapped_memory() + static_cast<double>(mallinfo2().fordblks) -
                      blas_buffers,
                    1.);
  }



  double
  LinearSolver::available_memory()
  {
    const double machine = machine_memory(), room = address_space_room();
    return machine == 0 ? room : room == 0 ? machine : std::min(machine, room);
  }



  bool
  LinearSolver::direct_fits(const unsigned int dim, const dealii::SparseMatrix<double> &matrix)
  {
    if (processes::n() > 1)
      {
        // Across processes the direct solver is MUMPS, its memory divided
        // among them as its own analysis says. The matrix is not assembled
        // yet and MUMPS's analysis reads values (it scales and permutes by
        // them): a trial analysis of the pattern with a unit diagonal, its
        // memory weighed as factorize() weighs it, then forgotten.
        if (!analysis_needed(dim, matrix.m(), dealii::Utilities::MPI::min(available_memory(), processes::communicator())))
          return true;
        dealii::SparseMatrix<double> unit(matrix.get_sparsity_pattern());
        for (const auto row : processes::owned_rows(matrix.m()))
          unit.set(row, row, 1.);
        DistributedDirectSolver trial;
        trial.analyse(unit);
        ++counts.symbolic_analyses;
        return trial.memory_ratio() <= 0.5;
      }
    const double available = available_memory();
    if (!analysis_needed(dim, matrix.m(), available))
      return true;
    // Newton's systems on one mesh may take both kinds: a Cholesky factor
    // (kept for the next symmetric system) and an LU one; and the assembly
    // and the iteration's own vectors take their share of what is free now
    // (under ulimit -v some 0.4 GB of 1.2 GB with 96,418 unknowns): the
    // direct solver is chosen where the factorisations take half of it.
    suitesparse->analyse_pattern(matrix);
    return 2 * (suitesparse->factorisation_bytes(true) + suitesparse->factorisation_bytes(false)) <= available;
  }



  void
  LinearSolver::require_factorisation_fits(const bool cholesky)
  {
    // Before each numeric factorisation, its memory from the analysis
    // against the memory free: a factorisation that does not fit is refused
    // with the sizes, not killed by the kernel without a word. Where even
    // the 3D estimate of the measured runs is far below the free memory,
    // the analysis is not needed.
    auto &       s         = *suitesparse;
    const double available = available_memory();
    if (!analysis_needed(3, s.n, available))
      return;
    const double needed = s.factorisation_bytes(cholesky);
    if (needed <= available)
      return;
    std::ostringstream message;
    message << std::fixed << std::setprecision(2) << "Linear solver/Method: the direct solver's factorisation of " << s.n
            << " unknowns needs about " << needed / 1e9 << " GB (from CHOLMOD's analysis), more than the "
            << available / 1e9 << " GB free: set Method = iterative"
            << (parameters.method == LinearSolverParameters::Method::automatic ? " (auto chose the direct solver for this mesh)" : " (or auto)")
            << ", or solve a coarser mesh";
    throw ResourceFailure(message.str());
  }



  double
  LinearSolver::direct_fallback_bytes(const unsigned int dim, const dealii::SparseMatrix<double> &matrix, const bool symmetric)
  {
    // Across processes the fallback is MUMPS's, weighed by its own analysis
    // when factorize() comes to it (that of the matrix then, the penalty form's).
    const double available = available_memory();
    if (processes::n() > 1 || !analysis_needed(dim, matrix.m(), available))
      return 0.;
    suitesparse->analyse_pattern(matrix);
    return suitesparse->factorisation_bytes(symmetric && parameters.direct_solver == LinearSolverParameters::DirectSolver::automatic);
  }



  bool
  LinearSolver::direct_fallback_fits(const unsigned int dim, const dealii::SparseMatrix<double> &matrix, const bool symmetric)
  {
    const double needed = direct_fallback_bytes(dim, matrix, symmetric);
    return needed == 0 || needed <= available_memory();
  }



  void
  LinearSolver::require_direct_fallback_fits(const unsigned int dim, const dealii::SparseMatrix<double> &matrix, const bool symmetric)
  {
    if (processes::n() > 1)
      {
        // MUMPS's analysis weighs the fallback in factorize(), told it is one.
        return;
      }
    const double needed    = direct_fallback_bytes(dim, matrix, symmetric);
    const double available = available_memory();
    if (needed == 0 || needed <= available)
      return;
    std::ostringstream message;
    message << std::fixed << std::setprecision(2) << "the iterative linear solver did not converge, and its direct "
            << "fallback for " << matrix.m() << " unknowns would need about " << needed / 1e9
            << " GB (from CHOLMOD's analysis), more than the " << available / 1e9
            << " GB free: loosen Linear solver/Iterative tolerance, or solve a coarser mesh "
            << "first and refine (Refinement/Cycles), so that each solve starts closer to its answer";
    throw ResourceFailure(message.str());
  }



  std::string
  LinearSolver::last_solver() const
  {
    if (processes::n() > 1)
      return "MUMPS";
    return suitesparse->last_was_cholesky ? "CHOLMOD" : "UMFPACK";
  }
} // namespace dieflow
