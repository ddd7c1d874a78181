#include <hemivem/contact/obstacle.hpp>

#include <hemivem/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace hemivem {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// A point where the ray x + t nu crosses the obstacle's surface, entering or leaving it.
struct Crossing {
  double t;
  bool entering;
};

/// The gap from the crossings of the whole ray (t over all reals): inside the obstacle at t = 0
/// when the last crossing before 0 enters it; then the gap is that crossing's t (<= 0).
/// Outside, it is the first entering crossing after 0, or +inf.
double gap_from(std::vector<Crossing> crossings) {
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) { return a.t < b.t; });
  const Crossing* last_before = nullptr;
  for (const auto& c : crossings)
    if (c.t <= 0.0) last_before = &c;
  if (last_before != nullptr && last_before->entering) return last_before->t;
  for (const auto& c : crossings)
    if (c.t > 0.0 && c.entering) return c.t;
  return kInfinity;
}

Vec2 left_normal(const Vec2& d) { return Vec2(-d.y(), d.x()); }

}  // namespace

double Obstacle::gap(const Vec2& x, const Vec2& nu) const {
  std::vector<Crossing> crossings;
  switch (shape) {
    case Shape::plane: {
      // f(t) = n . (x + t nu - point): > 0 on the body's side, < 0 in the obstacle
      const Vec2 n = normal.normalized();
      const double rate = n.dot(nu);
      if (rate != 0.0) crossings.push_back({-n.dot(x - point) / rate, rate < 0.0});
      break;
    }
    case Shape::circle: {
      // |x + t nu - center|^2 = radius^2 (nu a unit vector)
      const Vec2 d = x - center;
      const double b = nu.dot(d);
      const double disc = b * b - (d.squaredNorm() - radius * radius);
      if (disc > 0.0) {
        const double root = std::sqrt(disc);
        crossings.push_back({-b - root, true});
        crossings.push_back({-b + root, false});
      }
      break;
    }
    case Shape::polyline:
      for (std::size_t k = 0; k + 1 < points.size(); ++k) {
        // x + t nu = points[k] + s d, s in [0, 1]
        const Vec2 d = points[k + 1] - points[k];
        const Vec2 m = left_normal(d);  // towards the body
        const double rate = m.dot(nu);
        if (rate == 0.0) continue;
        const double t = -m.dot(x - points[k]) / rate;
        const Vec2 hit = x + t * nu;
        const double s = (hit - points[k]).dot(d) / d.squaredNorm();
        if (s < 0.0 || s > 1.0) continue;
        crossings.push_back({t, rate < 0.0});
      }
      break;
  }
  return gap_from(std::move(crossings));
}

std::string Obstacle::defect() const {
  switch (shape) {
    case Shape::plane:
      if (!(normal.norm() > 0.0)) return "the normal is zero";
      break;
    case Shape::circle:
      if (!(radius > 0.0)) return "the radius must be > 0";
      break;
    case Shape::polyline:
      if (points.size() < 2) return "a polyline needs at least 2 points";
      for (std::size_t k = 0; k + 1 < points.size(); ++k)
        if (points[k] == points[k + 1]) return "points " + std::to_string(k) + " and " + std::to_string(k + 1) + " are equal";
      break;
  }
  return {};
}

std::string to_string(Obstacle::Shape shape) {
  switch (shape) {
    case Obstacle::Shape::plane: return "plane";
    case Obstacle::Shape::circle: return "circle";
    case Obstacle::Shape::polyline: return "polyline";
  }
  throw InternalError("an obstacle shape out of range: " + std::to_string(static_cast<int>(shape)));
}

Obstacle::Shape obstacle_shape_from_string(const std::string& name) {
  if (name == "plane") return Obstacle::Shape::plane;
  if (name == "circle") return Obstacle::Shape::circle;
  if (name == "polyline") return Obstacle::Shape::polyline;
  throw InputError("unknown obstacle shape '" + name + "'; expected one of: plane, circle, polyline");
}

double Obstacle3D::gap(const Vec3& x, const Vec3& nu) const {
  std::vector<Crossing> crossings;
  // the crossings of the ray with the quadric |P (x + t nu - center)|^2 = radius^2 (P = I for a
  // sphere, the projection across the axis for a cylinder)
  auto quadric = [&](const Eigen::Matrix3d& P) {
    const Vec3 d = P * (x - center), e = P * nu;
    const double a = e.squaredNorm();
    if (!(a > 0.0)) return;  // a ray along a cylinder's axis never crosses its side
    const double b = e.dot(d) / a;
    const double disc = b * b - (d.squaredNorm() - radius * radius) / a;
    if (disc > 0.0) {
      const double root = std::sqrt(disc);
      crossings.push_back({-b - root, true});
      crossings.push_back({-b + root, false});
    }
  };
  switch (shape) {
    case Shape::plane: {
      const Vec3 n = normal.normalized();
      const double rate = n.dot(nu);
      if (rate != 0.0) crossings.push_back({-n.dot(x - point) / rate, rate < 0.0});
      break;
    }
    case Shape::sphere:
      quadric(Eigen::Matrix3d::Identity());
      break;
    case Shape::cylinder: {
      const Vec3 a = axis.normalized();
      quadric(Eigen::Matrix3d::Identity() - a * a.transpose());
      break;
    }
  }
  return gap_from(std::move(crossings));
}

std::string Obstacle3D::defect() const {
  const bool finite = point.allFinite() && normal.allFinite() && center.allFinite() && axis.allFinite() &&
                      std::isfinite(radius);
  if (!finite) return "the obstacle's data are not finite";
  if (shape == Shape::plane && !(normal.norm() > 0.0)) return "the plane's normal is zero";
  if (shape == Shape::cylinder && !(axis.norm() > 0.0)) return "the cylinder's axis is zero";
  if (shape != Shape::plane && !(radius > 0.0)) return "the radius must be positive";
  return {};
}

std::string to_string(Obstacle3D::Shape shape) {
  switch (shape) {
    case Obstacle3D::Shape::plane: return "plane";
    case Obstacle3D::Shape::sphere: return "sphere";
    case Obstacle3D::Shape::cylinder: return "cylinder";
  }
  throw InternalError("an Obstacle3D::Shape out of range");
}

Obstacle3D::Shape obstacle3d_shape_from_string(const std::string& name) {
  if (name == "plane") return Obstacle3D::Shape::plane;
  if (name == "sphere") return Obstacle3D::Shape::sphere;
  if (name == "cylinder") return Obstacle3D::Shape::cylinder;
  throw InputError("unknown obstacle shape '" + name + "' for a three-dimensional body; expected plane, sphere or cylinder");
}

}  // namespace hemivem
