// `startracker dark FRAMES...|DIR -o dark.fits`: the master dark of seed 004 §4.1, the
// per-pixel median of N dark exposures, for `solve --dark` and the tracker key
// detect_dark_file.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/cli/common_flags.hpp"
#include "app/cli/validators.hpp"
#include "app/command.hpp"
#include "imageio/image_file.hpp"
#include "common/output_file.hpp"
#include "solve/input_list.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"
#include "sensors/detect/dark_frame.hpp"

namespace st::app {

namespace {

/// The median rejects a value present in fewer than half the frames: with 2 frames a cosmic
/// ray in one of them would survive half-way, so 3 is the least that means "median".
constexpr int kMinDarkFrames = 3;

struct DarkArgs {
  bool force = false;  ///< replace an existing -o
  std::vector<std::string> inputs;
  std::string output;
  double hot_sigma = 5.0;
};

std::string describeType(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows) + " " +
         (m.depth() == CV_8U ? "8-bit" : "16-bit");
}

int runDark(const DarkArgs& a) {
  const std::vector<std::string> files = solve::expandInputs(a.inputs);
  std::vector<NamedPath> inputs;
  for (const std::string& f : files) inputs.push_back({f, "an input frame"});
  refuseSameFile(a.output, "-o/--output", inputs);
  prepareOutputFile(a.output, "-o/--output", a.force);
  if (static_cast<int>(files.size()) < kMinDarkFrames)
    throw InputError("dark: " + std::to_string(files.size()) + " frame(s) given; the median needs at least " +
                     std::to_string(kMinDarkFrames));
  std::vector<cv::Mat> frames;
  frames.reserve(files.size());
  for (const auto& f : files) {
    cv::Mat img = imageio::loadImage(f).image;
    if (!frames.empty() && (img.size() != frames[0].size() || img.type() != frames[0].type()))
      throw InputError(f + ": " + describeType(img) + " differs from the first dark frame " +
                       files[0] + " (" + describeType(frames[0]) + ")");
    frames.push_back(std::move(img));
  }
  const cv::Mat dark = medianDark(frames);
  imageio::writeImage(a.output, dark);
  const DarkStats s = darkStats(dark, a.hot_sigma);
  std::printf("dark: median of %zu frames (%s) -> %s\n", frames.size(),
              describeType(dark).c_str(), a.output.c_str());
  std::printf("mean %.2f ADU, robust sigma %.2f ADU, hot pixels %ld (above mean + %g sigma)\n",
              s.mean, s.sigma, s.hot_pixels, a.hot_sigma);
  return kExitOk;
}

}  // namespace

void addDarkCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand(
      "dark", "Build a master dark: the per-pixel median of dark frames (seed 004 sec. 4.1)");
  auto a = std::make_shared<DarkArgs>();
  cmd->add_option("frames", a->inputs, "Dark frames (8/16-bit mono, one size) or folders of them")
      ->required();
  cmd->add_option("-o,--output", a->output,
                  "The dark: .fits, or the image format the extension names (.png, .tif)")
      ->required();
  cli::addForceFlag(*cmd, a->force);
  cmd->add_option("--hot-sigma", a->hot_sigma,
                  "Report pixels above mean + this many robust sigma as hot")
      ->capture_default_str()
      ->check(cli::Number(0, cli::kNoBound, cli::Bound::kOpen));
  cmd->callback([a, &run] { run = [a] { return runDark(*a); }; });
}

}  // namespace st::app
