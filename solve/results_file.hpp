/// @file results_file.hpp
/// The JSON Lines results of a batch solve (`solve -o FILE`): one line per frame, the object
/// `--json` prints ("image" names the frame). A line is appended as its frame finishes, in one
/// write, so a run killed by SIGKILL (a Slurm time limit, a node taken back) keeps every frame
/// it finished and loses at most the frames in progress; `--resume` reads the file back,
/// removes a last line the kill cut, and solves only the frames without a line. The lines go
/// to the kernel at once but are not fsync'ed: a crash of the machine itself can lose the
/// last ones, which --resume then solves again.
///
/// `solve merge` joins the files of a sharded run into one, in the order of the frame list
/// (or of the frame names), refusing a frame twice, a frame missing, or a cut file.
#pragma once
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace st::solve {

/// Where a frame's line is in its file.
struct ResultLine {
  std::string image;        ///< the frame, as its "image" key names it
  std::uint64_t offset = 0;  ///< of the line's first byte
  std::uint64_t length = 0;  ///< without the newline
};

/// The frame `path` as its line names it: the path itself, but invalid UTF-8 replaced by
/// U+FFFD as in every JSON line (so resume and merge match a frame with such a name).
std::string resultKey(const std::string& path);

/// A results file read back: its complete lines in file order.
struct ResultsIndex {
  std::string path;
  std::vector<ResultLine> lines;
  std::uint64_t complete_bytes = 0;  ///< the file up to the end of its last complete line
  bool cut_last = false;             ///< a last line without its newline, or not JSON
};

/// Reads `path`, a results file (`flag` names it in messages: "-o", "merge"). InputError when
/// a line before the last is not a frame's result object, or a frame has two lines.
ResultsIndex readResults(const std::string& path, const std::string& flag);

/// The results file of one run, open for appending.
class ResultsLog {
 public:
  /// A new file at `path`; with `resume` an existing file is continued (read back into
  /// earlier(), its cut last line removed) and a missing one created. Without `resume` an
  /// existing file is refused (InputError: it is the product of an earlier run) unless
  /// `replace` (-f), which starts it afresh.
  ResultsLog(const std::string& path, bool resume, bool replace);
  ~ResultsLog();
  ResultsLog(const ResultsLog&) = delete;
  ResultsLog& operator=(const ResultsLog&) = delete;

  /// The lines found by --resume (empty for a new file).
  const ResultsIndex& earlier() const { return earlier_; }
  /// Appends `json` and a newline in one write. Throws InputError naming the file on failure
  /// (disk full): the run stops rather than solve frames whose results cannot be kept.
  void append(const std::string& json);

 private:
  std::string path_;
  int fd_ = -1;
  ResultsIndex earlier_;
};

/// Joins results files into `out` (written complete or not at all): ordered by `order` (the
/// frame list: every frame of it must have exactly one line, and no line may name a frame
/// outside it) or, when `order` is empty, by frame name. Returns the number of frames.
/// InputError naming the file and frame for a duplicate, a missing frame, or a cut file.
std::size_t mergeResults(const std::vector<std::string>& parts,
                         const std::vector<std::string>& order, const std::string& out);

}  // namespace st::solve
