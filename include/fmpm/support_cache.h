// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_support_cache_h
#define fmpm_support_cache_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * @brief Every locally owned material point of this step and its support:
   * the nodes i with S_ip and G_ip (seed 000 Eqs. 1.1, 2.8; S̄, Ḡ of seed 001
   * for GIMP/CPDI).
   *
   * Built once per step, at the positions of the step's start and in cell
   * order, for every shape function (classic included). Every pass of the
   * step reads it: m, p, f and m̃ to the grid (Sᵀ, Gᵀ), the strain update
   * (G), the particle update (S) and the USL+/USAVG+ re-extrapolation. No
   * pass evaluates a shape function.
   *
   * Hanging nodes are resolved here: a constrained node i with
   * v_i = Σ_j c_ij v_j passes its weights to its masters (S_jp += c_ij S_ip,
   * G_jp += c_ij G_ip), so that every entry is a free node. Sᵀ through the
   * cache is then the condensed extrapolation and S the interpolation of
   * the distributed field, with no constraint logic in any pass.
   *
   * Point k of the cache is point k of the MaterialPoints store (its
   * cells and cell ranges are the store's) until the points are re-binned
   * at the end of the step.
   *
   * @tparam dim space dimension
   */
  template <int dim>
  struct SupportCache
  {
    /** @name Per point, in the order of the point store */
    /** @{ */
    /** Material index of the point (filled with several materials only). */
    std::vector<unsigned char> material;
    /** The point's support is entries [support_begin[k], support_begin[k+1]).
     */
    std::vector<unsigned int> support_begin;
    /** @} */

    /** @name Per support entry */
    /** @{ */
    /** Local index of the node in the ghosted grid vectors. */
    std::vector<unsigned int> node;
    /** S_ip. */
    std::vector<double> S;
    /** G_ip = ∇S_i(x_p). Units: 1/m. */
    std::vector<Tensor<1, dim>> G;
    /** @} */

    /** @brief Number of cached points. */
    unsigned int
    n_points() const
    {
      return support_begin.empty() ? 0 : support_begin.size() - 1;
    }

    /** @brief Forget everything (keeps the memory). */
    void
    clear()
    {
      material.clear();
      support_begin.assign(1, 0);
      node.clear();
      S.clear();
      G.clear();
    }

    /**
     * @brief Append a support entry for node @p local_index to the point
     * being built, merging it with an entry for the same node added since
     * @p first (a master reached directly and through a hanging node).
     */
    void
    add_entry(const unsigned int    first,
              const unsigned int    local_index,
              const double          S_ip,
              const Tensor<1, dim> &G_ip)
    {
      for (unsigned int k = first; k < node.size(); ++k)
        if (node[k] == local_index)
          {
            S[k] += S_ip;
            G[k] += G_ip;
            return;
          }
      node.push_back(local_index);
      S.push_back(S_ip);
      G.push_back(G_ip);
    }

    /** @brief Bytes held (capacity), for the benchmark's memory figure. */
    std::size_t
    memory_consumption() const
    {
      return material.capacity() +
             (support_begin.capacity() + node.capacity()) *
               sizeof(unsigned int) +
             S.capacity() * sizeof(double) +
             G.capacity() * sizeof(Tensor<1, dim>);
    }
  };
} // namespace fmpm

#endif
