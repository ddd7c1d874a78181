#include <hemivem/error.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <algorithm>
#include <cctype>

#ifdef HEMIVEM_HAVE_SSN
#include <hemivem/ssn_minimizer.hpp>
#endif
#ifdef HEMIVEM_HAVE_BUNDLE_DCA
#include <hemivem/bundle_dca_minimizer.hpp>
#endif
#ifdef HEMIVEM_HAVE_NLOPT_MMA
#include <hemivem/nlopt_mma_minimizer.hpp>
#endif
#ifdef HEMIVEM_HAVE_CERES_ACTIVE_SET
#include <hemivem/ceres_active_set_minimizer.hpp>
#endif

namespace hemivem {

std::vector<std::string> available_minimizers() {
  std::vector<std::string> names;
#ifdef HEMIVEM_HAVE_SSN
  names.emplace_back("ssn");
#endif
#ifdef HEMIVEM_HAVE_BUNDLE_DCA
  names.emplace_back("bundle-dca");
#endif
#ifdef HEMIVEM_HAVE_NLOPT_MMA
  names.emplace_back("nlopt-mma");
#endif
#ifdef HEMIVEM_HAVE_CERES_ACTIVE_SET
  names.emplace_back("ceres-active-set");
#endif
  return names;
}

std::unique_ptr<NonsmoothMinimizer> make_minimizer(const std::string& name,
                                                   const std::map<std::string, double>& parameters) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(),
                 [](unsigned char c) { return c == '_' ? '-' : static_cast<char>(std::tolower(c)); });
#ifdef HEMIVEM_HAVE_SSN
  if (n == "ssn") return std::make_unique<SsnMinimizer>(options_from_parameters<SsnOptions>(parameters, "ssn"));
#endif
#ifdef HEMIVEM_HAVE_BUNDLE_DCA
  if (n == "bundle-dca") return std::make_unique<BundleDcaMinimizer>(options_from_parameters<BundleDcaOptions>(parameters, "bundle-dca"));
#endif
#ifdef HEMIVEM_HAVE_NLOPT_MMA
  if (n == "nlopt-mma") return std::make_unique<NloptMmaMinimizer>(options_from_parameters<NloptMmaOptions>(parameters, "nlopt-mma"));
#endif
#ifdef HEMIVEM_HAVE_CERES_ACTIVE_SET
  if (n == "ceres-active-set") return std::make_unique<CeresActiveSetMinimizer>(options_from_parameters<CeresActiveSetOptions>(parameters, "ceres-active-set"));
#endif
  std::string list;
  for (const auto& a : available_minimizers()) list += (list.empty() ? "" : ", ") + a;
  const bool known = n == "ssn" || n == "bundle-dca" || n == "nlopt-mma" || n == "ceres-active-set";
  throw InputError((known ? "minimizer '" + name + "' was not built" : "unknown minimizer '" + name + "'") +
                       "; available: " + (list.empty() ? "none" : list),
                   "minimizer");
}

}  // namespace hemivem
