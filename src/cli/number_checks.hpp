// Numbers on the command line as a user writes them: CLI11 reads an integer in any base (010 is
// octal 8, 0x10 is 16), wraps a negative one into an unsigned option (-1 becomes 2^64 - 1) and
// lets NaN through a range check. These checks refuse what would be read otherwise than written.
#pragma once

#include <CLI/CLI.hpp>

namespace freespace::cli {

// Adds to every option of `app`'s commands, by its type: integers must be decimal digits
// without a leading zero (a sign for signed ones only), numbers must be finite.
void CheckNumbers(CLI::App* app);

}  // namespace freespace::cli
