#include <hemivem/scene/expression.hpp>

#include <hemivem/error.hpp>

#include <muParser.h>

#include <charconv>
#include <mutex>
#include <numbers>

namespace hemivem {

struct ScalarExpression::Parser {
  mu::Parser parser;
  double x = 0.0, y = 0.0, z = 0.0, t = 1.0;
  std::mutex mutex;  // the variables are shared by every evaluation
};

namespace {

std::string shortest(double v) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, r.ptr);
}

}  // namespace

ScalarExpression::ScalarExpression(double value) : value_(value), text_(shortest(value)) {}

ScalarExpression ScalarExpression::parse(const std::string& text, int dimension) {
  ScalarExpression e;
  e.text_ = text;
  auto p = std::make_shared<Parser>();
  try {
    // muparser's own _pi has 12 digits when built with GCC (3.141592653589): the exact ones
    p->parser.DefineConst("_pi", std::numbers::pi);
    p->parser.DefineConst("_e", std::numbers::e);
    p->parser.DefineVar("x", &p->x);
    p->parser.DefineVar("y", &p->y);
    if (dimension == 3) p->parser.DefineVar("z", &p->z);
    p->parser.DefineVar("t", &p->t);
    p->parser.SetExpr(text);
    (void)p->parser.Eval();  // muparser reports syntax errors and unknown names on the first evaluation
    const auto& used = p->parser.GetUsedVar();
    e.uses_t_ = used.count("t") > 0;
    e.uses_position_ = used.count("x") > 0 || used.count("y") > 0 || used.count("z") > 0;
  } catch (const mu::Parser::exception_type& error) {
    // muparser's message names the offending token and its position (counted from 0)
    throw InputError("expression '" + text + "': " + error.GetMsg() +
                     (dimension == 3 ? " (expected an expression in x, y, z and t such as \"0.02 + 0.5*x^2\")"
                                     : " (expected an expression in x, y and t such as \"0.02 + 0.5*x^2\")"));
  }
  e.parser_ = std::move(p);
  return e;
}

double ScalarExpression::operator()(const Vec2& p, double t) const {
  if (!parser_) return value_;
  const std::lock_guard<std::mutex> lock(parser_->mutex);
  parser_->x = p.x();
  parser_->y = p.y();
  parser_->z = 0.0;
  parser_->t = t;
  try {
    return parser_->parser.Eval();
  } catch (const mu::Parser::exception_type& error) {
    throw InputError("expression '" + text_ + "' at (" + shortest(p.x()) + ", " + shortest(p.y()) + ")" +
                     (uses_t_ ? ", t = " + shortest(t) : std::string()) + ": " + error.GetMsg());
  }
}

double ScalarExpression::operator()(const Vec3& p, double t) const {
  if (!parser_) return value_;
  const std::lock_guard<std::mutex> lock(parser_->mutex);
  parser_->x = p.x();
  parser_->y = p.y();
  parser_->z = p.z();
  parser_->t = t;
  try {
    return parser_->parser.Eval();
  } catch (const mu::Parser::exception_type& error) {
    throw InputError("expression '" + text_ + "' at (" + shortest(p.x()) + ", " + shortest(p.y()) + ", " +
                     shortest(p.z()) + ")" + (uses_t_ ? ", t = " + shortest(t) : std::string()) + ": " + error.GetMsg());
  }
}

}  // namespace hemivem
