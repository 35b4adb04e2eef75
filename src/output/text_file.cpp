// Checked text output: see output/text_file.hpp.
#include "output/text_file.hpp"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/stream_error.hpp"
#include "freespace/errors.hpp"

namespace freespace {

TextFile::TextFile(std::string path) : path_(std::move(path)) {
  errno = 0;
  out_.open(path_, std::ios::binary | std::ios::trunc);
  if (!out_) Fail("cannot create");
}

namespace {

// Cuts `path` after its last newline (to nothing without one); leaves it as it is when it cannot
// be read.
void CutToLastLine(const std::string& path) {
  std::error_code error;
  std::uintmax_t end = std::filesystem::file_size(path, error);
  if (error) return;
  std::ifstream in(path, std::ios::binary);
  char buffer[4096];
  while (end > 0) {
    const std::uintmax_t from = end > sizeof buffer ? end - sizeof buffer : 0;
    in.seekg(std::streamoff(from));
    in.read(buffer, std::streamsize(end - from));
    if (!in) return;
    for (std::uintmax_t i = end - from; i-- > 0;) {
      if (buffer[i] == '\n') {
        std::filesystem::resize_file(path, from + i + 1, error);
        return;
      }
    }
    end = from;
  }
  std::filesystem::resize_file(path, 0, error);
}

}  // namespace

void TextFile::Write(std::string_view text) {
  errno = 0;
  out_.write(text.data(), std::streamsize(text.size()));
  if (!out_) FailWhole("write failed");
}

void TextFile::Close() {
  if (failed_) throw OutputError(path_ + ": an earlier write failed");
  if (!out_.is_open()) return;
  errno = 0;
  out_.flush();
  const bool flushed = bool(out_);
  out_.close();
  if (!flushed || out_.fail()) FailWhole("write failed");
}

void TextFile::Fail(const char* what) const { throw StreamError(path_, what); }

void TextFile::FailWhole(const char* what) {
  const OutputError error = StreamError(path_, what);  // errno before the cut
  failed_ = true;
  out_.close();
  CutToLastLine(path_);
  throw error;
}

void WriteTextFile(const std::string& path, std::string_view text) {
  TextFile file(path);
  try {
    file.Write(text);
    file.Close();
  } catch (const OutputError&) {
    std::error_code error;
    std::filesystem::remove(path, error);  // a document cut anywhere is no document
    throw;
  }
}

void CheckWritten(const std::string& path) {
  std::error_code error;
  const bool regular = std::filesystem::is_regular_file(path, error);
  const auto size = regular ? std::filesystem::file_size(path, error) : 0;
  if (!regular || error || size == 0) {
    throw OutputError(path + ": not written" + (error ? ": " + error.message() : std::string()));
  }
}

void CheckAviWritten(const std::string& path) {
  CheckWritten(path);
  // RIFF: "RIFF", the size of what follows (little-endian uint32, set when the writer closes),
  // "AVI ". A file cut short (a full disk) is smaller than its header says.
  std::ifstream in(path, std::ios::binary);
  unsigned char head[12] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  const std::uint64_t said = std::uint64_t(head[4]) | std::uint64_t(head[5]) << 8 |
                             std::uint64_t(head[6]) << 16 | std::uint64_t(head[7]) << 24;
  const std::uint64_t size = std::filesystem::file_size(path);
  if (!in || std::memcmp(head, "RIFF", 4) != 0 || std::memcmp(head + 8, "AVI ", 4) != 0) {
    throw OutputError(path + ": write failed: not an AVI file (" + std::to_string(size) +
                      " bytes)");
  }
  if (said + 8 != size) {
    throw OutputError(path + ": write failed: " + std::to_string(size) +
                      " bytes, its header says " + std::to_string(said + 8) + " (a full disk?)");
  }
}

}  // namespace freespace
