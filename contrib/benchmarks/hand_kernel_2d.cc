// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors
//
// hand_kernel_2d.cc: a standalone, hand-written, single-threaded MPM kernel
// of fmpm's benchmark scene parameters/benchmark_2d.prm (C++17 standard
// library only, no deal.II, not part of the build). It measures the speed
// floor of that scene on a machine: what the hardware allows for the same
// physics, the same point store and the same passes, to compare with
// build/applications/benchmark/fmpm-benchmark.
//
// The scene (as fmpm runs it; the kernel reproduces fmpm's time steps and
// energies to 11-12 digits):
//  - unit square, 200 x 200 Q1 cells, every boundary node fixed (both
//    velocity components zero);
//  - a disk, centre (0.5, 0.5), radius 0.45: the 2 x 2 midpoint points of
//    each cell that lie inside (fmpm's placement and test: 101,780 points,
//    volume h^2/4, mass 1000 h^2/4; ids in cell order);
//  - initial velocity (10 (y - 0.5), -10 (x - 0.5)), density 1000,
//    compressible neo-Hookean (fmpm's plane-strain formulas, log and exp),
//    K = 1e6 Pa, G = 4e5 Pa;
//  - FLIP (psi = 0), lumped mass, USF, Cayley increment of F
//    (dF = (I - L dt/2)^-1 (I + L dt/2)), fmpm's automatic time step
//    dt = 0.5 h_min / (c(J_max) + |V|_max) with the speeds of the last step
//    (the first from the initial state), 100 steps.
//
// The point store is fmpm's: structure of arrays in cell order (cells
// row-major, points by id in a cell): x (2), xi (2), id (64 bit), cell
// (32 bit), V, velocity (2), F (2x2 block; F33 = 1 is not stored), sigma
// (xx, yy, zz, xy), W, initial position (2); mass and initial volume are one
// value for all points. S and G are computed from xi in every pass that
// needs them. The passes loop over the cells with points (fmpm's
// cell_index / cell_point_begin).
//
// Phases of a step (each timed; ns per point-step = time / (points x steps)):
//  particles to grid  m = S^T M, p = S^T M V: per cell the moments
//           sum q, sum q xi, sum q eta, sum q xi eta of its points in
//           registers, turned into the 4 nodes' sums once per cell;
//  grid solve  conditions on p, v = p/m; after the stresses
//           p+ = p + f dt, conditions, f = (p+ - p)/dt, v+ = p+/m, a = f/m
//           (fmpm's operations; the divisions kept);
//  stress update  L = sum v_j (x) G_j, dF (Cayley), F, J, sigma, W, V = J V0
//           and the internal forces -V sigma G_j (USF: from the new stress),
//           added to the nodes once per cell. Two structures:
//             staged: batches of 256 consecutive points: L per cell, then
//                     the constitutive update as three loops over the batch
//                     (kinematics; log and exp; stress: the first and last
//                     vectorize, also at -O2), then the forces per cell;
//             fused:  everything per point, cell by cell (the scalar log
//                     and exp calls then cost a spill of the cell's values);
//  particle update  FLIP: V += (S a) dt, x += (S v+) dt, xi; a point that
//           left its cell gets its new cell and xi here (fmpm finds them in
//           its sort phase) and is listed;
//  re-bin   the store back in cell order, points by id in the cells that
//           received points (the order of a run that never moved them): the
//           new counts and starts of the cells (the arrivals by a radix
//           sort), the runs of points that stay, then every column. Two
//           variants:
//             in-place: per column, the values of the points that left go
//                       to a buffer, the runs of points that stay move within
//                       the column (runs moving right from the last, runs
//                       moving left from the first, runs that keep their
//                       places untouched; runs of <= 8 points as single
//                       moves in one loop without branches, longer ones by
//                       memmove), then the buffered values go to their
//                       places;
//             copying:  the method fmpm used before its in-place re-bin:
//                       every column copied run by run into a work array
//                       that then becomes the column.
// The sums over S_j and G_j are regrouped per cell (bilinear coefficients
// of the cell's nodal values): the same sums, rounded differently.
//
// Compile and run (from any directory): fmpm's Release flags, and native:
//   g++ -O2 -std=c++17 -funroll-loops -o hand_kernel_2d hand_kernel_2d.cc
//   g++ -O3 -march=native -std=c++17 -funroll-loops -o hand_kernel_2d_native
//       hand_kernel_2d.cc                               (one command line)
//   ./hand_kernel_2d [runs [configuration]]
// Default: 5 runs of each configuration, interleaved, in one process:
//   0 staged stress, in-place re-bin; 1 fused stress, in-place re-bin;
//   2 staged stress, copying re-bin. A second argument runs one of them.
// Options: -DHK_CPU_TIME times with the process's CPU time (std::clock)
// instead of wall time (on a loaded machine); -DHK_LIBMVEC (link with
// -lmvec) lets the staged stress update call glibc's vector log and exp
// (libmvec, up to 4 ulp instead of 1; the widest the build targets);
// -DHK_CHECK checks the store's order after every re-bin.
//
// Output per configuration: particle-steps per second over the 100 steps
// (set-up excluded), best and worst run; ns per point-step of each phase,
// best and worst run; the re-bin's statistics; t, dt and the kinetic and
// strain energy after step 100 (compare with fmpm's history.csv).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <limits>
#include <type_traits>
#include <vector>

#ifdef HK_LIBMVEC
#  include <immintrin.h>
extern "C"
{
#  if defined(__AVX512F__)
  __m512d _ZGVeN8v_log(__m512d);
  __m512d _ZGVeN8v_exp(__m512d);
#  elif defined(__AVX2__)
  __m256d _ZGVdN4v_log(__m256d);
  __m256d _ZGVdN4v_exp(__m256d);
#  else
  __m128d _ZGVbN2v_log(__m128d);
  __m128d _ZGVbN2v_exp(__m128d);
#  endif
}
#endif

namespace
{
  // ------------------------------------------------------------------ scene
  constexpr int    n_cells_x = 200;
  constexpr int    n_nodes_x = n_cells_x + 1;
  constexpr int    n_cells   = n_cells_x * n_cells_x;
  constexpr int    n_nodes   = n_nodes_x * n_nodes_x;
  constexpr double h         = 1.0 / n_cells_x; // deal.II: x_i = i (1-0)/200
  constexpr double inv_h     = n_cells_x;
  constexpr double density   = 1000;
  constexpr double K         = 1e6;
  constexpr double G         = 4e5;
  constexpr double courant   = 0.5;
  constexpr int    n_steps   = 100;
  constexpr double tolerance = 1e-12; // fmpm's is_inside()

  // The phase clock: wall time, or with -DHK_CPU_TIME the process's CPU
  // time (std::clock; a system call, 1 us resolution), which leaves out the
  // time the process waits for a core on a loaded machine.
  inline double
  now()
  {
#ifdef HK_CPU_TIME
    return double(std::clock()) / CLOCKS_PER_SEC;
#else
    return std::chrono::duration<double>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
#endif
  }

  /** 64-byte aligned array (zeroed: its pages are touched). */
  template <typename T>
  struct Buffer
  {
    T *p                   = nullptr;
    Buffer()               = default;
    Buffer(const Buffer &) = delete;
    Buffer &
    operator=(const Buffer &) = delete;
    ~Buffer()
    {
      std::free(p);
    }
    void
    allocate(const std::size_t n)
    {
      std::free(p);
      const std::size_t bytes = ((n * sizeof(T) + 63) / 64) * 64 + 64;
      p                       = static_cast<T *>(std::aligned_alloc(64, bytes));
      std::memset(static_cast<void *>(p), 0, bytes); // pages touched
    }
  };

  // -------------------------------------------------------------- the store
  enum Column : int
  {
    c_x,
    c_y,
    c_xi,
    c_eta,
    c_volume,
    c_vx,
    c_vy,
    c_fxx,
    c_fxy,
    c_fyx,
    c_fyy,
    c_sxx,
    c_syy,
    c_szz,
    c_sxy,
    c_w,
    c_x0,
    c_y0,
    n_double_columns
  };

  struct Store
  {
    std::size_t n = 0;
    double     *col[n_double_columns];
    uint64_t   *id;
    uint32_t   *cell;
    // The arrays behind the column pointers and the copying re-bin's work
    // arrays (the pointers are swapped).
    Buffer<double>   arrays[2][n_double_columns];
    Buffer<uint64_t> id_arrays[2];
    Buffer<uint32_t> cell_arrays[2];
    double          *work_col[n_double_columns];
    uint64_t        *work_id;
    uint32_t        *work_cell;
    // Cell structure: points of cell c at [begin[c], begin[c + 1]); the
    // cells with points and their first point (as fmpm's cell_index and
    // cell_point_begin).
    std::vector<uint32_t> count, begin, occupied_cell, occupied_begin;
    double                mass = 0, initial_volume = 0;

    void
    allocate(const std::size_t n_points)
    {
      for (int b = 0; b < 2; ++b)
        {
          for (int c = 0; c < n_double_columns; ++c)
            arrays[b][c].allocate(n_points);
          id_arrays[b].allocate(n_points);
          cell_arrays[b].allocate(n_points);
        }
      for (int c = 0; c < n_double_columns; ++c)
        {
          col[c]      = arrays[0][c].p;
          work_col[c] = arrays[1][c].p;
        }
      id        = id_arrays[0].p;
      work_id   = id_arrays[1].p;
      cell      = cell_arrays[0].p;
      work_cell = cell_arrays[1].p;
      count.assign(n_cells, 0);
      begin.assign(n_cells + 1, 0);
      occupied_cell.reserve(n_cells);
      occupied_begin.reserve(n_cells + 1);
    }

    void
    rebuild_occupied()
    {
      occupied_cell.clear();
      occupied_begin.clear();
      for (int c = 0; c < n_cells; ++c)
        if (count[c] != 0)
          {
            occupied_cell.push_back(c);
            occupied_begin.push_back(begin[c]);
          }
      occupied_begin.push_back(n); // (set-up only; the re-bin builds its own)
    }
  };

  // The grid: per node {m, px, py, -} and {vx, vy, fx, fy}, the latter
  // becoming {v+x, v+y, ax, ay} in the grid solve.
  struct alignas(32) NodeMass
  {
    double m, px, py, unused;
  };
  struct alignas(32) NodeVelocity
  {
    double vx, vy, fx, fy;
  };

  inline uint32_t
  first_node(const uint32_t c)
  {
    return c + c / n_cells_x; // j (n+1) + i with c = j n + i
  }

  std::vector<uint32_t> boundary_nodes;

  // --------------------------------------------------------------- set-up
  // fmpm's placement: cells in order, the QIterated<2>(QMidpoint, 2) points
  // of each (x fastest) mapped by the Q1 map, kept where
  // ((x - 0.5)/0.45)^2 + ((y - 0.5)/0.45)^2 <= 1; ids in that order.
  inline bool
  inside_disk(const double x, const double y)
  {
    return std::pow((x - 0.5) / 0.45, 2) + std::pow((y - 0.5) / 0.45, 2) <= 1.0;
  }

  template <typename F>
  void
  for_each_initial_point(const F &on_point)
  {
    const double q[2] = {0.25, 0.75};
    for (int j = 0; j < n_cells_x; ++j)
      for (int i = 0; i < n_cells_x; ++i)
        {
          const double x0 = i * h, x1 = (i + 1) * h, y0 = j * h,
                       y1 = (j + 1) * h;
          for (int b = 0; b < 2; ++b)
            for (int a = 0; a < 2; ++a)
              {
                // Q1 map: sum of S_i(xi) times the vertices.
                const double s0 = (1 - q[a]) * (1 - q[b]),
                             s1 = q[a] * (1 - q[b]), s2 = (1 - q[a]) * q[b],
                             s3 = q[a] * q[b];
                const double x  = s0 * x0 + s1 * x1 + s2 * x0 + s3 * x1;
                const double y  = s0 * y0 + s1 * y0 + s2 * y1 + s3 * y1;
                if (inside_disk(x, y))
                  on_point(j * n_cells_x + i, x, y, q[a], q[b]);
              }
        }
  }

  std::size_t
  count_initial_points()
  {
    std::size_t n = 0;
    for_each_initial_point([&](int, double, double, double, double) { ++n; });
    return n;
  }

  void
  initialize(Store &s)
  {
    std::fill(s.count.begin(), s.count.end(), 0);
    std::size_t k = 0;
    for_each_initial_point([&](const int    c,
                               const double x,
                               const double y,
                               const double xi,
                               const double eta) {
      s.col[c_x][k]      = x;
      s.col[c_y][k]      = y;
      s.col[c_xi][k]     = xi;
      s.col[c_eta][k]    = eta;
      s.col[c_volume][k] = 0.25 * h * h;
      s.col[c_vx][k]     = 10 * (y - 0.5);
      s.col[c_vy][k]     = -10 * (x - 0.5);
      s.col[c_fxx][k]    = 1;
      s.col[c_fxy][k]    = 0;
      s.col[c_fyx][k]    = 0;
      s.col[c_fyy][k]    = 1;
      s.col[c_sxx][k] = s.col[c_syy][k] = s.col[c_szz][k] = s.col[c_sxy][k] = 0;
      s.col[c_w][k]                                                         = 0;
      s.col[c_x0][k]                                                        = x;
      s.col[c_y0][k]                                                        = y;
      s.id[k]                                                               = k;
      s.cell[k]                                                             = c;
      ++s.count[c];
      ++k;
    });
    s.n = k;
    // fmpm's JxW of the midpoint rule: the cell's area / 4.
    s.initial_volume = 0.25 * h * h;
    s.mass           = density * s.initial_volume;
    s.begin[0]       = 0;
    for (int c = 0; c < n_cells; ++c)
      s.begin[c + 1] = s.begin[c] + s.count[c];
    s.rebuild_occupied();
  }

  // Wave speed of fmpm's neo-Hookean model at volume ratio J.
  inline double
  wave_speed(const double J)
  {
    const double tangent_bulk = 0.5 * K * (J + 1.0 / J);
    return std::sqrt((tangent_bulk + 4.0 / 3.0 * G) * J / density);
  }

  // ----------------------------------------------------------- phase: p2g
  void
  particles_to_grid(const Store &s, NodeMass *__restrict grid)
  {
    std::memset(static_cast<void *>(grid), 0, sizeof(NodeMass) * n_nodes);
    const double *__restrict xi_col  = s.col[c_xi];
    const double *__restrict eta_col = s.col[c_eta];
    const double *__restrict vx_col  = s.col[c_vx];
    const double *__restrict vy_col  = s.col[c_vy];
    const double   M                 = s.mass;
    const uint32_t n_occupied        = s.occupied_cell.size();
    for (uint32_t o = 0; o < n_occupied; ++o)
      {
        const uint32_t k_begin = s.occupied_begin[o],
                       k_end   = s.occupied_begin[o + 1];
        // sum_k S_j(xi_k) q_k from the moments sum q, sum q xi, sum q eta,
        // sum q xi eta of the cell's points (the bilinear S_j regrouped).
        double n = 0, s_x = 0, s_e = 0, s_xe = 0;
        double u = 0, u_x = 0, u_e = 0, u_xe = 0;
        double w = 0, w_x = 0, w_e = 0, w_xe = 0;
        for (uint32_t k = k_begin; k < k_end; ++k)
          {
            const double xi = xi_col[k], eta = eta_col[k], xe = xi * eta;
            const double vx = vx_col[k], vy = vy_col[k];
            n += 1;
            s_x += xi;
            s_e += eta;
            s_xe += xe;
            u += vx;
            u_x += vx * xi;
            u_e += vx * eta;
            u_xe += vx * xe;
            w += vy;
            w_x += vy * xi;
            w_e += vy * eta;
            w_xe += vy * xe;
          }
        NodeMass *const n0 = grid + first_node(s.occupied_cell[o]);
        NodeMass *const n2 = n0 + n_nodes_x;
        // S_0 = (1-xi)(1-eta), S_1 = xi(1-eta), S_2 = (1-xi) eta, S_3 = xi eta
        n0[0].m += M * ((n - s_x) - (s_e - s_xe));
        n0[0].px += M * ((u - u_x) - (u_e - u_xe));
        n0[0].py += M * ((w - w_x) - (w_e - w_xe));
        n0[1].m += M * (s_x - s_xe);
        n0[1].px += M * (u_x - u_xe);
        n0[1].py += M * (w_x - w_xe);
        n2[0].m += M * (s_e - s_xe);
        n2[0].px += M * (u_e - u_xe);
        n2[0].py += M * (w_e - w_xe);
        n2[1].m += M * s_xe;
        n2[1].px += M * u_xe;
        n2[1].py += M * w_xe;
      }
  }

  // ---------------------------------------------------------- phase: grid
  // Conditions on p (p = 0 on the fixed nodes), v = p/m, f = 0.
  void
  grid_velocity(NodeMass *__restrict mass_grid,
                NodeVelocity *__restrict v_grid,
                const double mass_floor)
  {
    for (const uint32_t b : boundary_nodes)
      mass_grid[b].px = mass_grid[b].py = 0;
    for (int i = 0; i < n_nodes; ++i)
      {
        const double m  = mass_grid[i].m;
        const bool   ok = m > mass_floor;
        v_grid[i].vx    = ok ? mass_grid[i].px / m : 0.0;
        v_grid[i].vy    = ok ? mass_grid[i].py / m : 0.0;
        v_grid[i].fx    = 0;
        v_grid[i].fy    = 0;
      }
  }

  // p+ = p + f dt, conditions, f = (p+ - p)(1/dt), v+ = p+/m, a = f/m, in
  // v_grid.
  inline void
  grid_node_update(const NodeMass &node,
                   NodeVelocity   &v,
                   const double    dt,
                   const double    inv_dt,
                   const double    mass_floor,
                   const bool      fixed)
  {
    const double m   = node.m;
    const bool   ok  = m > mass_floor;
    double       pxn = node.px + dt * v.fx;
    double       pyn = node.py + dt * v.fy;
    if (fixed)
      pxn = pyn = 0;
    const double fx = (pxn + -1. * node.px) * inv_dt;
    const double fy = (pyn + -1. * node.py) * inv_dt;
    v.vx            = ok ? pxn / m : 0.0;
    v.vy            = ok ? pyn / m : 0.0;
    v.fx            = ok ? fx / m : 0.0;
    v.fy            = ok ? fy / m : 0.0;
  }

  void
  grid_solve(const NodeMass *__restrict mass_grid,
             NodeVelocity *__restrict v_grid,
             const double dt,
             const double mass_floor)
  {
    const double inv_dt = 1. / dt;
    for (int i = 0; i < n_nodes; ++i)
      grid_node_update(mass_grid[i], v_grid[i], dt, inv_dt, mass_floor, false);
    // The fixed nodes again, with the condition p+ = 0 (the loop above
    // gave them p + f dt; 804 of 40401 nodes).
    for (const uint32_t b : boundary_nodes)
      grid_node_update(mass_grid[b], v_grid[b], dt, inv_dt, mass_floor, true);
  }

  // -------------------------------------------------------- phase: stress
  struct StressResult
  {
    double J_max  = 0;
    bool   failed = false;
  };

  // Cayley increment, F = dF F, J: the operations of fmpm's increments()
  // and its 2D F update.
  struct Kinematics
  {
    double Fxx, Fxy, Fyx, Fyy, J;
  };

  inline Kinematics
  kinematics(const double Lxx,
             const double Lxy,
             const double Lyx,
             const double Lyy,
             const double dt,
             const double Fxx,
             const double Fxy,
             const double Fyx,
             const double Fyy)
  {
    const double hxx = 0.5 * (Lxx * dt), hxy = 0.5 * (Lxy * dt),
                 hyx = 0.5 * (Lyx * dt), hyy = 0.5 * (Lyy * dt);
    const double A00 = 1.0 - hxx, A01 = 0.0 - hxy, A10 = 0.0 - hyx,
                 A11 = 1.0 - hyy;
    const double B00 = 1.0 + hxx, B01 = 0.0 + hxy, B10 = 0.0 + hyx,
                 B11                 = 1.0 + hyy;
    const double inverse_determinant = 1.0 / (A00 * A11 - A10 * A01);
    const double R00                 = A11 * inverse_determinant,
                 R01                 = -A01 * inverse_determinant,
                 R10                 = -A10 * inverse_determinant,
                 R11                 = A00 * inverse_determinant;
    const double d00 = R00 * B00 + R01 * B10, d01 = R00 * B01 + R01 * B11,
                 d10 = R10 * B00 + R11 * B10, d11 = R10 * B01 + R11 * B11;
    Kinematics k;
    k.Fxx = d00 * Fxx + d01 * Fyx;
    k.Fxy = d00 * Fxy + d01 * Fyy;
    k.Fyx = d10 * Fxx + d11 * Fyx;
    k.Fyy = d10 * Fxy + d11 * Fyy;
    k.J   = k.Fxx * k.Fyy - k.Fxy * k.Fyx;
    return k;
  }

  // fmpm's plane-strain neo-Hookean update after log J and J^(-2/3).
  struct Stress
  {
    double sxx, syy, szz, sxy, W;
  };

  inline Stress
  neo_hookean(const double Fxx,
              const double Fxy,
              const double Fyx,
              const double Fyy,
              const double J,
              const double log_J,
              const double J_m23)
  {
    const double b_xx          = J_m23 * (Fxx * Fxx + Fxy * Fxy);
    const double b_yy          = J_m23 * (Fyx * Fyx + Fyy * Fyy);
    const double b_xy          = J_m23 * (Fxx * Fyx + Fxy * Fyy);
    const double b_zz          = J_m23;
    const double I1_bar        = b_xx + b_yy + b_zz;
    const double pressure_part = 0.5 * K * (J * J - 1) - G * I1_bar / 3.0;
    Stress       s;
    s.sxx = (G * b_xx + pressure_part) / J;
    s.syy = (G * b_yy + pressure_part) / J;
    s.szz = (G * b_zz + pressure_part) / J;
    s.sxy = G * b_xy / J;
    s.W   = 0.5 * G * (I1_bar - 3) + 0.5 * K * (0.5 * (J * J - 1) - log_J);
    return s;
  }

  // Per cell: L = sum_j v_j (x) G_j with the bilinear S_j and
  // G_j = (1/h) dS_j/dxi is bilinear in the cell's nodal velocities:
  //   L_ax = (1/h) [(v_1 - v_0) + eta (v_3 - v_2 - v_1 + v_0)]_a,
  //   L_ay = (1/h) [(v_2 - v_0) + xi  (v_3 - v_2 - v_1 + v_0)]_a,
  // the same sum grouped per cell (it rounds differently from fmpm's
  // node-by-node sum: the results agree to round-off).
  struct CellVelocityGradient
  {
    double x10, x20, cx, y10, y20, cy;
    explicit CellVelocityGradient(const NodeVelocity *n0)
    {
      const NodeVelocity *n2 = n0 + n_nodes_x;
      x10                    = inv_h * (n0[1].vx - n0[0].vx);
      x20                    = inv_h * (n2[0].vx - n0[0].vx);
      cx  = inv_h * ((n2[1].vx - n2[0].vx) - (n0[1].vx - n0[0].vx));
      y10 = inv_h * (n0[1].vy - n0[0].vy);
      y20 = inv_h * (n2[0].vy - n0[0].vy);
      cy  = inv_h * ((n2[1].vy - n2[0].vy) - (n0[1].vy - n0[0].vy));
    }
    inline void
    at(const double xi,
       const double eta,
       double      &Lxx,
       double      &Lxy,
       double      &Lyx,
       double      &Lyy) const
    {
      Lxx = x10 + eta * cx;
      Lxy = x20 + xi * cx;
      Lyx = y10 + eta * cy;
      Lyy = y20 + xi * cy;
    }
  };

  // The internal forces f_j = -V sigma G_j of a cell's points, summed in
  // registers and added to the 4 nodes once per cell. With t = V sigma / h
  // and G_0 = (-(1-eta), -(1-xi))/h, G_1 = (1-eta, -xi)/h,
  // G_2 = (-eta, 1-xi)/h, G_3 = (eta, xi)/h:
  //   f_0x = A + B, f_1x = D - A, f_2x = C - B, f_3x = -(C + D) with
  //   A = sum (1-eta) t_xx, B = sum (1-xi) t_xy, C = sum eta t_xx,
  //   D = sum xi t_xy, and the same for y with t_xy, t_yy; the point adds
  //   sum t, sum eta t, sum xi t (seven sums).
  struct CellForces
  {
    double tx = 0, eta_tx = 0, txy = 0, xi_txy = 0, eta_txy = 0, ty = 0,
           xi_ty = 0;
    inline void
    add(const double xi,
        const double eta,
        const double V,
        const double sxx,
        const double syy,
        const double sxy)
    {
      const double Vh = V * inv_h;
      const double x = Vh * sxx, xy = Vh * sxy, y = Vh * syy;
      tx += x;
      eta_tx += eta * x;
      txy += xy;
      xi_txy += xi * xy;
      eta_txy += eta * xy;
      ty += y;
      xi_ty += xi * y;
    }
    inline void
    scatter(NodeVelocity *n0) const
    {
      const double  A = tx - eta_tx, B = txy - xi_txy, C = eta_tx, D = xi_txy;
      const double  E = txy - eta_txy, F = ty - xi_ty, G_ = eta_txy, H = xi_ty;
      NodeVelocity *n2 = n0 + n_nodes_x;
      n0[0].fx += A + B, n0[0].fy += E + F;
      n0[1].fx += D - A, n0[1].fy += H - E;
      n2[0].fx += C - B, n2[0].fy += G_ - F;
      n2[1].fx -= C + D, n2[1].fy -= G_ + H;
    }
  };

  StressResult
  stress_update_fused(Store &s, NodeVelocity *__restrict grid, const double dt)
  {
    double *__restrict xi_col  = s.col[c_xi];
    double *__restrict eta_col = s.col[c_eta];
    double *__restrict Fxx_col = s.col[c_fxx];
    double *__restrict Fxy_col = s.col[c_fxy];
    double *__restrict Fyx_col = s.col[c_fyx];
    double *__restrict Fyy_col = s.col[c_fyy];
    double *__restrict sxx_col = s.col[c_sxx];
    double *__restrict syy_col = s.col[c_syy];
    double *__restrict szz_col = s.col[c_szz];
    double *__restrict sxy_col = s.col[c_sxy];
    double *__restrict w_col   = s.col[c_w];
    double *__restrict V_col   = s.col[c_volume];
    const double   V0          = s.initial_volume;
    double         J_max = 0, J_min = std::numeric_limits<double>::max();
    bool           finite     = true;
    const uint32_t n_occupied = s.occupied_cell.size();
    for (uint32_t o = 0; o < n_occupied; ++o)
      {
        NodeVelocity *const        n0 = grid + first_node(s.occupied_cell[o]);
        const CellVelocityGradient v(n0);
        CellForces                 f;
        for (uint32_t k = s.occupied_begin[o]; k < s.occupied_begin[o + 1]; ++k)
          {
            const double xi = xi_col[k], eta = eta_col[k];
            double       Lxx, Lxy, Lyx, Lyy;
            v.at(xi, eta, Lxx, Lxy, Lyx, Lyy);
            const Kinematics F     = kinematics(Lxx,
                                            Lxy,
                                            Lyx,
                                            Lyy,
                                            dt,
                                            Fxx_col[k],
                                            Fxy_col[k],
                                            Fyx_col[k],
                                            Fyy_col[k]);
            const double     log_J = std::log(F.J);
            const double     J_m23 = std::exp(-2.0 / 3.0 * log_J);
            const Stress     sigma =
              neo_hookean(F.Fxx, F.Fxy, F.Fyx, F.Fyy, F.J, log_J, J_m23);
            const double V = F.J * V0;
            Fxx_col[k]     = F.Fxx;
            Fxy_col[k]     = F.Fxy;
            Fyx_col[k]     = F.Fyx;
            Fyy_col[k]     = F.Fyy;
            sxx_col[k]     = sigma.sxx;
            syy_col[k]     = sigma.syy;
            szz_col[k]     = sigma.szz;
            sxy_col[k]     = sigma.sxy;
            w_col[k]       = sigma.W;
            V_col[k]       = V;
            J_max          = std::max(J_max, F.J);
            J_min          = std::min(J_min, F.J);
            finite         = finite & (sigma.W - sigma.W == 0);
            f.add(xi, eta, V, sigma.sxx, sigma.syy, sigma.sxy);
          }
        f.scatter(n0);
      }
    StressResult r;
    r.J_max  = J_max;
    r.failed = !(J_min > 0) || !finite;
    return r;
  }

  // The staged variant: batches of consecutive points.
  constexpr uint32_t batch_size = 256;

  struct BatchScratch
  {
    alignas(64) double Lxx[batch_size];
    alignas(64) double Lxy[batch_size];
    alignas(64) double Lyx[batch_size];
    alignas(64) double Lyy[batch_size];
    alignas(64) double J[batch_size];
    alignas(64) double log_J[batch_size];
    alignas(64) double J_m23[batch_size];
  };

  // The constitutive part of a batch, in three loops over the batch's
  // points (restrict-qualified parameters: GCC ignores restrict on local
  // pointers, and its -O2 vectorizer needs a constant trip count, which the
  // full batches have).
  template <typename Count>
  inline void
  batch_kinematics(const Count  n,
                   const double dt,
                   const double *__restrict Lxx,
                   const double *__restrict Lxy,
                   const double *__restrict Lyx,
                   const double *__restrict Lyy,
                   double *__restrict Fxx,
                   double *__restrict Fxy,
                   double *__restrict Fyx,
                   double *__restrict Fyy,
                   double *__restrict J)
  {
    for (uint32_t q = 0; q < n; ++q)
      {
        const Kinematics F = kinematics(
          Lxx[q], Lxy[q], Lyx[q], Lyy[q], dt, Fxx[q], Fxy[q], Fyx[q], Fyy[q]);
        Fxx[q] = F.Fxx;
        Fxy[q] = F.Fxy;
        Fyx[q] = F.Fyx;
        Fyy[q] = F.Fyy;
        J[q]   = F.J;
      }
  }

  template <typename Count>
  inline void
  batch_log_exp(const Count n,
                const double *__restrict J,
                double *__restrict log_J,
                double *__restrict J_m23)
  {
    uint32_t q = 0;
#ifdef HK_LIBMVEC
#  if defined(__AVX512F__)
    for (; q + 8 <= n; q += 8)
      {
        const __m512d l = _ZGVeN8v_log(_mm512_load_pd(J + q));
        _mm512_store_pd(log_J + q, l);
        _mm512_store_pd(J_m23 + q,
                        _ZGVeN8v_exp(
                          _mm512_mul_pd(_mm512_set1_pd(-2.0 / 3.0), l)));
      }
#  elif defined(__AVX2__)
    for (; q + 4 <= n; q += 4)
      {
        const __m256d l = _ZGVdN4v_log(_mm256_load_pd(J + q));
        _mm256_store_pd(log_J + q, l);
        _mm256_store_pd(J_m23 + q,
                        _ZGVdN4v_exp(
                          _mm256_mul_pd(_mm256_set1_pd(-2.0 / 3.0), l)));
      }
#  else
    for (; q + 2 <= n; q += 2)
      {
        const __m128d l = _ZGVbN2v_log(_mm_load_pd(J + q));
        _mm_store_pd(log_J + q, l);
        _mm_store_pd(J_m23 + q,
                     _ZGVbN2v_exp(_mm_mul_pd(_mm_set1_pd(-2.0 / 3.0), l)));
      }
#  endif
#endif
    for (; q < n; ++q)
      {
        log_J[q] = std::log(J[q]);
        J_m23[q] = std::exp(-2.0 / 3.0 * log_J[q]);
      }
  }

  template <typename Count>
  inline void
  batch_stress(const Count  n,
               const double V0,
               const double *__restrict Fxx,
               const double *__restrict Fxy,
               const double *__restrict Fyx,
               const double *__restrict Fyy,
               const double *__restrict J,
               const double *__restrict log_J,
               const double *__restrict J_m23,
               double *__restrict sxx,
               double *__restrict syy,
               double *__restrict szz,
               double *__restrict sxy,
               double *__restrict W,
               double *__restrict V)
  {
    for (uint32_t q = 0; q < n; ++q)
      {
        const Stress sigma =
          neo_hookean(Fxx[q], Fxy[q], Fyx[q], Fyy[q], J[q], log_J[q], J_m23[q]);
        sxx[q] = sigma.sxx;
        syy[q] = sigma.syy;
        szz[q] = sigma.szz;
        sxy[q] = sigma.sxy;
        W[q]   = sigma.W;
        V[q]   = J[q] * V0;
      }
  }

  template <typename Count>
  inline void
  constitutive_batch(Store         &s,
                     const uint32_t k0,
                     const Count    n,
                     const double   dt,
                     BatchScratch  &b,
                     double        &J_max,
                     double        &J_min,
                     bool          &finite)
  {
    batch_kinematics(n,
                     dt,
                     b.Lxx,
                     b.Lxy,
                     b.Lyx,
                     b.Lyy,
                     s.col[c_fxx] + k0,
                     s.col[c_fxy] + k0,
                     s.col[c_fyx] + k0,
                     s.col[c_fyy] + k0,
                     b.J);
    batch_log_exp(n, b.J, b.log_J, b.J_m23);
    batch_stress(n,
                 s.initial_volume,
                 s.col[c_fxx] + k0,
                 s.col[c_fxy] + k0,
                 s.col[c_fyx] + k0,
                 s.col[c_fyy] + k0,
                 b.J,
                 b.log_J,
                 b.J_m23,
                 s.col[c_sxx] + k0,
                 s.col[c_syy] + k0,
                 s.col[c_szz] + k0,
                 s.col[c_sxy] + k0,
                 s.col[c_w] + k0,
                 s.col[c_volume] + k0);
    // J range and finite W (four independent chains).
    const double *J = b.J, *W = s.col[c_w] + k0;
    double        hi[4] = {J_max, J_max, J_max, J_max},
           lo[4] = {J_min, J_min, J_min, J_min}, bad[4] = {0, 0, 0, 0};
    uint32_t q = 0;
    for (; q + 4 <= n; q += 4)
      for (int l = 0; l < 4; ++l)
        {
          hi[l] = J[q + l] > hi[l] ? J[q + l] : hi[l];
          lo[l] = J[q + l] < lo[l] ? J[q + l] : lo[l];
          bad[l] += W[q + l] - W[q + l];
        }
    for (; q < n; ++q)
      {
        hi[0] = J[q] > hi[0] ? J[q] : hi[0];
        lo[0] = J[q] < lo[0] ? J[q] : lo[0];
        bad[0] += W[q] - W[q];
      }
    J_max  = std::max(std::max(hi[0], hi[1]), std::max(hi[2], hi[3]));
    J_min  = std::min(std::min(lo[0], lo[1]), std::min(lo[2], lo[3]));
    finite = finite && bad[0] + bad[1] + bad[2] + bad[3] == 0;
  }

  StressResult
  stress_update_staged(Store &s,
                       NodeVelocity *__restrict grid,
                       const double  dt,
                       BatchScratch &b)
  {
    const double *__restrict xi_col  = s.col[c_xi];
    const double *__restrict eta_col = s.col[c_eta];
    double   J_max = 0, J_min = std::numeric_limits<double>::max();
    bool     finite = true;
    uint32_t o      = 0; // the occupied cell holding the batch's first point
    for (uint32_t k0 = 0; k0 < s.n; k0 += batch_size)
      {
        const uint32_t k1 = std::min<uint32_t>(k0 + batch_size, s.n);
        // 1. L per cell (the part of it in the batch).
        for (uint32_t c = o;
             c < s.occupied_cell.size() && s.occupied_begin[c] < k1;
             ++c)
          {
            const CellVelocityGradient v(grid + first_node(s.occupied_cell[c]));
            const uint32_t             kb = std::max(s.occupied_begin[c], k0),
                           ke = std::min(s.occupied_begin[c + 1], k1);
            for (uint32_t k = kb; k < ke; ++k)
              {
                const uint32_t q = k - k0;
                v.at(xi_col[k],
                     eta_col[k],
                     b.Lxx[q],
                     b.Lxy[q],
                     b.Lyx[q],
                     b.Lyy[q]);
              }
          }
        // 2. The constitutive update over the batch.
        if (k1 - k0 == batch_size)
          constitutive_batch(s,
                             k0,
                             std::integral_constant<uint32_t, batch_size>(),
                             dt,
                             b,
                             J_max,
                             J_min,
                             finite);
        else
          constitutive_batch(s, k0, k1 - k0, dt, b, J_max, J_min, finite);
        // 3. The forces per cell.
        const double *__restrict V_col   = s.col[c_volume];
        const double *__restrict sxx_col = s.col[c_sxx];
        const double *__restrict syy_col = s.col[c_syy];
        const double *__restrict sxy_col = s.col[c_sxy];
        for (; o < s.occupied_cell.size() && s.occupied_begin[o] < k1; ++o)
          {
            NodeVelocity *const n0 = grid + first_node(s.occupied_cell[o]);
            const uint32_t      kb = std::max(s.occupied_begin[o], k0),
                           ke      = std::min(s.occupied_begin[o + 1], k1);
            CellForces f;
            for (uint32_t k = kb; k < ke; ++k)
              f.add(xi_col[k],
                    eta_col[k],
                    V_col[k],
                    sxx_col[k],
                    syy_col[k],
                    sxy_col[k]);
            f.scatter(n0);
            if (s.occupied_begin[o + 1] > k1)
              break; // the cell continues in the next batch
          }
      }
    StressResult r;
    r.J_max  = J_max;
    r.failed = !(J_min > 0) || !finite;
    return r;
  }

  // -------------------------------------------------------- phase: update
  // The points that left their cells, in store order, with their new cells
  // and reference coordinates (found by the particle update, which has the
  // positions in registers; fmpm finds them in its sort).
  struct Leavers
  {
    std::vector<uint32_t> index, cell;
    std::vector<double>   xi, eta;
    void
    reserve(const std::size_t n)
    {
      index.resize(n);
      cell.resize(n);
      xi.resize(n);
      eta.resize(n);
    }
  };

  // The cell that holds (x, y), across the faces crossed from cell c
  // (fmpm walks from neighbour to neighbour the same way), and xi there.
  inline bool
  find_cell(const double   x,
            const double   y,
            const uint32_t c,
            uint32_t      &cell,
            double        &xi,
            double        &eta)
  {
    int j = c / n_cells_x, i = c - j * n_cells_x;
    for (int hop = 0; hop < 4; ++hop)
      {
        xi  = inv_h * (x - i * h);
        eta = inv_h * (y - j * h);
        if (xi < -tolerance)
          --i;
        else if (xi > 1 + tolerance)
          ++i;
        else if (eta < -tolerance)
          --j;
        else if (eta > 1 + tolerance)
          ++j;
        else
          {
            cell = j * n_cells_x + i;
            return true;
          }
        if (i < 0 || j < 0 || i >= n_cells_x || j >= n_cells_x)
          return false; // left the mesh
      }
    return false;
  }

  struct UpdateResult
  {
    double   max_V2 = 0;
    uint32_t n_left = 0;
    bool     ok     = true;
  };

  UpdateResult
  particle_update(Store &s,
                  const NodeVelocity *__restrict grid,
                  const double dt,
                  Leavers     &leavers)
  {
    double *__restrict x_col   = s.col[c_x];
    double *__restrict y_col   = s.col[c_y];
    double *__restrict xi_col  = s.col[c_xi];
    double *__restrict eta_col = s.col[c_eta];
    double *__restrict vx_col  = s.col[c_vx];
    double *__restrict vy_col  = s.col[c_vy];
    double         max_V2      = 0;
    uint32_t       n_left      = 0;
    bool           found       = true;
    const uint32_t n_occupied  = s.occupied_cell.size();
    for (uint32_t o = 0; o < n_occupied; ++o)
      {
        const uint32_t            c  = s.occupied_cell[o];
        const NodeVelocity *const n0 = grid + first_node(c);
        const NodeVelocity *const n2 = n0 + n_nodes_x;
        // sum_j S_j q_j = q0 + (q1 - q0) xi + eta [(q2 - q0) + (q3 - q2 -
        // q1 + q0) xi] for the bilinear S_j (the same sum, rounded
        // differently): 3 multiply-adds per field and point.
        double c0[4], c1[4], c2[4], c3[4];
        {
          const double *q0 = &n0[0].vx, *q1 = &n0[1].vx, *q2 = &n2[0].vx,
                       *q3 = &n2[1].vx;
          for (int f = 0; f < 4; ++f)
            {
              c0[f] = q0[f];
              c1[f] = q1[f] - q0[f];
              c2[f] = q2[f] - q0[f];
              c3[f] = (q3[f] - q2[f]) - c1[f];
            }
        }
        const uint32_t j = c / n_cells_x, i = c - j * n_cells_x;
        const double   x0 = i * h, y0 = j * h;
        for (uint32_t k = s.occupied_begin[o]; k < s.occupied_begin[o + 1]; ++k)
          {
            const double xi = xi_col[k], eta = eta_col[k];
            double       q[4];
            for (int f = 0; f < 4; ++f)
              q[f] = c0[f] + c1[f] * xi + eta * (c2[f] + c3[f] * xi);
            const double vx_grid = q[0], vy_grid = q[1], ax = q[2], ay = q[3];
            const double vx      = vx_col[k] + ax * dt;
            const double vy      = vy_col[k] + ay * dt;
            const double x       = x_col[k] + vx_grid * dt;
            const double y       = y_col[k] + vy_grid * dt;
            vx_col[k]            = vx;
            vy_col[k]            = vy;
            x_col[k]             = x;
            y_col[k]             = y;
            max_V2               = std::max(max_V2, vx * vx + vy * vy);
            const double xi_new  = inv_h * (x - x0);
            const double eta_new = inv_h * (y - y0);
            const bool   inside =
              (xi_new >= -tolerance) & (xi_new <= 1 + tolerance) &
              (eta_new >= -tolerance) & (eta_new <= 1 + tolerance);
            if (inside)
              {
                xi_col[k]  = xi_new;
                eta_col[k] = eta_new;
              }
            else
              {
                // (xi in the store stays the old cell's until the re-bin.)
                leavers.index[n_left] = k;
                found                 = found & find_cell(x,
                                          y,
                                          c,
                                          leavers.cell[n_left],
                                          leavers.xi[n_left],
                                          leavers.eta[n_left]);
                ++n_left;
              }
          }
      }
    UpdateResult r;
    r.max_V2 = max_V2;
    r.n_left = n_left;
    r.ok     = std::isfinite(max_V2) && found;
    return r;
  }

  // --------------------------------------------------------- phase: rebin
  struct Run
  {
    uint32_t src, dst, len;
  };
  struct Arrival
  {
    uint32_t dst, slot;
  };

  // Runs of at most this many points are moved point by point.
  constexpr uint32_t short_run = 8;

  struct RebinScratch
  {
    Leavers               leavers;
    std::vector<uint32_t> order, order_scratch; // slots by new cell, id
    std::vector<uint32_t> new_begin, new_occupied_cell, new_occupied_begin;
    std::vector<Run>      runs, right, leftward;
    std::vector<Arrival>  arrivals;
    // The in-place variant's moves (element moves, then a run, per
    // segment) and buffered records of the points that left.
    struct Segment
    {
      uint32_t pairs_end;
      Run      run;
    };
    std::vector<Segment>  segments;
    std::vector<uint32_t> pair_dst, pair_src;
    std::vector<double>   buffer[n_double_columns];
    std::vector<uint64_t> buffer_id;
    std::vector<uint32_t> buffer_cell;
    // Statistics.
    double n_left_sum = 0, n_runs_sum = 0, n_moved_runs_sum = 0,
           n_moved_sum = 0, n_calls = 0;
  };

  template <typename T>
  inline void
  apply_copy(T *&a,
             T *&work,
             const T *__restrict new_values,
             const uint32_t *__restrict left,
             const std::vector<Run>     &runs,
             const std::vector<Arrival> &arrivals)
  {
    T *__restrict out      = work;
    const T *__restrict in = a;
    for (const Run &run : runs)
      std::memcpy(out + run.dst, in + run.src, run.len * sizeof(T));
    if (new_values)
      for (const Arrival &arrival : arrivals)
        out[arrival.dst] = new_values[arrival.slot];
    else
      for (const Arrival &arrival : arrivals)
        out[arrival.dst] = in[left[arrival.slot]];
    std::swap(a, work);
  }

  void
  rebin(Store &s, RebinScratch &r, const uint32_t n_left, const bool in_place)
  {
    r.n_calls += 1;
    r.n_left_sum += n_left;
    if (n_left == 0)
      return;
    const uint32_t *const left     = r.leavers.index.data();
    const uint32_t *const new_cell = r.leavers.cell.data();
    // 1. The counts, and the arrivals by new cell (a stable radix sort of
    //    the 16-bit cell numbers), by id in a cell.
    static_assert(n_cells <= 65536, "two radix passes of 8 bits");
    r.order.resize(n_left);
    r.order_scratch.resize(n_left);
    {
      uint32_t low[257] = {}, high[257] = {};
      for (uint32_t l = 0; l < n_left; ++l)
        {
          --s.count[s.cell[left[l]]];
          ++s.count[new_cell[l]];
          ++low[(new_cell[l] & 255) + 1];
          ++high[(new_cell[l] >> 8) + 1];
        }
      for (int b = 0; b < 256; ++b)
        low[b + 1] += low[b], high[b + 1] += high[b];
      for (uint32_t l = 0; l < n_left; ++l)
        r.order_scratch[low[new_cell[l] & 255]++] = l;
      for (uint32_t l = 0; l < n_left; ++l)
        {
          const uint32_t slot                  = r.order_scratch[l];
          r.order[high[new_cell[slot] >> 8]++] = slot;
        }
    }
    for (uint32_t a = 1; a < n_left; ++a)
      {
        // insertion sort by id within equal cells (groups of a few)
        const uint32_t slot   = r.order[a];
        const uint32_t cell_a = new_cell[slot];
        const uint64_t id_a   = s.id[left[slot]];
        uint32_t       b      = a;
        while (b > 0 && new_cell[r.order[b - 1]] == cell_a &&
               s.id[left[r.order[b - 1]]] > id_a)
          {
            r.order[b] = r.order[b - 1];
            --b;
          }
        r.order[b] = slot;
      }
    // 2. The new cell starts and the new list of cells with points.
    r.new_begin.resize(n_cells + 1);
    r.new_occupied_cell.resize(n_cells);
    r.new_occupied_begin.resize(n_cells + 1);
    {
      uint32_t  sum = 0, n_occupied = 0;
      uint32_t *nb = r.new_begin.data(), *oc = r.new_occupied_cell.data(),
               *ob          = r.new_occupied_begin.data();
      const uint32_t *count = s.count.data();
      for (uint32_t c = 0; c < uint32_t(n_cells); ++c)
        {
          nb[c]          = sum;
          oc[n_occupied] = c;
          ob[n_occupied] = sum;
          n_occupied += count[c] != 0 ? 1 : 0;
          sum += count[c];
        }
      nb[n_cells]    = sum;
      ob[n_occupied] = sum;
      r.new_occupied_cell.resize(n_occupied);
      r.new_occupied_begin.resize(n_occupied + 1);
    }
    // 3. The runs of points that stay, and the places of the arrivals: the
    //    cells without departures or arrivals keep their points in one run
    //    per stretch; a cell with either is merged point by point by id.
    r.runs.clear();
    r.arrivals.clear();
    Run  open{0, 0, 0};
    auto stay =
      [&](const uint32_t src, const uint32_t dst, const uint32_t len) {
        if (len == 0)
          return;
        if (open.len != 0 && open.src + open.len == src &&
            open.dst + open.len == dst)
          open.len += len;
        else
          {
            if (open.len != 0)
              r.runs.push_back(open);
            open = {src, dst, len};
          }
      };
    {
      const uint32_t *old_begin = s.begin.data();
      const uint32_t *new_begin = r.new_begin.data();
      uint32_t        next_cell = 0; // the first cell not yet handled
      uint32_t        d = 0, a = 0;  // next departure, next arrival
      while (d < n_left || a < n_left)
        {
          const uint32_t cd = d < n_left ? s.cell[left[d]] : UINT32_MAX;
          const uint32_t ca = a < n_left ? new_cell[r.order[a]] : UINT32_MAX;
          const uint32_t c  = std::min(cd, ca);
          stay(old_begin[next_cell],
               new_begin[next_cell],
               old_begin[c] - old_begin[next_cell]);
          uint32_t       k = old_begin[c], dst = new_begin[c];
          const uint32_t k_end = old_begin[c + 1];
          for (;;)
            {
              if (k < k_end && d < n_left && left[d] == k)
                {
                  ++d, ++k;
                  continue;
                }
              const bool arrival = a < n_left && new_cell[r.order[a]] == c;
              if (k == k_end && !arrival)
                break;
              if (arrival && (k == k_end || s.id[left[r.order[a]]] < s.id[k]))
                {
                  r.arrivals.push_back({dst, r.order[a]});
                  ++dst, ++a;
                }
              else
                {
                  stay(k, dst, 1);
                  ++k, ++dst;
                }
            }
          next_cell = c + 1;
        }
      stay(old_begin[next_cell],
           new_begin[next_cell],
           uint32_t(s.n) - old_begin[next_cell]);
      if (open.len != 0)
        r.runs.push_back(open);
    }
    r.n_runs_sum += r.runs.size();

    // 4. Every column.
    if (in_place)
      {
        r.right.clear();
        r.leftward.clear();
        double moved = 0;
        for (const Run &run : r.runs)
          if (run.dst > run.src)
            r.right.push_back(run), moved += run.len;
          else if (run.dst < run.src)
            r.leftward.push_back(run), moved += run.len;
        r.n_moved_sum += moved + r.arrivals.size();
        r.n_moved_runs_sum += r.right.size() + r.leftward.size();
        // Short runs (most of them: the points between departures and
        // arrivals in the cells that changed) become single moves, done by
        // one loop without branches; long runs are memmoves. The order is
        // kept: runs moving right from the last, runs moving left from the
        // first.
        r.segments.clear();
        r.pair_dst.clear();
        r.pair_src.clear();
        auto add_run = [&](const Run &run, const bool rightward) {
          if (run.len > short_run)
            {
              r.segments.push_back({uint32_t(r.pair_dst.size()), run});
              return;
            }
          for (uint32_t j = 0; j < run.len; ++j)
            {
              const uint32_t e = rightward ? run.len - 1 - j : j;
              r.pair_dst.push_back(run.dst + e);
              r.pair_src.push_back(run.src + e);
            }
        };
        for (std::size_t i = r.right.size(); i-- > 0;)
          add_run(r.right[i], true);
        for (const Run &run : r.leftward)
          add_run(run, false);
        r.segments.push_back({uint32_t(r.pair_dst.size()), Run{0, 0, 0}});
        // Column by column: the records of the points that left (with their
        // new cell and xi) to a buffer, the moves, the buffered records to
        // their places.
        auto move_column =
          [&](auto *const column, const auto *new_values, auto &buffer) {
            using T = std::remove_reference_t<decltype(*column)>;
            buffer.resize(n_left);
            if (new_values)
              std::copy(new_values, new_values + n_left, buffer.begin());
            else
              for (uint32_t l = 0; l < n_left; ++l)
                buffer[l] = column[left[l]];
            const uint32_t *const pair_dst = r.pair_dst.data();
            const uint32_t *const pair_src = r.pair_src.data();
            uint32_t              p        = 0;
            for (const RebinScratch::Segment &segment : r.segments)
              {
                for (; p < segment.pairs_end; ++p)
                  column[pair_dst[p]] = column[pair_src[p]];
                std::memmove(column + segment.run.dst,
                             column + segment.run.src,
                             segment.run.len * sizeof(T));
              }
            for (const Arrival &arrival : r.arrivals)
              column[arrival.dst] = buffer[arrival.slot];
          };
        for (int c = 0; c < n_double_columns; ++c)
          move_column(s.col[c],
                      c == c_xi  ? r.leavers.xi.data() :
                      c == c_eta ? r.leavers.eta.data() :
                                   static_cast<const double *>(nullptr),
                      r.buffer[c]);
        move_column(s.id, static_cast<const uint64_t *>(nullptr), r.buffer_id);
        move_column(s.cell, new_cell, r.buffer_cell);
      }
    else
      {
        r.n_moved_sum += s.n;
        r.n_moved_runs_sum += r.runs.size();
        for (int c = 0; c < n_double_columns; ++c)
          apply_copy(s.col[c],
                     s.work_col[c],
                     c == c_xi  ? r.leavers.xi.data() :
                     c == c_eta ? r.leavers.eta.data() :
                                  static_cast<const double *>(nullptr),
                     left,
                     r.runs,
                     r.arrivals);
        apply_copy(s.id,
                   s.work_id,
                   static_cast<const uint64_t *>(nullptr),
                   left,
                   r.runs,
                   r.arrivals);
        apply_copy(s.cell, s.work_cell, new_cell, left, r.runs, r.arrivals);
      }
    // 5. The cell structure.
    s.begin.swap(r.new_begin);
    s.occupied_cell.swap(r.new_occupied_cell);
    s.occupied_begin.swap(r.new_occupied_begin);
  }

#ifdef HK_CHECK
  void
  check_store(const Store &s)
  {
    for (uint32_t k = 0; k < s.n; ++k)
      {
        const uint32_t c = s.cell[k];
        if (k < s.begin[c] || k >= s.begin[c + 1] ||
            (k > s.begin[c] && s.id[k - 1] >= s.id[k]) ||
            (k > 0 && s.cell[k - 1] > c) || s.col[c_xi][k] < -1e-12 ||
            s.col[c_xi][k] > 1 + 1e-12 || s.col[c_eta][k] < -1e-12 ||
            s.col[c_eta][k] > 1 + 1e-12)
          {
            std::printf("store check failed at %u\n", k);
            std::exit(1);
          }
        const int    j = c / n_cells_x, i = c - j * n_cells_x;
        const double xi = inv_h * (s.col[c_x][k] - i * h);
        if (std::abs(xi - s.col[c_xi][k]) > 1e-9)
          {
            std::printf("store check: xi wrong at %u\n", k);
            std::exit(1);
          }
      }
  }
#endif

  // ------------------------------------------------------------ the run
  enum Phase
  {
    p_p2g,
    p_stress,
    p_grid,
    p_update,
    p_rebin,
    n_phases
  };
  const char *phase_names[n_phases] = {"particles to grid",
                                       "stress update (incl. forces)",
                                       "grid solve",
                                       "particle update",
                                       "re-bin"};

  struct RunResult
  {
    double seconds = 0, cpu_seconds = 0;
    double phase[n_phases] = {};
    double t = 0, dt = 0, kinetic = 0, strain = 0;
    bool   ok = true;
  };

  struct Config
  {
    const char *name;
    bool        staged;
    bool        in_place;
  };

  RunResult
  run(Store        &s,
      NodeMass     *mass_grid,
      NodeVelocity *v_grid,
      RebinScratch &r,
      BatchScratch &batch,
      const Config &config)
  {
    initialize(s);
    RunResult result;
    // Initial signal speed: c(J = V/V0 = 1) + |V|max; h_min of the mesh.
    double max_V2 = 0;
    for (uint32_t k = 0; k < s.n; ++k)
      max_V2 = std::max(max_V2,
                        s.col[c_vx][k] * s.col[c_vx][k] +
                          s.col[c_vy][k] * s.col[c_vy][k]);
    double h_min = std::numeric_limits<double>::max();
    for (int i = 0; i < n_cells_x; ++i)
      h_min = std::min(h_min, (i + 1) * h - i * h);
    double       signal_speed = wave_speed(1.0) + std::sqrt(max_V2);
    const double mass_floor   = 1e-12 * s.mass;
    double       t            = 0;
    r.leavers.reserve(s.n + 1);

    const double       start     = now();
    const std::clock_t cpu_start = std::clock();
    for (int step = 0; step < n_steps; ++step)
      {
        const double dt = courant * h_min / signal_speed;
        const double t0 = now();
        particles_to_grid(s, mass_grid);
        const double t1 = now();
        grid_velocity(mass_grid, v_grid, mass_floor);
        const double       t2 = now();
        const StressResult stress =
          config.staged ? stress_update_staged(s, v_grid, dt, batch) :
                          stress_update_fused(s, v_grid, dt);
        const double t3 = now();
        grid_solve(mass_grid, v_grid, dt, mass_floor);
        const double       t4     = now();
        const UpdateResult update = particle_update(s, v_grid, dt, r.leavers);
        const double       t5     = now();
        rebin(s, r, update.n_left, config.in_place);
        const double t6 = now();
        result.phase[p_p2g] += t1 - t0;
        result.phase[p_grid] += (t2 - t1) + (t4 - t3);
        result.phase[p_stress] += t3 - t2;
        result.phase[p_update] += t5 - t4;
        result.phase[p_rebin] += t6 - t5;
        if (stress.failed || !update.ok)
          {
            std::printf("step %d failed (stress %d, update %d)\n",
                        step + 1,
                        int(stress.failed),
                        int(!update.ok));
            result.ok = false;
            break;
          }
#ifdef HK_CHECK
        check_store(s);
#endif
        t += dt;
        result.dt    = dt;
        signal_speed = wave_speed(stress.J_max) + std::sqrt(update.max_V2);
      }
    result.seconds     = now() - start;
    result.cpu_seconds = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    result.t           = t;
    for (uint32_t k = 0; k < s.n; ++k)
      {
        const double vx = s.col[c_vx][k], vy = s.col[c_vy][k];
        result.kinetic += 0.5 * s.mass * (vx * vx + vy * vy);
        result.strain += s.initial_volume * s.col[c_w][k];
      }
    return result;
  }
} // namespace



int
main(int argc, char **argv)
{
  const int n_runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  for (int j = 0; j < n_nodes_x; ++j)
    for (int i = 0; i < n_nodes_x; ++i)
      if (i == 0 || j == 0 || i == n_cells_x || j == n_cells_x)
        boundary_nodes.push_back(j * n_nodes_x + i);

  const std::size_t n_points = count_initial_points();
  Store             store;
  store.allocate(n_points);
  Buffer<NodeMass>     mass_grid;
  Buffer<NodeVelocity> v_grid;
  mass_grid.allocate(n_nodes);
  v_grid.allocate(n_nodes);
  static BatchScratch batch;
  // The best combination first; each variant of a phase appears once more.
  const Config all_configs[] = {{"staged stress, in-place re-bin", true, true},
                                {"fused stress, in-place re-bin", false, true},
                                {"staged stress, copying re-bin", true, false}};
  std::vector<Config> configs;
  for (int c = 0; c < 3; ++c)
    if (argc <= 2 || std::atoi(argv[2]) == c)
      configs.push_back(all_configs[c]);
  const int                           n_configs = configs.size();
  std::vector<std::vector<RunResult>> results(n_configs);
  std::vector<RebinScratch>           scratches(n_configs);

  initialize(store);
  double kinetic0 = 0;
  for (uint32_t k = 0; k < store.n; ++k)
    kinetic0 += 0.5 * store.mass *
                (store.col[c_vx][k] * store.col[c_vx][k] +
                 store.col[c_vy][k] * store.col[c_vy][k]);
  std::printf("hand kernel 2D: %zu points, %d cells, %d nodes, mass %.12g, "
              "initial kinetic energy %.12g\n",
              store.n,
              n_cells,
              n_nodes,
              store.mass * store.n,
              kinetic0);
#ifdef HK_LIBMVEC
  std::printf("(staged stress update with libmvec's vector log/exp)\n");
#endif

  // Interleaved: run r of every configuration, then run r + 1.
  for (int r = 0; r < n_runs; ++r)
    for (int c = 0; c < n_configs; ++c)
      {
        results[c].push_back(
          run(store, mass_grid.p, v_grid.p, scratches[c], batch, configs[c]));
        if (!results[c].back().ok)
          return 1;
      }

  const double point_steps = double(store.n) * n_steps;
  for (int c = 0; c < n_configs; ++c)
    {
      const std::vector<RunResult> &rs   = results[c];
      double                        best = 1e300, worst = 0, best_cpu = 0;
      for (const RunResult &x : rs)
        {
          if (x.seconds < best)
            best = x.seconds, best_cpu = x.cpu_seconds;
          worst = std::max(worst, x.seconds);
        }
      std::printf("\n=== %s (%d runs of %d steps)\n",
                  configs[c].name,
                  n_runs,
                  n_steps);
      std::printf("    particle-steps per second: best %.3e, worst %.3e "
                  "(best run: CPU time / wall time %.3f)\n",
                  point_steps / best,
                  point_steps / worst,
                  best_cpu / best);
      std::printf("    ns per point-step            best    worst\n");
      double sum_best = 0;
      for (int p = 0; p < n_phases; ++p)
        {
          double lo = 1e300, hi = 0;
          for (const RunResult &x : rs)
            lo = std::min(lo, x.phase[p]), hi = std::max(hi, x.phase[p]);
          sum_best += lo;
          std::printf("      %-28s %6.2f  %6.2f\n",
                      phase_names[p],
                      1e9 * lo / point_steps,
                      1e9 * hi / point_steps);
        }
      std::printf("      %-28s %6.2f  (whole step, best run: %.2f)\n",
                  "sum of the best phases",
                  1e9 * sum_best / point_steps,
                  1e9 * best / point_steps);
      const RebinScratch &sc = scratches[c];
      std::printf("    re-bin: %.0f points left their cell per step, %.0f runs "
                  "(%.0f copied), %.0f points moved (%.1f %%)\n",
                  sc.n_left_sum / sc.n_calls,
                  sc.n_runs_sum / sc.n_calls,
                  sc.n_moved_runs_sum / sc.n_calls,
                  sc.n_moved_sum / sc.n_calls,
                  100. * sc.n_moved_sum / sc.n_calls / store.n);
      const RunResult &x = rs.back();
      std::printf("    after step %d: t = %.12g, dt = %.12g, kinetic energy "
                  "%.12g, strain energy %.12g, total %.12g\n",
                  n_steps,
                  x.t,
                  x.dt,
                  x.kinetic,
                  x.strain,
                  x.kinetic + x.strain);
    }
  return 0;
}
