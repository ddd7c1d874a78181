// A contact part between two bodies paired by projection, frictionless Signorini contact: what the
// tests of bodies whose surfaces do not coincide pose, in either dimension.
#pragma once

#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/problem.hpp>

#include <vector>

namespace hemivem::test {

/// The part "interface" of the facets `facets` meeting the other body's `against`, each node
/// paired with the point along its normal (BodyPairing::projection): the zero law, one-sided.
template <int dim>
BasicContactPart<dim> projected_part(const std::vector<int>& facets, const std::vector<int>& against) {
  BasicContactPart<dim> part;
  part.name = "interface";
  part.facets = facets;
  part.against = against;
  part.pairing = BodyPairing::projection;
  part.law = zero_law();
  part.constraint = ConstraintKind::one_sided;
  return part;
}

}  // namespace hemivem::test
