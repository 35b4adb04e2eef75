// Number checks of the command line: see number_checks.hpp.
#include "number_checks.hpp"

#include <cmath>
#include <cstdlib>
#include <string>

namespace freespace::cli {
namespace {

// "" when `text` is an integer in decimal digits, no leading zero, a sign only where `sign`.
std::string DecimalError(const std::string& text, bool sign) {
  const std::size_t start = sign && !text.empty() && (text[0] == '-' || text[0] == '+') ? 1 : 0;
  bool ok = start < text.size() && !(text[start] == '0' && text.size() > start + 1);
  for (std::size_t i = start; ok && i < text.size(); ++i) ok = text[i] >= '0' && text[i] <= '9';
  if (ok) return "";
  return "'" + text + "' is not " + (sign ? "an integer" : "a non-negative integer") +
         " in decimal digits without a leading zero";
}

std::string FiniteError(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0') return "";  // CLI11 reports what is no number
  // Past the largest double strtod gives infinity; a number too small for one is read as 0.
  if (!std::isfinite(v)) return "'" + text + "' is not a finite number";
  return "";
}

}  // namespace

void CheckNumbers(CLI::App* app) {
  for (CLI::Option* option : app->get_options()) {
    const std::string type = option->get_type_name();
    if (type.rfind("UINT", 0) == 0) {
      option->check(CLI::Validator([](std::string& s) { return DecimalError(s, false); }, ""));
    } else if (type.rfind("INT", 0) == 0) {
      option->check(CLI::Validator([](std::string& s) { return DecimalError(s, true); }, ""));
    } else if (type.rfind("FLOAT", 0) == 0) {
      option->check(CLI::Validator([](std::string& s) { return FiniteError(s); }, ""));
    }
  }
  for (CLI::App* command : app->get_subcommands({})) CheckNumbers(command);
}

}  // namespace freespace::cli
