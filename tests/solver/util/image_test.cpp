// PNG and EXR files round-trip through OpenImageIO; writes are atomic.
#include "solver/util/image.h"

#include <cstdint>
#include <filesystem>
#include <string>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "tests/test_files.h"

namespace bumprad {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  return test::fresh_temp_dir("image");
}

Image gradient() {
  Image img(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) img.set(x, y, Rgb(x / 15.0, y / 7.0, 0.25));
  return img;
}

TEST(Image, ExrKeepsLinearRadianceToHalfPrecision) {
  fs::path p = temp_dir() / "g.exr";
  write_image(p, gradient(), /*exposure ignored for EXR*/ 4.0);
  Image back = read_image(p);
  ASSERT_EQ(back.width, 16);
  ASSERT_EQ(back.height, 8);
  for (std::size_t i = 0; i < back.rgb.size(); ++i)
    EXPECT_NEAR(back.rgb[i], gradient().rgb[i], 1e-3);
}

TEST(Image, PngAppliesExposureAndSrgb) {
  fs::path p = temp_dir() / "g.png";
  write_image(p, gradient(), 0.5);
  Image back = read_image(p);
  for (std::size_t i = 0; i < back.rgb.size(); ++i)
    EXPECT_NEAR(back.rgb[i], 0.5 * gradient().rgb[i], 0.01);  // 8-bit steps in sRGB
  EXPECT_NEAR(srgb_encode(0.0031308), 0.04045, 1e-5);
  EXPECT_DOUBLE_EQ(srgb_encode(2.0), 1.0);
}

TEST(Image, EncodesInMemoryTheBytesAFileWouldHold) {
  fs::path p = temp_dir() / "g.png";
  write_image(p, gradient(), 1);
  std::string png = encode_image(gradient(), ImageFormat::Png, 1);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.size(), fs::file_size(p));
  std::string exr = encode_image(gradient(), ImageFormat::Exr, 1);
  EXPECT_EQ(exr.substr(0, 4), std::string("\x76\x2f\x31\x01", 4));  // OpenEXR magic
  std::string jpeg = encode_image(gradient(), ImageFormat::Jpeg, 1);
  EXPECT_EQ(jpeg.substr(0, 3), std::string("\xff\xd8\xff", 3));  // JPEG SOI marker
  write_image(p.parent_path() / "g.jpg", gradient(), 1);
  EXPECT_NEAR(read_image(p.parent_path() / "g.jpg").at(3, 2).g, gradient().at(3, 2).g, 0.05)
      << "lossy, but close";
  EXPECT_EQ(image_format_for("A.EXR"), ImageFormat::Exr);
  EXPECT_EQ(image_format_for("a.JPEG"), ImageFormat::Jpeg);
  EXPECT_EQ(image_format_for("a.tif"), std::nullopt);
  EXPECT_EQ(mime_type(ImageFormat::Jpeg), "image/jpeg");
  EXPECT_EQ(format_name(ImageFormat::Exr), "exr");
}

// Heights and normals keep 16 bits and no curve.
TEST(Image, DataPngsKeepTheirValues) {
  const fs::path p = temp_dir() / "data.png";
  test::write_file(p, encode_data_png(gradient()));
  const Image back = read_image(p, nullptr, PixelMeaning::Data);
  ASSERT_EQ(back.width, 16);
  for (std::size_t i = 0; i < back.rgb.size(); ++i)
    EXPECT_NEAR(back.rgb[i], gradient().rgb[i], 0.5 / 65535) << i;
}

// Grey and grey + alpha files read as grey in all three channels, as stored: alpha neither
// becomes a colour nor darkens one (a normal map's or height map's alpha must not bend it).
TEST(Image, GreyFilesReadAsGreyWhateverTheirAlpha) {
  const fs::path p = temp_dir() / "ga.png";
  auto out = OIIO::ImageOutput::create(p.string());
  ASSERT_TRUE(out);
  const std::uint8_t pixels[] = {0, 255, 128, 0, 255, 64};  // grey, alpha
  ASSERT_TRUE(out->open(p.string(), OIIO::ImageSpec(3, 1, 2, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels));
  ASSERT_TRUE(out->close());
  const Image grey = read_image(p, nullptr, PixelMeaning::Data);
  for (int x = 0; x < 3; ++x) {
    EXPECT_DOUBLE_EQ(grey.at(x, 0).r, double(pixels[2 * x] / 255.f)) << x;
    EXPECT_EQ(grey.at(x, 0), Rgb(grey.at(x, 0).r)) << x;
  }
}

// The budget is checked from headers: what each image keeps adds up, and the one that would
// pass the limit, with its decoder's buffer, is refused before it is decoded.
TEST(Image, ABudgetRefusesTheImageThatWouldPassIt) {
  const fs::path p = temp_dir() / "g.png";
  write_image(p, gradient(), 1);  // 16 x 8, 8-bit RGB: keeps 1,536 bytes, 1,920 while decoding
  ImageBudget budget(0, 1536 + 1920 - 1);
  EXPECT_EQ(read_image(p, &budget).width, 16);
  EXPECT_EQ(budget.taken(), 1536u);
  try {
    read_image(p, &budget);
    FAIL() << "the second image fits no more";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("16 x 8 pixels take 2 KB to decode, over what is left of "
                                         "the 4 KB one scene's images may take (2 KB taken by the "
                                         "images before it)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(budget.taken(), 1536u);
  ImageBudget pixels(100, 0);
  EXPECT_THROW(read_image(p, &pixels), std::runtime_error);  // 128 pixels, over 100
  EXPECT_EQ(pixels.taken(), 0u);
}

TEST(Image, RefusesUnknownTypesAndLeavesNoTemporaryFiles) {
  fs::path d = temp_dir();
  EXPECT_THROW(write_image(d / "x.bmpx", gradient(), 1), std::runtime_error);
  write_image(d / "keep.png", gradient(), 1);
  auto before = fs::file_size(d / "keep.png");
  // An unwritable target directory: the old file stays whole and nothing is left behind.
  EXPECT_THROW(write_image(d / "missing" / "x.png", gradient(), 1), std::exception);
  EXPECT_EQ(fs::file_size(d / "keep.png"), before);
  int files = 0;
  for (auto& e : fs::directory_iterator(d)) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
}

}  // namespace
}  // namespace bumprad
