#pragma once
// Triangular solves for the small factors of the per-cycle model algorithms (6 x 6 Gram matrices, the 10 x 10
// joint-space inertia): plain substitution, column by column. Eigen's solvers for dynamic sizes block for large
// matrices and cost several times more at these sizes (measured with bench/ik_benchmark.cpp).
// lower: a Cholesky factor's storage as Eigen::LLT::matrixLLT() keeps it (L in the lower triangle).
#include <Eigen/Core>

namespace hapticd::model::detail {

// X <- L^-1 X (column-oriented: each solved entry updates the rest of its column from L's contiguous column).
template <class Factor, class Derived>
void solve_lower_in_place(const Factor& lower, Eigen::MatrixBase<Derived>& x) noexcept {
  const Eigen::Index m = lower.rows();
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    for (Eigen::Index k = 0; k < m; ++k) {
      const double v = x(k, c) / lower(k, k);
      x(k, c) = v;
      for (Eigen::Index i = k + 1; i < m; ++i) x(i, c) -= lower(i, k) * v;
    }
  }
}

// X <- L^-T X (row i of L^T is L's contiguous column i).
template <class Factor, class Derived>
void solve_upper_in_place(const Factor& lower, Eigen::MatrixBase<Derived>& x) noexcept {
  const Eigen::Index m = lower.rows();
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    for (Eigen::Index i = m - 1; i >= 0; --i) {
      double v = x(i, c);
      for (Eigen::Index k = i + 1; k < m; ++k) v -= lower(k, i) * x(k, c);
      x(i, c) = v / lower(i, i);
    }
  }
}

// X <- (L L^T)^-1 X.
template <class Factor, class Derived>
void cholesky_solve_in_place(const Factor& lower, Eigen::MatrixBase<Derived>& x) noexcept {
  solve_lower_in_place(lower, x);
  solve_upper_in_place(lower, x);
}

}  // namespace hapticd::model::detail
