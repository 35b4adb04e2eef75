// What every test process needs before its first case.
#include "freespace/baselines.hpp"

namespace freespace::test {
namespace {

// The rotated-map baseline is there for every test that configures it.
const bool kBaselinesRegistered = (RegisterBaselines(), true);

}  // namespace
}  // namespace freespace::test
