// The command-line side of the option table: a flag per table option that has one, its help
// entry generated from the table ("<help>, <range> (default <default>)"), its value parsed by
// type (percentages for fractions, choice names for enums) and refused out of range in the
// table's words, naming the flag.
#pragma once

#include <string>

#include "absl/strings/string_view.h"

#include "absl/status/status.h"
#include "common/flags.h"
#include "engine/simplify.h"

namespace femsimp {

// Adds the flags of the table's options in `section` ("target", "engine", "fidelity",
// "backend"), in table order, storing into *options.
void AddOptionFlags(flags::FlagSet& set, absl::string_view section, SimplifyOptions* options);

// The flag of one option ("ratio", "cell.spes"); default_text, when given, replaces the default
// shown (a program whose own default differs, e.g. femsimp-load's ratio 0.5).
void AddOptionFlag(flags::FlagSet& set, absl::string_view path, SimplifyOptions* options,
                   std::string default_text = "");

// After parsing: a cell option's flag needs --backend cell ("--spes needs --backend cell").
absl::Status CheckCellFlags(const flags::FlagSet::Parsed& parsed, const SimplifyOptions& options);

}  // namespace femsimp
