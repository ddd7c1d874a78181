// Scalar functions of the position and the load factor given as text: "0.02 + 0.5*x^2",
// "-8*(1 - x)", "sin(_pi*x)", "-0.05*t". Parsed and evaluated by muparser (its operators,
// functions sin cos tan asin acos atan sinh cosh tanh exp ln log log2 log10 sqrt abs sign rint
// min max sum avg, the constants _pi and _e to double precision); the variables are x and y
// (and z in three dimensions), the point, and t, the load factor along a loading path (t = 1 in
// a static solve; the rule for data that do not mention t is in scene.hpp, set_load_factor).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// A scalar field of the point (x, y), or (x, y, z), and the load factor t: a constant or a
/// parsed expression.
class ScalarExpression {
 public:
  /// The constant `value`.
  explicit ScalarExpression(double value = 0.0);
  /// Parses `text` (InputError naming the text, the position and what muparser expected, for
  /// a syntax error or a variable other than x, y and t; with `dimension` 3 the variable z is
  /// known too).
  static ScalarExpression parse(const std::string& text, int dimension = 2);

  /// The value at p and load factor t; may be non-finite where the expression is (1/x at
  /// x = 0).
  double operator()(const Vec2& p, double t = 1.0) const;
  /// The value at a point of space (z is 0 for an expression parsed in two dimensions, which
  /// does not mention it).
  double operator()(const Vec3& p, double t = 1.0) const;
  bool is_constant() const noexcept { return !parser_; }
  /// Whether the expression mentions t (false for a constant).
  bool uses_t() const noexcept { return uses_t_; }
  /// Whether the expression mentions x, y or z (false for a constant).
  bool uses_position() const noexcept { return uses_position_; }
  /// The text it was parsed from, or the constant's shortest round-trip text.
  const std::string& text() const noexcept { return text_; }

 private:
  struct Parser;
  std::shared_ptr<Parser> parser_;  // null for a constant
  double value_ = 0.0;
  bool uses_t_ = false;
  bool uses_position_ = false;
  std::string text_;
};

}  // namespace hemivem
