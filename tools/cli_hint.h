// "Did you mean" for the command line: when CLI11 refuses a command line,
// the command it was meant for (so that the error names that command's
// --help) and, for a mistyped command or option, the closest name there is.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace svo::tools {

struct CommandLineHint {
  std::string command;  // the deepest command named: "svo", "svo render", "svo bench zoom"
  std::string message;  // "unknown command 'rendr' (did you mean 'render'?)"; empty: CLI11's own message
  // The message is about a number option given nan or inf ("--exposure nan:
  // not a finite number"), which CLI11's range checks let through (nan) or
  // refuse naming DBL_MAX (inf): refused before parsing.
  bool non_finite = false;
};

// Reads argv as CLI11 would (subcommands by name, options up to '=', "--"
// ends the options) and finds the first name that is neither a command nor
// an option of the command it follows, or the first value of a number
// option that reads as nan or inf.
CommandLineHint command_line_hint(CLI::App& app, int argc, const char* const* argv);

// The name in `names` closest to `word`: the only one that starts with it,
// else the one at the least edit distance (insertions, deletions,
// substitutions, transpositions) when that distance is at most a third of
// the word's length (at least 1); empty when none is that close.
std::string closest_name(const std::string& word, const std::vector<std::string>& names);

// A check for options that must be greater than 0: "0 is not a positive
// number". CLI::PositiveNumber refuses 0 naming its range, "0.000000 to"
// DBL_MAX written out in 309 digits. Non-finite values are refused before
// parsing (CommandLineHint::non_finite).
const CLI::Validator& positive_number();

// The body of main() for svo and svo-render: parses argv into `app` (named
// after the program, with its commands added) and runs the command; help
// and version on stdout, any error as one line "<command>: <message>" on
// stderr with exit code 1. Returns the exit code.
int run_command_line(CLI::App& app, const std::string& version, int argc, char** argv, const int& exit_code);

}  // namespace svo::tools
