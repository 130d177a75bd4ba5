// Usage errors that CLI11 reports poorly: options given where no command
// takes them. CLI11 lists such leftovers in reverse order and without a
// reason; these name each option and, when another subcommand takes it,
// where it belongs.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace surfdeform::cli {

// One line per argument of argv that looks like an option (not a number)
// that neither the program nor the subcommand given takes (before the
// subcommand: that the program does not take): "unknown option", "an
// option of deform and batch: give it after the subcommand", or "..., not
// of flatten". Empty when every option is known (the leftovers are then
// positional, and CLI11's own message says so).
std::string ExplainUnexpected(CLI::App& app, int argc, const char* const* argv);

}  // namespace surfdeform::cli
