// Isotropic linear elastic materials, one per element region (docs/reference/scenes.md, [material]).
#pragma once

#include <Eigen/Core>

#include <string>
#include <string_view>
#include <vector>

namespace hemivem {

/// Plane strain uses the paper's Lamé constants; plane stress replaces lambda by
/// 2*lambda*mu/(lambda + 2*mu). Always an explicit choice, never a silent default.
enum class PlaneModel { strain, stress };

std::string to_string(PlaneModel model);
/// "strain"/"plane-strain" or "stress"/"plane-stress" (case-insensitive); InputError otherwise.
PlaneModel plane_model_from_string(std::string_view name);

struct Material {
  double young = 1.0;    ///< E > 0
  double poisson = 0.0;  ///< -1 < nu < 0.5
};

struct Lame {
  double lambda = 0.0;
  double mu = 0.0;
};

/// Throws InputError naming the field when E <= 0, nu outside (-1, 0.5) or a value is not finite.
void validate(const Material& material);

/// lambda = E nu / ((1+nu)(1-2nu)), 2 mu = E/(1+nu); for plane stress lambda* = 2 lambda mu/(lambda+2mu).
Lame lame(const Material& material, PlaneModel model);

/// The 3x3 elasticity matrix in Voigt notation (xx, yy, 2xy — engineering shear), so
/// that sigma:eps = e^T C e for e = (eps_xx, eps_yy, 2 eps_xy).
Eigen::Matrix3d elasticity_matrix(const Lame& lame);

/// Materials by region id: region r of the mesh uses materials()[r].
class MaterialTable {
 public:
  MaterialTable() = default;
  /// One material for every region (whatever its id: a Gmsh file's surface tags are kept).
  explicit MaterialTable(Material material, PlaneModel model = PlaneModel::strain);
  MaterialTable(std::vector<Material> by_region, PlaneModel model);

  PlaneModel model() const noexcept { return model_; }
  const std::vector<Material>& materials() const noexcept { return materials_; }
  /// Throws InputError when region is not covered.
  const Material& material(int region) const;
  Lame lame(int region) const;

 private:
  std::vector<Material> materials_;
  PlaneModel model_ = PlaneModel::strain;
  bool uniform_ = false;  ///< one material for every region id
};

}  // namespace hemivem
