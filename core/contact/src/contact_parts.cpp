// The contact parts of a problem (hemivem/contact/problem.hpp).
#include <hemivem/contact/problem.hpp>
#include <hemivem/error.hpp>

#include <set>

namespace hemivem {

template <int dim>
std::vector<BasicContactPart<dim>> contact_parts(const BasicContactProblem<dim>& problem) {
  check_contact_parts(problem.parts);
  return problem.parts;
}
template std::vector<BasicContactPart<2>> contact_parts(const BasicContactProblem<2>&);
template std::vector<BasicContactPart<3>> contact_parts(const BasicContactProblem<3>&);

template <int dim>
void check_contact_parts(const std::vector<BasicContactPart<dim>>& parts) {
  std::set<std::string> names;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const BasicContactPart<dim>& part = parts[k];
    const std::string which = part.name.empty() ? "contact part " + std::to_string(k) : "contact part '" + part.name + "'";
    if (part.name.empty()) throw InputError(which + " has no name");
    if (part.facets.empty()) throw InputError(which + (dim == 2 ? " has no edges" : " has no faces"));
    if (!names.insert(part.name).second) throw InputError("two contact parts are named '" + part.name + "'");
  }
}
template void check_contact_parts(const std::vector<BasicContactPart<2>>&);
template void check_contact_parts(const std::vector<BasicContactPart<3>>&);

}  // namespace hemivem
