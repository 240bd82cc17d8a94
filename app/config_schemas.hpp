/// @file config_schemas.hpp
/// The registry of schema printers used by `startracker config` (config/printer_registry.hpp).
#pragma once
#include "config/printer_registry.hpp"

namespace st::app {

/// Adds every schema the program knows, in recognition order (defined in config_schemas.cpp).
void addConfigSchemas(SchemaPrinters& printers);

}  // namespace st::app
