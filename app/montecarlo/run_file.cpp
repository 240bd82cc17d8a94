#include "common/output_file.hpp"
#include "app/montecarlo/run_file.hpp"

#include <mrpt/config/CConfigFileMemory.h>

#include <fstream>
#include <sstream>

#include "app/montecarlo/experiment.hpp"
#include "common/errors.hpp"

namespace st::app::mc {

namespace {
const SectionSchema<McOptions>& storedOptionsSchema() {
  using O = McOptions;
  static const auto schema =
      SectionSchema<O>()
          .choice("experiment", &O::experiment, Experiment::names(), "experiment")
          .required()
          .add("runs", &O::runs, "trials (random attitudes)")
          .add("seed", &O::seed, "run seed")
          .add("fov_deg", &O::fov_deg, "[deg] horizontal FOV of the simulated camera")
          .add("width", &O::width, "[px] image width")
          .add("height", &O::height, "[px] image height")
          .add("mag_limit", &O::mag_limit, "[mag] faintest catalog star")
          .add("mags", &O::mags, "[mag] magnitude grid (star-count, fov-selection)")
          .add("fovs_deg", &O::fovs_deg, "[deg] FOV grid (fov-selection); empty = default")
          .add("algorithms", &O::algorithms, "identification algorithms, comma-separated; empty = default")
          .add("solvers", &O::solvers, "Wahba solvers, comma-separated; empty = all")
          .add("noise_px", &O::noise_px, "[px] centroid noise, 1 sigma per axis")
          .add("merge_arcsec", &O::merge_arcsec, "[arcsec] database double-star merge distance")
          .add("catalog", &O::catalog, "catalog file; empty = the committed Hipparcos subset")
          .add("field_stop_deg", &O::field_stop_deg, "[deg] circular field stop (full angle); 0 = the image")
          .add("heads", &O::heads, "camera heads, boresights 90 deg apart (fov-selection)");
  return schema;
}
}  // namespace

const SectionSchema<McRunFile>& runFileSchema() {
  static const auto schema = SectionSchema<McRunFile>()
                                 .include(storedOptionsSchema(), &McRunFile::options)
                                 .add("shard", &McRunFile::shard, "i/N: this file's shard")
                                 .add("rows", &McRunFile::rows, "rows of the trials CSV");
  return schema;
}

void writeRunFile(const McOptions& o, std::size_t rows, const std::string& path) {
  McRunFile run{o, std::to_string(o.shard_index) + "/" + std::to_string(o.shard_count), rows};
  writeFileAtomically(path,
                      "# startracker montecarlo run description (read by `startracker montecarlo "
                      "merge`)\n" + runFileSchema().print(kRunSection, run));
}

McRunFile readRunFile(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError("cannot read '" + path + "'");
  std::stringstream text;
  text << f.rdbuf();
  std::string s = text.str();
  // Bare key = value lines (before the section existed): the same keys, one section.
  if (s.find("\n[") == std::string::npos && s.rfind("[", 0) != 0)
    s = "[" + std::string(kRunSection) + "]\n" + s;
  // MRPT's ini preprocessor throws std::runtime_error (e.g. an unclosed `$env{`).
  refuseDuplicateKeys(s, path);
  mrpt::config::CConfigFileMemory cfg;
  try {
    cfg.setContent(s);
  } catch (const std::exception& e) {
    const std::string why = e.what();
    throw InputError(path + ": not a readable .ini file (" + why.substr(0, why.find('\n')) + ")");
  }
  const IniReader r{cfg, path};
  if (!cfg.sectionExists(kRunSection))
    throw InputError(path + ": not a montecarlo run file (no [" + kRunSection + "] section)");
  r.onlySections({kRunSection}, "a montecarlo run file");
  McRunFile run;
  runFileSchema().read(r, kRunSection, run);
  try {
    parseShard(run.shard, run.options.shard_index, run.options.shard_count);
  } catch (const InputError& e) {  // parseShard speaks of the flag: name the file's key
    throw InputError(r.whereKey(kRunSection, "shard") + ": " + e.what());
  }
  return run;
}

std::map<std::string, std::string> runFileKeyValues(const McRunFile& run) {
  auto kv = run.options.toKeyValues();
  kv["shard"] = run.shard;
  kv["rows"] = std::to_string(run.rows);
  return kv;
}

std::string printRunFile(const IniReader& r, const std::string& section) {
  r.onlySections({kRunSection}, "a montecarlo run file");
  McRunFile run;
  runFileSchema().read(r, section, run);
  return runFileSchema().print(section, run);
}

}  // namespace st::app::mc
