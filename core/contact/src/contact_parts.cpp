// The contact parts of a problem (hemivem/contact/problem.hpp).
#include <hemivem/contact/problem.hpp>
#include <hemivem/error.hpp>

#include <set>

namespace hemivem {

std::vector<ContactPart> contact_parts(const ContactProblem& problem) {
  std::vector<ContactPart> parts;
  if (problem.contact_edges.empty() && problem.more_contact.empty()) return parts;
  parts.push_back(ContactPart{problem.contact_name, problem.contact_edges, problem.gap, problem.obstacle, problem.law,
                              problem.constraint, problem.law_from_surface, problem.friction,
                              problem.friction_bound});
  parts.insert(parts.end(), problem.more_contact.begin(), problem.more_contact.end());
  check_contact_parts(parts);
  return parts;
}

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

void set_contact_parts(ContactProblem& problem, std::vector<ContactPart> parts) {
  problem.more_contact.clear();
  if (parts.empty()) {
    problem.contact_edges.clear();
    problem.gap = {};
    problem.obstacle.reset();
    problem.law = nullptr;
    problem.friction = nullptr;
    problem.friction_bound.reset();
    return;
  }
  ContactPart& first = parts.front();
  problem.contact_name = std::move(first.name);
  problem.contact_edges = std::move(first.facets);
  problem.gap = std::move(first.gap);
  problem.obstacle = std::move(first.obstacle);
  problem.law = std::move(first.law);
  problem.constraint = first.constraint;
  problem.law_from_surface = first.law_from_surface;
  problem.friction = std::move(first.friction);
  problem.friction_bound = std::move(first.friction_bound);
  problem.more_contact.assign(std::make_move_iterator(parts.begin() + 1), std::make_move_iterator(parts.end()));
}

}  // namespace hemivem
