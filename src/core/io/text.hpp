// Small helpers for the line-oriented log formats: splitting a line into fields and parsing
// numbers with a message that names the field.
#pragma once

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace freespace::io {

// Splits `line` at spaces and tabs into `fields` (views into `line`).
inline void SplitFields(std::string_view line, std::vector<std::string_view>* fields) {
  fields->clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) fields->push_back(line.substr(start, i - start));
  }
}

// Parses a whole field as a decimal double ("nan" and "inf" included; not strtod's hexadecimal
// form). Returns false when the field is not entirely a number.
inline bool ParseDouble(std::string_view field, double* value) {
  char buffer[64];
  if (field.empty() || field.size() >= sizeof buffer) return false;
  if (field.find_first_of("xX") != std::string_view::npos) return false;
  field.copy(buffer, field.size());
  buffer[field.size()] = '\0';
  char* end = nullptr;
  errno = 0;
  *value = std::strtod(buffer, &end);
  return end == buffer + field.size() && errno != ERANGE;
}

inline bool ParseInt(std::string_view field, long* value) {
  char buffer[32];
  if (field.empty() || field.size() >= sizeof buffer) return false;
  field.copy(buffer, field.size());
  buffer[field.size()] = '\0';
  char* end = nullptr;
  errno = 0;
  *value = std::strtol(buffer, &end, 10);
  return end == buffer + field.size() && errno != ERANGE;
}

// A printable excerpt of `text` for a message, at most `max_bytes` long before its suffix:
// bytes outside printable ASCII become \xNN (4 characters), and a text cut short ends in
// "... (N bytes)". A message never carries more than a few hundred bytes of its input, however
// long the line or binary the file.
inline std::string Excerpt(std::string_view text, std::size_t max_bytes = 40) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(max_bytes + 24);
  std::size_t i = 0;
  for (; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const bool printable = c >= 0x20 && c < 0x7f;
    if (out.size() + (printable ? 1 : 4) > max_bytes) break;
    if (printable) {
      out += char(c);
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (i < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

// `text` as a YAML double-quoted scalar that reads back as `text`: quotes, backslashes and
// control characters escaped (a file name or sensor name may hold '#', ": " or quotes).
inline std::string YamlQuoted(std::string_view text) {
  static const char kHex[] = "0123456789abcdef";
  std::string out = "\"";
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c == 0x7f) {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    } else {
      out += ch;
    }
  }
  return out + '"';
}

// The note on a last line without a newline: a file cut short while written ends so.
inline constexpr const char* kNoFinalNewline =
    "the last line ends without a newline (a file cut short?); read as it is";

inline bool IsCommentOrBlank(std::string_view line) {
  for (const char c : line) {
    if (c == '#') return true;
    if (c != ' ' && c != '\t' && c != '\r') return false;
  }
  return true;
}

}  // namespace freespace::io
