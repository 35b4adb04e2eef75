// Checked text output: see output/text_file.hpp.
#include "output/text_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "freespace/errors.hpp"

namespace freespace {

TextFile::TextFile(std::string path) : path_(std::move(path)) {
  errno = 0;
  out_.open(path_, std::ios::binary | std::ios::trunc);
  if (!out_) Fail("cannot create");
}

void TextFile::Write(std::string_view text) {
  errno = 0;
  out_.write(text.data(), std::streamsize(text.size()));
  if (!out_) Fail("write failed");
}

void TextFile::Close() {
  if (!out_.is_open()) return;
  errno = 0;
  out_.flush();
  const bool flushed = bool(out_);
  out_.close();
  if (!flushed || out_.fail()) Fail("write failed");
}

void TextFile::Fail(const char* what) const {
  // errno is set by the failing system call on the platforms this builds on; an ofstream does
  // not promise it, hence the fallback.
  const std::string reason = errno != 0 ? std::strerror(errno) : "the stream reported an error";
  throw OutputError(path_ + ": " + what + ": " + reason);
}

void WriteTextFile(const std::string& path, std::string_view text) {
  TextFile file(path);
  file.Write(text);
  file.Close();
}

void CheckWritten(const std::string& path) {
  std::error_code error;
  const bool regular = std::filesystem::is_regular_file(path, error);
  const auto size = regular ? std::filesystem::file_size(path, error) : 0;
  if (!regular || error || size == 0) {
    throw OutputError(path + ": not written" + (error ? ": " + error.message() : std::string()));
  }
}

}  // namespace freespace
