// DofMap (hemivem/vem/assembly.hpp): the free numbering of the dofs from the prescribed ones alone.
//
// The slots of a numbering are the dofs in its order (dof order, or vertex by vertex along a
// vertex order), prescribed ones included; a free dof's index is its slot less the prescribed
// slots before it. slots_ holds the prescribed slots, increasing: slots_[j] - j free slots lie
// before slots_[j], so the free index f lies at the slot f + k, k the number of j with
// slots_[j] - j <= f.
#include <hemivem/vem/assembly.hpp>

#include <hemivem/error.hpp>

#include <algorithm>
#include <string>
#include <utility>

namespace hemivem {

DofMap::DofMap(int num_dofs, int components, std::vector<int> prescribed_dofs, Eigen::VectorXd values,
               std::vector<int> vertex_order)
    : num_dofs_(num_dofs),
      components_(components),
      prescribed_(std::move(prescribed_dofs)),
      values_(std::move(values)),
      order_(std::move(vertex_order)) {
  if (num_dofs < 0 || components < 1 || num_dofs % components != 0 ||
      values_.size() != static_cast<Eigen::Index>(prescribed_.size()) ||
      (!order_.empty() && static_cast<int>(order_.size()) != num_dofs / components))
    throw InternalError("a dof map of " + std::to_string(num_dofs) + " dofs, " + std::to_string(components) +
                        " per vertex, " + std::to_string(prescribed_.size()) + " prescribed dofs with " +
                        std::to_string(values_.size()) + " values and an order of " + std::to_string(order_.size()) +
                        " vertices");
  for (std::size_t j = 0; j < prescribed_.size(); ++j)
    if (prescribed_[j] < 0 || prescribed_[j] >= num_dofs || (j > 0 && prescribed_[j] <= prescribed_[j - 1]))
      throw InternalError("a dof map's prescribed dofs are not increasing dofs of the " + std::to_string(num_dofs));
  if (!order_.empty()) {
    position_.assign(order_.size(), -1);
    for (std::size_t p = 0; p < order_.size(); ++p) {
      const int v = order_[p];
      if (v < 0 || v >= static_cast<int>(order_.size()) || position_[static_cast<std::size_t>(v)] >= 0)
        throw InternalError("a dof map's vertex order is not a permutation of its " + std::to_string(order_.size()) +
                            " vertices (make_dof_map checks the orders it is given)");
      position_[static_cast<std::size_t>(v)] = static_cast<int>(p);
    }
    slots_.reserve(prescribed_.size());
    for (const int d : prescribed_) slots_.push_back(slot_of(d));
    std::sort(slots_.begin(), slots_.end());
  }
}

int DofMap::slot_of(int dof) const {
  if (order_.empty()) return dof;
  return components_ * position_[static_cast<std::size_t>(dof / components_)] + dof % components_;
}

int DofMap::dof_at(int slot) const {
  if (order_.empty()) return slot;
  return components_ * order_[static_cast<std::size_t>(slot / components_)] + slot % components_;
}

bool DofMap::is_prescribed(int dof) const { return std::binary_search(prescribed_.begin(), prescribed_.end(), dof); }

int DofMap::free_index(int dof) const {
  if (is_prescribed(dof)) return -1;
  const int slot = slot_of(dof);
  const std::vector<int>& slots = order_.empty() ? prescribed_ : slots_;
  return slot - static_cast<int>(std::lower_bound(slots.begin(), slots.end(), slot) - slots.begin());
}

int DofMap::free_dof(int f) const {
  const std::vector<int>& slots = order_.empty() ? prescribed_ : slots_;
  // the first j with slots[j] - j > f: slots[j] - j does not decrease with j
  int lo = 0, hi = static_cast<int>(slots.size());
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (slots[static_cast<std::size_t>(mid)] - mid <= f)
      lo = mid + 1;
    else
      hi = mid;
  }
  return dof_at(f + lo);
}

double DofMap::prescribed_value(int dof) const {
  const auto it = std::lower_bound(prescribed_.begin(), prescribed_.end(), dof);
  return it != prescribed_.end() && *it == dof ? values_(it - prescribed_.begin()) : 0.0;
}

void DofMap::set_prescribed_values(Eigen::VectorXd values) {
  if (values.size() != static_cast<Eigen::Index>(prescribed_.size()))
    throw InternalError("a dof map of " + std::to_string(prescribed_.size()) + " prescribed dofs given " +
                        std::to_string(values.size()) + " values");
  values_ = std::move(values);
}

Eigen::VectorXd DofMap::prescribed_part(const Eigen::VectorXd& all) const {
  if (all.size() != num_dofs_)
    throw InternalError("the prescribed values of a vector of " + std::to_string(all.size()) + " entries for " +
                        std::to_string(num_dofs_) + " dofs");
  Eigen::VectorXd part(static_cast<Eigen::Index>(prescribed_.size()));
  for (std::size_t j = 0; j < prescribed_.size(); ++j) part(static_cast<Eigen::Index>(j)) = all(prescribed_[j]);
  return part;
}

Eigen::VectorXd DofMap::prescribed() const {
  Eigen::VectorXd all = Eigen::VectorXd::Zero(num_dofs_);
  for (std::size_t j = 0; j < prescribed_.size(); ++j) all(prescribed_[j]) = values_(static_cast<Eigen::Index>(j));
  return all;
}

std::vector<int> DofMap::free_index_table() const {
  std::vector<int> table(static_cast<std::size_t>(num_dofs_), -1);
  for_each_free([&](int dof, int f) { table[static_cast<std::size_t>(dof)] = f; });
  return table;
}

Eigen::VectorXd DofMap::free_part(const Eigen::VectorXd& u) const {
  if (u.size() != num_dofs_)
    throw InputError("expected " + std::to_string(num_dofs_) + " values, one per dof, got " + std::to_string(u.size()));
  Eigen::VectorXd free(num_free());
  for_each_free([&](int dof, int f) { free(f) = u(dof); });
  return free;
}

Eigen::VectorXd DofMap::expand(const Eigen::VectorXd& free_values) const {
  if (free_values.size() != num_free())
    throw InputError("expected " + std::to_string(num_free()) + " free values, got " + std::to_string(free_values.size()));
  Eigen::VectorXd u(num_dofs_);
  for_each_free([&](int dof, int f) { u(dof) = free_values(f); });
  for (std::size_t k = 0; k < prescribed_.size(); ++k) u(prescribed_[k]) = values_(static_cast<Eigen::Index>(k));
  return u;
}

}  // namespace hemivem
