#include <hemivem/contact_law.hpp>
#include <hemivem/error.hpp>

#include <cctype>

namespace hemivem {

std::string to_string(LawPart part) {
  switch (part) {
    case LawPart::j: return "j";
    case LawPart::j1: return "j1";
    case LawPart::j2: return "j2";
  }
  throw InternalError("a LawPart out of range: " + std::to_string(static_cast<int>(part)));
}

LawPart law_part_from_string(std::string_view name) {
  std::string s(name);
  for (auto& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  for (LawPart part : {LawPart::j, LawPart::j1, LawPart::j2})
    if (s == to_string(part)) return part;
  throw InputError("unknown part of a law '" + std::string(name) + "'; expected j, j1 or j2");
}

}  // namespace hemivem
