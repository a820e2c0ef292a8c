// The memory budget: sizes from headers and specs are refused before anything is allocated.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/maps/image.hpp>

#include <cstdlib>

namespace brdfbake {
namespace {

struct LimitGuard {
  explicit LimitGuard(const char* value) { ::setenv("BRDFBAKE_MEMORY_LIMIT", value, 1); }
  ~LimitGuard() { ::unsetenv("BRDFBAKE_MEMORY_LIMIT"); }
};

TEST(MemoryBudget, ParsesTheEnvironmentVariable) {
  {
    LimitGuard limit("8G");
    EXPECT_EQ(memoryBudgetBytes(), 8ull << 30);
  }
  {
    LimitGuard limit("1536K");
    EXPECT_EQ(memoryBudgetBytes(), 1536ull * 1024);
  }
  {
    LimitGuard limit("12345");
    EXPECT_EQ(memoryBudgetBytes(), 12345u);
  }
  {
    LimitGuard limit("lots");
    EXPECT_THROW(memoryBudgetBytes(), Error);
  }
}

TEST(MemoryBudget, ImagesOverTheBudgetAreRefusedBeforeAllocating) {
  LimitGuard limit("1M");            // 65536 float RGBA texels
  EXPECT_NO_THROW(Image(128, 128));  // 256 KiB
  try {
    Image image(1024, 1024);  // 16 MiB
    FAIL() << "expected a refusal";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::Resource);
    EXPECT_NE(std::string(e.what()).find("a 1024 x 1024 float RGBA image needs 16 MiB"), std::string::npos) << e.what();
  }
}

TEST(MemoryBudget, HugeSizesAreRefusedWithoutOverflow) {
  try {
    Image image(65536 * 4, 65536 * 4);  // 1 TiB: far beyond this machine's budget
    FAIL() << "expected a refusal";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::Resource);
    EXPECT_NE(std::string(e.what()).find("1.02e+03 GiB"), std::string::npos) << e.what();  // 16 bytes x 2^36
  }
}

TEST(MemoryBudget, FormatsBytes) {
  EXPECT_EQ(formatBytes(100), "100 bytes");
  EXPECT_EQ(formatBytes(1536), "1.5 KiB");
  EXPECT_EQ(formatBytes(16.0 * 1024 * 1024), "16 MiB");
  EXPECT_EQ(formatBytes(2.4e9), "2.24 GiB");
}

}  // namespace
}  // namespace brdfbake
