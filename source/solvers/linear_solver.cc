// The linear solves of the Newton systems: CHOLMOD or UMFPACK reused per mesh, the iterative path and its direct fallback, and their memory (the entries: linear_solver_parameters.cc).
#include <dieflow/base/processes.h>
#include <dieflow/solvers/distributed_direct_solver.h>
#include <dieflow/solvers/linear_solver.h>

#include <suitesparse/cholmod.h>
#include <suitesparse/umfpack.h>
#include <malloc.h>
#include <sys/resource.h>

#include <thread>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>

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



  /**
   * The matrix in SuiteSparse's compressed-column form, with maps from
   * deal.II's row-wise storage (the diagonal first in each row) to it, built
   * once per sparsity pattern; and the factorisations.
   */
  struct LinearSolver::SuiteSparse
  {
    SuiteSparse()
    {
      cholmod_l_start(&common);
      // A matrix that is not positive definite is reported through
      // common.status and goes to LU; CHOLMOD's own warning on stderr would
      // only be noise in the user's log.
      common.print = 0;
      umfpack_dl_defaults(control);
    }

    ~SuiteSparse()
    {
      free_factorisations();
      cholmod_l_finish(&common);
    }

    void
    free_factorisations()
    {
      if (numeric != nullptr)
        umfpack_dl_free_numeric(&numeric);
      if (symbolic != nullptr)
        umfpack_dl_free_symbolic(&symbolic);
      if (factor != nullptr)
        cholmod_l_free_factor(&factor, &common);
      numeric = symbolic = nullptr;
      factor             = nullptr;
      factor_counted     = false;
    }

    /// Builds the column-compressed structure (full and lower triangle) and
    /// the maps from the matrix's storage order, if the pattern is new.
    void
    analyse_pattern(const dealii::SparseMatrix<double> &matrix)
    {
      const auto &pattern = matrix.get_sparsity_pattern();
      if (pattern_known && n == static_cast<long>(matrix.m()) && nnz == pattern.n_nonzero_elements())
        return;
      free_factorisations();
      n   = matrix.m();
      nnz = pattern.n_nonzero_elements();
      // The pattern is structurally symmetric (finite element couplings), so
      // column j of A has the rows of pattern row j.
      Ap.assign(n + 1, 0);
      Ai.clear();
      Ai.reserve(nnz);
      for (long j = 0; j < n; ++j)
        {
          std::vector<long> rows;
          for (auto e = pattern.begin(j); e != pattern.end(j); ++e)
            rows.push_back(e->column());
          std::sort(rows.begin(), rows.end());
          Ai.insert(Ai.end(), rows.begin(), rows.end());
          Ap[j + 1] = Ai.size();
        }
      Lp.assign(n + 1, 0);
      Li.clear();
      for (long j = 0; j < n; ++j)
        {
          for (long k = Ap[j]; k < Ap[j + 1]; ++k)
            if (Ai[k] >= j)
              Li.push_back(Ai[k]);
          Lp[j + 1] = Li.size();
        }
      // Entry (i, j) in storage order -> its place in column j.
      full_place.resize(nnz);
      lower_place.resize(nnz);
      std::size_t p = 0;
      for (long i = 0; i < n; ++i)
        for (auto e = pattern.begin(i); e != pattern.end(i); ++e, ++p)
          {
            const long j  = e->column();
            full_place[p] = std::lower_bound(Ai.begin() + Ap[j], Ai.begin() + Ap[j + 1], i) - Ai.begin();
            lower_place[p] =
              (i >= j) ? std::lower_bound(Li.begin() + Lp[j], Li.begin() + Lp[j + 1], i) - Li.begin() : -1;
          }
      Ax.resize(Ai.size());
      Lx.resize(Li.size());
      pattern_known = true;
    }

    void
    copy_values(const dealii::SparseMatrix<double> &matrix)
    {
      std::size_t p = 0;
      for (long i = 0; i < n; ++i)
        for (auto e = matrix.begin(i); e != matrix.end(i); ++e, ++p)
          {
            Ax[full_place[p]] = e->value();
            if (lower_place[p] >= 0)
              Lx[lower_place[p]] = e->value();
          }
    }

    /// The pattern's lower triangle with the values, as CHOLMOD reads it.
    cholmod_sparse
    lower_triangle()
    {
      cholmod_sparse A;
      A.nrow   = n;
      A.ncol   = n;
      A.nzmax  = Li.size();
      A.p      = Lp.data();
      A.i      = Li.data();
      A.x      = Lx.data();
      A.nz     = nullptr;
      A.z      = nullptr;
      A.stype  = -1; // symmetric, lower triangle stored
      A.itype  = CHOLMOD_LONG;
      A.xtype  = CHOLMOD_REAL;
      A.dtype  = CHOLMOD_DOUBLE;
      A.sorted = 1;
      A.packed = 1;
      return A;
    }

    /**
     * CHOLMOD's analysis of the pattern (an ordering and the symbolic
     * factor, which depend on the pattern only: kept for the Cholesky
     * factorisations of this pattern), and from it the bytes of the numeric
     * factor: its values (xsize) and, supernodal, their row indices
     * (ssize); simplicial, the values and indices of L. 0 if it fails.
     */
    double
    cholesky_factor_bytes()
    {
      if (factor == nullptr)
        {
          cholmod_sparse A = lower_triangle();
          factor           = cholmod_l_analyze(&A, &common);
          if (factor == nullptr)
            return 0;
          factor_bytes = factor->is_super ? 8. * (factor->xsize + factor->ssize) : 16. * common.lnz;
        }
      return factor_bytes;
    }

    /**
     * The memory the next numeric factorisation will add, from CHOLMOD's
     * analysis: 1.25 times its factor for a Cholesky factorisation (nothing
     * once the factor holds values: it is refactorised in place), 2.5 times
     * for an LU one (L and U, UMFPACK's work space: 1.9 to 2.2 times the
     * Cholesky factor measured from 40,000 unknowns in 2D and 3D, more only
     * on small meshes that fit anyway; UMFPACK's own estimate, an upper
     * bound for any pivoting, was 7 to 30 times what it used:
     * doc/benchmarks.md, "Direct solves and the memory left").
     */
    double
    factorisation_bytes(const bool cholesky)
    {
      if (cholesky)
        return (factor != nullptr && factor->xtype != CHOLMOD_PATTERN) ? 0. : 1.25 * cholesky_factor_bytes();
      return 2.5 * cholesky_factor_bytes();
    }

    bool
    cholesky()
    {
      if (!factor_counted)
        {
          ++analyses;
          factor_counted = true;
        }
      if (cholesky_factor_bytes() == 0)
        return false;
      cholmod_sparse A = lower_triangle();
      cholmod_l_factorize(&A, factor, &common);
      out_of_memory = out_of_memory || common.status == CHOLMOD_OUT_OF_MEMORY;
      return common.status == CHOLMOD_OK && factor->minor == static_cast<std::size_t>(n);
    }

    bool
    lu()
    {
      double info[UMFPACK_INFO];
      if (numeric != nullptr)
        umfpack_dl_free_numeric(&numeric);
      if (symbolic == nullptr)
        {
          ++analyses;
          const int status = umfpack_dl_symbolic(n, n, Ap.data(), Ai.data(), Ax.data(), &symbolic, control, info);
          out_of_memory    = out_of_memory || status == UMFPACK_ERROR_out_of_memory;
          if (status != UMFPACK_OK)
            return false;
        }
      const int status = umfpack_dl_numeric(Ap.data(), Ai.data(), Ax.data(), symbolic, &numeric, control, info);
      out_of_memory    = out_of_memory || status == UMFPACK_ERROR_out_of_memory;
      return status == UMFPACK_OK;
    }

    long                     n = 0;
    std::size_t              nnz = 0;
    bool                     pattern_known = false;
    std::vector<long>        Ap, Ai, Lp, Li;
    std::vector<double>      Ax, Lx;
    std::vector<long>        full_place, lower_place;
    cholmod_common           common;
    cholmod_factor *         factor   = nullptr;
    void *                   symbolic = nullptr;
    void *                   numeric  = nullptr;
    double                   control[UMFPACK_CONTROL];
    bool                     last_was_cholesky = false;
    /// Bytes of the Cholesky factor (cholesky_factor_bytes()), and whether
    /// its analysis served a factorisation (counted in analyses).
    double                   factor_bytes   = 0;
    bool                     factor_counted = false;
    /// Whether the last factorisation ran out of memory (its allocations
    /// failed under the address-space cap that factorize() sets).
    bool                     out_of_memory = false;
    /// Orderings and symbolic factorisations computed (both kinds).
    unsigned int             analyses = 0;
  };



  LinearSolver::LinearSolver(const LinearSolverParameters &parameters)
    : parameters(parameters)
    , suitesparse(std::make_unique<SuiteSparse>())
  {}

  LinearSolver::~LinearSolver() = default;



  void
  LinearSolver::reset()
  {
    if (distributed)
      distributed->reset();
    suitesparse->free_factorisations();
    suitesparse->pattern_known = false;
  }



  void
  LinearSolver::factorize(const dealii::SparseMatrix<double> &matrix, const bool symmetric)
  {
    if (processes::n() > 1)
      {
        // Across the processes: MUMPS's LU (its memory divided among them,
        // which the serial path's estimate and cap do not describe).
        if (!distributed)
          distributed = std::make_unique<DistributedDirectSolver>();
        const bool analysed = distributed->has_factorisation();
        distributed->factorize(matrix);
        counts.symbolic_analyses += analysed ? 0 : 1;
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
        cholmod_dense b;
        b.nrow  = s.n;
        b.ncol  = 1;
        b.nzmax = s.n;
        b.d     = s.n;
        b.x     = const_cast<double *>(rhs.begin());
        b.z     = nullptr;
        b.xtype = CHOLMOD_REAL;
        b.dtype = CHOLMOD_DOUBLE;
        cholmod_dense *x = cholmod_l_solve(CHOLMOD_A, s.factor, &b, &s.common);
        if (x == nullptr)
          throw SolverFailure("CHOLMOD could not solve with its factorisation");
        std::copy(static_cast<double *>(x->x), static_cast<double *>(x->x) + s.n, solution.begin());
        cholmod_l_free_dense(&x, &s.common);
        return;
      }
    double info[UMFPACK_INFO];
    // The stored arrays are J in compressed columns: UMFPACK_At solves J^T x = b.
    if (umfpack_dl_solve(transpose ? UMFPACK_At : UMFPACK_A, s.Ap.data(), s.Ai.data(), s.Ax.data(), solution.begin(), rhs.begin(),
                         s.numeric, s.control, info) < 0)
      throw SolverFailure("UMFPACK could not solve with its factorisation");
  }



  bool
  LinearSolver::has_factorisation() const
  {
    if (processes::n() > 1)
      return distributed && distributed->has_factorisation();
    const auto &s = *suitesparse;
    return s.pattern_known && (s.last_was_cholesky ? s.factor != nullptr : s.numeric != nullptr);
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
    if (info.converged)
      return;
    require_direct_fallback_fits(dim, matrix, symmetric);
    ++counts.direct_fallbacks;
    factorize(matrix, symmetric);
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
  LinearSolver::available_memory()
  {
    // The machine's free memory (MemAvailable) ...
    std::ifstream meminfo("/proc/meminfo");
    std::string   key;
    double        kilobytes = 0;
    while (meminfo >> key >> kilobytes && key != "MemAvailable:")
      meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    double     available = key == "MemAvailable:" && kilobytes > 0 ? 1024. * kilobytes : 0.;
    const auto at_most   = [&](const double room) {
      if (available == 0 || room < available)
        available = std::max(room, 1.);
    };
    // ... no more than the address space this process may still take
    // (ulimit -v): the limit less what is mapped, plus what the allocator
    // holds free for reuse (freed memory stays mapped in its arenas) ...
    struct rlimit limit;
    if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
      {
        // OpenBLAS maps a work buffer of 128 MB per thread at its first
        // call and, where it cannot, retries for ever (seen hung in
        // CHOLMOD's dpotrf under ulimit -v): that much is kept back until
        // a factorisation has run (then the buffers are in VmSize).
        const double blas_buffers = blas_buffers_mapped ? 0. : blas_buffer_bytes();
        at_most(static_cast<double>(limit.rlim_cur) - mapped_memory() + static_cast<double>(mallinfo2().fordblks) -
                blas_buffers);
      }
    // ... and no more than the control group's limit leaves (a container's).
    std::ifstream max("/sys/fs/cgroup/memory.max");
    std::string   text;
    if (max >> text && text != "max")
      at_most(std::stod(text) - number_in("/sys/fs/cgroup/memory.current"));
    return available;
  }



  bool
  LinearSolver::direct_fits(const unsigned int dim, const dealii::SparseMatrix<double> &matrix)
  {
    // Across processes the direct solver is MUMPS, its memory divided
    // among them, which CHOLMOD's analysis does not describe (doc/parallel.md).
    if (processes::n() > 1)
      return true;
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
    // Across processes the fallback is MUMPS's, its memory divided (see factorize()).
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
