/// @file input_list.hpp
/// The frames of one `solve` run: every IMAGE argument in the order given; a folder stands
/// for its images (not its sub-folders), sorted by name, so a night's frames solve in time
/// order. An image in a folder is a file with one of the image extensions (case-insensitive);
/// a file named on the command line is taken whatever its extension (a star list, say).
#pragma once
#include <string>
#include <vector>

namespace st::solve {

/// The extensions a folder's images have: png jpg jpeg tif tiff fits fit fts pgm ppm pnm bmp.
bool hasImageExtension(const std::string& path);

/// The frames in order. InputError naming a folder without images; a missing file stays in
/// the list and fails as its own frame (loading names it).
std::vector<std::string> expandInputs(const std::vector<std::string>& args);

/// The frames named in a list file (`--files-from`; "-" reads standard input): one path per
/// line as the working folder sees it, surrounding blanks (and a CR) dropped, empty lines and
/// lines starting with '#' skipped; a folder named stands for its images, as on the command
/// line. InputError naming the list when it cannot be read or names no frame.
std::vector<std::string> readFileList(const std::string& list);

/// True when the arguments are one file (not a folder): the run is a single solve.
bool isSingleFrame(const std::vector<std::string>& args);

}  // namespace st::solve
