#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace ejecta {

// Monotone piecewise-cubic Hermite interpolant (Fritsch & Carlson 1980, with the Fritsch &
// Butland harmonic-mean slopes). Preserves monotonicity of the data, so a compaction curve
// interpolated with it stays monotone and its tangent modulus stays non-negative.
class MonotoneCubic {
 public:
  MonotoneCubic() = default;
  MonotoneCubic(std::vector<double> x, std::vector<double> y) : x_(std::move(x)), y_(std::move(y)) {
    const std::size_t n = x_.size();
    if (n < 2 || y_.size() != n) throw std::invalid_argument("MonotoneCubic: need >= 2 points");
    for (std::size_t i = 1; i < n; ++i)
      if (!(x_[i] > x_[i - 1])) throw std::invalid_argument("MonotoneCubic: x must increase");
    std::vector<double> h(n - 1), delta(n - 1);
    for (std::size_t i = 0; i + 1 < n; ++i) {
      h[i] = x_[i + 1] - x_[i];
      delta[i] = (y_[i + 1] - y_[i]) / h[i];
    }
    d_.assign(n, 0.0);
    for (std::size_t i = 1; i + 1 < n; ++i) {
      if (delta[i - 1] * delta[i] > 0.0) {
        const double w1 = 2 * h[i] + h[i - 1], w2 = h[i] + 2 * h[i - 1];
        d_[i] = (w1 + w2) / (w1 / delta[i - 1] + w2 / delta[i]);
      }
    }
    d_[0] = endSlope(h[0], h.size() > 1 ? h[1] : h[0], delta[0], delta.size() > 1 ? delta[1] : delta[0]);
    d_[n - 1] = endSlope(h[n - 2], n > 2 ? h[n - 3] : h[n - 2], delta[n - 2],
                         n > 2 ? delta[n - 3] : delta[n - 2]);
  }

  double operator()(double x) const { return eval(x, false); }
  double derivative(double x) const { return eval(x, true); }
  double xmin() const { return x_.front(); }
  double xmax() const { return x_.back(); }

 private:
  static double endSlope(double h0, double h1, double d0, double d1) {
    // Three-point, shape-preserving end condition.
    double d = ((2 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
    if (d * d0 <= 0.0) return 0.0;
    if (d0 * d1 <= 0.0 && std::abs(d) > std::abs(3 * d0)) return 3 * d0;
    return d;
  }

  double eval(double x, bool deriv) const {
    x = std::clamp(x, x_.front(), x_.back());
    auto it = std::upper_bound(x_.begin(), x_.end(), x);
    std::size_t i = std::min<std::size_t>(std::max<std::ptrdiff_t>(it - x_.begin() - 1, 0), x_.size() - 2);
    const double h = x_[i + 1] - x_[i], t = (x - x_[i]) / h;
    const double t2 = t * t, t3 = t2 * t;
    if (deriv) {
      return ((6 * t2 - 6 * t) * y_[i] + (3 * t2 - 4 * t + 1) * h * d_[i] + (-6 * t2 + 6 * t) * y_[i + 1] +
              (3 * t2 - 2 * t) * h * d_[i + 1]) / h;
    }
    return (2 * t3 - 3 * t2 + 1) * y_[i] + (t3 - 2 * t2 + t) * h * d_[i] + (-2 * t3 + 3 * t2) * y_[i + 1] +
           (t3 - t2) * h * d_[i + 1];
  }

  std::vector<double> x_, y_, d_;
};

// Root of a monotone function by bisection on [lo, hi] where f(lo) <= 0 <= f(hi).
template <class F>
double bisect(F&& f, double lo, double hi, double rel_tol = 1e-14, int max_iter = 200) {
  for (int it = 0; it < max_iter && (hi - lo) > rel_tol * std::max(std::abs(lo), std::abs(hi)); ++it) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace ejecta
