// The iterative solvers' operators across the MPI processes: vectors divided among them (RowLayout), products by each process's rows with the border's entries exchanged (RowBlockMatrix), an ML hierarchy.
#include <dieflow/base/processes.h>
#include <dieflow/solvers/rigid_body_modes.h>
#include <dieflow/solvers/row_blocks.h>

#include <deal.II/base/parallel.h>

#include <Teuchos_ParameterList.hpp>

#include <algorithm>
#include <cstdint>

namespace dieflow
{
  namespace
  {
    /// A tag of its own for the products' messages.
    constexpr int import_tag = 17;
  } // namespace



  void
  RowLayout::reinit_rows(const size_type size, const unsigned int block)
  {
    n         = size;
    group     = 1;
    row_block = block;
    own_groups.clear();
    owner_of_group.clear();
    place_of_group.clear();
    grouped = false;
    // Every process's start (processes::owned_rows(n, block)'s blocks).
    starts.resize(processes::n() + 1);
    for (unsigned int q = 0; q <= processes::n(); ++q)
      starts[q] = processes::first_owned_row(n, block, q);
    AssertDimension(starts.back(), n);
    first      = starts[processes::rank()];
    local_size = starts[processes::rank() + 1] - first;
    dealii::IndexSet owned(n);
    owned.add_range(first, first + local_size);
    partitioner = std::make_shared<dealii::Utilities::MPI::Partitioner>(owned, processes::communicator());
  }



  void
  RowLayout::reinit_groups(const std::vector<unsigned int> &owner, const unsigned int group_size)
  {
    grouped = true;
    group   = group_size;
    n       = size_type(owner.size()) * group;
    first = 0;
    starts.clear();
    owner_of_group = owner;
    place_of_group.assign(owner.size(), 0);
    own_groups.clear();
    std::vector<size_type> count(processes::n(), 0);
    for (unsigned int g = 0; g < owner.size(); ++g)
      {
        AssertIndexRange(owner[g], processes::n());
        place_of_group[g] = count[owner[g]]++;
        if (owner[g] == processes::rank())
          own_groups.push_back(g);
      }
    offsets.assign(processes::n() + 1, 0);
    for (unsigned int q = 0; q < processes::n(); ++q)
      offsets[q + 1] = offsets[q] + count[q] * group;
    local_size = size_type(own_groups.size()) * group;
    dealii::IndexSet owned(n);
    owned.add_range(offsets[processes::rank()], offsets[processes::rank() + 1]);
    partitioner = std::make_shared<dealii::Utilities::MPI::Partitioner>(owned, processes::communicator());
  }



  unsigned int
  RowLayout::owner(const size_type i) const
  {
    if (contiguous())
      return static_cast<unsigned int>(std::upper_bound(starts.begin(), starts.end(), i) - starts.begin()) - 1;
    return owner_of_group[i / group];
  }



  RowLayout::size_type
  RowLayout::local_index(const size_type i) const
  {
    if (contiguous())
      return i - starts[owner(i)];
    return size_type(place_of_group[i / group]) * group + i % group;
  }



  void
  RowLayout::reinit(DistributedVector &v) const
  {
    v.reinit(partitioner);
  }



  void
  RowLayout::extract(const dealii::Vector<double> &whole, DistributedVector &v) const
  {
    AssertDimension(whole.size(), n);
    reinit(v);
    if (contiguous())
      std::copy(whole.begin() + first, whole.begin() + first + local_size, v.begin());
    else
      for (size_type k = 0; k < local_size; ++k)
        v.local_element(k) = whole[whole_index(k)];
  }



  void
  RowLayout::gather(const DistributedVector &v, dealii::Vector<double> &whole) const
  {
    AssertDimension(v.locally_owned_size(), local_size);
    if (whole.size() != n)
      whole.reinit(n, true);
    if (processes::n() == 1)
      {
        std::copy(v.begin(), v.begin() + local_size, whole.begin());
        return;
      }
    if (contiguous())
      {
        std::copy(v.begin(), v.begin() + local_size, whole.begin() + first);
        processes::gather(whole, row_block);
        return;
      }
    std::vector<int> counts(processes::n()), displacements(processes::n());
    for (unsigned int q = 0; q < processes::n(); ++q)
      {
        displacements[q] = static_cast<int>(offsets[q]);
        counts[q]        = static_cast<int>(offsets[q + 1] - offsets[q]);
      }
    // The parts in the order of the ranks, then each group to its place.
    std::vector<double> parts(n);
    MPI_Allgatherv(v.begin(), static_cast<int>(local_size), MPI_DOUBLE, parts.data(), counts.data(),
                   displacements.data(), MPI_DOUBLE, processes::communicator());
    for (std::size_t g = 0; g < owner_of_group.size(); ++g)
      std::copy_n(parts.begin() + offsets[owner_of_group[g]] + size_type(place_of_group[g]) * group, group,
                  whole.begin() + g * group);
  }



  void
  ColumnImport::reinit(const dealii::SparsityPattern &pattern, const RowLayout &rows, const RowLayout &column_layout)
  {
    columns = &column_layout;
    const unsigned int P = processes::n(), me = processes::rank();
    send_local.assign(P, {});
    receive_whole.assign(P, {});
    send_buffers.assign(P, {});
    receive_buffers.assign(P, {});
    if (P == 1)
      return;
    // The columns this process's rows read that others hold, by holder
    // (each once, in increasing order).
    std::vector<bool>                       seen(pattern.n_cols(), false);
    std::vector<std::vector<std::uint64_t>> wanted(P);
    for (RowLayout::size_type k = 0; k < rows.n_local(); ++k)
      {
        const auto i = rows.whole_index(k);
        for (auto entry = pattern.begin(i); entry != pattern.end(i); ++entry)
          {
            const auto j = entry->column();
            if (seen[j])
              continue;
            seen[j]              = true;
            const unsigned int q = column_layout.owner(j);
            if (q != me)
              wanted[q].push_back(j);
          }
      }
    for (unsigned int q = 0; q < P; ++q)
      {
        std::sort(wanted[q].begin(), wanted[q].end());
        receive_whole[q].assign(wanted[q].begin(), wanted[q].end());
        receive_buffers[q].resize(wanted[q].size());
      }
    const auto asked = processes::exchange(wanted);
    for (unsigned int q = 0; q < P; ++q)
      {
        send_local[q].reserve(asked[q].size());
        for (const auto j : asked[q])
          send_local[q].push_back(static_cast<unsigned int>(column_layout.local_index(j)));
        send_buffers[q].resize(asked[q].size());
      }
  }



  void
  ColumnImport::import(const DistributedVector &src, dealii::Vector<double> &whole) const
  {
    const unsigned int       P = processes::n();
    std::vector<MPI_Request> requests;
    for (unsigned int q = 0; q < P; ++q)
      if (!receive_buffers[q].empty())
        {
          requests.emplace_back();
          MPI_Irecv(receive_buffers[q].data(), static_cast<int>(receive_buffers[q].size()), MPI_DOUBLE,
                    static_cast<int>(q), import_tag, processes::communicator(), &requests.back());
        }
    for (unsigned int q = 0; q < P; ++q)
      if (!send_local[q].empty())
        {
          for (std::size_t k = 0; k < send_local[q].size(); ++k)
            send_buffers[q][k] = src.local_element(send_local[q][k]);
          requests.emplace_back();
          MPI_Isend(send_buffers[q].data(), static_cast<int>(send_buffers[q].size()), MPI_DOUBLE, static_cast<int>(q),
                    import_tag, processes::communicator(), &requests.back());
        }
    // This process's own entries while the messages travel.
    const RowLayout &layout = *columns;
    if (layout.contiguous())
      std::copy(src.begin(), src.begin() + layout.n_local(), whole.begin() + layout.first_whole());
    else
      for (RowLayout::size_type k = 0; k < layout.n_local(); ++k)
        whole[layout.whole_index(k)] = src.local_element(k);
    MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
    for (unsigned int q = 0; q < P; ++q)
      for (std::size_t k = 0; k < receive_whole[q].size(); ++k)
        whole[receive_whole[q][k]] = receive_buffers[q][k];
  }



  void
  RowBlockMatrix::reinit(const dealii::SparseMatrix<double> &m, const RowLayout &row_layout,
                         const RowLayout &column_layout)
  {
    AssertDimension(m.m(), row_layout.size());
    AssertDimension(m.n(), column_layout.size());
    matrix       = &m;
    rows         = &row_layout;
    values       = processes::matrix_values(m);
    agreed_shape = {{m.m(), m.n(), m.n_nonzero_elements()}};
    whole_src.reinit(0);
    if (processes::n() == 1)
      return;
    import.reinit(m.get_sparsity_pattern(), row_layout, column_layout);
    whole_src.reinit(m.n());
  }



  void
  RowBlockMatrix::reinit_values(const dealii::SparseMatrix<double> &m)
  {
    Assert(has_pattern_of(m), dealii::ExcMessage("reinit_values() needs a matrix of the pattern reinit() was given"));
    matrix = &m;
    values = processes::matrix_values(m);
  }



  bool
  RowBlockMatrix::has_pattern_of(const dealii::SparseMatrix<double> &m) const
  {
    return matrix != nullptr && &m.get_sparsity_pattern() == &matrix->get_sparsity_pattern() &&
           agreed_shape == std::array<std::size_t, 3>{{m.m(), m.n(), m.n_nonzero_elements()}};
  }



  void
  RowBlockMatrix::multiply(DistributedVector &dst, const DistributedVector &src, const DistributedVector *b,
                           const Product what) const
  {
    Assert(&dst != &src, dealii::ExcMessage("a product's source and destination must differ"));
    if (dst.size() != matrix->m())
      rows->reinit(dst);
    AssertDimension(dst.locally_owned_size(), rows->n_local());
    AssertDimension(src.size(), matrix->n());
    Assert(b == nullptr || b->locally_owned_size() == rows->n_local(), dealii::ExcInternalError());
    const double *x = src.begin();
    if (processes::n() > 1)
      {
        import.import(src, whole_src);
        x = whole_src.begin();
      }
    const dealii::SparsityPattern &pattern = matrix->get_sparsity_pattern();
    double *const                  y       = dst.begin();
    const double *const            r       = b != nullptr ? b->begin() : nullptr;
    // The rows in chunks among this process's threads, as deal.II's own
    // product divides them. (deal.II's product itself reads a distributed
    // vector through its global index, a range check per entry: slower
    // on one process too, doc/parallel.md.)
    const bool      contiguous = rows->contiguous();
    const size_type first      = rows->first_whole();
    dealii::parallel::apply_to_subranges(
      size_type(0),
      rows->n_local(),
      [&](const size_type begin, const size_type end) {
        for (size_type k = begin; k < end; ++k)
          {
            const size_type    i      = contiguous ? first + k : rows->whole_index(k);
            const unsigned int length = pattern.row_length(i);
            // Started from dst or b, as deal.II's vmult_add and residual
            // do: one process computes the same bits as they did.
            double sum = what == Product::set ? 0. : what == Product::add ? y[k] : r[k];
            if (length > 0)
              {
                const double *const row = values + pattern.begin(i)->global_index();
                if (what == Product::residual)
                  for (unsigned int e = 0; e < length; ++e)
                    sum -= row[e] * x[pattern.column_number(i, e)];
                else
                  for (unsigned int e = 0; e < length; ++e)
                    sum += row[e] * x[pattern.column_number(i, e)];
              }
            y[k] = sum;
          }
      },
      1000);
  }



  void
  RowBlockMatrix::vmult(DistributedVector &dst, const DistributedVector &src) const
  {
    multiply(dst, src, nullptr, Product::set);
  }



  void
  RowBlockMatrix::vmult_add(DistributedVector &dst, const DistributedVector &src) const
  {
    multiply(dst, src, nullptr, Product::add);
  }



  void
  RowBlockMatrix::residual(DistributedVector &dst, const DistributedVector &x, const DistributedVector &b) const
  {
    multiply(dst, x, &b, Product::residual);
  }



  void
  RowBlockMatrix::inverse_diagonal(DistributedVector &d) const
  {
    AssertDimension(matrix->m(), matrix->n());
    rows->reinit(d);
    for (size_type k = 0; k < rows->n_local(); ++k)
      d.local_element(k) = 1. / matrix->diag_element(rows->whole_index(k));
  }



  template <int dim>
  void
  RowBlockAMG::initialize(const dealii::SparseMatrix<double> &                              matrix,
                          const std::vector<double> &                                       modes,
                          const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &data,
                          const unsigned int                                                pde_equations,
                          const unsigned int                                                prolongator_sweeps)
  {
    if (processes::n() == 1)
      {
        initialize_with_rigid_body_modes<dim>(amg, copy, matrix, modes, data, pde_equations, prolongator_sweeps);
        return;
      }
    // Whole nodes per process: ML aggregates the pde_equations rows of a node together.
    rows = processes::owned_rows(matrix.m(), pde_equations);
    // A pattern made afresh: on one it knows, Trilinos's copy would keep
    // the old value where the new one is zero.
    amg.clear();
    copy.clear();
    copy.reinit(rows, rows, matrix, processes::communicator());
    Teuchos::ParameterList              parameters;
    std::unique_ptr<Epetra_MultiVector> constant_modes;
    data.set_parameters(parameters, constant_modes, copy);
    // ML reads this process's rows of each near-null vector, one after the
    // other, while initialize() builds the hierarchy.
    const std::size_t n = matrix.m(), n_local = rows.n_elements(), n_modes = modes.size() / n;
    const std::size_t first = processes::first_owned_row(n, pde_equations, processes::rank());
    // (at least one entry: ML stops a process whose null space pointer is null)
    local_modes.resize(std::max<std::size_t>(1, n_modes * n_local));
    for (std::size_t k = 0; k < n_modes; ++k)
      for (std::size_t i = 0; i < n_local; ++i)
        local_modes[k * n_local + i] = modes[k * n + first + i];
    parameters.set("null space: type", "pre-computed");
    parameters.set("null space: dimension", static_cast<int>(n_modes));
    parameters.set("null space: vectors", local_modes.data());
    if (pde_equations > 1)
      parameters.set("PDE equations", static_cast<int>(pde_equations));
    parameters.set("aggregation: smoothing sweeps", static_cast<int>(prolongator_sweeps));
    amg.initialize(copy, parameters);
  }



  void
  RowBlockAMG::vmult(DistributedVector &dst, const DistributedVector &src) const
  {
    // On P > 1 src and dst hold this process's rows, as ML's matrix does.
    if (dst.size() != src.size())
      dst.reinit(src, true);
    amg.vmult(dst, src);
  }

  template void
  RowBlockAMG::initialize<2>(const dealii::SparseMatrix<double> &,
                             const std::vector<double> &,
                             const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &,
                             const unsigned int,
                             const unsigned int);
  template void
  RowBlockAMG::initialize<3>(const dealii::SparseMatrix<double> &,
                             const std::vector<double> &,
                             const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &,
                             const unsigned int,
                             const unsigned int);
} // namespace dieflow
