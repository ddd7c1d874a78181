#include <hemivem/app/launcher.hpp>

#include <cstdlib>

namespace hemivem::app {

namespace {
/// A non-negative integer from the environment, or -1.
int environment_count(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v) return -1;
  char* end = nullptr;
  const long n = std::strtol(v, &end, 10);
  return *end == '\0' && n >= 0 && n <= (1L << 30) ? static_cast<int>(n) : -1;
}
}  // namespace

LaunchedProcesses launched_processes() {
  static constexpr const char* kNames[][2] = {
      {"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"}, {"PMI_SIZE", "PMI_RANK"}, {"MV2_COMM_WORLD_SIZE", "MV2_COMM_WORLD_RANK"}};
  for (const auto& [size_name, rank_name] : kNames) {
    const int size = environment_count(size_name);
    if (size < 1) continue;
    const int rank = environment_count(rank_name);
    return {rank < 0 ? 0 : rank, size};
  }
  return {};
}

}  // namespace hemivem::app
