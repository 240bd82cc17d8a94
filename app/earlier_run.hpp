/// @file earlier_run.hpp
/// A rawlog output over an earlier run: `simulate` and `live` keep it unless asked.
#pragma once
#include <string>

namespace st::app {

/// An earlier run at the same path is replaced only on request, and then whole: frames of a
/// longer earlier run would otherwise survive beside the new rawlog's, looking like its own.
/// Without `force`: InputError naming -o/--output when the rawlog exists or its
/// `<stem>_Images` folder holds images; with it, that folder is emptied (a link to another
/// run's folder is removed, not followed).
void replaceEarlierRun(const std::string& rawlog, bool force);

}  // namespace st::app
