// The penalty term of the Q2-P1disc pair in mixed form: the blocks B and B^T, the cell masses M_K, and lambda, eta and h per cell.
#include <dieflow/base/processes.h>
#include <dieflow/solvers/mixed_penalty.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <cmath>

#include <algorithm>

namespace dieflow
{
  template <int dim>
  void
  MixedPenalty<dim>::reinit(const dealii::DoFHandler<dim> &          dof_handler,
                             const dealii::AffineConstraints<double> &hanging,
                             const unsigned int                       modes_per_cell)
  {
    n_modes = modes_per_cell;
    n_cells = dof_handler.get_triangulation().n_active_cells();
    const unsigned int n_dofs = dof_handler.n_dofs();

    // The update constraints other than hanging nodes couple the
    // components of one node (walls, contact), which every cell couples
    // anyway: the hanging-node pattern serves all, as for the velocity block.
    // B^T as the velocity block on P > 1 processes: each process's cells'
    // entries, to which RowSums adds the others' in its own rows.
    dealii::AffineConstraints<double>           none;
    none.close();
    dealii::DynamicSparsityPattern              b(n_cells * n_modes, n_dofs), bt(n_dofs, n_cells * n_modes);
    std::vector<dealii::types::global_dof_index> dofs(dof_handler.get_fe().n_dofs_per_cell()), modes(n_modes);
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(dofs);
        for (unsigned int m = 0; m < n_modes; ++m)
          modes[m] = cell->active_cell_index() * n_modes + m;
        none.add_entries_local_to_global(modes, hanging, dofs, b, true);
        if (processes::owns(cell))
          hanging.add_entries_local_to_global(dofs, none, modes, bt, true);
      }
    divergence.clear();
    gradient.clear();
    divergence_pattern.copy_from(b);
    gradient_sums.reinit(bt, gradient_pattern);
    divergence.reinit(divergence_pattern);
    gradient.reinit(gradient_pattern);
    part.assign(n_cells, 0);
    if (processes::n() > 1)
      for (const auto &cell : dof_handler.active_cell_iterators())
        part[cell->active_cell_index()] = cell->subdomain_id();
    masses.assign(n_cells * n_modes * n_modes, 0.);
    inverse_masses.assign(n_cells * n_modes * n_modes, 0.);
    penalty.reinit(n_cells);
    viscosity.reinit(n_cells);
    size.reinit(n_cells);
  }



  template <int dim>
  void
  MixedPenalty<dim>::clear_values()
  {
    divergence = 0;
    gradient   = 0;
    penalty    = 0;
    viscosity  = 0;
    size       = 0;
    std::fill(masses.begin(), masses.end(), 0.);
    std::fill(inverse_masses.begin(), inverse_masses.end(), 0.);
  }



  template <int dim>
  void
  MixedPenalty<dim>::sum_over_processes()
  {
    processes::sum(divergence);
    gradient_sums.sum(gradient);
    processes::sum(penalty);
    processes::sum(viscosity);
    processes::sum(size);
    processes::sum(masses);
    processes::sum(inverse_masses);
  }



  template <int dim>
  void
  MixedPenalty<dim>::set_cell(const unsigned int                cell,
                              const dealii::FullMatrix<double> &mass,
                              const dealii::FullMatrix<double> &inverse_mass,
                              const double                      cell_penalty,
                              const double                      cell_viscosity,
                              const double                      cell_size)
  {
    double *M    = &masses[cell * n_modes * n_modes];
    double *Minv = &inverse_masses[cell * n_modes * n_modes];
    for (unsigned int m = 0; m < n_modes; ++m)
      for (unsigned int n = 0; n < n_modes; ++n)
        {
          M[m * n_modes + n]    = mass(m, n);
          Minv[m * n_modes + n] = inverse_mass(m, n);
        }
    penalty[cell]   = cell_penalty;
    viscosity[cell] = cell_viscosity;
    size[cell]      = cell_size;
  }



  namespace
  {
    /// dst_k = factor_c K_c src_k for the k-th cell (c = cells[k], or k
    /// where @p cells is null), K_c the cell's block of @p blocks, on
    /// @p n_cells cells of n_modes entries each (in place allowed).
    void
    block_diagonal_vmult(const std::vector<double> &   blocks,
                         const unsigned int            n_modes,
                         const std::size_t             n_cells,
                         const unsigned int *          cells,
                         double *                      dst,
                         const double *                src,
                         const dealii::Vector<double> &factor)
    {
      std::vector<double> sum(n_modes);
      for (std::size_t k = 0; k < n_cells; ++k)
        {
          const std::size_t c = cells != nullptr ? cells[k] : k;
          const double *    K = &blocks[c * n_modes * n_modes];
          for (unsigned int m = 0; m < n_modes; ++m)
            {
              sum[m] = 0;
              for (unsigned int n = 0; n < n_modes; ++n)
                sum[m] += K[m * n_modes + n] * src[k * n_modes + n];
            }
          for (unsigned int m = 0; m < n_modes; ++m)
            dst[k * n_modes + m] = factor[c] * sum[m];
        }
    }
  } // namespace



  template <int dim>
  void
  MixedPenalty<dim>::mass_vmult(dealii::Vector<double> &      dst,
                                const dealii::Vector<double> &src,
                                const dealii::Vector<double> &factor) const
  {
    if (dst.size() != src.size())
      dst.reinit(src.size());
    block_diagonal_vmult(masses, n_modes, factor.size(), nullptr, dst.begin(), src.begin(), factor);
  }



  template <int dim>
  void
  MixedPenalty<dim>::inverse_mass_vmult(dealii::Vector<double> &      dst,
                                        const dealii::Vector<double> &src,
                                        const dealii::Vector<double> &factor) const
  {
    if (dst.size() != src.size())
      dst.reinit(src.size());
    block_diagonal_vmult(inverse_masses, n_modes, factor.size(), nullptr, dst.begin(), src.begin(), factor);
  }

  template <int dim>
  void
  MixedPenalty<dim>::cell_vmult(const CellBlock               which,
                                DistributedVector &           dst,
                                const DistributedVector &     src,
                                const dealii::Vector<double> &factor,
                                const RowLayout &             pressure) const
  {
    AssertDimension(pressure.group_size(), n_modes);
    if (dst.size() != src.size())
      pressure.reinit(dst);
    block_diagonal_vmult(which == CellBlock::mass ? masses : inverse_masses, n_modes, pressure.groups().size(),
                         pressure.groups().data(), dst.begin(), src.begin(), factor);
  }



  template <int dim>
  dealii::Vector<double>
  MixedPenalty<dim>::penalty_magnitude(const dealii::Vector<double> &v) const
  {
    dealii::Vector<double> b(n_pressure()), c(n_pressure()), rows(gradient.m());
    for (unsigned int i = 0; i < divergence.m(); ++i)
      for (auto e = divergence.begin(i); e != divergence.end(i); ++e)
        b[i] += std::abs(e->value() * v[e->column()]);
    for (unsigned int k = 0; k < n_cells; ++k)
      for (unsigned int m = 0; m < n_modes; ++m)
        for (unsigned int n = 0; n < n_modes; ++n)
          c[k * n_modes + m] += penalty[k] * std::abs(inverse_masses[(k * n_modes + m) * n_modes + n]) * b[k * n_modes + n];
    // B^T's rows where each process holds them (all on one), gathered.
    for (const auto i : processes::owned_rows(gradient.m()))
      for (auto e = gradient.begin(i); e != gradient.end(i); ++e)
        rows[i] += std::abs(e->value()) * c[e->column()];
    processes::gather(rows);
    return rows;
  }

  template class MixedPenalty<2>;
  template class MixedPenalty<3>;
} // namespace dieflow
