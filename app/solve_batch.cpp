// `startracker solve`'s run: one frame as before (its errors end the run), or a batch: every
// image of the arguments, one database for all (solve_run.hpp), --threads frames at once,
// results printed in input order as they finish, a progress bar on a terminal and a summary.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <thread>
#include <unordered_map>
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
#include "common/shard.hpp"
#include "common/stop_signal.hpp"
#include "solve/results_file.hpp"

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
  if (!o.output.empty()) {
    // A results file is never an image: one named like a frame is a slip in the command.
    if (hasImageExtension(o.output))
      throw InputError("-o " + o.output + ": the results are JSON Lines (name it .jsonl), not an image");
    if (!o.files_from.empty() && o.files_from != "-") inputs.push_back({o.files_from, "--files-from"});
    refuseSameFile(o.output, "-o", inputs);
    refuseSameFile(o.output, "-o", {{o.annotate, "--annotate"}, {o.wcs, "--wcs"}});
  }
  if (!o.annotate.empty()) {
    if (!imageio::isPngPath(o.annotate))
      throw InputError("--annotate " + o.annotate + ": the picture is a PNG (name it .png)");
    prepareOutputFile(o.annotate, "--annotate", o.force);
  }
  if (!o.wcs.empty()) prepareOutputFile(o.wcs, "--wcs", o.force);
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

/// The frames of this run: the IMAGE arguments, then --files-from's, then this --shard's part.
struct BatchFrames {
  std::vector<std::string> all;   ///< the whole list (every shard's)
  std::vector<std::string> mine;  ///< this shard's part of it, in list order
  Shard shard;
};

BatchFrames batchFrames(const SolveOptions& o) {
  BatchFrames b;
  if (!o.inputs.empty()) b.all = expandInputs(o.inputs);
  if (!o.files_from.empty()) {
    const std::vector<std::string> listed = readFileList(o.files_from);
    b.all.insert(b.all.end(), listed.begin(), listed.end());
  }
  if (b.all.empty()) throw InputError("missing IMAGE: PNG, JPEG, TIFF or FITS images, star lists or folders, or --files-from LIST");
  if (!o.shard.empty()) b.shard = Shard::parse(o.shard);
  for (std::size_t k = 0; k < b.all.size(); ++k)
    if (b.shard.takes(k)) b.mine.push_back(b.all[k]);
  if (!o.output.empty()) {
    // The results are keyed by frame: a frame listed twice would be solved once and its second
    // place left without a line by --resume and merge.
    std::unordered_map<std::string, std::size_t> at;
    for (std::size_t k = 0; k < b.all.size(); ++k)
      if (const auto [it, fresh] = at.emplace(b.all[k], k); !fresh)
        throw InputError(b.all[k] + ": listed twice (frames " + std::to_string(it->second + 1) +
                         " and " + std::to_string(k + 1) + "); the -o file keeps one result per frame");
  }
  return b;
}

/// This run's frames without a line in `earlier` (--resume), in list order; `skipped` counts
/// those with one. InputError when the file holds a frame this run does not solve: another
/// list or --shard wrote it.
std::vector<std::string> framesLeft(const ResultsIndex& earlier, const BatchFrames& b,
                                    std::size_t& skipped) {
  skipped = earlier.lines.size();
  if (earlier.lines.empty()) return b.mine;
  std::unordered_map<std::string, bool> done;  // a line's frame -> this run solves it
  for (const ResultLine& l : earlier.lines) done.emplace(l.image, false);
  std::vector<std::string> left;
  for (const std::string& f : b.mine) {
    const auto it = done.find(resultKey(f));
    if (it == done.end())
      left.push_back(f);
    else
      it->second = true;
  }
  for (const ResultLine& l : earlier.lines)
    if (!done.at(l.image))
      throw InputError("--resume " + earlier.path + ": holds " + l.image + ", a frame this run " +
                       (b.shard.whole() ? "does not list" : "(--shard " + b.shard.label() + ") does not solve") +
                       "; resume with the list and --shard that wrote it");
  return left;
}

int runBatch(const SolveOptions& o, const BatchFrames& batch) {
  installStopSignals();  // SIGTERM is how Slurm ends a task at its time limit
  std::unique_ptr<ResultsLog> results;
  std::vector<std::string> frames = batch.mine;
  std::size_t done_before = 0;
  if (!o.output.empty()) {
    results = std::make_unique<ResultsLog>(o.output, o.resume, o.force);
    frames = framesLeft(results->earlier(), batch, done_before);
    if (results->earlier().cut_last)
      log::info("%s: its last line was cut by the interruption; that frame is solved again",
                o.output.c_str());
  }
  const std::string who = batch.shard.whole() ? "" : "shard " + batch.shard.label() + ": ";
  const std::string skipped =
      done_before == 0 ? "" : ", " + std::to_string(done_before) + " with a result in " + o.output + " skipped";

  const PlateSolver solver(o);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::unique_ptr<FrameOutcome>> finished(frames.size());
  std::vector<double> ms;
  std::size_t next_print = 0;
  int solved = 0, failed = 0, errors = 0, worst = kExitOk;
  std::string write_error;
  std::mutex mutex;
  ProgressBar bar("solve", frames.size(), ::isatty(STDERR_FILENO) != 0);
  std::atomic<std::size_t> next{0};
  auto stopping = [&] { return stopSignal() != 0 || !write_error.empty(); };
  auto worker = [&] {
    for (std::size_t i = next++; i < frames.size() && !stopping(); i = next++) {
      auto f = solver.solveFileCaught(frames[i]);
      std::lock_guard<std::mutex> lock(mutex);
      // Kept the moment it is solved, whatever the order: a kill loses only frames in progress.
      if (results && write_error.empty()) try {
          results->append(jsonLine(outcomeJson(*f)));
        } catch (const std::exception& e) {
          write_error = e.what();
        }
      finished[i] = std::move(f);
      // Print in input order: a script reading the lines can zip them with its file list.
      for (; next_print < frames.size() && finished[next_print]; ++next_print) {
        FrameOutcome& p = *finished[next_print];
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
        finished[next_print].reset();  // the frame's image is not kept past its line
        bar.update(next_print + 1);
      }
    }
  };
  std::vector<std::thread> pool;
  const int n = std::max(1, std::min<int>(o.threads, int(frames.size())));
  for (int k = 1; k < n; ++k) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  bar.finish();
  std::sort(ms.begin(), ms.end());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::size_t run = ms.size();
  if (stopSignal() != 0)
    log::warn("%sinterrupted by %s after %zu of %zu frames%s", who.c_str(), stopSignalName(), run,
              frames.size(), results ? "; --resume continues" : "");
  log::info("%s%zu frames%s: %d solved, %d not solved, %d errors; median %.1f ms per frame, %.2f s "
            "in all (%d thread%s)",
            who.c_str(), run, skipped.c_str(), solved, failed, errors,
            ms.empty() ? 0.0 : ms[ms.size() / 2], wall, n, n == 1 ? "" : "s");
  if (!write_error.empty()) throw InputError(write_error);
  if (stopSignal() != 0) return kExitInterrupted;
  // With -o the results file carries each frame's outcome: the run succeeded when every frame
  // has its line (a Slurm array's merge waits on every task's exit 0).
  return results ? kExitOk : worst;
}

}  // namespace

int runSolveMerge(const SolveOptions& o, const std::vector<std::string>& other_flags) {
  if (!other_flags.empty())
    throw InputError("solve merge: " + other_flags.front() +
                     " does not apply; merge takes the parts, -o and --files-from");
  // A folder stands for its .jsonl files (a Slurm array's parts), sorted by name.
  std::vector<std::string> parts;
  for (auto it = o.inputs.begin() + 1; it != o.inputs.end(); ++it) {
    std::error_code ec;
    if (!std::filesystem::is_directory(*it, ec)) {
      parts.push_back(*it);
      continue;
    }
    std::vector<std::string> in_dir;
    for (const auto& e : std::filesystem::directory_iterator(*it, ec))
      if (e.path().extension() == ".jsonl" && e.path().filename().string().rfind(".partial-", 0) != 0)
        in_dir.push_back(e.path().string());
    if (ec) throw InputError("solve merge: " + *it + ": cannot list the folder: " + ec.message());
    if (in_dir.empty()) throw InputError("solve merge: " + *it + ": no .jsonl file in the folder");
    std::sort(in_dir.begin(), in_dir.end());
    parts.insert(parts.end(), in_dir.begin(), in_dir.end());
  }
  if (o.output.empty()) throw InputError("solve merge: give the merged file with -o");
  std::vector<NamedPath> inputs;
  for (const std::string& p : parts) inputs.push_back({p, "a part"});
  if (!o.files_from.empty() && o.files_from != "-") inputs.push_back({o.files_from, "--files-from"});
  refuseSameFile(o.output, "-o", inputs);
  const std::vector<std::string> order =
      o.files_from.empty() ? std::vector<std::string>{} : readFileList(o.files_from);
  prepareOutputFile(o.output, "-o", o.force);
  const std::size_t n = mergeResults(parts, order, o.output);
  log::info("%zu frames from %zu part%s merged into %s%s", n, parts.size(),
            parts.size() == 1 ? "" : "s", o.output.c_str(),
            order.empty() ? " (ordered by frame name)" : ", in the list's order");
  return kExitOk;
}

int runSolve(const SolveOptions& options) {
  bool printed = false;
  const SolveOptions& o = options;
  try {
    if (o.resume && o.output.empty())
      throw InputError("--resume continues a results file: give it with -o");
    if (isSingleFrame(o.inputs) && o.files_from.empty() && o.shard.empty() && o.output.empty())
      return runSingle(o, printed);
    const BatchFrames batch = batchFrames(o);
    checkBeforeWork(o, batch.mine.size());
    printed = true;  // from here each frame reports its own errors
    return runBatch(o, batch);
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
