// Error types shared by every layer.
//
// Nothing below drivers/ prints or exits: problems travel up as exceptions of
// these types, each carrying a message a user can act on. Drivers map them to
// exit codes.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace hemivem {

/// Base of every error hemivem throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input: a file, a parameter or a problem definition that cannot be used.
/// `where()` names the file and line (or field) when one is known.
/// What part of a problem an InputError is about, when the code that finds it knows no key of
/// the input (the contact boundary, the supports): the application names its own key from it
/// (a scene's `contact` or `clamped`), so that no caller matches messages.
enum class ProblemPart { unknown, contact, supports };

class InputError : public Error {
 public:
  explicit InputError(const std::string& message, std::string where = {})
      : Error(where.empty() ? message : where + ": " + message),
        where_(std::move(where)),
        detail_(message) {}
  const std::string& where() const noexcept { return where_; }
  const std::string& detail() const noexcept { return detail_; }
  /// What the error is about (ProblemPart::unknown unless marked).
  ProblemPart about() const noexcept { return about_; }
  /// Marks the error as about `part`, unless it is marked already.
  InputError& mark_about(ProblemPart part) noexcept {
    if (about_ == ProblemPart::unknown) about_ = part;
    return *this;
  }

 private:
  std::string where_;
  std::string detail_;
  ProblemPart about_ = ProblemPart::unknown;
};

/// Runs f(); an InputError it throws leaves marked as about `part` (InputError::mark_about).
template <class F>
decltype(auto) about(ProblemPart part, F&& f) {
  try {
    return f();
  } catch (InputError& e) {
    e.mark_about(part);
    throw;
  }
}

/// A mesh that violates the rules of a valid polygonal mesh. `element()` is the
/// offending element (or -1 when the defect is not tied to one element).
class MeshError : public InputError {
 public:
  MeshError(const std::string& message, int element, std::string where = {})
      : InputError(message, std::move(where)), element_(element) {}
  int element() const noexcept { return element_; }

 private:
  int element_;
};

/// A numerical failure inside an engine (e.g. a matrix that is not positive definite).
class NumericalError : public Error {
 public:
  using Error::Error;
};

/// A programming error: a call that breaks a contract (arguments that do not fit, calls out
/// of order). No input file or parameter can cause it.
class InternalError : public Error {
 public:
  using Error::Error;
};

}  // namespace hemivem
