#include "solve/input_list.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "common/errors.hpp"

namespace st::solve {
namespace fs = std::filesystem;

bool hasImageExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  static const char* const kExt[] = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".fits", ".fit",
                                     ".fts", ".pgm", ".ppm",  ".pnm", ".bmp"};
  return std::any_of(std::begin(kExt), std::end(kExt), [&](const char* e) { return ext == e; });
}

std::vector<std::string> expandInputs(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  for (const std::string& a : args) {
    std::error_code ec;
    if (!fs::is_directory(a, ec)) {
      // A missing file is reported where it is opened (loadImage names it), so that one
      // missing frame of a batch fails that frame only.
      out.push_back(a);
      continue;
    }
    std::vector<std::string> images;
    for (const auto& e : fs::directory_iterator(a, ec))
      if (e.is_regular_file(ec) && hasImageExtension(e.path().string()))
        images.push_back(e.path().string());
    if (ec) throw InputError(a + ": cannot list the folder: " + ec.message());
    if (images.empty())
      throw InputError(a + ": a folder without images (.png .jpg .tif .fits .pgm ...)");
    std::sort(images.begin(), images.end());
    out.insert(out.end(), images.begin(), images.end());
  }
  return out;
}

std::vector<std::string> readFileList(const std::string& list) {
  std::ifstream file;
  if (list != "-") {
    std::error_code ec;
    if (fs::is_directory(list, ec))
      throw InputError("--files-from " + list + ": a folder; give a text file with one frame per line");
    file.open(list);
    if (!file) throw InputError("--files-from " + list + ": cannot read the list");
  }
  std::istream& in = list == "-" ? std::cin : file;
  std::vector<std::string> named;
  std::string line;
  while (std::getline(in, line)) {
    const auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos || line[b] == '#') continue;
    named.push_back(line.substr(b, line.find_last_not_of(" \t\r") + 1 - b));
  }
  if (in.bad()) throw InputError("--files-from " + list + ": read error");
  if (named.empty()) throw InputError("--files-from " + list + ": names no frame");
  return expandInputs(named);
}

bool isSingleFrame(const std::vector<std::string>& args) {
  std::error_code ec;
  return args.size() == 1 && !fs::is_directory(args[0], ec);
}

}  // namespace st::solve
