// OpenImageIO is loaded on the first image read or written, not at start-up (shared builds load it
// through the module brdfbake_image_oiio; static builds link it and skip this test). Its own
// executable, linked with brdfbake::bake only, so that nothing else maps OpenImageIO first.
#include <gtest/gtest.h>
#include <brdfbake/io/image_io.hpp>

#include <fstream>
#include <sstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {

// Whether a file whose name contains `name` is mapped into this process (Linux /proc/self/maps).
bool mapped(const std::string& name) {
  std::ifstream maps("/proc/self/maps");
  std::stringstream text;
  text << maps.rdbuf();
  return text.str().find(name) != std::string::npos;
}

TEST(ImageModule, OpenImageIOIsLoadedOnTheFirstImageOnly) {
  if (std::string(BRDFBAKE_IMAGE_MODULE).empty()) GTEST_SKIP() << "static build: OpenImageIO is linked in";
  ASSERT_TRUE(mapped("libbrdfbake_io")) << "cannot read /proc/self/maps";
  EXPECT_FALSE(mapped("libOpenImageIO")) << "OpenImageIO loaded before any image was touched";
  EXPECT_FALSE(mapped(BRDFBAKE_IMAGE_MODULE));

  test::TempDir dir;
  Image image(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) image.set(x, y, Rgba(x + 0.25, y - 0.5, 1e3, 0.125 * (x + 1)));
  image.metadata = {{"kind", "test"}};
  writeImage(image, dir / "a.exr");
  EXPECT_TRUE(mapped("libOpenImageIO")) << "writing an image loads OpenImageIO";
  EXPECT_TRUE(mapped(BRDFBAKE_IMAGE_MODULE));

  // Float OpenEXR holds every value written exactly (they are all representable in float).
  const Image read = readImage(dir / "a.exr");
  ASSERT_EQ(read.width(), 3);
  ASSERT_EQ(read.height(), 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      EXPECT_EQ(read.at(x, y)[0], x + 0.25f);
      EXPECT_EQ(read.at(x, y)[1], y - 0.5f);
      EXPECT_EQ(read.at(x, y)[2], 1000.0f);
      EXPECT_EQ(read.at(x, y)[3], 0.125f * (x + 1));
    }
  EXPECT_EQ(read.metadata["kind"], "test");
  EXPECT_EQ(imageMipLevelCount(dir / "a.exr"), 1);
}

}  // namespace
}  // namespace brdfbake
