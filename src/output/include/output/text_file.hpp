// Text files the command-line tools write (polygons.jsonl, summary.json, config.yaml): every
// write and the close are checked, so that a full disk or a directory in the way ends in an
// OutputError naming the file instead of a silently cut file. A file of lines that fails keeps
// its whole lines only; a whole document that fails is removed.
#pragma once

#include <fstream>
#include <string>
#include <string_view>

namespace freespace {

class TextFile {
 public:
  // Creates (truncates) `path`; throws OutputError when it cannot.
  explicit TextFile(std::string path);

  // Appends `text`; throws OutputError when the stream fails (the write or a flush of the
  // buffer before it), the file then closed and cut after its last newline.
  void Write(std::string_view text);
  // Flushes and closes; throws OutputError when the data did not all reach the file (cut after
  // its last newline).
  void Close();
  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void Fail(const char* what) const;
  [[noreturn]] void FailWhole(const char* what);

  std::string path_;
  std::ofstream out_;
  bool failed_ = false;  // a write failed: Close() says so again
};

// Writes `text` to `path` as a whole (create, write, close), each step checked; a failed write
// removes the file.
void WriteTextFile(const std::string& path, std::string_view text);

// Throws OutputError when `path` is not a non-empty regular file (a writer that reports no
// errors of its own, such as OpenCV's video writer, checked after it is closed).
void CheckWritten(const std::string& path);
// CheckWritten(), and an AVI file whose RIFF header's size is the file's (OpenCV's video writer
// reports no write error: a file cut short by a full disk is caught here). Throws OutputError.
void CheckAviWritten(const std::string& path);

}  // namespace freespace
