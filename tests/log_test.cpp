// The library's messages reach the caller's log callback and nothing else: `backend: auto`
// reports the backend it took through the callback, and with no callback set nothing is printed.
#include <string>
#include <utility>
#include <vector>

#include "test_util.hpp"

namespace freespace {
namespace {

// Sets a callback that records messages for the test's lifetime, then restores the old one.
class LogCapture {
 public:
  LogCapture() {
    previous_ = SetLogCallback([this](LogLevel level, const std::string& message) {
      messages_.emplace_back(level, message);
    });
  }
  ~LogCapture() { SetLogCallback(std::move(previous_)); }
  const std::vector<std::pair<LogLevel, std::string>>& messages() const { return messages_; }

 private:
  LogCallback previous_;
  std::vector<std::pair<LogLevel, std::string>> messages_;
};

Config AutoConfig() {
  Config c = test::SmallConfig(40, 40, 0.2);
  c.backend.kind = BackendKind::kAuto;
  return c;
}

TEST(Log, BackendAutoSaysWhichBackendThroughTheCallback) {
  LogCapture capture;
  testing::internal::CaptureStderr();
  Estimator estimator(AutoConfig());
  const std::string printed = testing::internal::GetCapturedStderr();
  EXPECT_EQ(printed, "") << "the library printed on its own";
  ASSERT_EQ(capture.messages().size(), 1u);
  const auto& [level, message] = capture.messages()[0];
  if (estimator.backend_name() == "tbb") {
    EXPECT_EQ(level, LogLevel::kWarning);
    EXPECT_NE(message.find("using tbb"), std::string::npos) << message;
  } else {
    EXPECT_EQ(level, LogLevel::kInfo);
    EXPECT_EQ(message, "backend auto: using " + estimator.backend_name());
  }
}

TEST(Log, WithoutACallbackNothingIsPrinted) {
  LogCallback previous = SetLogCallback(nullptr);
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  { Estimator estimator(AutoConfig()); }
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  SetLogCallback(std::move(previous));
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
}

TEST(Log, SetLogCallbackReturnsThePreviousOne) {
  int calls = 0;
  LogCallback previous = SetLogCallback([&calls](LogLevel, const std::string&) { ++calls; });
  LogCallback mine = SetLogCallback(std::move(previous));
  ASSERT_TRUE(mine);
  mine(LogLevel::kInfo, "x");
  EXPECT_EQ(calls, 1);
  EXPECT_STREQ(ToString(LogLevel::kWarning), "warning");
}

TEST(Version, HeaderAndLibraryAgree) {
  EXPECT_STREQ(LibraryVersion(), kVersion);
  EXPECT_EQ(std::string(kVersion), std::to_string(kVersionMajor) + "." +
                                       std::to_string(kVersionMinor) + "." +
                                       std::to_string(kVersionPatch));
}

}  // namespace
}  // namespace freespace
