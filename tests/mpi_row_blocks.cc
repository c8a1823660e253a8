// The operations that divide the systems among MPI processes, against deal.II's whole-matrix ones: RowBlockMatrix's products on distributed vectors, RowSums and processes::sum.
//
// The program launches itself under mpirun on 2 and 3 processes (tests/mpi_runs.h
// sets Open MPI up for root). Each process builds the same random matrices
// and vectors (one seed), then checks:
//  - RowBlockMatrix's vmult, vmult_add and residual on distributed vectors
//    (each process computes its entries from its rows, the entries of x
//    they read from other processes imported; the results gathered by
//    RowLayout::gather) against deal.II's product of
//    the whole matrix, row by row within 1e-13 of sum_j |M_ij x_j| (the
//    same terms, vmult_add's added in another order; the bound also leaves
//    room for a compiler that contracts them into fused multiply-adds), on
//    a square matrix, a rectangular one with empty rows (the mixed form's B
//    and B^T have the pressure's and the velocity's shapes), one whose first
//    200 rows are empty and one of 2 rows (on 3 processes the first owns
//    none); the rectangular one and its transpose also with the rows (the
//    columns) in groups of 7 held by random processes, as the pressure
//    modes by their cells' parts (RowLayout::reinit_groups: extract and
//    gather through it); and the same bits on every process
//    (processes::require_same);
//  - galerkin_product (p-multigrid's coarse operator P^T D A D P, each
//    process summing its block of fine rows into the pattern of
//    galerkin_entries(), the sums into each process's coarse rows by
//    RowSums) against deal.II's mmult and Tmmult of the whole matrices,
//    entry by entry both ways in each process's rows within 1e-13 of the
//    sum of the terms' magnitudes (|P|^T D |A| D |P|: the same terms in
//    another order), NaN in the other rows, on random A (1001 x 1001), P
//    (1001 x 240) and D (a fifth of the rows constrained; the pattern built
//    with none, as on a mesh whose contact set changes);
//  - RowBlockMatrix's products and inverse diagonal (what Chebyshev is
//    given) on a square matrix summed by RowSums (NaN in the rows a
//    process does not own: a product that read them would be NaN) against
//    deal.II's of the whole matrix;
//  - processes::sum of vectors of 1, 2, 5 and 1,001 entries (fewer entries
//    than processes included) and of a sparse matrix's values, each process
//    adding (rank + 1) x an integer: the sums are integers, so they must be
//    exact, and the same bits on every process; processes::RowSums of
//    the same kind of values, exact in each process's rows and NaN in the
//    others, on patterns whole on every process (a square matrix, one whose
//    first rows are empty and one of 2 rows) and on a matrix assembled by
//    parts (each process its cells' entries; rows owned in uneven blocks,
//    processes::own_rows_by_part()) against the same cells assembled whole;
//  - RowBlockMatrix::has_pattern_of: a pattern made anew in place (the
//    same object and size, other and more entries) is told from the one reinit()
//    agreed the exchanges for, which is kept;
//  - two spaces of one shared mesh (Q2 and Q1 velocity) numbered by part
//    at once (processes::distribute_dofs, number_dofs_by_part): each process owns
//    exactly the dofs DoFTools::get_subdomain_association gives its part,
//    in each space.
#include <dieflow/base/processes.h>
#include <dieflow/solvers/p_multigrid.h>
#include <dieflow/solvers/row_blocks.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace
{
  using dealii::SparseMatrix;
  using dealii::Vector;
  using namespace dieflow;

  /// A pattern of @p m x @p n: the diagonal where square, about @p per_row
  /// random columns per row, no entries in rows i with i % @p empty_every == 0
  /// (0: none empty) or i < @p first_empty_rows.
  dealii::SparsityPattern
  random_pattern(const unsigned int m,
                 const unsigned int n,
                 const unsigned int per_row,
                 const unsigned int empty_every,
                 const unsigned int first_empty_rows,
                 std::mt19937 &     random)
  {
    dealii::DynamicSparsityPattern pattern(m, n);
    std::uniform_int_distribution<unsigned int> column(0, n - 1);
    for (unsigned int i = 0; i < m; ++i)
      {
        if ((empty_every > 0 && i % empty_every == 0) || i < first_empty_rows)
          continue;
        if (m == n)
          pattern.add(i, i);
        for (unsigned int k = 0; k < per_row; ++k)
          pattern.add(i, column(random));
      }
    dealii::SparsityPattern result;
    result.copy_from(pattern);
    return result;
  }

  void
  fill(SparseMatrix<double> &matrix, std::mt19937 &random)
  {
    std::uniform_real_distribution<double> value(-1., 1.);
    for (auto entry = matrix.begin(); entry != matrix.end(); ++entry)
      entry->value() = value(random);
  }

  Vector<double>
  random_vector(const unsigned int n, std::mt19937 &random)
  {
    std::uniform_real_distribution<double> value(-1., 1.);
    Vector<double>                         v(n);
    for (auto &x : v)
      x = value(random);
    return v;
  }

  /// Whether @p y equals @p z within 1e-13 of sum_j |M_ij x_j| in every row.
  bool
  agrees(const Vector<double> &y, const Vector<double> &z, const SparseMatrix<double> &M, const Vector<double> &x)
  {
    for (unsigned int i = 0; i < M.m(); ++i)
      {
        double magnitude = 0;
        for (auto entry = M.begin(i); entry != M.end(i); ++entry)
          magnitude += std::abs(entry->value() * x[entry->column()]);
        if (!(std::abs(y[i] - z[i]) <= 1e-13 * magnitude))
          return false;
      }
    return true;
  }

  /// Whether every process holds the same bits of @p v.
  bool
  same_everywhere(const Vector<double> &v)
  {
    try
      {
        processes::require_same(v, "the test");
        return true;
      }
    catch (const std::logic_error &)
      {
        return false;
      }
  }

  /// @p layout for @p n entries: blocks of rows (@p group 0), or groups of
  /// @p group entries each held by a random process (the same on all: one
  /// seed), as the mixed form's pressure modes by their cells' parts.
  /// With @p first_only every group on the first process (the others none).
  void
  make_layout(RowLayout &layout, const unsigned int n, const unsigned int group, std::mt19937 &random,
              const bool first_only)
  {
    if (group == 0)
      {
        layout.reinit_rows(n);
        return;
      }
    std::uniform_int_distribution<unsigned int> process(0, processes::n() - 1);
    std::vector<unsigned int>                   owner(n / group);
    for (auto &q : owner)
      q = first_only ? 0 : process(random);
    layout.reinit_groups(owner, group);
  }

  /// The checks on one matrix; one line each into @p out. RowBlockMatrix
  /// multiplies with @p summed where given (M summed by RowSums: M
  /// in this process's rows, NaN in the others), else with M; its rows
  /// and columns divided as make_layout() with @p row_group and
  /// @p column_group. The distributed results are gathered whole.
  void
  check_products(const std::string &         name,
                 const SparseMatrix<double> &M,
                 std::mt19937 &              random,
                 std::ostream &              out,
                 const SparseMatrix<double> *summed       = nullptr,
                 const unsigned int          row_group    = 0,
                 const unsigned int          column_group = 0,
                 const bool                  first_only   = false)
  {
    const Vector<double> x = random_vector(M.n(), random), y0 = random_vector(M.m(), random),
                         b = random_vector(M.m(), random);
    RowLayout            rows, columns;
    make_layout(rows, M.m(), row_group, random, first_only);
    make_layout(columns, M.n(), column_group, random, first_only);
    RowBlockMatrix product;
    product.reinit(summed != nullptr ? *summed : M, rows, columns);
    DistributedVector x_part, y_part, b_part;
    columns.extract(x, x_part);

    Vector<double> y, z(M.m());
    product.vmult(y_part, x_part);
    rows.gather(y_part, y);
    M.vmult(z, x);
    // Every process takes part in the comparison (a collective) first.
    bool same = same_everywhere(y);
    out << name << ": vmult as deal.II's: " << (same && agrees(y, z, M, x) ? "ok" : "FAILS") << "\n";

    rows.extract(y0, y_part);
    z = y0;
    product.vmult_add(y_part, x_part);
    rows.gather(y_part, y);
    M.vmult_add(z, x);
    same = same_everywhere(y);
    out << name << ": vmult_add as deal.II's: " << (same && agrees(y, z, M, x) ? "ok" : "FAILS") << "\n";

    if (M.m() == M.n())
      {
        rows.extract(b, b_part);
        product.residual(y_part, x_part, b_part);
        rows.gather(y_part, y);
        M.residual(z, x, b);
        same = same_everywhere(y);
        out << name << ": residual as deal.II's: " << (same && agrees(y, z, M, x) ? "ok" : "FAILS") << "\n";
        // The inverse diagonal Chebyshev is given, in each process's rows.
        Vector<double> diagonal;
        product.inverse_diagonal(y_part);
        rows.gather(y_part, diagonal);
        bool exact = true;
        for (unsigned int i = 0; i < M.m(); ++i)
          exact = exact && diagonal[i] == 1. / M.el(i, i);
        same = same_everywhere(diagonal);
        out << name << ": inverse diagonal as deal.II's: " << (same && exact ? "ok" : "FAILS") << "\n";
      }
  }

  /// Whether @p verdict holds on every process (a collective).
  bool
  everywhere(const bool verdict)
  {
    std::vector<double> failures{verdict ? 0. : 1.};
    processes::sum(failures);
    return failures[0] == 0;
  }

  /// RowSums of @p pattern's entries on every process (the pattern whole).
  struct WholeRowSums
  {
    WholeRowSums(const dealii::SparsityPattern &whole)
    {
      dealii::DynamicSparsityPattern entries(whole.n_rows(), whole.n_cols());
      for (auto entry = whole.begin(); entry != whole.end(); ++entry)
        entries.add(entry->row(), entry->column());
      sums.reinit(entries, pattern);
    }
    processes::RowSums      sums;
    dealii::SparsityPattern pattern;
  };

  /// M as RowSums leaves it: process 0 holds M, the others zero, summed
  /// (adding zeros is exact: M's values in this process's rows).
  SparseMatrix<double>
  summed_own_rows(const SparseMatrix<double> &M, const WholeRowSums &sums)
  {
    SparseMatrix<double> summed(sums.pattern);
    if (processes::rank() == 0)
      for (auto entry = M.begin(); entry != M.end(); ++entry)
        summed.set(entry->row(), entry->column(), entry->value());
    sums.sums.sum(summed);
    return summed;
  }

  /// What one process of the launched run checks (the first writes the lines).
  int
  launched(const std::string &file)
  {
    const processes::Session session;
    std::ostringstream       out;
    std::mt19937             random(2026);

    const dealii::SparsityPattern square      = random_pattern(1001, 1001, 12, 0, 0, random);
    const dealii::SparsityPattern rectangular = random_pattern(301, 1001, 20, 7, 0, random);
    // Rectangular: a square pattern would keep its diagonal in the empty rows.
    const dealii::SparsityPattern empty_first = random_pattern(500, 499, 8, 0, 200, random);
    const dealii::SparsityPattern two_rows    = random_pattern(2, 1001, 30, 0, 0, random);
    SparseMatrix<double>          A(square), B(rectangular), C(empty_first), D(two_rows);
    fill(A, random);
    fill(B, random);
    fill(C, random);
    fill(D, random);
    dealii::SparseMatrix<double> BT;
    dealii::DynamicSparsityPattern transposed(B.n(), B.m());
    for (auto entry = B.begin(); entry != B.end(); ++entry)
      transposed.add(entry->column(), entry->row());
    dealii::SparsityPattern transposed_pattern;
    transposed_pattern.copy_from(transposed);
    BT.reinit(transposed_pattern);
    for (auto entry = B.begin(); entry != B.end(); ++entry)
      BT.set(entry->column(), entry->row(), entry->value());

    check_products("square 1001 x 1001", A, random, out);
    check_products("rectangular 301 x 1001, every 7th row empty", B, random, out);
    check_products("its transpose 1001 x 301", BT, random, out);
    {
      // (a generator of their own: the later checks' matrices stay those of the other lines)
      std::mt19937 groups_random(7);
      check_products("rectangular 301 x 1001, its rows in groups of 7 on random processes", B, groups_random, out,
                     nullptr, 7);
      check_products("its transpose 1001 x 301, its columns in groups of 7 on random processes", BT, groups_random, out,
                     nullptr, 0, 7);
      // Processes that hold nothing: every group on the first; a square
      // matrix whose rows' blocks leave a process out (the last of 2, the
      // middle one of 3: own_rows_by_part(), for this size alone).
      check_products("rectangular 301 x 1001, its rows in groups of 7 all on the first process", B, groups_random, out,
                     nullptr, 7, 0, true);
      check_products("its transpose 1001 x 301, its columns in groups of 7 all on the first process", BT, groups_random,
                     out, nullptr, 0, 7, true);
      const dealii::SparsityPattern square_601 = random_pattern(601, 601, 12, 0, 0, groups_random);
      SparseMatrix<double>          E(square_601);
      fill(E, groups_random);
      std::vector<dealii::types::global_dof_index> rows_of_part(processes::n(), 0);
      rows_of_part.front() = processes::n() == 2 ? 601 : 300;
      rows_of_part.back() += 601 - rows_of_part.front();
      processes::own_rows_by_part(rows_of_part);
      check_products("square 601 x 601, a process owning no rows", E, groups_random, out);
    }
    check_products("500 x 499, rows 0-199 empty", C, random, out);
    check_products("2 x 1001", D, random, out);
    {
      // A pattern made anew in place for another mesh of the same size (the
      // object, and the matrix on it, kept): has_pattern_of() tells it from
      // the one reinit() agreed the exchanges for, so the saddle-point
      // solver agrees them anew. Its own generator: the lines after keep theirs.
      std::mt19937            own_random(7);
      dealii::SparsityPattern pattern;
      pattern.copy_from(random_pattern(1001, 1001, 12, 0, 0, own_random));
      SparseMatrix<double> M(pattern);
      fill(M, own_random);
      RowLayout rows;
      rows.reinit_rows(M.m());
      RowBlockMatrix product;
      product.reinit(M, rows, rows);
      const bool kept = product.has_pattern_of(M);
      const dealii::SparsityPattern other = random_pattern(1001, 1001, 13, 0, 0, own_random);
      pattern.copy_from(other);
      M.reinit(pattern);
      const bool made_anew = product.has_pattern_of(M);
      out << "a pattern made anew in place (1001 x 1001, " << pattern.n_nonzero_elements()
          << " entries): told from the one agreed, that one kept: "
          << (everywhere(kept && !made_anew) ? "ok" : "FAILS") << "\n";
    }
    {
      const WholeRowSums         sums(square);
      const SparseMatrix<double> summed = summed_own_rows(A, sums);
      check_products("square 1001 x 1001 summed by RowSums", A, random, out, &summed);
    }

    {
      // P^T D A D P against deal.II's products of the whole matrices; the
      // bound from the products of the magnitudes.
      const dealii::SparsityPattern embedding_pattern = random_pattern(1001, 240, 4, 0, 0, random);
      SparseMatrix<double>          P(embedding_pattern);
      fill(P, random);
      Vector<double> free(1001);
      for (unsigned int i = 0; i < free.size(); ++i)
        free[i] = (i % 5 == 3) ? 0. : 1.;
      dealii::SparsityPattern product_pattern, coarse_pattern;
      SparseMatrix<double>    product(product_pattern), expected(coarse_pattern);
      // The pattern as the mesh's first set-up builds it, D = I there.
      Vector<double> all_free(free.size());
      all_free = 1.;
      A.mmult(product, P, all_free, true);
      P.Tmmult(expected, product, all_free, true);
      // (without a new pattern deal.II's products add to what is there)
      product  = 0;
      expected = 0;
      A.mmult(product, P, free, false);
      P.Tmmult(expected, product, free, false);
      // Each process's terms into its own coarse rows (RowSums).
      dealii::DynamicSparsityPattern entries(P.n(), P.n());
      galerkin_entries(square, embedding_pattern, entries);
      processes::RowSums      sums;
      dealii::SparsityPattern computed_pattern;
      sums.reinit(entries, computed_pattern);
      SparseMatrix<double> computed(computed_pattern);
      galerkin_product(A, P, free, sums, computed);
      SparseMatrix<double> absolute_A(square), absolute_P(embedding_pattern), absolute_product(product_pattern),
        bound(coarse_pattern);
      for (auto e = A.begin(), f = absolute_A.begin(); e != A.end(); ++e, ++f)
        f->value() = std::abs(e->value());
      for (auto e = P.begin(), f = absolute_P.begin(); e != P.end(); ++e, ++f)
        f->value() = std::abs(e->value());
      absolute_A.mmult(absolute_product, absolute_P, free, false);
      absolute_P.Tmmult(bound, absolute_product, free, false);
      // Both ways in this process's rows (an entry missing from either
      // pattern reads 0), NaN in the others.
      bool                   agree = true;
      const dealii::IndexSet own   = processes::owned_rows(computed.m());
      for (auto e = expected.begin(), b = bound.begin(); e != expected.end(); ++e, ++b)
        if (own.is_element(e->row()))
          agree = agree && std::abs(computed.el(e->row(), e->column()) - e->value()) <= 1e-13 * b->value();
      for (auto e = computed.begin(); e != computed.end(); ++e)
        agree = agree && (own.is_element(e->row()) ?
                            std::abs(e->value() - expected.el(e->row(), e->column())) <=
                              1e-13 * bound.el(e->row(), e->column()) :
                            std::isnan(e->value()));
      out << "P^T D A D P (" << expected.n_nonzero_elements()
          << " entries) as deal.II's products, each process's coarse rows: " << (everywhere(agree) ? "ok" : "FAILS")
          << "\n";
    }

    const double rank_factor = processes::rank() + 1., total = processes::n() * (processes::n() + 1.) / 2.;
    for (const unsigned int n : {1u, 2u, 5u, 1001u})
      {
        std::vector<double> v(n);
        for (unsigned int i = 0; i < n; ++i)
          v[i] = rank_factor * (i + 1);
        processes::sum(v);
        bool exact = true;
        for (unsigned int i = 0; i < n; ++i)
          exact = exact && v[i] == total * (i + 1);
        const bool same = same_everywhere(Vector<double>(v.begin(), v.end()));
        out << "sum of " << n << " entries: exact: " << (same && exact ? "ok" : "FAILS") << "\n";
      }
    {
      SparseMatrix<double> S(square);
      unsigned int         k = 0;
      for (auto entry = S.begin(); entry != S.end(); ++entry)
        entry->value() = rank_factor * (++k);
      processes::sum(S);
      bool           exact = true;
      Vector<double> values(S.n_nonzero_elements());
      k = 0;
      for (auto entry = S.begin(); entry != S.end(); ++entry, ++k)
        {
          exact         = exact && entry->value() == total * (k + 1);
          values[k]     = entry->value();
        }
      const bool same = same_everywhere(values);
      out << "sum of a sparse matrix's " << S.n_nonzero_elements() << " values: exact: "
          << (same && exact ? "ok" : "FAILS") << "\n";
    }
    // RowSums of a pattern whole on every process: the exact sums in this
    // process's rows, NaN in the others; a square matrix, one whose first
    // 200 rows are empty and one of 2 rows (on 3 processes the first owns
    // none).
    for (const auto &[name, pattern] : {std::pair{"1001 x 1001", &square},
                                        std::pair{"500 x 499, rows 0-199 empty", &empty_first},
                                        std::pair{"2 x 1001", &two_rows}})
      {
        const WholeRowSums   sums(*pattern);
        SparseMatrix<double> S(sums.pattern);
        unsigned int         k = 0;
        for (auto entry = S.begin(); entry != S.end(); ++entry)
          entry->value() = rank_factor * (++k);
        sums.sums.sum(S);
        const dealii::IndexSet own   = processes::owned_rows(S.m());
        bool                   exact = true;
        k                            = 0;
        for (auto entry = S.begin(); entry != S.end(); ++entry, ++k)
          exact = exact && (own.is_element(entry->row()) ? entry->value() == total * (k + 1) : std::isnan(entry->value()));
        out << "RowSums of a " << name << " matrix's " << S.n_nonzero_elements()
            << " values on every process: exact in each process's rows, NaN in the others: "
            << (everywhere(exact) ? "ok" : "FAILS") << "\n";
      }
    {
      // A matrix assembled by parts, as the flow's: 777 rows owned in
      // uneven blocks (own_rows_by_part()), "cells" k of the rows {k, k + 1,
      // 37 k + 5 mod 777}, cell k assembled by the owner of row k (so its
      // entries reach the next block and, through the third row, any
      // other), integer values: each process's rows, summed by RowSums
      // from the entries each process added, must equal exactly those of
      // the same cells assembled whole (every entry, both ways), the other
      // rows NaN.
      const unsigned int                           n = 777, P = processes::n();
      std::vector<dealii::types::global_dof_index> rows_of_part(P);
      dealii::types::global_dof_index              given = 0;
      for (unsigned int r = 0; r < P; ++r)
        given += rows_of_part[r] = r + 1 < P ? 2 * n * (r + 1) / (P * (P + 1)) : n - given;
      processes::own_rows_by_part(rows_of_part);
      const dealii::IndexSet own = processes::owned_rows(n);
      dealii::types::global_dof_index first = 0;
      for (unsigned int r = 0; r < processes::rank(); ++r)
        first += rows_of_part[r];
      const auto cell_rows = [&](const unsigned int k) {
        std::vector<dealii::types::global_dof_index> rows{k, k + 1, (37 * k + 5) % n};
        std::sort(rows.begin(), rows.end());
        rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
        return rows;
      };
      const auto owner = [&](const dealii::types::global_dof_index row) {
        unsigned int                    r   = 0;
        dealii::types::global_dof_index end = rows_of_part[0];
        while (row >= end)
          end += rows_of_part[++r];
        return r;
      };
      const auto value = [&](const unsigned int k, const unsigned int a, const unsigned int b) {
        return (owner(k) + 1.) * (1 + (k + 3 * a + 5 * b) % 11);
      };
      dealii::DynamicSparsityPattern mine(n), whole(n);
      for (unsigned int k = 0; k + 1 < n; ++k)
        for (const auto i : cell_rows(k))
          for (const auto j : cell_rows(k))
            {
              whole.add(i, j);
              if (owner(k) == processes::rank())
                mine.add(i, j);
            }
      processes::RowSums      sums;
      dealii::SparsityPattern pattern, whole_pattern;
      sums.reinit(mine, pattern);
      whole_pattern.copy_from(whole);
      SparseMatrix<double> S(pattern), W(whole_pattern);
      for (unsigned int k = 0; k + 1 < n; ++k)
        {
          const auto rows = cell_rows(k);
          for (unsigned int a = 0; a < rows.size(); ++a)
            for (unsigned int b = 0; b < rows.size(); ++b)
              {
                W.add(rows[a], rows[b], value(k, a, b));
                if (owner(k) == processes::rank())
                  S.add(rows[a], rows[b], value(k, a, b));
              }
        }
      sums.sum(S);
      bool exact = own.n_elements() == rows_of_part[processes::rank()] &&
                   (own.n_elements() == 0 || own.nth_index_in_set(0) == first);
      for (auto e = W.begin(); e != W.end(); ++e)
        if (own.is_element(e->row()))
          exact = exact && S.el(e->row(), e->column()) == e->value();
      for (auto e = S.begin(); e != S.end(); ++e)
        exact = exact && (own.is_element(e->row()) ? e->value() == W.el(e->row(), e->column()) : std::isnan(e->value()));
      out << "RowSums of a matrix assembled by parts (" << n << " rows in uneven blocks): exact in each process's "
          << "rows, NaN in the others: " << (everywhere(exact) ? "ok" : "FAILS") << "\n";
    }
    {
      // Two spaces of one mesh numbered by part at once, as the flow's
      // (processes::distribute_dofs) and p-multigrid's Q1 level
      // (number_dofs_by_part): for each size, a process's rows are exactly
      // the dofs get_subdomain_association() gives its part (an interface
      // dof goes with the part of smaller id), in blocks of whole nodes;
      // the second space does not take the first one's rows away.
      // (the run's mesh: parallel::shared, partitioned by deal.II)
      const auto mesh = processes::new_triangulation<3>();
      dealii::GridGenerator::subdivided_hyper_rectangle(*mesh, {6, 4, 3}, dealii::Point<3>(),
                                                        dealii::Point<3>(3., 2., 1.));
      dealii::DoFHandler<3>   fine(*mesh), coarse(*mesh);
      const dealii::FESystem<3> q2(dealii::FE_Q<3>(2), 3), q1(dealii::FE_Q<3>(1), 3);
      processes::distribute_dofs(fine, q2);
      coarse.distribute_dofs(q1);
      processes::number_dofs_by_part(coarse);
      const auto by_part = [](const dealii::DoFHandler<3> &dofs) {
        std::vector<dealii::types::subdomain_id> part(dofs.n_dofs());
        dealii::DoFTools::get_subdomain_association(dofs, part);
        const dealii::IndexSet own = processes::owned_rows(dofs.n_dofs(), 3);
        bool                   ok  = own.n_elements() > 0;
        for (dealii::types::global_dof_index i = 0; i < dofs.n_dofs(); ++i)
          ok = ok && (part[i] == processes::rank()) == own.is_element(i);
        return ok;
      };
      const bool both = by_part(fine) && by_part(coarse);
      out << "Q2 and Q1 velocity dofs of one mesh (" << fine.n_dofs() << " and " << coarse.n_dofs()
          << ") numbered by part: each process owns its part's dofs of each: " << (everywhere(both) ? "ok" : "FAILS")
          << "\n";
    }
    if (processes::writes_output())
      std::ofstream(file) << out.str();
    return 0;
  }
} // namespace



int
main(int argc, char **argv)
{
  if (argc == 3 && std::string(argv[1]) == "--launched")
    return launched(argv[2]);

  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  unsetenv("DEAL_II_NUM_THREADS");
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  for (const unsigned int processes : {2u, 3u})
    {
      const std::string file = "lines-" + std::to_string(processes) + ".txt";
      std::filesystem::remove(file);
      const std::string command = "mpirun --oversubscribe --bind-to none -np " + std::to_string(processes) + " " +
                                  self + " --launched " + file + " > out-" + std::to_string(processes) +
                                  ".txt 2>&1";
      const int status = std::system(command.c_str());
      std::cout << "# " << processes << " processes: exit " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1)
                << std::endl;
      std::ifstream lines(file);
      std::cout << (lines ? std::string(std::istreambuf_iterator<char>(lines), {}) : "no lines written\n");
    }
  return 0;
}
