// Shows that a centroider compiled into an executable is one file and ONE registration
// line: "iwc_in_test" (the iterative weighted centroid under another name, a trivial-but-valid
// member) is registered below, and the family's accuracy suite
// (AllCentroiders/CentroidAccuracy.* in test_simulated_accuracy.cpp) runs on it without
// being edited.
#include "common/family_registry.hpp"
#include "sensors/detect/centroider.hpp"

namespace st {
namespace {

class IwcInTest final : public Centroider {
 public:
  std::string name() const override { return "iwc_in_test"; }

 private:
  bool doCentroid(const StarPatch& patch, Centroid& out, std::string* reason) const override {
    return iwc_->centroid(patch, out, reason);
  }
  std::unique_ptr<Centroider> iwc_ = Centroider::create("iwc");
};

std::unique_ptr<Centroider> makeIwcInTest() { return std::make_unique<IwcInTest>(); }

}  // namespace
}  // namespace st

ST_REGISTER_FAMILY_MEMBER(st::Centroider, "iwc_in_test", "iwc, registered by a test",
                          &st::makeIwcInTest);
