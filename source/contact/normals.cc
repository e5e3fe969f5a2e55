// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/contact/normals.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fmpm
{
  namespace Contact
  {
    EdgeDistance::EdgeDistance(const ShapeFunction::Type type,
                               const double              half_length)
    {
      AssertThrow(half_length > 0 && half_length < 1,
                  ExcMessage("d(x) fit: the points' half-length must be "
                             "between 0 and 1 cell."));
      // Linear grid function of the node at 0 and its integral.
      auto N = [](const double s) { return std::max(0., 1. - std::abs(s)); };
      auto integral = [](const double s) {
        if (s <= -1)
          return 0.;
        if (s <= 0)
          return 0.5 * (s + 1) * (s + 1);
        if (s <= 1)
          return 1. - 0.5 * (1 - s) * (1 - s);
        return 1.;
      };
      auto shape = [&](const double center) {
        switch (type)
          {
            case ShapeFunction::Type::classic:
              return N(center);
            case ShapeFunction::Type::cpdi: // mean of the corner values
              return 0.5 * (N(center - half_length) + N(center + half_length));
            default: // uGIMP, cpGIMP: N averaged over the point's domain
              return (integral(center + half_length) -
                      integral(center - half_length)) /
                     (2 * half_length);
          }
      };
      const double reach = 1 + half_length;
      const double step  = 1e-3;
      for (double edge = -reach; edge <= reach; edge += step)
        {
          double sum_S = 0, sum_Sx = 0;
          for (double center = edge - half_length; center > -reach;
               center -= 2 * half_length)
            {
              const double S = shape(center);
              sum_S += S;
              sum_Sx += S * center;
            }
          if (sum_S < 1e-12)
            continue;
          const double x = sum_Sx / sum_S;
          if (!x_table.empty() && x <= x_table.back() + 1e-12)
            {
              if (x_table.size() > 1)
                break; // the end of the rising branch
              continue;
            }
          x_table.push_back(x);
          d_table.push_back(edge);
        }
      AssertThrow(x_table.size() > 1, ExcInternalError());
    }



    double
    EdgeDistance::alpha(const double x) const
    {
      if (x <= x_table.front())
        return d_table.front() + (x - x_table.front());
      if (x >= x_table.back())
        return d_table.back() + (x - x_table.back());
      const auto   upper = std::upper_bound(x_table.begin(), x_table.end(), x);
      const auto   k     = upper - x_table.begin();
      const double w     = (x - x_table[k - 1]) / (x_table[k] - x_table[k - 1]);
      return (1 - w) * d_table[k - 1] + w * d_table[k];
    }



    namespace
    {
      /** Solve the SPD system A y = b of size n <= 4 by Cholesky; false if
       * A is not positive definite. */
      bool
      cholesky_solve(double *A, double *b, const unsigned int n)
      {
        for (unsigned int j = 0; j < n; ++j)
          {
            double diagonal = A[j * n + j];
            for (unsigned int k = 0; k < j; ++k)
              diagonal -= A[j * n + k] * A[j * n + k];
            if (!(diagonal > 1e-300))
              return false;
            const double L_jj = std::sqrt(diagonal);
            A[j * n + j]      = L_jj;
            for (unsigned int i = j + 1; i < n; ++i)
              {
                double value = A[i * n + j];
                for (unsigned int k = 0; k < j; ++k)
                  value -= A[i * n + k] * A[j * n + k];
                A[i * n + j] = value / L_jj;
              }
          }
        for (unsigned int i = 0; i < n; ++i) // L z = b
          {
            for (unsigned int k = 0; k < i; ++k)
              b[i] -= A[i * n + k] * b[k];
            b[i] /= A[i * n + i];
          }
        for (unsigned int i = n; i-- > 0;) // Lᵀ y = z
          {
            for (unsigned int k = i + 1; k < n; ++k)
              b[i] -= A[k * n + i] * b[k];
            b[i] /= A[i * n + i];
          }
        return true;
      }
    } // namespace



    template <int dim>
    RegressionResult<dim>
    logistic_regression_normal(const Tensor<1, dim> *x,
                               const double         *c,
                               const unsigned int    n_points,
                               const double          cell_size,
                               const double          tolerance,
                               const unsigned int    max_iterations)
    {
      constexpr unsigned int n = dim + 1; // φ = (normal, offset)
      RegressionResult<dim>  result;
      if (n_points == 0)
        return result;
      Tensor<1, dim> origin;
      for (unsigned int p = 0; p < n_points; ++p)
        origin += x[p];
      origin /= n_points;
      // λ = 10⁻⁷ Δx² on the normal's components, none on the offset.
      double lambda[n];
      for (unsigned int j = 0; j < dim; ++j)
        lambda[j] = 1e-7 * cell_size * cell_size;
      lambda[dim] = 0;

      // The centred positions with the offset's 1, once per fit.
      thread_local std::vector<std::array<double, n>> centred;
      centred.resize(n_points);
      for (unsigned int p = 0; p < n_points; ++p)
        {
          for (unsigned int d = 0; d < dim; ++d)
            centred[p][d] = x[p][d] - origin[d];
          centred[p][dim] = 1;
        }

      double phi[n] = {};
      for (unsigned int iteration = 0; iteration <= max_iterations; ++iteration)
        {
          // Eq. 21 with Eqs. 54-56: (JᵀWJ + Λ) Δφ = JᵀW(c − f) − Λφ,
          // J_pj = ψ(x_p) x_pj, ψ = 2e^{−s}/(1 + e^{−s})². One exponential
          // of −|s| gives f (Eq. 20, odd in s) and ψ (even) without
          // overflow; at φ⁽⁰⁾ = 0, f = 0 and ψ = 1/2.
          double A[n * n] = {}, b[n];
          for (unsigned int j = 0; j < n; ++j)
            b[j] = -lambda[j] * phi[j];
          for (unsigned int p = 0; p < n_points; ++p)
            {
              const double *const xp  = centred[p].data();
              double              psi = 0.5, f = 0;
              if (iteration > 0)
                {
                  double s = 0;
                  for (unsigned int j = 0; j < n; ++j)
                    s += xp[j] * phi[j];
                  if (std::abs(s) > 40) // ψ < 1e-17: ψ² x x below λ's round-off
                    continue;
                  const double e     = std::exp(-std::abs(s));
                  const double inv   = 1. / (1. + e);
                  const double f_abs = (1. - e) * inv;
                  psi                = 2. * e * inv * inv;
                  f                  = s < 0 ? -f_abs : f_abs;
                }
              const double psi2     = psi * psi;
              const double residual = psi * (c[p] - f);
              for (unsigned int j = 0; j < n; ++j)
                {
                  b[j] += residual * xp[j];
                  for (unsigned int k = 0; k <= j; ++k)
                    A[j * n + k] += psi2 * xp[j] * xp[k];
                }
            }
          for (unsigned int j = 0; j < n; ++j)
            {
              A[j * n + j] += lambda[j];
              for (unsigned int k = 0; k < j; ++k)
                A[k * n + j] = A[j * n + k];
            }
          if (!cholesky_solve(A, b, n))
            break;
          double candidate[n];
          for (unsigned int j = 0; j < n; ++j)
            candidate[j] = phi[j] + b[j];
          Tensor<1, dim> normal;
          for (unsigned int d = 0; d < dim; ++d)
            normal[d] = candidate[d];
          const double length = normal.norm();
          if (!(length > 0) || !std::isfinite(length))
            break;
          normal /= length;
          std::copy(candidate, candidate + n, phi);
          if (!result.valid) // φ⁽¹⁾: the linear regression
            {
              result.valid  = true;
              result.normal = normal;
              continue;
            }
          ++result.iterations;
          const double change = 1. - normal * result.normal; // Eq. 57
          result.normal       = normal;
          if (change < tolerance)
            {
              result.converged = true;
              break;
            }
        }
      return result;
    }

    template RegressionResult<2>
    logistic_regression_normal(const Tensor<1, 2> *,
                               const double *,
                               const unsigned int,
                               const double,
                               const double,
                               const unsigned int);
    template RegressionResult<3>
    logistic_regression_normal(const Tensor<1, 3> *,
                               const double *,
                               const unsigned int,
                               const double,
                               const double,
                               const unsigned int);

    std::string
    normal_method_names()
    {
      return Plugins::Registry<NormalMethodInterface<2>>::instance().pattern();
    }



    std::string
    normal_method_documentation()
    {
      return Plugins::Registry<NormalMethodInterface<2>>::instance()
        .documentation();
    }



    template <int dim>
    std::unique_ptr<NormalMethodInterface<dim>>
    create_normal_method(const std::string &name)
    {
      ParameterHandler unused; // the methods read subsection Contact
      return Plugins::Registry<NormalMethodInterface<dim>>::instance().create(
        name, unused);
    }

    template std::unique_ptr<NormalMethodInterface<2>>
    create_normal_method<2>(const std::string &);
    template std::unique_ptr<NormalMethodInterface<3>>
    create_normal_method<3>(const std::string &);



    namespace
    {
      /** n̂ = (g^α − g^β)/|g^α − g^β| (Eq. 13); false where it vanishes. */
      template <int dim>
      bool
      gradient_normal(const NormalInputs<dim> &node, Tensor<1, dim> &normal)
      {
        const Tensor<1, dim> difference =
          node.volume_gradient_alpha - node.volume_gradient_beta;
        const double norm = difference.norm();
        if (!(norm > 0))
          return false;
        normal = difference / norm;
        return true;
      }

      /** n̂ of Eq. 13; contact whenever approaching (Eq. 14 alone). */
      template <int dim>
      class VelocityOnly : public NormalMethodInterface<dim>
      {
      public:
        NormalNeeds
        needs() const override
        {
          NormalNeeds needs;
          needs.volume_gradients = true;
          return needs;
        }

        NodeGeometry<dim>
        geometry(const NormalInputs<dim> &node) override
        {
          NodeGeometry<dim> result;
          result.touching = gradient_normal(node, result.normal);
          return result;
        }
      };

      /** n̂ of Eq. 13; approaching and (x^β − x^α)·n̂ < δc h (Eqs. 16-17):
       * δc of 'Critical separation' (CP), or of the linear d(x) fit of the
       * shape function (AG: Eq. 17, 0.92 cells classic and GIMP, 0.96
       * CPDI). */
      template <int dim>
      class SeparationBelowCritical : public NormalMethodInterface<dim>
      {
      public:
        explicit SeparationBelowCritical(const bool user_critical_separation)
          : user_critical_separation(user_critical_separation)
        {}

        NormalNeeds
        needs() const override
        {
          NormalNeeds needs;
          needs.volume_gradients = true;
          needs.positions        = true;
          needs.cell_size        = true;
          return needs;
        }

        void
        set_up(const Parameters &contact, const NormalSetup &setup) override
        {
          critical_separation = user_critical_separation ?
                                  contact.critical_separation :
                                setup.type == ShapeFunction::Type::cpdi ? 0.96 :
                                                                          0.92;
        }

        NodeGeometry<dim>
        geometry(const NormalInputs<dim> &node) override
        {
          NodeGeometry<dim> result;
          if (!gradient_normal(node, result.normal))
            {
              result.touching = false;
              return result;
            }
          const Tensor<1, dim> x_alpha =
            node.position_moment_alpha / node.mass_alpha;
          const Tensor<1, dim> x_beta =
            node.position_moment_beta / node.mass_beta;
          result.separation =
            (x_beta - x_alpha) * result.normal / node.cell_size;
          result.touching = result.separation < critical_separation;
          return result;
        }

      private:
        const bool user_critical_separation;
        double     critical_separation = 0.92;
      };

      template <int dim>
      class AverageGradient : public SeparationBelowCritical<dim>
      {
      public:
        AverageGradient()
          : SeparationBelowCritical<dim>(false)
        {}
      };

      template <int dim>
      class ContactPosition : public SeparationBelowCritical<dim>
      {
      public:
        ContactPosition()
          : SeparationBelowCritical<dim>(true)
        {}
      };

      /** n̂ of Eq. 13; approaching and d(x^β) − d(x^α) < 0 (Eq. 15) with d
       * the edge distance of the shape function in use (EdgeDistance). */
      template <int dim>
      class DFit : public NormalMethodInterface<dim>
      {
      public:
        NormalNeeds
        needs() const override
        {
          NormalNeeds needs;
          needs.volume_gradients = true;
          needs.positions        = true;
          needs.cell_size        = true;
          needs.node_positions   = true;
          needs.measures_gap     = true;
          return needs;
        }

        void
        set_up(const Parameters &, const NormalSetup &setup) override
        {
          edge_distance.clear();
          for (const unsigned int points_per_cell : setup.points_per_cell)
            edge_distance.emplace_back(setup.type, 0.5 / points_per_cell);
        }

        NodeGeometry<dim>
        geometry(const NormalInputs<dim> &node) override
        {
          NodeGeometry<dim> result;
          if (!gradient_normal(node, result.normal))
            {
              result.touching = false;
              return result;
            }
          const double         h = node.cell_size;
          const Tensor<1, dim> x_alpha =
            node.position_moment_alpha / node.mass_alpha;
          const Tensor<1, dim> x_beta =
            node.position_moment_beta / node.mass_beta;
          const double gap =
            edge_distance[node.first_beta].beta((x_beta - node.node_position) *
                                                result.normal / h) -
            edge_distance[node.first_alpha].alpha(
              (x_alpha - node.node_position) * result.normal / h);
          result.separation = gap;
          result.touching   = gap < 0;
          return result;
        }

      private:
        /** d(x) per material (its points' half-length). */
        std::vector<EdgeDistance> edge_distance;
      };

      /** n̂ and d_LR from the node's point cloud (Eqs. 19-25). */
      template <int dim>
      class LogisticRegression : public NormalMethodInterface<dim>
      {
      public:
        NormalNeeds
        needs() const override
        {
          NormalNeeds needs;
          needs.cell_size    = true;
          needs.point_clouds = true;
          needs.measures_gap = true;
          return needs;
        }

        NodeGeometry<dim>
        geometry(const NormalInputs<dim> &node) override
        {
          // Eqs. 19-21: the plane between the two classes of the cloud;
          // Eqs. 22-25: d_LR from the points nearest to it, R_p of their
          // deformed ellipsoids.
          NodeGeometry<dim> result;
          cloud_x.clear();
          cloud_c.clear();
          cloud_k.clear();
          for (unsigned int k = 0; k < node.cloud.size(); ++k)
            {
              const int side = node.side_of_material[node.cloud[k].material];
              if (side == 0)
                continue;
              Tensor<1, dim> x;
              for (unsigned int d = 0; d < dim; ++d)
                x[d] = node.cloud[k].position[d];
              cloud_x.push_back(x);
              cloud_c.push_back(side);
              cloud_k.push_back(k);
            }
          const auto fit = logistic_regression_normal<dim>(cloud_x.data(),
                                                           cloud_c.data(),
                                                           cloud_x.size(),
                                                           node.cell_size);
          ++fits;
          iterations += fit.iterations;
          if (!fit.valid)
            {
              result.touching = false;
              return result;
            }
          result.normal     = fit.normal;
          double alpha_edge = -std::numeric_limits<double>::max();
          double beta_edge  = std::numeric_limits<double>::max();
          for (unsigned int q = 0; q < cloud_k.size(); ++q)
            {
              const CloudPoint<dim> &point = node.cloud[cloud_k[q]];
              Tensor<2, dim>         F_inverse;
              Tensor<1, dim>         radii;
              for (unsigned int a = 0; a < dim; ++a)
                {
                  radii[a] = point.initial_radii[a];
                  for (unsigned int b = 0; b < dim; ++b)
                    F_inverse[a][b] = point.F_inverse[a * dim + b];
                }
              const double R = deformed_radius(F_inverse, radii, result.normal);
              const double s = cloud_x[q] * result.normal;
              if (cloud_c[q] < 0)
                alpha_edge = std::max(alpha_edge, s + R); // Eq. 22
              else
                beta_edge = std::min(beta_edge, s - R); // Eq. 23
            }
          const double d_LR = beta_edge - alpha_edge; // Eq. 24
          result.separation = d_LR / node.cell_size;
          result.touching   = d_LR < 0;
          return result;
        }

        std::vector<std::pair<std::string, double>>
        statistics(const MPI_Comm comm) const override
        {
          const double all_fits =
            Utilities::MPI::sum(static_cast<double>(fits), comm);
          const double all_iterations =
            Utilities::MPI::sum(static_cast<double>(iterations), comm);
          if (!(all_fits > 0))
            return {};
          return {{"logistic_regression_fits", all_fits},
                  {"logistic_regression_iterations_mean",
                   all_iterations / all_fits}};
        }

      private:
        /** Scratch: the cloud's positions, classes and places. */
        std::vector<Tensor<1, dim>> cloud_x;
        std::vector<double>         cloud_c;
        std::vector<unsigned int>   cloud_k;
        /** Fits and NLLS iterations since the start (benchmark figures). */
        unsigned long long fits = 0, iterations = 0;
      };

      /** 'Specified normal' from the lower-numbered material to the
       * higher; contact when approaching. */
      template <int dim>
      class Specified : public NormalMethodInterface<dim>
      {
      public:
        NormalNeeds
        needs() const override
        {
          return NormalNeeds();
        }

        void
        set_up(const Parameters &contact, const NormalSetup &) override
        {
          for (unsigned int d = 0; d < dim; ++d)
            normal[d] = contact.specified_normal[d];
          if (normal.norm() > 0)
            normal /= normal.norm();
        }

        NodeGeometry<dim>
        geometry(const NormalInputs<dim> &node) override
        {
          NodeGeometry<dim> result;
          result.normal =
            (node.first_alpha < node.first_beta ? 1. : -1.) * normal;
          return result;
        }

      private:
        Tensor<1, dim> normal;
      };
    } // namespace

    FMPM_REGISTER_CONTACT_NORMALS(
      VelocityOnly,
      "velocity only",
      "n from the volume gradients (Eq. 13), contact whenever the materials "
      "approach (Eq. 14).")
    FMPM_REGISTER_CONTACT_NORMALS(
      AverageGradient,
      "average gradient",
      "n of Eq. 13, approach and separation of the extrapolated positions "
      "below the delta_c of the linear d(x) fit (Eq. 17: 0.92 cells for "
      "classic and GIMP, 0.96 for CPDI).")
    FMPM_REGISTER_CONTACT_NORMALS(
      ContactPosition,
      "contact position",
      "the same with delta_c = 'Critical separation' (Eq. 16).")
    FMPM_REGISTER_CONTACT_NORMALS(
      Specified,
      "specified",
      "n = 'Specified normal' from the lower-numbered material to the "
      "higher, contact when approaching.")
    FMPM_REGISTER_CONTACT_NORMALS(
      DFit,
      "d fit",
      "(DF): n of Eq. 13, approach and d(x^b) - d(x^a) < 0 (Eq. 15) with "
      "d(x) the edge distance of the shape function in use, tabulated at "
      "start-up.")
    FMPM_REGISTER_CONTACT_NORMALS(
      LogisticRegression,
      "logistic regression",
      "(LR): n and the separation d_LR from the point cloud around the node "
      "(Eqs. 19-25), contact when approaching and d_LR < 0 (see 'Touching "
      "tolerance').")
  } // namespace Contact
} // namespace fmpm
