// Names as users type them: lower case, and the suggestion for a misspelt one.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace hemivem {

/// `s` in lower case (ASCII).
std::string to_lower(std::string_view s);

/// "; did you mean 'x'?" for the name of `valid` nearest to `name` when it is close (an edit
/// distance of at most max(2, a third of the name's length), or one a prefix of the other),
/// else "": a far suggestion is noise.
std::string did_you_mean(std::string_view name, const std::vector<std::string>& valid);

}  // namespace hemivem
