// A two-level p-multigrid cycle for the Q2 velocity block: Chebyshev smoothing on Q2, one AMG V-cycle on the Q1 Galerkin operator.
#include <dieflow/base/processes.h>
#include <dieflow/solvers/iterative_solver.h>
#include <dieflow/solvers/p_multigrid.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>

#include <algorithm>

namespace dieflow
{
  template <int dim>
  void
  PMultigrid<dim>::reinit(const dealii::DoFHandler<dim> &dof_handler)
  {
    coarse_dofs.reinit(dof_handler.get_triangulation());
    coarse_dofs.distribute_dofs(coarse_fe);
    // On P > 1 numbered part by part as the flow's dofs are: each process
    // then owns its part's Q1 rows, and the transfers P and P^T exchange
    // only the entries at the parts' border (numbered as they come, the
    // restriction imported some half of the fine vector at every cycle).
    processes::number_dofs_by_part(coarse_dofs);
    coarse_modes = rigid_body_modes(coarse_dofs);

    const auto &               fe = dof_handler.get_fe();
    dealii::FullMatrix<double> local(fe.n_dofs_per_cell(), coarse_fe.n_dofs_per_cell());
    dealii::FETools::get_interpolation_matrix(coarse_fe, fe, local);
    // f(fine dof, coarse dof, value) for every entry of P, cell by cell.
    const auto for_each_entry = [&](const auto &f) {
      std::vector<dealii::types::global_dof_index> fine(fe.n_dofs_per_cell()), coarse(coarse_fe.n_dofs_per_cell());
      auto coarse_cell = coarse_dofs.begin_active();
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          cell->get_dof_indices(fine);
          coarse_cell->get_dof_indices(coarse);
          for (unsigned int i = 0; i < fine.size(); ++i)
            for (unsigned int j = 0; j < coarse.size(); ++j)
              if (std::abs(local(i, j)) > 1e-12)
                f(fine[i], coarse[j], local(i, j));
          ++coarse_cell;
        }
    };
    dealii::DynamicSparsityPattern pattern(dof_handler.n_dofs(), coarse_dofs.n_dofs()),
      transposed(coarse_dofs.n_dofs(), dof_handler.n_dofs());
    // P^T on P > 1 in the coarse rows this process owns alone (those the
    // restriction computes; whole nodes, as RowBlockAMG reads them). One
    // process restricts with P itself (Tvmult), and stores no P^T.
    const dealii::IndexSet restricted = processes::n() > 1 ? processes::owned_rows(coarse_dofs.n_dofs(), dim) :
                                                              dealii::IndexSet(coarse_dofs.n_dofs());
    for_each_entry([&](const auto i, const auto j, const double) {
      pattern.add(i, j);
      if (restricted.is_element(j))
        transposed.add(j, i);
    });
    embedding.clear();
    restriction.clear();
    embedding_pattern.copy_from(pattern);
    embedding.reinit(embedding_pattern);
    restriction_pattern.copy_from(transposed);
    restriction.reinit(restriction_pattern);
    // The embedding is continuous: every cell sharing a fine dof gives it
    // the same row, so setting (not adding) is consistent. A Q1 vertex is
    // the Q2 node where its shape function is 1.
    vertex_dof.assign(coarse_dofs.n_dofs(), 0);
    for_each_entry([&](const auto i, const auto j, const double value) {
      embedding.set(i, j, value);
      if (restricted.is_element(j))
        restriction.set(j, i, value);
      if (std::abs(value - 1.) < 1e-12)
        vertex_dof[j] = i;
    });
    product.clear();
    coarse_matrix.clear();
    patterns_built = false;
  }



  void
  galerkin_entries(const dealii::SparsityPattern &A, const dealii::SparsityPattern &embedding,
                   dealii::DynamicSparsityPattern &entries)
  {
    std::vector<bool>                            in_row(embedding.n_cols(), false);
    std::vector<dealii::types::global_dof_index> columns;
    for (const auto i : processes::owned_rows(A.n_rows()))
      {
        columns.clear();
        for (auto a = A.begin(i); a != A.end(i); ++a)
          for (auto p = embedding.begin(a->column()); p != embedding.end(a->column()); ++p)
            if (!in_row[p->column()])
              {
                in_row[p->column()] = true;
                columns.push_back(p->column());
              }
        std::sort(columns.begin(), columns.end());
        for (auto p = embedding.begin(i); p != embedding.end(i); ++p)
          entries.add_entries(p->column(), columns.begin(), columns.end(), true);
        for (const auto j : columns)
          in_row[j] = false;
      }
  }



  void
  galerkin_product(const dealii::SparseMatrix<double> &A,
                   const dealii::SparseMatrix<double> &embedding,
                   const dealii::Vector<double> &      free,
                   const processes::RowSums &          sums,
                   dealii::SparseMatrix<double> &      coarse_matrix)
  {
    // A_1 = sum over the fine rows i of P(i,:)^T D_i (A D P)(i,:): each
    // process sums its block of rows (processes::owned_rows()), row by row
    // through a dense accumulator of A D P's row, into A_1's pattern, and
    // the partial A_1 are summed into each process's own coarse rows.
    // deal.II's products have no range of rows: on every process they
    // formed the whole A_1 at every set-up, 4-5 % of each process's time
    // in a 2-process run of the 3D bar (perf).
    coarse_matrix = 0;
    std::vector<double>                          row(coarse_matrix.n(), 0.);
    std::vector<bool>                            in_row(coarse_matrix.n(), false);
    std::vector<dealii::types::global_dof_index> columns;
    std::vector<double>                          values;
    for (const auto i : processes::owned_rows(A.m()))
      {
        if (free[i] == 0)
          continue;
        columns.clear();
        for (auto a = A.begin(i); a != A.end(i); ++a)
          if (free[a->column()] != 0)
            for (auto p = embedding.begin(a->column()); p != embedding.end(a->column()); ++p)
              {
                if (!in_row[p->column()])
                  {
                    in_row[p->column()] = true;
                    columns.push_back(p->column());
                  }
                row[p->column()] += a->value() * p->value();
              }
        std::sort(columns.begin(), columns.end());
        values.resize(columns.size());
        for (auto p = embedding.begin(i); p != embedding.end(i); ++p)
          {
            for (unsigned int c = 0; c < columns.size(); ++c)
              values[c] = p->value() * row[columns[c]];
            coarse_matrix.add(p->column(), columns.size(), columns.data(), values.data(), false, true);
          }
        for (const auto j : columns)
          {
            row[j]    = 0;
            in_row[j] = false;
          }
      }
    sums.sum(coarse_matrix);
  }



  template <int dim>
  void
  PMultigrid<dim>::initialize(const RowBlockMatrix &                    A_rows,
                              const dealii::AffineConstraints<double> &constraints,
                              const dealii::Vector<double> *           flow)
  {
    matrix                                = &A_rows;
    const dealii::SparseMatrix<double> &A = A_rows.whole();
    const RowLayout &                   fine  = A_rows.row_layout();
    dealii::Vector<double> free_whole(A.m());
    for (unsigned int i = 0; i < A.m(); ++i)
      free_whole[i] = constraints.is_constrained(i) ? 0. : 1.;

    // A_1 = P^T D A D P, D = diag(free).
    // The patterns depend on the mesh only (A's pattern and P): built once
    // per mesh, then only the values are recomputed.
    const bool first = !patterns_built;
    patterns_built   = true;
    if (first)
      {
        // Whole nodes per process on Q1, as RowBlockAMG reads its rows;
        // the transfers' exchanges agreed once per mesh.
        coarse_layout.reinit_rows(coarse_dofs.n_dofs(), dim);
        prolongation_rows.reinit(embedding, fine, coarse_layout);
        if (processes::n() > 1)
          restriction_rows.reinit(restriction, coarse_layout, fine);
      }
    if (processes::n() > 1)
      {
        // A holds its sums, and its pattern, in each process's own rows
        // alone (processes::RowSums): deal.II's products, which read every
        // row, would form NaN. A_1 by A's own rows, into each process's own
        // coarse rows (whole nodes, as RowBlockAMG reads them).
        if (first)
          {
            dealii::DynamicSparsityPattern entries(coarse_dofs.n_dofs(), coarse_dofs.n_dofs());
            galerkin_entries(A.get_sparsity_pattern(), embedding.get_sparsity_pattern(), entries);
            coarse_sums.reinit(entries, coarse_pattern, dim);
          }
        coarse_matrix.reinit(coarse_pattern);
        galerkin_product(A, embedding, free_whole, coarse_sums, coarse_matrix);
      }
    else
      {
        if (first)
          {
            product_pattern.reinit(0, 0, 0);
            product_pattern.compress();
            product.reinit(product_pattern);
            coarse_pattern.reinit(0, 0, 0);
            coarse_pattern.compress();
            coarse_matrix.reinit(coarse_pattern);
          }
        else
          {
            product.reinit(product_pattern);
            coarse_matrix.reinit(coarse_pattern);
          }
        A.mmult(product, embedding, free_whole, first);
        embedding.Tmmult(coarse_matrix, product, free_whole, first);
      }
    // Only the patterns are kept between set-ups: A P's values, a share of
    // the peak heap, are not needed once A_1 is formed.
    product.clear();
    // Coarse dofs that reach only constrained fine dofs have empty rows
    // (on P > 1 each process mends its own rows, the mean over all).
    const dealii::IndexSet coarse_rows = processes::n() > 1 ? processes::owned_rows(coarse_matrix.m(), dim) :
                                                              dealii::complete_index_set(coarse_matrix.m());
    std::vector<double>    diagonal_sum{0.};
    for (const auto i : coarse_rows)
      diagonal_sum[0] += std::abs(coarse_matrix.diag_element(i));
    processes::sum(diagonal_sum);
    for (const auto i : coarse_rows)
      if (coarse_matrix.diag_element(i) == 0)
        coarse_matrix.diag_element(i) = diagonal_sum[0] / coarse_matrix.m();

    typename decltype(smoother)::AdditionalData data;
    // The outer iterations depend little on the Chebyshev degree and range
    // (doc/benchmarks.md); power iteration because slipping friction makes
    // A non-symmetric.
    data.degree               = 3;
    data.smoothing_range      = 15;
    data.eig_cg_n_iterations  = 12;
    data.eigenvalue_algorithm = decltype(data)::EigenvalueAlgorithm::power_iteration;
    // The diagonal given, of this process's rows (deal.II would read
    // every row's, whole).
    data.preconditioner = std::make_shared<dealii::DiagonalMatrix<DistributedVector>>();
    A_rows.inverse_diagonal(data.preconditioner->get_vector());
    smoother.initialize(A_rows, data);

    // The rigid-body modes, and the flow as one more where it is given.
    std::vector<double> modes_with_flow;
    const bool          with_flow = flow != nullptr && flow->linfty_norm() > 0;
    if (with_flow)
      {
        modes_with_flow.reserve(coarse_modes.size() + vertex_dof.size());
        modes_with_flow.assign(coarse_modes.begin(), coarse_modes.end());
        for (const auto i : vertex_dof)
          modes_with_flow.push_back((*flow)[i]);
      }
    const std::vector<double> &modes = with_flow ? modes_with_flow : coarse_modes;
    auto amg_data = velocity_amg_data({}, false);
    // Aggregation across every connection: dropping the weak ones (below
    // 0.02 of the diagonals, as ASPECT does) weakens ML's cycle where the
    // viscosity contrast is strong; for a Newtonian material it changes
    // little (doc/benchmarks.md, "Figures behind the code's rules").
    amg_data.aggregation_threshold = 0;
    // Four Chebyshev sweeps on each ML level instead of two: fewer Krylov
    // iterations and less time, Newtonian or strongly shear-thinning, as
    // the Q1 levels are cheap beside the Q2 smoothing (doc/benchmarks.md).
    amg_data.smoother_sweeps = 4;
    // Aggregates of whole nodes (the dim velocity components of a vertex,
    // consecutive in coarse_dofs; numbering by part keeps them so, as a
    // vertex's dofs go with one part): smoothed
    // aggregation interpolates the rotations only where an aggregate holds
    // every component of its nodes (Vanek, Mandel, Brezina 1996). With
    // aggregates of single dofs the Krylov iterations per decade grow with
    // the mesh; with whole nodes they stay as with the Q1 problem solved
    // exactly, and on die2d it is neutral in time (doc/benchmarks.md).
    // In 2D two Jacobi sweeps on ML's tentative prolongator instead of
    // one: on sheared Q1 cells one sweep leaves ML's V-cycle weaker with
    // every refinement, two keep it as strong as an exact Q1 solve, in the
    // same time for some more memory. In 3D the second sweep saved no
    // iterations and cost time and memory: one sweep there
    // (doc/benchmarks.md, "Figures behind the code's rules").
    const unsigned int prolongator_sweeps = dim == 2 ? 2 : 1;
    coarse_amg.initialize<dim>(coarse_matrix, modes, amg_data, dim, prolongator_sweeps);
    fine.extract(free_whole, free);
    fine.reinit(residual);
    coarse_layout.reinit(coarse_residual);
    coarse_layout.reinit(coarse_correction);
    // ML works on its own (Trilinos) copy of A_1.
    coarse_matrix.clear();
  }



  template <int dim>
  void
  PMultigrid<dim>::vmult(DistributedVector &dst, const DistributedVector &src) const
  {
    smoother.vmult(dst, src);
    matrix->residual(residual, dst, src);
    residual.scale(free);
    if (processes::n() > 1)
      restriction_rows.vmult(coarse_residual, residual);
    else
      embedding.Tvmult(coarse_residual, residual);
    coarse_amg.vmult(coarse_correction, coarse_residual);
    prolongation_rows.vmult(residual, coarse_correction);
    residual.scale(free);
    dst += residual;
    smoother.step(dst, src);
  }

  template class PMultigrid<2>;
  template class PMultigrid<3>;
} // namespace dieflow
