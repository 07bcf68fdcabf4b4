#pragma once
// 2D vector math in SI units (metres, metres per second). Plain value type, no dependencies.
#include <cmath>
#include <limits>

namespace salsa {

struct Vec2 {
  double x = 0, y = 0;

  constexpr Vec2() = default;
  constexpr Vec2(double x_, double y_) : x(x_), y(y_) {}

  static Vec2 polar(double length, double angle) { return {length * std::cos(angle), length * std::sin(angle)}; }
  bool finite() const { return std::isfinite(x) && std::isfinite(y); }

  constexpr Vec2 operator+(Vec2 o) const { return {x + o.x, y + o.y}; }
  constexpr Vec2 operator-(Vec2 o) const { return {x - o.x, y - o.y}; }
  constexpr Vec2 operator-() const { return {-x, -y}; }
  constexpr Vec2 operator*(double s) const { return {x * s, y * s}; }
  constexpr Vec2 operator/(double s) const { return {x / s, y / s}; }
  constexpr Vec2& operator+=(Vec2 o) { x += o.x; y += o.y; return *this; }
  constexpr Vec2& operator-=(Vec2 o) { x -= o.x; y -= o.y; return *this; }
  constexpr Vec2& operator*=(double s) { x *= s; y *= s; return *this; }
  constexpr Vec2& operator/=(double s) { x /= s; y /= s; return *this; }
  constexpr bool operator==(const Vec2&) const = default;

  constexpr double dot(Vec2 o) const { return x * o.x + y * o.y; }
  constexpr double cross(Vec2 o) const { return x * o.y - y * o.x; }
  constexpr double length_squared() const { return x * x + y * y; }
  /// Exact for every finite vector: where x² + y² would overflow (components ≳ 1e154) or underflow, the
  /// vector is scaled first. Infinite for an infinite component, NaN for a NaN one.
  double length() const {
    const double l2 = length_squared();
    if (ordinary(l2)) return std::sqrt(l2);
    if (is_zero() || std::isnan(l2)) return l2;
    if (std::isinf(x) || std::isinf(y)) return std::numeric_limits<double>::infinity();
    const double s = largest();
    return s * scaled_down().short_length();
  }
  double angle() const { return std::atan2(y, x); }
  constexpr bool is_zero() const { return x == 0 && y == 0; }

  /// Unit vector in the same direction; the zero vector stays zero, and so does one with a NaN
  /// component. An infinite component gives the direction it points in: (inf, 5) → (1, 0).
  Vec2 normalized() const {
    const double l2 = length_squared();
    if (ordinary(l2)) {
      const double l = std::sqrt(l2);
      return {x / l, y / l};
    }
    if (is_zero() || std::isnan(l2)) return {};
    const Vec2 u = scaled_down();
    return u / u.short_length();
  }
  /// Same direction, length at most `max_length`. Any length clamps, however large (a steering of
  /// (1e200, 0) gives (max_length, 0)); an infinite component clamps along the direction it points in;
  /// a NaN component stays NaN (the core refuses a non-finite steering, naming the drone).
  Vec2 clamped(double max_length) const {
    const double l2 = length_squared();
    if (ordinary(l2)) {
      if (l2 <= max_length * max_length) return *this;
      return *this * (max_length / std::sqrt(l2));
    }
    if (is_zero() || std::isnan(l2)) return *this;
    const Vec2 u = scaled_down();
    const double lu = u.short_length();
    if (!std::isinf(x) && !std::isinf(y) && largest() * lu <= max_length) return *this;
    return u * (max_length / lu);
  }
  /// Same direction, exactly `new_length` (zero stays zero).
  Vec2 with_length(double new_length) const { return normalized() * new_length; }
  Vec2 rotated(double angle) const {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * x - s * y, s * x + c * y};
  }

 private:
  /// x² + y² neither overflowed nor underflowed (nor is NaN): the plain formulas are exact enough.
  static bool ordinary(double l2) { return l2 >= std::numeric_limits<double>::min() && l2 <= std::numeric_limits<double>::max(); }
  double largest() const { return std::fabs(x) > std::fabs(y) ? std::fabs(x) : std::fabs(y); }
  /// Divided by its largest |component| (length in [1, √2]); for infinite components, the direction
  /// they point in. Not for the zero vector or NaN components.
  Vec2 scaled_down() const {
    if (std::isinf(x) || std::isinf(y))
      return {std::isinf(x) ? std::copysign(1.0, x) : 0.0, std::isinf(y) ? std::copysign(1.0, y) : 0.0};
    const double s = largest();
    return {x / s, y / s};
  }
  double short_length() const { return std::sqrt(length_squared()); }
};

constexpr Vec2 operator*(double s, Vec2 v) { return v * s; }
inline double distance(Vec2 a, Vec2 b) { return (a - b).length(); }
constexpr double distance_squared(Vec2 a, Vec2 b) { return (a - b).length_squared(); }

/// Axis-aligned rectangle, e.g. a map's bounds (m).
struct Rect {
  Vec2 min, max;
  constexpr double width() const { return max.x - min.x; }
  constexpr double height() const { return max.y - min.y; }
  constexpr double area() const { return width() * height(); }
  constexpr Vec2 centre() const { return {(min.x + max.x) / 2, (min.y + max.y) / 2}; }
  constexpr bool contains(Vec2 p) const { return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y; }
  constexpr bool operator==(const Rect&) const = default;
};

inline constexpr double pi = 3.14159265358979323846;

}  // namespace salsa
