// The one table of centroiders: names, help, CLI choices and factories come from here.
// A new centroider: its own file defining `std::unique_ptr<Centroider> makeXCentroider()` in
// namespace st, plus ONE line below, X("name", makeXCentroider, "help"), which declares the
// factory and lists it (common/family_registry.hpp says why not a self-registering object).
#include "common/family_registry.hpp"
#include "sensors/detect/centroider.hpp"

// clang-format off
#define ST_CENTROIDERS(X)                                                                       \
  X("cog", makeCogCentroider, "intensity-weighted centre of gravity, background removed (fastest)") \
  X("iwc", makeIwcCentroider, "iterative weighted centroid with a Gaussian window (robust to wings and noise)") \
  X("gauss", makeGaussFitCentroider, "maximum-likelihood fit of the pixel-integrated Gaussian PSF (most accurate)")
// clang-format on

namespace st {

#define ST_DECLARE_CENTROIDER_FACTORY(name, factory, help) Centroider::Make factory;
ST_CENTROIDERS(ST_DECLARE_CENTROIDER_FACTORY)

namespace {

FamilyRegistry<Centroider::Factory>& registry() {
  static FamilyRegistry<Centroider::Factory> r("centroider",
                                               {ST_CENTROIDERS(ST_FAMILY_TABLE_ENTRY)});
  return r;
}

}  // namespace

void Centroider::registerMember(const std::string& name, const std::string& help,
                                Factory make) {
  registry().add({name, help, make});
}

bool Centroider::centroid(const StarPatch& patch, Centroid& out, std::string* reason) const {
  if (patch.values.empty()) {
    if (reason) *reason = "empty window";
    return false;
  }
  std::string why;
  if (!doCentroid(patch, out, &why)) {
    if (reason) *reason = why.empty() ? "not found" : why;
    return false;
  }
  if (!out.px.allFinite() || !out.cov_px.allFinite()) {
    if (reason) *reason = "non-finite result";
    return false;
  }
  return true;
}

std::unique_ptr<Centroider> Centroider::create(const std::string& name, std::string* error) {
  return registry().create(name, error);
}

std::vector<std::string> Centroider::names() { return registry().names(); }

std::string Centroider::help() {
  std::string s;
  for (const auto& m : registry().members()) s += "  " + m.name + ": " + m.help + "\n";
  return s;
}

}  // namespace st
