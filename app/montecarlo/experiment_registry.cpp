// The one table of Monte Carlo experiments: name, one line of help, factory.
#include <functional>

#include "app/montecarlo/experiment.hpp"
#include "app/montecarlo/experiments.hpp"
#include "common/errors.hpp"

namespace st::app::mc {
namespace {

struct Entry {
  const char* name;
  const char* help;
  std::function<std::unique_ptr<Experiment>()> make;
};

const std::vector<Entry>& registry() {
  static const std::vector<Entry> table = {
      {"star-count", "histogram of catalog stars in the image over random attitudes, per magnitude limit (seeds 000 Fig. 1, 004 Fig. 5.1/5.2)", makeStarCount},
      {"fov-selection", "P(N < 3), P(N < 4) vs square FOV size and magnitude limit; smallest FOV with P < 0.01 (seed 002 eq. 14)", makeFovSelection},
      {"lis-robustness", "lost-in-space success and false-ID rates per error situation (false, dropped, displaced stars, noise), per algorithm (seed 003 Tables 2-3)", makeLisRobustness},
      {"error-vs-stars", "attitude error (cross-boresight, roll) vs number of stars against the covariance prediction, per Wahba solver (seeds 000 Fig. 12, 003 Fig. 18)", makeErrorVsStars},
      {"timing", "time per frame per stage (detection on rendered images, pattern search, verification, solve) and candidates examined vs star count (seed 000 Figs. 10-11)", makeTiming},
      {"centroid-defocus", "centroid error vs PSF width (defocus) and SNR, and centroider time per magnitude, weighted sum vs maximum likelihood (seed 004 Figs. 4.4-4.5, Table 4.2)", makeCentroidDefocus},
      {"few-stars", "lost-in-space with 2-3 stars by the magnitude tie-break vs Pyramid alone in seed 000's camera: solved fraction vs fraction with >= 3 stars, wrong attitudes (seed 000, issue 17)", makeFewStars},
      {"magnitude-error", "measured minus assigned magnitude of 20 stars per image at V = 0..4 in the camera of seed 004 Table 5.2 (seed 004 Table 5.3)", makeMagnitudeError},
      {"near-field", "seed 001 Tables 1-5 on the near-field star display: stars matched and Euler-angle errors vs the prediction error and over updates of the iterative solution (run with --runs 250 --fov-deg 30 --size 640 480 --noise-px 0.25)", makeNearField},
  };
  return table;
}

}  // namespace

std::size_t Table::col(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i;
  throw ProcessingError("trial table has no column '" + name + "'");
}

uint64_t trialSeed(uint64_t seed, uint64_t trial, uint64_t stream) {
  auto splitmix = [](uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  };
  return splitmix(splitmix(splitmix(seed) ^ trial) ^ (stream * 0xd1b54a32d192ed03ULL));
}

std::unique_ptr<Experiment> Experiment::create(const std::string& name, std::string* error) {
  for (const Entry& e : registry())
    if (name == e.name) return e.make();
  if (error) {
    std::string valid;
    for (const Entry& e : registry()) valid += (valid.empty() ? "" : ", ") + std::string(e.name);
    *error = "unknown experiment '" + name + "'; valid: " + valid + " (or merge)";
  }
  return nullptr;
}

std::vector<std::string> Experiment::names() {
  std::vector<std::string> n;
  for (const Entry& e : registry()) n.push_back(e.name);
  return n;
}

std::string Experiment::help() {
  std::string h;
  for (const Entry& e : registry()) h += std::string("  ") + e.name + ": " + e.help + "\n";
  return h;
}

}  // namespace st::app::mc
