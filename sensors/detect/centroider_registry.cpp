// The one table of centroiders: names, help and factories come from here.
#include <sstream>

#include "sensors/detect/centroider.hpp"

namespace st {
namespace {

struct Entry {
  const char* name;
  const char* help;
  std::unique_ptr<Centroider> (*make)();
};

const Entry kCentroiders[] = {
    {"cog", "intensity-weighted centre of gravity, background removed (fastest)",
     &makeCogCentroider},
    {"iwc", "iterative weighted centroid with a Gaussian window (robust to wings and noise)",
     &makeIwcCentroider},
    {"gauss", "maximum-likelihood fit of the pixel-integrated Gaussian PSF (most accurate)",
     &makeGaussFitCentroider},
};

}  // namespace

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
  for (const Entry& e : kCentroiders)
    if (name == e.name) return e.make();
  if (error) {
    std::ostringstream os;
    os << "unknown centroider '" << name << "'; valid:";
    for (const Entry& e : kCentroiders) os << ' ' << e.name;
    *error = os.str();
  }
  return nullptr;
}

std::vector<std::string> Centroider::names() {
  std::vector<std::string> out;
  for (const Entry& e : kCentroiders) out.emplace_back(e.name);
  return out;
}

std::string Centroider::help() {
  std::ostringstream os;
  for (const Entry& e : kCentroiders) os << "  " << e.name << ": " << e.help << '\n';
  return os.str();
}

}  // namespace st
