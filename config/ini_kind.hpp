/// @file ini_kind.hpp
/// What an .ini file is, told by what it contains (its sections), so that a file of one
/// schema given where another is expected is refused by name ("this is a scenario file;
/// replay --config takes a tracker file"), and the sections each kind owns.
#pragma once
#include <set>
#include <string>

#include "config/ini_reader.hpp"

namespace st {

/// The section of a Monte Carlo run file (app/montecarlo/run_file.hpp).
constexpr const char* kMontecarloRunSection = "montecarlo_run";
/// The sections a tracker file may have (replay --config, the .ini live writes beside a
/// recording).
const std::set<std::string>& trackerIniSections();

/// A live .ini (rawlog-grabber style): a [global] section or a sensor section (`driver`).
bool isLiveIni(const IniReader& r);
/// The sections a live .ini owns: [global], [filter], [navigator], its sensor sections and
/// the sections they name (keys ending in `_section`/`_sections`).
std::set<std::string> liveIniSections(const IniReader& r);

/// "a live .ini", "a scenario file", "a montecarlo run file", "a tracker file", or "" when
/// none of their sections is present.
std::string iniKind(const IniReader& r);

/// Throws InputError when the file is of another kind than `expected` (one of iniKind's
/// answers), naming the file, what it is and what `who` takes.
void requireIniKind(const IniReader& r, const std::string& expected, const std::string& who);

}  // namespace st
