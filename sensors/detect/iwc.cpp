// "iwc": iterative weighted centroid. The CoG weighted by a Gaussian of the PSF's width,
// re-centred on the estimate until it stops moving: it down-weights the noisy wings (close
// to the matched filter for a faint star) and starts from the plain CoG.
#include "sensors/detect/weighted_centroid.hpp"

namespace st {
namespace {

class IwcCentroider final : public Centroider {
 public:
  std::string name() const override { return "iwc"; }

 private:
  bool doCentroid(const StarPatch& patch, Centroid& out, std::string* reason) const override {
    Centroid cog;
    if (!detail::weightedCentroid(patch, patch.guess, 0.0, 1, cog, reason)) return false;
    return detail::weightedCentroid(patch, cog.px, patch.psf_sigma, 30, out, reason);
  }
};

}  // namespace

std::unique_ptr<Centroider> makeIwcCentroider() { return std::make_unique<IwcCentroider>(); }

}  // namespace st
