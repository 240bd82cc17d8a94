#include "solve/results_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unordered_set>

#include "common/errors.hpp"
#include "common/output_file.hpp"

namespace st::solve {
namespace {

/// The frame a line is the result of, or "" when the line is not a result object.
std::string imageOf(const std::string& line) {
  const auto j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) return "";
  const auto it = j.find("image");
  return it != j.end() && it->is_string() ? it->get<std::string>() : "";
}

std::string lineLabel(const std::string& path, std::size_t number) {
  return path + ":" + std::to_string(number);
}

}  // namespace

std::string resultKey(const std::string& path) {
  const std::string quoted =
      nlohmann::json(path).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return nlohmann::json::parse(quoted).get<std::string>();
}

ResultsIndex readResults(const std::string& path, const std::string& flag) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(flag + " " + path + ": cannot read the results file");
  ResultsIndex idx;
  idx.path = path;
  std::unordered_map<std::string, std::size_t> seen;  // frame -> its line number
  std::string line, bad;
  std::size_t number = 0, bad_number = 0;
  std::uint64_t offset = 0;
  while (std::getline(in, line)) {
    ++number;
    const bool complete = !in.eof();  // getline stopped at a newline
    const std::uint64_t start = offset;
    offset += line.size() + (complete ? 1 : 0);
    // A bad line is an error only when a line follows it: the last one may have been cut by
    // the kill that ended the run (or hold zeros after a crash).
    if (!bad.empty())
      throw InputError(lineLabel(path, bad_number) + ": not the result of a frame (" + bad +
                       "); " + flag + " takes `startracker solve -o` files");
    const std::string image = complete ? imageOf(line) : "";
    if (image.empty()) {
      bad = complete ? "no JSON object with an \"image\"" : "cut before its end";
      bad_number = number;
      continue;
    }
    if (const auto [it, fresh] = seen.emplace(image, number); !fresh)
      throw InputError(lineLabel(path, number) + ": " + image + " has a result already on line " +
                       std::to_string(it->second));
    idx.lines.push_back({image, start, line.size()});
    idx.complete_bytes = offset;
  }
  if (in.bad()) throw InputError(flag + " " + path + ": read error");
  idx.cut_last = !bad.empty();
  return idx;
}

ResultsLog::ResultsLog(const std::string& path, bool resume, bool replace) : path_(path) {
  prepareOutputFile(path, "-o", /*replace=*/true);  // existing: continued, replaced or refused below
  const bool exists = ::access(path.c_str(), F_OK) == 0;
  if (exists && !resume && !replace)
    throw InputError("-o " + path + ": the results of an earlier run are there; --resume " +
                     "continues it (frames with a result are skipped), -f/--force replaces it");
  if (exists && resume) earlier_ = readResults(path, "-o");
  // -f without --resume: the earlier results go now (this file is written as frames finish,
  // so it cannot wait for a rename at the end).
  const int trunc = exists && !resume ? O_TRUNC : 0;
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | trunc, 0644);
  if (fd_ < 0) throw InputError("-o " + path + ": cannot open: " + std::strerror(errno));
  // The cut last line goes: its frame is solved again and appended whole.
  if (earlier_.cut_last && ::ftruncate(fd_, static_cast<off_t>(earlier_.complete_bytes)) != 0)
    throw InputError("-o " + path + ": cannot remove its cut last line: " + std::strerror(errno));
}

ResultsLog::~ResultsLog() {
  if (fd_ >= 0) ::close(fd_);
}

void ResultsLog::append(const std::string& json) {
  const std::string line = json + "\n";
  // One write per line: O_APPEND puts it whole at the end; a short write (disk full) is
  // finished or reported, never left silently cut.
  for (std::size_t done = 0; done < line.size();) {
    const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw InputError("-o " + path_ + ": cannot write a result: " +
                       std::strerror(n < 0 ? errno : ENOSPC));
    done += static_cast<std::size_t>(n);
  }
}

std::size_t mergeResults(const std::vector<std::string>& parts,
                         const std::vector<std::string>& order, const std::string& out) {
  if (parts.empty()) throw InputError("merge: give the results files (-o of each shard)");
  struct Where {
    std::size_t part;
    ResultLine line;
  };
  std::vector<ResultsIndex> idx;
  std::unordered_map<std::string, Where> where;
  for (const std::string& p : parts) {
    idx.push_back(readResults(p, "merge"));
    const ResultsIndex& r = idx.back();
    if (r.cut_last)
      throw InputError("merge: " + p + ": its last line is cut (the run was killed): run it " +
                       "again with --resume, then merge");
    for (const ResultLine& l : r.lines)
      if (const auto [it, fresh] = where.emplace(l.image, Where{idx.size() - 1, l}); !fresh)
        throw InputError("merge: " + l.image + " has a result in " + idx[it->second.part].path +
                         " and in " + p);
  }
  std::vector<const Where*> sorted;
  if (order.empty()) {
    for (const auto& [image, w] : where) sorted.push_back(&w);
    std::sort(sorted.begin(), sorted.end(),
              [](const Where* a, const Where* b) { return a->line.image < b->line.image; });
  } else {
    std::size_t missing = 0;
    std::string first_missing;
    std::unordered_set<std::string> listed;
    for (const std::string& frame : order) {
      const std::string image = resultKey(frame);
      if (!listed.insert(image).second)
        throw InputError("merge: the frame list names " + image + " twice");
      const auto it = where.find(image);
      if (it == where.end()) {
        if (missing++ == 0) first_missing = image;
        continue;
      }
      sorted.push_back(&it->second);
    }
    if (missing > 0)
      throw InputError("merge: " + std::to_string(missing) + " of the list's " +
                       std::to_string(order.size()) + " frames have no result (the first: " +
                       first_missing + "); run their shards again with --resume");
    for (const auto& [image, w] : where)
      if (!listed.count(image))
        throw InputError("merge: " + idx[w.part].path + " holds " + image +
                         ", a frame not in the list");
  }
  PendingOutput pending(out);
  std::ofstream os(pending.tempPath(), std::ios::binary);
  std::vector<std::ifstream> in;
  for (const ResultsIndex& r : idx) in.emplace_back(r.path, std::ios::binary);
  std::string text;
  for (const Where* w : sorted) {
    std::ifstream& f = in[w->part];
    text.resize(w->line.length);
    f.seekg(static_cast<std::streamoff>(w->line.offset));
    f.read(text.data(), static_cast<std::streamsize>(text.size()));
    if (!f) throw InputError("merge: " + idx[w->part].path + ": changed while merging");
    os << text << '\n';
  }
  os.close();
  if (!os) throw InputError("merge -o " + out + ": cannot write the merged results");
  pending.commit();
  return sorted.size();
}

}  // namespace st::solve
