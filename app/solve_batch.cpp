// `startracker solve`'s run: one frame as before (its errors end the run), or a batch: every
// image of the arguments, one database for all (solve_run.hpp), --threads frames at once,
// results printed in input order as they finish, a progress bar on a terminal and a summary.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "app/command.hpp"
#include "common/output_file.hpp"
#include "solve/input_list.hpp"
#include "solve/solve_options.hpp"
#include "solve/plate_solver.hpp"
#include "solve/wcs_header.hpp"
#include "solve/camera_report.hpp"
#include "imageio/image_file.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"
#include "common/progress.hpp"

namespace st::app {
namespace {

using namespace st::solve;

/// The checks that need no work: a finished solve must not be lost to a typo.
void checkBeforeWork(const SolveOptions& o, std::size_t frames) {
  if (frames > 1 && (!o.annotate.empty() || !o.wcs.empty()))
    throw InputError(std::string(o.annotate.empty() ? "--wcs" : "--annotate") +
                     ": one output file for " + std::to_string(frames) +
                     " frames; give it with one image");
  std::vector<NamedPath> inputs;
  for (const std::string& in : o.inputs) inputs.push_back({in, "an input"});
  if (!o.camera.camera_file.empty()) inputs.push_back({o.camera.camera_file, "--camera"});
  if (!o.database.empty()) inputs.push_back({o.database, "--database"});
  if (!o.dark.empty()) inputs.push_back({o.dark, "--dark"});
  refuseSameFile(o.annotate, "--annotate", inputs);
  refuseSameFile(o.wcs, "--wcs", inputs);
  refuseSameFile(o.wcs, "--wcs", {{o.annotate, "--annotate"}});
  if (!o.annotate.empty()) {
    if (!imageio::isPngPath(o.annotate))
      throw InputError("--annotate " + o.annotate + ": the picture is a PNG (name it .png)");
    prepareOutputFile(o.annotate, "--annotate");
  }
  if (!o.wcs.empty()) prepareOutputFile(o.wcs, "--wcs");
  o.positionHint();  // a bad hint fails before any work
}

/// Prints the frame (text, or one JSON line) and writes --annotate / --wcs; returns its code.
int reportFrame(const FrameOutcome& f) {
  const SolveOptions& o = f.o;
  if (!f.rep) {
    if (o.json) printJson(outcomeJson(f));
    // Most messages name the file already (loadImage's do).
    if (f.error.rfind(o.input, 0) == 0)
      log::error("%s", f.error.c_str());
    else
      log::error("%s: %s", o.input.c_str(), f.error.c_str());
    return f.code;
  }
  const SolveReport& rep = *f.rep;
  if (log::verbose() && !rep.in.star_list) {
    log::debug("%s: %zu detections (%d radiation hits, ranked last; %zu blobs rejected), PSF "
               "three-pixel width %.2f px along x, %.2f px along y; brightest first:",
               o.input.c_str(), rep.in.stars.size(), rep.in.hits, rep.in.rejected.size(),
               rep.in.psf_width_x, rep.in.psf_width_y);
    printDetections(rep.in);
  }
  if (!rep.failure.empty()) {
    if (o.json) printJson(outcomeJson(f));
    log::error("%s: not solved: %s", o.input.c_str(), rep.failure.c_str());
    // The picture of a failed frame shows why: what detection made of each blob.
    if (!o.annotate.empty()) writeSolveAnnotation(rep, o.annotate);
    return kExitFailure;
  }
  if (const std::string d = cameraDiscrepancy(rep); !d.empty()) log::warn("%s", d.c_str());
  if (o.json)
    printJson(outcomeJson(f));
  else
    printSolutionText(rep);
  if (!o.wcs.empty()) writeWcsHeader(rep, o.wcs);
  if (!o.annotate.empty()) writeSolveAnnotation(rep, o.annotate);
  return kExitOk;
}

int runSingle(const SolveOptions& o, bool& printed) {
  checkBeforeWork(o, 1);
  const PlateSolver solver(o);
  auto f = solver.solveFile(o.inputs.front());
  printed = true;  // a failing --annotate / --wcs must not take the solution with it
  return reportFrame(*f);
}

int runBatch(const SolveOptions& o, const std::vector<std::string>& frames) {
  const PlateSolver solver(o);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::unique_ptr<FrameOutcome>> done(frames.size());
  std::vector<double> ms;
  std::size_t next_print = 0;
  int solved = 0, failed = 0, errors = 0, worst = kExitOk;
  std::mutex mutex;
  ProgressBar bar("solve", frames.size(), ::isatty(STDERR_FILENO) != 0);
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next++; i < frames.size(); i = next++) {
      auto f = solver.solveFileCaught(frames[i]);
      std::lock_guard<std::mutex> lock(mutex);
      done[i] = std::move(f);
      // Print in input order: a script reading the lines can zip them with its file list.
      for (; next_print < frames.size() && done[next_print]; ++next_print) {
        FrameOutcome& p = *done[next_print];
        int code = p.code;
        try {
          code = reportFrame(p);
        } catch (const std::exception& e) {
          log::error("%s: %s", p.o.input.c_str(), e.what());
          code = kExitFailure;
        }
        (code == kExitOk ? solved : p.rep ? failed : errors)++;
        worst = std::max(worst, code);
        ms.push_back(p.ms);
        done[next_print].reset();  // the frame's image is not kept past its line
        bar.update(next_print + 1);
      }
    }
  };
  std::vector<std::thread> pool;
  const int n = std::min<int>(o.threads, int(frames.size()));
  for (int k = 1; k < n; ++k) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  bar.finish();
  std::sort(ms.begin(), ms.end());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log::info("%zu frames: %d solved, %d not solved, %d errors; median %.1f ms per frame, %.2f s "
            "in all (%d thread%s)",
            frames.size(), solved, failed, errors, ms.empty() ? 0.0 : ms[ms.size() / 2], wall, n,
            n == 1 ? "" : "s");
  return worst;
}

}  // namespace

int runSolve(const SolveOptions& options) {
  bool printed = false;
  const SolveOptions& o = options;
  try {
    if (isSingleFrame(o.inputs)) return runSingle(o, printed);
    const std::vector<std::string> frames = expandInputs(o.inputs);
    checkBeforeWork(o, frames.size());
    printed = true;  // from here each frame reports its own errors
    return runBatch(o, frames);
  } catch (const InputError& e) {
    // With --json the one object on stdout is solve's (main would print a second one).
    if (!o.json || printed) throw;
    log::error("%s", e.what());
    printJson(errorJson(e.what(), kExitUsage));
    return kExitUsage;
  } catch (const std::exception& e) {
    if (!o.json || printed) throw;
    log::error("%s", e.what());
    printJson(errorJson(e.what(), kExitFailure));
    return kExitFailure;
  }
}

}  // namespace st::app
