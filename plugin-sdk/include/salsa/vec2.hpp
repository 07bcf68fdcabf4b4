#pragma once
// 2D vector math in SI units (metres, metres per second). Plain value type, no dependencies.
#include <cmath>

namespace salsa {

struct Vec2 {
  double x = 0, y = 0;

  constexpr Vec2() = default;
  constexpr Vec2(double x_, double y_) : x(x_), y(y_) {}

  static Vec2 polar(double length, double angle) { return {length * std::cos(angle), length * std::sin(angle)}; }

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
  double length() const { return std::sqrt(length_squared()); }
  double angle() const { return std::atan2(y, x); }
  constexpr bool is_zero() const { return x == 0 && y == 0; }

  /// Unit vector in the same direction; the zero vector stays zero.
  Vec2 normalized() const {
    const double l = length();
    return l > 0 ? Vec2{x / l, y / l} : Vec2{};
  }
  /// Same direction, length at most `max_length`.
  Vec2 clamped(double max_length) const {
    const double l2 = length_squared();
    if (l2 <= max_length * max_length) return *this;
    return *this * (max_length / std::sqrt(l2));
  }
  /// Same direction, exactly `new_length` (zero stays zero).
  Vec2 with_length(double new_length) const { return normalized() * new_length; }
  Vec2 rotated(double angle) const {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * x - s * y, s * x + c * y};
  }
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
