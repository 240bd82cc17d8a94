#include "sensors/detect/centroid.hpp"

#include <utility>

namespace st {

std::string centroidFlagNames(uint32_t flags) {
  static const std::pair<CentroidFlag, const char*> kNames[] = {
      {kSaturated, "saturated"}, {kTouchesEdge, "edge"},     {kElongated, "elongated"},
      {kHotPixel, "hot-pixel"},  {kExtended, "extended"},    {kDiffuse, "diffuse"},
      {kRadiationHit, "hit"}};
  std::string out;
  for (const auto& [bit, name] : kNames)
    if (flags & bit) out += (out.empty() ? "" : ",") + std::string(name);
  return out.empty() ? "-" : out;
}

}  // namespace st
