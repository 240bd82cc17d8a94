// "cog": intensity-weighted centre of gravity over the window, background removed
// (seed 004 eq. 4.1, 4.23/4.24). One pass; covariance by first-order propagation.
#include "sensors/detect/weighted_centroid.hpp"

namespace st {
namespace {

class CogCentroider final : public Centroider {
 public:
  std::string name() const override { return "cog"; }

 private:
  bool doCentroid(const StarPatch& patch, Centroid& out, std::string* reason) const override {
    return detail::weightedCentroid(patch, patch.guess, 0.0, 1, out, reason);
  }
};

}  // namespace

std::unique_ptr<Centroider> makeCogCentroider() { return std::make_unique<CogCentroider>(); }

}  // namespace st
