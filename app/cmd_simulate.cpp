// `startracker simulate SCENARIO.ini -o run.rawlog`: sky images + gyro + truth -> rawlog.
#include <cstdio>
#include <filesystem>
#include <system_error>
#include <vector>

#include "app/cli/common_flags.hpp"
#include "app/command.hpp"
#include "app/earlier_run.hpp"
#include "common/output_file.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"
#include "sensors/sim/rawlog_writer.hpp"
#include "sensors/sim/scenario.hpp"

namespace st::app {

namespace {

namespace fs = std::filesystem;

}  // namespace

void addSimulateCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand(
      "simulate",
      "Simulate a star camera + gyro from a scenario .ini into a rawlog (CAMERA, GYRO, "
      "GROUND_TRUTH); images go to <stem>_Images/ beside the rawlog");
  struct Opts {
    std::string scenario, output;
    uint64_t seed = 0;
    int frames = 0;
    bool inline_images = false, force = false;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("scenario", o->scenario, "Scenario .ini (see sensors/sim/scenario.hpp)")
      ->required();
  cmd->add_option("-o,--output", o->output, "Output rawlog (.rawlog, gz-compressed)")->required();
  auto* seed_opt = cmd->add_option("--seed", o->seed, "Random seed (default: the scenario's)");
  auto* frames_opt = cmd->add_option("--frames", o->frames, "Limit the run to N frames");
  cmd->add_flag("--inline-images", o->inline_images, "Store images inside the rawlog");
  cli::addForceFlag(*cmd, o->force,
                "Replace an existing rawlog, emptying its <stem>_Images/ first");
  cmd->callback([o, seed_opt, frames_opt, &run] {
    run = [o, seed_opt, frames_opt] {
      const Scenario sc = Scenario::load(o->scenario);
      replaceEarlierRun(o->output, o->force);  // refused without -f, with its images folder
      prepareOutputFile(o->output, "-o/--output", /*replace=*/true);
      SimulateOptions opts;
      if (seed_opt->count() > 0) opts.seed = o->seed;
      if (frames_opt->count() > 0) opts.frames = o->frames;
      opts.external_images = !o->inline_images;
      opts.progress = !log::quiet();
      const SimulateSummary s = simulateToRawlog(sc, o->output, opts);
      std::printf("%s: %d frames (%d dropped), %d gyro samples, %zu observations, seed %llu\n",
                  o->output.c_str(), s.frames, s.frames_dropped, s.gyro_samples, s.objects,
                  static_cast<unsigned long long>(s.seed));
      if (sc.orbit)
        std::printf("orbit: %.0f km, inclination %.1f deg, %.3f km/s (aberration up to %.2f arcsec), "
                    "%d velocity samples\n",
                    sc.orbit->altitude_km, sc.orbit->inclination_deg, sc.orbit->speedKmS(),
                    rad2arcsec(sc.orbit->speedKmS() / kSpeedOfLightKmS), s.velocity_samples);
      std::printf("camera: %s\n", sc.camera.describe().c_str());
      if (!s.images_dir.empty()) std::printf("images: %s\n", s.images_dir.c_str());
      return kExitOk;
    };
  });
}

}  // namespace st::app
