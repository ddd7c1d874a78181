// The pairs of engines of check and bench (hemivem/app/engine_pairs.hpp), under the command's
// namespace as well.
#pragma once

#include <hemivem/app/engine_pairs.hpp>

namespace hemivem::cli {

using namespace hemivem::app;

}  // namespace hemivem::cli
