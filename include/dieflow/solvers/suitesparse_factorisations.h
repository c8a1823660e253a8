// SuiteSparse's factorisations of one sparsity pattern (CHOLMOD, UMFPACK), held by LinearSolver: only its sources include this.
#ifndef dieflow_suitesparse_factorisations_h
#define dieflow_suitesparse_factorisations_h

#include <dieflow/solvers/linear_solver.h>

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <suitesparse/cholmod.h>
#include <suitesparse/umfpack.h>

#include <algorithm>
#include <vector>

namespace dieflow
{
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

    /// Whether @p pattern is the one analysed, entry for entry.
    bool
    same_pattern(const dealii::SparsityPattern &pattern) const
    {
      if (!pattern_known || n != static_cast<long>(pattern.n_rows()) || nnz != pattern.n_nonzero_elements())
        return false;
      std::vector<long> rows;
      for (long j = 0; j < n; ++j)
        {
          rows.clear();
          for (auto e = pattern.begin(j); e != pattern.end(j); ++e)
            rows.push_back(e->column());
          std::sort(rows.begin(), rows.end());
          if (!std::equal(rows.begin(), rows.end(), Ai.begin() + Ap[j], Ai.begin() + Ap[j + 1]))
            return false;
        }
      return true;
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

    /// Whether a factorisation of this mesh as it is (not moved since) is held.
    bool
    holds_current() const
    {
      return pattern_known && factorisation_current && (last_was_cholesky ? factor != nullptr : numeric != nullptr);
    }

    /// The rows of @p matrix (same pattern) whose values moved by more
    /// than a tenth of their norm from those factorised (in Ax).
    unsigned int
    changed_rows(const dealii::SparseMatrix<double> &matrix) const
    {
      unsigned int changed = 0;
      std::size_t  p       = 0;
      for (long i = 0; i < n; ++i)
        {
          double difference = 0, size = 0;
          for (auto e = matrix.begin(i); e != matrix.end(i); ++e, ++p)
            {
              const double d = e->value() - Ax[full_place[p]];
              difference += d * d;
              size += e->value() * e->value();
            }
          changed += difference > 1e-2 * size;
        }
      return changed;
    }

    /// x = M^-1 b with the factorisation M held (GMRES's preconditioner in
    /// LinearSolver::solve_step()): no iterative refinement, whose steps
    /// would refine towards M, not towards the matrix GMRES solves.
    void
    apply_factorisation(dealii::Vector<double> &x, const dealii::Vector<double> &b)
    {
      if (last_was_cholesky)
        {
          cholmod_dense rhs;
          rhs.nrow            = n;
          rhs.ncol            = 1;
          rhs.nzmax           = n;
          rhs.d               = n;
          rhs.x               = const_cast<double *>(b.begin());
          rhs.z               = nullptr;
          rhs.xtype           = CHOLMOD_REAL;
          rhs.dtype           = CHOLMOD_DOUBLE;
          cholmod_dense *result = cholmod_l_solve(CHOLMOD_A, factor, &rhs, &common);
          if (result == nullptr)
            throw SolverFailure("CHOLMOD could not solve with its factorisation");
          std::copy(static_cast<double *>(result->x), static_cast<double *>(result->x) + n, x.begin());
          cholmod_l_free_dense(&result, &common);
          return;
        }
      double no_refinement[UMFPACK_CONTROL];
      std::copy(control, control + UMFPACK_CONTROL, no_refinement);
      no_refinement[UMFPACK_IRSTEP] = 0;
      double info[UMFPACK_INFO];
      if (umfpack_dl_solve(UMFPACK_A, Ap.data(), Ai.data(), Ax.data(), x.begin(), b.begin(), numeric, no_refinement, info) < 0)
        throw SolverFailure("UMFPACK could not solve with its factorisation");
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
    /// Whether the factorisation held is of this mesh as it is (not moved since).
    bool                     factorisation_current = false;
    /// Whether the last Newton step was solved by GMRES on it (LinearSolver::solve_step()).
    bool                     last_step_reused = false;
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
} // namespace dieflow

#endif
