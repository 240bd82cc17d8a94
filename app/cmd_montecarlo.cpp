// `startracker montecarlo EXPERIMENT`: the seed papers' Monte Carlo experiments (star counts,
// FOV selection, lost-in-space robustness, attitude error vs stars, timing) over random
// attitudes, with deterministic per-trial seeds so that `--shard i/N` pieces run anywhere and
// `startracker montecarlo merge DIR...` rebuilds the same tables. See app/montecarlo/.
#include <memory>

#include "app/cli/validators.hpp"
#include "app/command.hpp"
#include "app/montecarlo/experiment.hpp"
#include "app/montecarlo/mc_options.hpp"
#include "app/montecarlo/runner.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"

namespace st::app {

void addMontecarloCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand(
      "montecarlo",
      "Monte Carlo experiments over random attitudes -> Markdown/CSV tables and PNG plots.\n"
      "Experiments:\n" + mc::Experiment::help() +
          "  merge DIR...: combine the shard files of `--shard i/N` runs into one report");
  auto o = std::make_shared<mc::McOptions>();
  auto dirs = std::make_shared<std::vector<std::string>>();
  auto shard = std::make_shared<std::string>("0/1");
  auto size = std::make_shared<std::vector<int>>();
  auto no_plots = std::make_shared<bool>(false);
  cmd->add_option("experiment", o->experiment, "Experiment name, or 'merge'")->required();
  cmd->add_option("dirs", *dirs, "merge: directories with shard files");
  using cli::Bound;
  using cli::Number;
  using cli::WholeNumber;
  // The bounds keep a typo from taking a shared machine down: the trial tables are
  // allocated up front (--runs), and every thread holds a worker with its own images.
  cmd->add_option("--runs,-n", o->runs, "Trials (random attitudes)")
      ->check(WholeNumber(1, 10'000'000))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Base seed; trial k uses a hash of (seed, k)")
      ->check(WholeNumber(0, cli::kMaxU64))
      ->capture_default_str();
  cmd->add_option("--threads,-j", o->threads, "Worker threads (0 = all cores); results do not "
                  "depend on it")->check(WholeNumber(0, 256))->capture_default_str();
  cmd->add_option("--shard", *shard, "Run only trials k with k % N == i (i/N)")
      ->capture_default_str();
  cmd->add_option("--out,-o", o->out_dir, "Output directory")->capture_default_str();
  cmd->add_option("--fov-deg", o->fov_deg, "Horizontal FOV of the simulated camera [deg]")
      ->check(Number(0, 180, Bound::kOpen, Bound::kOpen))
      ->capture_default_str();
  cmd->add_option("--size", *size, "Image size W H of the simulated camera (default 1024 1024)")
      ->check(WholeNumber(8, 16384))
      ->expected(2);
  // Magnitudes: Sirius is V = -1.46; no catalog the program reads goes past V = 20.
  cmd->add_option("--mag-limit", o->mag_limit, "Faintest V magnitude seen by the camera")
      ->check(Number(-2, 20))
      ->capture_default_str();
  cmd->add_option("--mags", o->mags, "Magnitude limits (star-count, fov-selection)")
      ->check(Number(-2, 20))
      ->delimiter(',');
  cmd->add_option("--fovs", o->fovs_deg, "Square FOV sizes [deg] (fov-selection)")
      ->check(Number(0, 180, Bound::kOpen, Bound::kOpen))
      ->delimiter(',');
  cmd->add_option("--algorithms", o->algorithms, "Identification algorithms (default: all for "
                  "lis-robustness, pyramid for timing)")->delimiter(',');
  cmd->add_option("--solvers", o->solvers, "Wahba solvers (default: all)")->delimiter(',');
  cmd->add_option("--noise-px", o->noise_px, "Centroid noise 1-sigma per axis [px]")
      ->check(Number(0, cli::kNoBound))
      ->capture_default_str();
  cmd->add_option("--merge-arcsec", o->merge_arcsec, "Double-star merge distance [arcsec]")
      ->check(Number(0, 3600))
      ->capture_default_str();
  cmd->add_option("--catalog", o->catalog, "Star catalog (default: the committed Hipparcos "
                  "subset)");
  cmd->add_option("--field-stop-deg", o->field_stop_deg, "Circular field stop inside the image, "
                  "full angle [deg]: stars beyond half of it from the boresight are not seen "
                  "(0 = the whole image)")
      ->check(Number(0, 180, Bound::kClosed, Bound::kOpen))
      ->capture_default_str();
  cmd->add_option("--heads", o->heads, "Identical camera heads with boresights 90 deg apart; "
                  "their star counts add up (fov-selection)")
      ->check(WholeNumber(1, 3))
      ->capture_default_str();
  cmd->add_flag("--no-plots", *no_plots, "Write tables only (no gnuplot)");
  cmd->add_option("--gnuplot", o->gnuplot, "gnuplot program (default $ST_GNUPLOT or gnuplot)");
  cmd->callback([=, &run] {
    run = [=] {
      mc::McOptions opts = *o;
      opts.plots = !*no_plots;
      opts.progress = !log::quiet();  // -q, -v: app/cli/common_flags.hpp
      if (size->size() == 2) {
        opts.width = (*size)[0];
        opts.height = (*size)[1];
      }
      mc::parseShard(*shard, opts.shard_index, opts.shard_count);
      log::debug("%s --threads %d --shard %s --out %s", opts.commandLine().c_str(), opts.threads,
                 shard->c_str(), opts.out_dir.c_str());
      if (opts.experiment == "merge") return mc::mergeRuns(*dirs, opts);
      if (!dirs->empty())
        throw InputError("unexpected argument '" + dirs->front() + "' after the experiment name");
      return mc::runExperiment(opts);
    };
  });
}

}  // namespace st::app
