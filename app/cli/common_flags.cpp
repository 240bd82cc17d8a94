#include "app/cli/common_flags.hpp"

#include <opencv2/core/utils/logger.hpp>

#include "app/cli/parse_errors.hpp"
#include "common/log.hpp"

namespace st::app::cli {
namespace {

/// "-v,--verbose" less the names `app` already has (a command's own -q stays its own).
std::string freeNames(const CLI::App& app, const std::string& short_name,
                      const std::string& long_name) {
  std::string names;
  for (const std::string& n : {short_name, long_name})
    if (app.get_option_no_throw(n) == nullptr) names += (names.empty() ? "" : ",") + n;
  return names;
}

std::size_t countOf(const CLI::App& app, const std::string& name) {
  const CLI::Option* opt = app.get_option_no_throw(name);
  return opt != nullptr ? opt->count() : 0;
}

}  // namespace

void addCommonFlags(CLI::App& root, const std::string& version_text) {
  if (root.get_option_no_throw("--version") == nullptr)
    root.set_version_flag("--version", version_text);
  const std::string verbose = freeNames(root, "-v", "--verbose");
  if (!verbose.empty()) root.add_flag(verbose, "More messages: debug lines and OpenCV's warnings");
  const std::string quiet = freeNames(root, "-q", "--quiet");
  if (!quiet.empty()) root.add_flag(quiet, "Errors and warnings only: no progress bars or info lines");
  for (CLI::App* sub : root.get_subcommands([](CLI::App*) { return true; })) {
    if (sub->get_group() == "Subcommands") sub->group("Commands");  // the help's heading
    addCommonFlags(*sub, version_text);
  }
}

void applyCommonFlags(const CLI::App& root) {
  std::size_t verbose = 0, quiet = 0;
  for (const CLI::App* app = &root;;) {
    verbose += countOf(*app, "--verbose");
    quiet += countOf(*app, "--quiet");
    if (app->get_subcommands().empty()) break;
    app = app->get_subcommands().front();
  }
  log::setVerbosity(verbose > 0 ? log::Verbosity::kVerbose
                                : quiet > 0 ? log::Verbosity::kQuiet : log::Verbosity::kNormal);
  // The tag is the command's first word: "catalog build" speaks as [catalog].
  const std::string path = commandPath(chosenCommand(root));
  log::setTag(path.substr(0, path.find(' ')));
  cv::utils::logging::setLogLevel(log::verbose() ? cv::utils::logging::LOG_LEVEL_WARNING
                                                 : cv::utils::logging::LOG_LEVEL_ERROR);
}

CLI::Option* addForceFlag(CLI::App& cmd, bool& force, const std::string& help) {
  return cmd.add_flag("-f,--force", force, help);
}

}  // namespace st::app::cli
