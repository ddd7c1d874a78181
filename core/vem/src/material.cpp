#include <hemivem/error.hpp>
#include <hemivem/vem/material.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>

namespace hemivem {

std::string to_string(PlaneModel model) {
  switch (model) {
    case PlaneModel::strain: return "plane-strain";
    case PlaneModel::stress: return "plane-stress";
  }
  throw InternalError("a PlaneModel out of range: " + std::to_string(static_cast<int>(model)));
}

PlaneModel plane_model_from_string(std::string_view name) {
  std::string s(name);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (s == "strain" || s == "plane-strain" || s == "plane_strain") return PlaneModel::strain;
  if (s == "stress" || s == "plane-stress" || s == "plane_stress") return PlaneModel::stress;
  throw InputError("unknown plane model '" + std::string(name) + "'; expected plane-strain or plane-stress");
}

void validate(const Material& m) {
  auto num = [](double v) {  // shortest text that reads back to v
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
  };
  if (!std::isfinite(m.young) || !(m.young > 0.0))
    throw InputError("Young's modulus E = " + num(m.young) + " must be finite and > 0", "material.E");
  if (!std::isfinite(m.poisson) || !(m.poisson > -1.0 && m.poisson < 0.5))
    throw InputError("Poisson's ratio nu = " + num(m.poisson) + " must lie in (-1, 0.5)", "material.nu");
}

Lame lame(const Material& m, PlaneModel model) {
  validate(m);
  const double E = m.young, nu = m.poisson;
  Lame l;
  l.mu = E / (2.0 * (1.0 + nu));
  l.lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  if (model == PlaneModel::stress) l.lambda = 2.0 * l.lambda * l.mu / (l.lambda + 2.0 * l.mu);
  return l;
}

Eigen::Matrix3d elasticity_matrix(const Lame& l) {
  Eigen::Matrix3d C;
  C << l.lambda + 2 * l.mu, l.lambda, 0,  //
      l.lambda, l.lambda + 2 * l.mu, 0,   //
      0, 0, l.mu;
  return C;
}

MaterialTable::MaterialTable(Material material, PlaneModel model) : MaterialTable(std::vector{material}, model) {
  uniform_ = true;
}

MaterialTable::MaterialTable(std::vector<Material> by_region, PlaneModel model)
    : materials_(std::move(by_region)), model_(model) {
  for (std::size_t r = 0; r < materials_.size(); ++r) {
    try {
      validate(materials_[r]);
    } catch (const InputError& e) {
      throw InputError(e.detail(), "materials[" + std::to_string(r) + "]." + e.where().substr(e.where().find('.') + 1));
    }
  }
}

const Material& MaterialTable::material(int region) const {
  if (uniform_ && region >= 0) return materials_.front();
  if (region < 0 || static_cast<std::size_t>(region) >= materials_.size())
    throw InputError("no material for region " + std::to_string(region) + " (" + std::to_string(materials_.size()) +
                     " region(s) defined)");
  return materials_[static_cast<std::size_t>(region)];
}

Lame MaterialTable::lame(int region) const { return hemivem::lame(material(region), model_); }

}  // namespace hemivem
