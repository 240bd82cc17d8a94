#include "app/cli/parse_errors.hpp"

#include <algorithm>
#include <cstdlib>
#include <regex>

#include "app/cli/validators.hpp"

namespace st::app::cli {
namespace {

std::string join(const std::vector<std::string>& items, const std::string& sep) {
  std::string s;
  for (const auto& item : items) s += (s.empty() ? "" : sep) + item;
  return s;
}

/// Edit distance that counts a swap of two neighbouring letters as one edit: typed
/// commands are misspelt that way ("slove"), and plain Levenshtein (config's editDistance,
/// used for .ini keys) would rank "live" as near as "solve".
int typoDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<int>> d(a.size() + 1, std::vector<int>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = static_cast<int>(i);
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1,
                          d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

/// " (did you mean 'x'?)" for the nearest candidate when it is near enough to be a typo
/// (the .ini reader's rule, config/ini_reader.hpp closestKey), else "".
std::string suggestion(const std::string& typed, const std::vector<std::string>& candidates) {
  std::string best;
  int best_d = 0;
  for (const std::string& c : candidates) {
    const int d = typoDistance(typed, c);
    if (best.empty() || d < best_d) {
      best = c;
      best_d = d;
    }
  }
  const int limit = std::max(2, static_cast<int>(typed.size()) / 3);
  return best.empty() || best_d > limit ? "" : " (did you mean '" + best + "'?)";
}

std::vector<std::string> commandNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  return names;
}

/// The option CLI11 called `name`, looked up from the chosen command outwards.
const CLI::Option* findOption(const CLI::App* app, const std::string& name) {
  for (; app != nullptr; app = app->get_parent())
    if (const CLI::Option* opt = app->get_option_no_throw(name)) return opt;
  return nullptr;
}

/// The option's name as the user typed it (`-n` or `--runs`), else CLI11's name.
std::string typedName(const CLI::Option* opt, const std::string& fallback,
                      const std::vector<std::string>& args) {
  if (opt == nullptr) return fallback;
  for (const std::string& arg : args) {
    if (arg == "--") break;
    if (arg.size() < 2 || arg[0] != '-') continue;
    const std::string flag = arg.substr(0, arg.find('='));
    if (opt->check_name(flag)) return flag;
  }
  return fallback;
}

/// "a whole number" or "a number", from the option's CLI11 type.
std::string numberKind(const CLI::Option* opt) {
  if (opt == nullptr) return "a number";
  const std::string type = opt->get_type_name().substr(0, opt->get_type_name().find(':'));
  return type == "INT" || type == "UINT" ? "a whole number" : "a number";
}

std::string unknownCommand(const CLI::App& root, const CLI::App* chosen) {
  std::string typed;
  for (const std::string& arg : root.remaining(true))
    if (!arg.empty() && arg[0] != '-') {
      typed = arg;
      break;
    }
  const std::vector<std::string> names = commandNames(*chosen);
  const std::string path = commandPath(chosen);
  const std::string list = "; commands: " + join(names, ", ");
  if (typed.empty())
    return (path.empty() ? "missing command" : path + " needs a command") + list +
           " (--help for each)";
  return "unknown " + (path.empty() ? std::string() : path + " ") + "command '" + typed + "'" +
         suggestion(typed, names) + list;
}

std::string missing(const std::string& name, const CLI::App* chosen) {
  const CLI::Option* opt = findOption(chosen, name);
  std::string what = opt != nullptr ? opt->get_description() : "";
  what = what.substr(0, what.find('\n'));
  return "missing " + name + (what.empty() ? "" : ": " + what);
}

std::string extras(const std::string& msg, const CLI::App* chosen) {
  static const std::regex kExtras("^The following arguments? (?:was|were) not expected: (.*)$");
  std::smatch m;
  if (!std::regex_match(msg, m, kExtras)) return msg;
  std::vector<std::string> tokens;
  std::string list = m[1];
  for (std::size_t pos = 0; pos <= list.size();) {
    const std::size_t end = std::min(list.find(' ', pos), list.size());
    if (end > pos) tokens.insert(tokens.begin(), list.substr(pos, end - pos));  // CLI11 lists them last first
    pos = end + 1;
  }
  std::vector<std::string> flags;
  for (const CLI::App* app = chosen; app != nullptr; app = app->get_parent())
    for (const CLI::Option* opt : app->get_options())
      for (const std::string& n : opt->get_lnames()) flags.push_back("--" + n);
  // An unknown option strands the values after it: name the option alone then.
  std::vector<std::string> parts;
  for (const std::string& t : tokens)
    if (t.size() > 1 && t[0] == '-')
      parts.push_back("unknown option '" + t + "'" + suggestion(t.substr(0, t.find('=')), flags));
  if (parts.empty())
    for (const std::string& t : tokens) parts.push_back("unexpected argument '" + t + "'");
  const std::string path = commandPath(chosen);
  return join(parts, "; ") + (path.empty() ? "" : " for " + path) + " (see " +
         (path.empty() ? "" : path + " ") + "--help)";
}

std::string validation(const std::string& name, const std::string& body, const CLI::Option* opt,
                       const std::vector<std::string>& args) {
  const std::string flag = typedName(opt, name, args);
  if (body.rfind("must be ", 0) == 0) return flag + " " + body;
  std::smatch m;
  static const std::regex kRange(R"(^Value (.*) not in range (\S+) to (\S+)$)");
  if (std::regex_match(body, m, kRange)) {
    // CLI::Range prints its bounds with std::to_string: 0.100000, or 309 digits for
    // NonNegativeNumber's numeric_limits<double>::max().
    const double lo = std::strtod(m[2].str().c_str(), nullptr);
    const double hi = std::strtod(m[3].str().c_str(), nullptr);
    const std::string range = hi >= 1e300 ? ">= " + formatNumber(lo)
                                           : "from " + formatNumber(lo) + " to " + formatNumber(hi);
    return flag + " must be " + numberKind(opt) + " " + range + ", got " + m[1].str();
  }
  static const std::regex kMember(R"(^(.*) not in \{(.*)\}$)");
  if (std::regex_match(body, m, kMember)) {
    std::vector<std::string> names;
    const std::string list = m[2];
    for (std::size_t pos = 0; pos <= list.size();) {
      const std::size_t end = std::min(list.find(',', pos), list.size());
      names.push_back(list.substr(pos, end - pos));
      pos = end + 1;
    }
    return flag + " must be one of " + join(names, ", ") + "; got '" + m[1].str() + "'" +
           suggestion(m[1], names);
  }
  return flag + ": " + body;
}

}  // namespace

const CLI::App* chosenCommand(const CLI::App& root) {
  const CLI::App* app = &root;
  while (!app->get_subcommands().empty()) app = app->get_subcommands().front();
  return app;
}

std::string commandPath(const CLI::App* app) {
  std::string path;
  for (; app != nullptr && app->get_parent() != nullptr; app = app->get_parent())
    path = app->get_name() + (path.empty() ? "" : " " + path);
  return path;
}

std::string describeParseError(const CLI::ParseError& e, const CLI::App& root,
                               const std::vector<std::string>& args) {
  const CLI::App* chosen = chosenCommand(root);
  const std::string msg = e.what();
  std::smatch m;
  if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
    if (msg.find("subcommand") != std::string::npos) return unknownCommand(root, chosen);
    static const std::regex kRequired("^(.*) is required$");
    if (std::regex_match(msg, m, kRequired)) return missing(m[1], chosen);
    return msg;
  }
  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) return extras(msg, chosen);
  if (dynamic_cast<const CLI::ValidationError*>(&e) != nullptr) {
    static const std::regex kNamed(R"(^(\S+): (.*)$)");
    if (!std::regex_match(msg, m, kNamed)) return msg;
    return validation(m[1], m[2], findOption(chosen, m[1]), args);
  }
  if (dynamic_cast<const CLI::ConversionError*>(&e) != nullptr) {
    static const std::regex kConvert(R"(^Could not convert: (\S+) = (.*)$)");
    if (!std::regex_match(msg, m, kConvert)) return msg;
    const CLI::Option* opt = findOption(chosen, m[1]);
    const std::string flag = typedName(opt, m[1], args);
    static const std::regex kWhole(R"(^[-+]?[0-9]+$)");
    if (std::regex_match(m[2].str(), kWhole))  // passed the digit check, not the type's width
      return flag + " is out of range, got " + m[2].str();
    return flag + " must be " + numberKind(opt) + ", got '" + m[2].str() + "'";
  }
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr) {
    static const std::regex kCount(R"(^(\S+): (?:At least|At Most|Exactly)? ?(\d+) required but received (\d+)$)");
    if (!std::regex_match(msg, m, kCount)) return msg;
    const std::string flag = typedName(findOption(chosen, m[1]), m[1], args);
    return flag + " takes " + m[2].str() + " value" + (m[2] == "1" ? "" : "s") + ", got " +
           m[3].str();
  }
  if (dynamic_cast<const CLI::ExcludesError*>(&e) != nullptr) {
    static const std::regex kExcludes(R"(^(\S+) excludes (\S+)$)");
    if (std::regex_match(msg, m, kExcludes))
      return m[1].str() + " and " + m[2].str() + " cannot be used together";
  }
  return msg;
}

}  // namespace st::app::cli
