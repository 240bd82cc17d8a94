// The one table of identification algorithms: names, help and CLI choices come from here.
#include <sstream>

#include "sensors/identify/algorithms.hpp"

namespace st {
namespace {
using Factory = std::unique_ptr<StarIdentifier> (*)(const IdentifyOptions&);
struct Entry {
  const char* name;
  const char* help;
  Factory make;
};
using namespace identify_detail;
constexpr Entry kRegistry[] = {
    {"pyramid", "Mortari's Pyramid: k-vector triangles confirmed by a 4th star (seed 002)", &makePyramid},
    {"voting", "Mortari's reference-star matching with the spike rule (seed 000)", &makeVoting},
    {"liebe", "Liebe's triangular feature from the neighbour table (seed 003)", &makeLiebe},
    {"planar", "planar triangles matched by area and polar moment (seed 001 eq. 2-7)", &makePlanarTriangle},
    {"spherical", "spherical triangles matched by area and polar moment (seed 001 eq. 8-12)", &makeSphericalTriangle},
    {"nvertex", "4-vertex match with a self-consistency check (seed 004 sec. 5.5.4)", &makeNVertex},
};
}  // namespace

std::unique_ptr<StarIdentifier> StarIdentifier::create(const std::string& name,
                                                       const IdentifyOptions& options,
                                                       std::string* error) {
  for (const Entry& e : kRegistry)
    if (name == e.name) return e.make(options);
  if (error) {
    *error = "unknown identification algorithm '" + name + "' (choose one of:";
    for (const Entry& e : kRegistry) *error += std::string(" ") + e.name;
    *error += ")";
  }
  return nullptr;
}

std::vector<std::string> StarIdentifier::names() {
  std::vector<std::string> out;
  for (const Entry& e : kRegistry) out.push_back(e.name);
  return out;
}

std::string StarIdentifier::help() {
  std::ostringstream os;
  for (const Entry& e : kRegistry) os << e.name << ": " << e.help << "\n";
  return os.str();
}

}  // namespace st
