// host::SetCellBits, the per-scan layers' bitset rows (the echoes, the face layer): each cell's
// bit lands in its row and column on every map width up to the widest, and the next call clears
// the last one's.
#include <algorithm>

#include "host/host_backend.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

TEST(CellBits, EveryCellLandsInItsRowAndColumnAndTheNextCallClearsIt) {
  for (const int width : {1, 2, 63, 64, 65, 300, 1500, 8191, 8192}) {
    const int height = 8192, words = (width + 63) / 64;
    // The first and last columns and a few between, on the first and last rows and a few between.
    std::vector<std::int32_t> cols = {0, width / 3, width / 2, width - 1};
    std::vector<std::int32_t> rows = {0, 1, 2, 4095, 8190, 8191};
    std::vector<std::int32_t> cells;
    for (const int r : rows) {
      for (const int c : cols) cells.push_back(r * width + c);
    }
    std::vector<std::uint64_t> bits(std::size_t(words) * height, 0);
    std::vector<std::int32_t> held;
    host::SetCellBits(cells.data(), int(cells.size()), width, words, &held, &bits);
    std::size_t set = 0;
    for (const std::uint64_t w : bits) set += std::size_t(__builtin_popcountll(w));
    std::vector<std::int32_t> distinct = cells;
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    EXPECT_EQ(set, distinct.size()) << "width " << width;
    for (const int r : rows) {
      for (const int c : cols) {
        EXPECT_TRUE((bits[std::size_t(r) * words + c / 64] >> (c % 64)) & 1)
            << "width " << width << " row " << r << " col " << c;
      }
    }
    // The next layer (one cell) replaces this one.
    const std::int32_t one = 5 * width + width - 1;
    host::SetCellBits(&one, 1, width, words, &held, &bits);
    set = 0;
    for (const std::uint64_t w : bits) set += std::size_t(__builtin_popcountll(w));
    EXPECT_EQ(set, 1u) << "width " << width;
    EXPECT_TRUE((bits[std::size_t(5) * words + (width - 1) / 64] >> ((width - 1) % 64)) & 1);
  }
}

}  // namespace
}  // namespace freespace
