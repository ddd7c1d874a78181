#include <hemivem/engine_names.hpp>
#include <hemivem/krylov_solver.hpp>

namespace hemivem {

const std::vector<std::string>& known_krylov_solvers() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const std::string_view name : known_krylov_engines()) out.emplace_back(name);
    return out;
  }();
  return names;
}

bool is_krylov_solver(const std::string& name) { return is_known_engine(known_krylov_engines(), name); }

}  // namespace hemivem
