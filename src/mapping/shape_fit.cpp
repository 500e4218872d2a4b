// Shape completion of one fruit (mapping/shape_fit.h).

#include "canopy/mapping/shape_fit.h"

#include <Eigen/Dense>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include <algorithm>
#include <cmath>
#include <limits>

namespace canopy::mapping {

double FruitShape::volume_m3() const { return 4.0 / 3.0 * M_PI * semi_axes.x() * semi_axes.y() * semi_axes.z(); }

double FruitShape::distance(const Vec3& p) const {
  const Vec3 d = p - centre;
  const double n = d.cwiseQuotient(semi_axes).norm();
  if (!(n > 1e-12)) return -semi_axes.minCoeff();
  return d.norm() * (1.0 - 1.0 / n);
}

bool FruitShape::inside(const Vec3& p, double scale) const {
  return (p - centre).cwiseQuotient(semi_axes * scale).squaredNorm() <= 1.0;
}

namespace {

// Residuals of the MAP fit: one radial distance per point over point_sigma, then the two
// semi-axes' prior terms. x = (centre, log horizontal semi-axis, log vertical semi-axis).
Vec3 axes_of(const Eigen::VectorXd& x) {
  const double h = std::exp(x[3]), v = std::exp(x[4]);
  return Vec3(h, h, v);
}

struct FitFunctor {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };

  const std::vector<Vec3>* points = nullptr;
  Vec3 prior = Vec3::Zero();
  double inv_point_sigma = 1.0, inv_prior_sigma = 1.0;

  int inputs() const { return 5; }
  int values() const { return int(points->size()) + 2; }

  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    const Vec3 c = x.head<3>();
    const Vec3 s = axes_of(x);
    const std::size_t n = points->size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 d = (*points)[i] - c;
      const double q = d.cwiseQuotient(s).norm();
      f[Eigen::Index(i)] = (q > 1e-12 ? d.norm() * (1.0 - 1.0 / q) : -s.minCoeff()) * inv_point_sigma;
    }
    f[Eigen::Index(n)] = (s.x() - prior.x()) * inv_prior_sigma;
    f[Eigen::Index(n) + 1] = (s.z() - prior.z()) * inv_prior_sigma;
    return 0;
  }
};

double cost(const FitFunctor& fn, const Eigen::VectorXd& x) {
  Eigen::VectorXd f(fn.values());
  fn(x, f);
  return f.squaredNorm();
}

}  // namespace

FruitShape fit_fruit_shape(const std::vector<Vec3>& points, const ShapeFitParams& params) {
  FruitShape out;
  out.points = points.size();
  if (points.empty()) return out;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= double(points.size());
  const Vec3 prior(params.prior_horizontal_m, params.prior_horizontal_m, params.prior_vertical_m);
  out.centre = mean;
  out.semi_axes = prior;
  if (int(points.size()) < params.min_points) return out;

  // Starts: the algebraic sphere through the points (|p|^2 = 2 c.p + k, centred on the mean
  // for conditioning), and the prior's size behind each side of the points' flattest direction.
  std::vector<Vec3> starts;
  Eigen::MatrixXd A(points.size(), 4);
  Eigen::VectorXd b(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 d = points[i] - mean;
    A.row(Eigen::Index(i)) << 2.0 * d.x(), 2.0 * d.y(), 2.0 * d.z(), 1.0;
    b[Eigen::Index(i)] = d.squaredNorm();
    cov += d * d.transpose();
  }
  const Eigen::Vector4d sphere = A.colPivHouseholderQr().solve(b);
  const double r2 = sphere[3] + sphere.head<3>().squaredNorm();
  const double r_prior = prior.mean();
  if (sphere.allFinite() && r2 > 0.0 && std::sqrt(r2) < 3.0 * r_prior && std::sqrt(r2) > 0.3 * r_prior)
    starts.push_back(mean + sphere.head<3>());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Vec3 normal = eig.eigenvectors().col(0);  // smallest spread
  starts.push_back(mean + r_prior * normal);
  starts.push_back(mean - r_prior * normal);

  FitFunctor fn;
  fn.points = &points;
  fn.prior = prior;
  fn.inv_point_sigma = 1.0 / params.point_sigma_m;
  fn.inv_prior_sigma = 1.0 / params.prior_sigma_m;
  double best = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_x;
  int best_iterations = 0;
  for (const Vec3& c0 : starts) {
    Eigen::VectorXd x(5);
    x << c0, std::log(prior.x()), std::log(prior.z());
    Eigen::NumericalDiff<FitFunctor> nd(fn);
    Eigen::LevenbergMarquardt<Eigen::NumericalDiff<FitFunctor>> lm(nd);
    lm.parameters.maxfev = 10 * params.max_iterations;
    lm.parameters.xtol = 1e-10;
    lm.parameters.ftol = 1e-10;
    lm.minimize(x);
    if (!x.allFinite()) continue;
    const double c = cost(fn, x);
    if (c < best) {
      best = c;
      best_x = x;
      best_iterations = int(lm.nfev);
    }
  }
  if (best_x.size() != 5) return out;
  out.centre = best_x.head<3>();
  out.semi_axes = axes_of(best_x);
  out.iterations = best_iterations;
  double ss = 0.0;
  for (const Vec3& p : points) ss += std::pow(out.distance(p), 2);
  out.rms_m = std::sqrt(ss / double(points.size()));
  out.ok = out.centre.allFinite() && out.semi_axes.allFinite();
  return out;
}

std::vector<Vec3> shape_surface(const FruitShape& s, int n) {
  std::vector<Vec3> out;
  if (n <= 0) return out;
  out.reserve(std::size_t(n));
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (double(i) + 0.5) / double(n);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * double(i);
    out.push_back(s.centre + Vec3(s.semi_axes.x() * r * std::cos(phi), s.semi_axes.y() * r * std::sin(phi),
                                  s.semi_axes.z() * z));
  }
  return out;
}

std::vector<Vec3> shape_surface_spaced(const FruitShape& s, double spacing_m) {
  // Knud Thomsen's approximation of an ellipsoid's area (within 1.1 %).
  const double p = 1.6075;
  const double a = std::pow(s.semi_axes.x(), p), b = std::pow(s.semi_axes.y(), p), c = std::pow(s.semi_axes.z(), p);
  const double area = 4.0 * M_PI * std::pow((a * b + a * c + b * c) / 3.0, 1.0 / p);
  const int n = std::max(12, int(std::lround(area / (spacing_m * spacing_m))));
  return shape_surface(s, std::min(n, 100000));
}

}  // namespace canopy::mapping
