// The one table of identification algorithms: names, help, CLI choices and factories come
// from here. A new algorithm: its own file defining `std::unique_ptr<StarIdentifier>
// identify_detail::makeX(const IdentifyOptions&)`, plus ONE line below,
// X("name", makeX, "help"), which declares the factory and lists it
// (common/family_registry.hpp says why not a self-registering object). Default first.
#include "common/family_registry.hpp"
#include "sensors/identify/identifier.hpp"

// clang-format off
#define ST_IDENTIFIERS(X)                                                                       \
  X("pyramid", makePyramid, "Mortari's Pyramid: k-vector triangles confirmed by a 4th star (seed 002)") \
  X("voting", makeVoting, "Mortari's reference-star matching with the spike rule (seed 000)")  \
  X("liebe", makeLiebe, "Liebe's triangular feature from the neighbour table (seed 003)")      \
  X("planar", makePlanarTriangle, "planar triangles matched by area and polar moment (seed 001 eq. 2-7)") \
  X("spherical", makeSphericalTriangle, "spherical triangles matched by area and polar moment (seed 001 eq. 8-12)") \
  X("nvertex", makeNVertex, "4-vertex match with a self-consistency check (seed 004 sec. 5.5.4)") \
  X("nvertex3", makeNVertex3, "the n-vertex match with n = 3: a triangle, all baselines at once (seed 004 sec. 5.5.4)") \
  X("nvertex5", makeNVertex5, "the n-vertex match with n = 5: ten baselines at once (seed 004 sec. 5.5.4)")
// clang-format on

namespace st {
namespace identify_detail {
#define ST_DECLARE_IDENTIFIER_FACTORY(name, factory, help) StarIdentifier::Make factory;
ST_IDENTIFIERS(ST_DECLARE_IDENTIFIER_FACTORY)
}  // namespace identify_detail

namespace {

FamilyRegistry<StarIdentifier::Factory>& registry() {
  using namespace identify_detail;
  static FamilyRegistry<StarIdentifier::Factory> r("identification algorithm",
                                                   {ST_IDENTIFIERS(ST_FAMILY_TABLE_ENTRY)});
  return r;
}

}  // namespace

void StarIdentifier::registerMember(const std::string& name, const std::string& help,
                                    Factory make) {
  registry().add({name, help, make});
}

std::unique_ptr<StarIdentifier> StarIdentifier::create(const std::string& name,
                                                       const IdentifyOptions& options,
                                                       std::string* error) {
  std::string why;
  if (registry().find(name) && !options.isValid(&why)) {  // a known name, bad options
    if (error) *error = why;
    return nullptr;
  }
  return registry().create(name, error, options);
}

std::vector<std::string> StarIdentifier::names() { return registry().names(); }

std::string StarIdentifier::help() {
  std::string s;
  for (const auto& m : registry().members()) s += m.name + ": " + m.help + "\n";
  return s;
}

}  // namespace st
