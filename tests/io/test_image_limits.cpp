// Image files at their limits: headers that claim more than their file can hold are refused before
// OpenImageIO allocates anything, images are decoded a strip at a time, and every write is checked
// (a full disk is an error naming the output; nothing but a regular file is replaced).
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/image_io.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <future>
#include <random>
#include <thread>

#include "test_support.hpp"
#include "tiny_filesystem.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::errorOf;
using test::hiddenTemporaries;
using test::put;
using test::slurp;

std::string bigEndian32(std::uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8), static_cast<char>(v)};
}
std::string littleEndian32(std::uint32_t v) {
  return {static_cast<char>(v), static_cast<char>(v >> 8), static_cast<char>(v >> 16), static_cast<char>(v >> 24)};
}

std::string junk(std::size_t bytes) {
  std::mt19937 rng(7);
  std::string out(bytes, '\0');
  for (char& c : out) c = static_cast<char>(rng());
  return out;
}

// A PNG whose IHDR claims width x height RGB of 8 bits (or grey of `greyBits`), followed by
// `dataBytes` of IDAT (junk).
std::string pngClaiming(std::uint32_t width, std::uint32_t height, std::size_t dataBytes, char greyBits = 0) {
  const std::string depthAndColour = greyBits ? std::string{greyBits, '\0'} : std::string("\x08\x02", 2);
  std::string ihdr = bigEndian32(width) + bigEndian32(height) + depthAndColour + std::string(3, '\0');
  return std::string("\x89PNG\r\n\x1a\n", 8) + bigEndian32(13) + "IHDR" + ihdr + bigEndian32(0) +
         bigEndian32(static_cast<std::uint32_t>(dataBytes)) + "IDAT" + junk(dataBytes) + bigEndian32(0) +
         bigEndian32(0) + "IEND" + bigEndian32(0xAE426082);
}

// One OpenEXR attribute: name, type, size, value.
std::string exrAttribute(const std::string& name, const std::string& type, const std::string& value) {
  return name + '\0' + type + '\0' + littleEndian32(static_cast<std::uint32_t>(value.size())) + value;
}

// A scanline OpenEXR header of half RGBA with the given data window and compression, then `dataBytes`.
std::string exrClaiming(std::uint32_t width, std::uint32_t height, char compression, std::size_t dataBytes) {
  std::string channels;
  for (const char* c : {"A", "B", "G", "R"})
    channels +=
        std::string(c) + '\0' + littleEndian32(1) + std::string(4, '\0') + littleEndian32(1) + littleEndian32(1);
  channels += '\0';
  const std::string window =
      littleEndian32(0) + littleEndian32(0) + littleEndian32(width - 1) + littleEndian32(height - 1);
  return std::string("\x76\x2f\x31\x01", 4) + littleEndian32(2) + exrAttribute("channels", "chlist", channels) +
         exrAttribute("compression", "compression", std::string(1, compression)) +
         exrAttribute("dataWindow", "box2i", window) + exrAttribute("displayWindow", "box2i", window) +
         exrAttribute("lineOrder", "lineOrder", std::string(1, '\0')) +
         exrAttribute("pixelAspectRatio", "float", littleEndian32(0x3F800000)) +
         exrAttribute("screenWindowCenter", "v2f", std::string(8, '\0')) +
         exrAttribute("screenWindowWidth", "float", littleEndian32(0x3F800000)) + '\0' + std::string(dataBytes, '\0');
}

TEST(ImageLimits, HeadersClaimingMoreThanTheirFileHoldsAreRefusedBeforeDecoding) {
  test::TempDir dir;
  struct Case {
    const char* name;
    std::string bytes;
    const char* says;
  };
  const std::vector<Case> cases = {
      {"big.png", pngClaiming(17000, 17000, 300 * 1024), "the header says 17000 x 17000 pixels"},
      {"big.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 18000 +X 18000\n" + junk(400 * 1024),
       "the header says 18000 x 18000 pixels"},
      {"big.exr", exrClaiming(18000, 18000, 3, 401 * 1024), "the header says 18000 x 18000 pixels"},
      // An uncompressed 2^30-line scanline file: its offset table alone would be 8 GiB.
      {"tall.exr", exrClaiming(1, 1u << 30, 0, 4096), "whose offset table alone needs more than"},
      {"big.tif",
       "II*" + std::string(1, '\0') + littleEndian32(8) + std::string("\x04\x00", 2) +
           std::string("\x00\x01\x04\x00\x01\x00\x00\x00", 8) + littleEndian32(20000) +
           std::string("\x01\x01\x04\x00\x01\x00\x00\x00", 8) + littleEndian32(20000) +
           std::string("\x03\x01\x03\x00\x01\x00\x00\x00\x01\x00\x00\x00", 12) +
           std::string("\x15\x01\x03\x00\x01\x00\x00\x00\x03\x00\x00\x00", 12) + littleEndian32(0) + junk(300 * 1024),
       "the header says 20000 x 20000 pixels"},
      // 2^64 - 2^34 + 4 bytes of samples: shown whole (as a double), never wrapped to a negative number.
      {"huge.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2147483647 +X 2147483647\n" + junk(1024),
       "(18446744056529682432 bytes of samples;"},
  };
  for (const Case& c : cases) {
    put(dir / c.name, c.bytes);
    SCOPED_TRACE(c.name);
    const std::string message = errorOf([&] { readImage(dir / c.name); }, Error::Kind::InvalidInput);
    EXPECT_EQ(message.rfind((dir / c.name).string() + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(c.says), std::string::npos) << message;
  }
}

TEST(ImageLimits, ASmallFileNeverDecodesToGigabytes) {
  // 1-bit PNGs whose headers fit their deflate bound (1032 raw bytes per byte) but would decode to
  // 2 GiB and 8 GiB of float RGBA: refused from the header, whatever the memory budget.
  test::TempDir dir;
  struct Case {
    std::uint32_t width, height;
    std::size_t bytes;
    const char* decoded;  // width x height x 16
  };
  for (const Case& c : {Case{16384, 8192, 17 * 1024, "2147483648"}, Case{32768, 16384, 66 * 1024, "8589934592"}}) {
    const std::string png = pngClaiming(c.width, c.height, c.bytes, 1);
    put(dir / "flat.png", png);
    const std::string message = errorOf([&] { readImage(dir / "flat.png"); }, Error::Kind::InvalidInput);
    const std::string says = std::string(c.decoded) + " bytes as float RGBA from a " + std::to_string(png.size());
    EXPECT_NE(message.find(says), std::string::npos) << message;
  }
  // The floor: 128 MiB of floats (4096 x 2048) is decoded from any file its header check allows.
  put(dir / "sky.png", pngClaiming(4096, 2048, 9 * 1024, 1));
  EXPECT_EQ(errorOf([&] { readImage(dir / "sky.png"); }, Error::Kind::Io).find("bytes as float RGBA"),
            std::string::npos);
}

TEST(ImageLimits, AFileReplacedWhileItIsReadIsReadWholeOldOrNew) {
  // Another process renames a new picture over the input (an atomic replace) while it is read: the
  // header check and the decoder see the same open file, so every read is one picture or the other.
  test::TempDir dir;
  Image small(64, 64, Rgba(0.25f, 0.25f, 0.25f, 1.0f)), large(96, 96, Rgba(0.75f, 0.75f, 0.75f, 1.0f));
  writeImage(small, dir / "small.exr");
  writeImage(large, dir / "large.exr");
  fs::copy_file(dir / "small.exr", dir / "sky.exr");
  std::atomic<bool> stop{false};
  std::thread replacer([&] {
    for (int i = 0; !stop; ++i) {
      fs::copy_file(dir / (i % 2 ? "small.exr" : "large.exr"), dir / "next.exr", fs::copy_options::overwrite_existing);
      fs::rename(dir / "next.exr", dir / "sky.exr");
    }
  });
  int failures = 0;
  std::string firstFailure;
  for (int read = 0; read < 300; ++read) {
    try {
      const Image image = readImage(dir / "sky.exr");
      const float expected = image.width() == 64 ? 0.25f : 0.75f;
      if ((image.width() != 64 && image.width() != 96) || image.height() != image.width() ||
          image.at(image.width() - 1, image.height() - 1)[0] != expected)
        ++failures;
    } catch (const Error& e) {
      if (failures++ == 0) firstFailure = e.what();
    }
  }
  stop = true;
  replacer.join();
  EXPECT_EQ(failures, 0) << firstFailure;
}

TEST(ImageLimits, OpenExrAttributesBeyondTheFileAreRefused) {
  // The fuzzer's reproducer: a string attribute claiming 2 GB, which OpenEXR 3.1 allocated and
  // zero-filled inside OIIO::ImageInput::open.
  const fs::path reproducer = test::sourcePath("tests/stability/fuzz_regressions/image/exr_huge_string_attribute");
  test::TempDir dir;
  put(dir / "a.exr", slurp(reproducer));
  const std::string message = errorOf([&] { readImage(dir / "a.exr"); }, Error::Kind::InvalidInput);
  EXPECT_NE(message.find("attribute 'capDate' claims"), std::string::npos) << message;
  EXPECT_NE(message.find("more than the 29-byte file has after it"), std::string::npos) << message;
}

TEST(ImageLimits, OnlyTheFormatsWhoseHeadersAreCheckedAreRead) {
  test::TempDir dir;
  put(dir / "photo.exr", std::string("\xff\xd8\xff\xe0\x00\x10JFIF", 10) + junk(1000));  // a JPEG
  EXPECT_NE(errorOf([&] { readImage(dir / "photo.exr"); }, Error::Kind::Io)
                .find("not an OpenEXR, Radiance HDR, PNG or TIFF file"),
            std::string::npos);
  put(dir / "jpeg.tif", "II*" + std::string(1, '\0') + littleEndian32(8) + std::string("\x03\x00", 2) +
                            std::string("\x00\x01\x03\x00\x01\x00\x00\x00\x04\x00\x00\x00", 12) +
                            std::string("\x01\x01\x03\x00\x01\x00\x00\x00\x04\x00\x00\x00", 12) +
                            std::string("\x03\x01\x03\x00\x01\x00\x00\x00\x07\x00\x00\x00", 12) + littleEndian32(0));
  EXPECT_NE(errorOf([&] { readImage(dir / "jpeg.tif"); }, Error::Kind::InvalidInput).find("TIFF compression 7"),
            std::string::npos);
}

TEST(ImageLimits, TheMostCompressibleRealImagesStillRead) {
  // A constant PNG compresses about as far as deflate goes: its header must still pass the bound.
  test::TempDir dir;
  Image flat(1024, 1024);
  for (int y = 0; y < 1024; ++y)
    for (int x = 0; x < 1024; ++x) flat.set(x, y, Rgba(0.5, 0.5, 0.5, 1.0));
  for (const char* name : {"flat.png", "flat.exr", "flat.tif", "flat.hdr"}) {
    writeImage(flat, dir / name);
    const Image back = readImage(dir / name);
    EXPECT_EQ(back.width(), 1024) << name;
    EXPECT_NEAR(back.at(1023, 1023)[1], 0.5, 0.01) << name;
  }
}

TEST(ImageLimits, ImagesAreDecodedInStripsWithEveryRowInPlace) {
  // 1100 x 1100 float RGBA is 19 MB of samples: decoded in two strips of at most 16 MiB.
  test::TempDir dir;
  Image image(1100, 1100);
  for (int y = 0; y < 1100; ++y)
    for (int x = 0; x < 1100; ++x) image.set(x, y, Rgba(x, y, x + 1100.0 * y, 0.25));
  writeImage(image, dir / "big.exr");
  writeImage(image, dir / "big.tif");
  for (const char* name : {"big.exr", "big.tif"}) {
    const Image back = readImage(dir / name);
    for (int y = 0; y < 1100; y += 7)
      for (int x = 0; x < 1100; x += 13) {
        ASSERT_EQ(back.at(x, y)[0], x) << name;
        ASSERT_EQ(back.at(x, y)[1], y) << name;
        ASSERT_EQ(back.at(x, y)[2], static_cast<float>(x + 1100.0 * y)) << name;
      }
  }
}

Image noise(int w, int h) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image.set(x, y, Rgba(u(rng), u(rng), u(rng), 1.0));
  image.metadata = {{"brdfbake", "test"}};
  return image;
}

TEST(ImageLimits, AFullDiskIsAnErrorNamingTheImageForEveryFormat) {
  BRDFBAKE_REQUIRE_TINY_FILESYSTEM(disk, "200k");
  const Image image = noise(512, 512);  // incompressible: far more than 200 KB in every format
  for (const char* name : {"big.png", "big.exr", "big.tif", "big.hdr", "big.ktx2", "big.ktx", "big.dds"}) {
    put(disk / name, "old");
    const std::string message = errorOf([&] { writeImage(image, disk / name); }, Error::Kind::Io);
    EXPECT_EQ(message.rfind((disk / name).string() + ": ", 0), 0u) << message;
    EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
    EXPECT_EQ(slurp(disk / name), "old") << name;
    EXPECT_FALSE(fs::exists(disk / (std::string(name) + ".json"))) << name;
    EXPECT_EQ(hiddenTemporaries(disk.path()), 0) << name;
  }
}

TEST(ImageLimits, ATiledMipChainOnAFullDiskFailsInsteadOfHanging) {
  BRDFBAKE_REQUIRE_TINY_FILESYSTEM(disk, "200k");
  std::vector<Image> levels;
  for (int w = 512, h = 256; w >= 1; w /= 2, h = std::max(1, h / 2)) levels.push_back(noise(w, h));
  // With a deadline: OpenEXR's writeTiles waited for ever here. (A thread, not a child process:
  // after fork the child lacks OpenEXR's worker threads and would wait for them instead.)
  auto write = std::async(std::launch::async, [&] {
    try {
      writeTiledMipChain(levels, {{"a", 1}}, disk / "tiled.exr", "clamp,clamp");
    } catch (const Error& e) {
      return std::string(e.what()) + (e.kind() == Error::Kind::Io ? "" : " (not Io)");
    }
    return std::string("(no error)");
  });
  if (write.wait_for(std::chrono::seconds(120)) != std::future_status::ready) {
    ADD_FAILURE() << "writeTiledMipChain hung on a full disk";
    std::fflush(nullptr);
    std::_Exit(1);  // the hung thread cannot be joined
  }
  const std::string message = write.get();
  EXPECT_EQ(message.rfind((disk / "tiled.exr").string() + ": ", 0), 0u) << message;
  EXPECT_NE(message.find("No space left on device (disk full)"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(disk / "tiled.exr"));
  EXPECT_EQ(hiddenTemporaries(disk.path()), 0);
}

TEST(ImageLimits, ASidecarThatCannotBeWrittenIsNamedByItsImage) {
  test::TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "m.hdr.json").c_str(), 0600), 0);  // Radiance HDR drops metadata: a sidecar is needed
  const std::string message = errorOf([&] { writeImage(noise(4, 4), dir / "m.hdr"); }, Error::Kind::Io);
  EXPECT_EQ(message.rfind((dir / "m.hdr").string() + ": cannot write its metadata sidecar: ", 0), 0u) << message;
  EXPECT_NE(message.find("is a FIFO"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(dir / "m.hdr"));
}

// A sidecar (X.dds.json, X.hdr.json) over the JSON limit is refused before it is read, for every format
// that keeps its metadata beside it: a 1,000 MB sparse sidecar once took 2 GB to read and refuse.
TEST(ImageLimits, AnOversizeSidecarIsRefusedBeforeItIsRead) {
  test::TempDir dir;
  for (const char* name : {"m.hdr", "m.dds"}) {
    writeImage(noise(4, 4), dir / name);
    const fs::path sidecar = metadataSidecarPath(dir / name);
    ASSERT_TRUE(fs::exists(sidecar)) << name;
    fs::resize_file(sidecar, std::uintmax_t{1000} << 20);  // sparse: no disk, but 1,000 MB to read
    const std::string message = errorOf([&] { readImage(dir / name); }, Error::Kind::Resource);
    EXPECT_NE(message.find(sidecar.string()), std::string::npos) << message;
    EXPECT_NE(message.find("more than the 16777216 bytes accepted for a metadata sidecar"), std::string::npos)
        << message;
  }
}

TEST(ImageLimits, ALinkAtTheOutputIsNeitherFollowedNorReplaced) {
  test::TempDir dir;
  put(dir / "victim.exr", "keep");
  fs::create_symlink(dir / "victim.exr", dir / "out.exr");
  EXPECT_NE(errorOf([&] { writeImage(noise(4, 4), dir / "out.exr"); }, Error::Kind::Io).find("is a symbolic link"),
            std::string::npos);
  EXPECT_EQ(slurp(dir / "victim.exr"), "keep");
  EXPECT_TRUE(fs::is_symlink(dir / "out.exr"));
}

}  // namespace
}  // namespace brdfbake
