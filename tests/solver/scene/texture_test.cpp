// Bilinear image sampling with wrap modes, checker textures, and their means.
#include "solver/scene/texture.h"

#include <gtest/gtest.h>

namespace bumprad {
namespace {

Image ramp() {  // 4 x 2, red = column index, green = row index
  Image img(4, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) img.set(x, y, Rgb(x, y, 1));
  return img;
}

TEST(Texture, BilinearAtAndBetweenTexelCentres) {
  Image img = ramp();
  EXPECT_EQ(sample_image(img, {0.125, 0.25}, Wrap::Clamp), Rgb(0, 0, 1));  // texel (0,0)
  EXPECT_EQ(sample_image(img, {0.625, 0.75}, Wrap::Clamp), Rgb(2, 1, 1));  // texel (2,1)
  Rgb mid = sample_image(img, {0.5, 0.5}, Wrap::Clamp);                    // between 4 texels
  EXPECT_DOUBLE_EQ(mid.r, 1.5);
  EXPECT_DOUBLE_EQ(mid.g, 0.5);
}

TEST(Texture, WrapModesAtTheEdge) {
  Image img = ramp();
  // Half a texel left of the first column's centre: halfway to the texel at index -1.
  EXPECT_DOUBLE_EQ(sample_image(img, {0.0, 0.25}, Wrap::Clamp).r, 0.0);   // -1 -> 0
  EXPECT_DOUBLE_EQ(sample_image(img, {0.0, 0.25}, Wrap::Repeat).r, 1.5);  // -1 -> 3
  EXPECT_DOUBLE_EQ(sample_image(img, {0.0, 0.25}, Wrap::Mirror).r, 0.0);  // -1 -> 0
  EXPECT_DOUBLE_EQ(sample_image(img, {1.125, 0.25}, Wrap::Repeat).r, 0.0);
  EXPECT_DOUBLE_EQ(sample_image(img, {1.125, 0.25}, Wrap::Mirror).r, 3.0);  // 4 -> 3
}

TEST(Texture, CheckerAlternatesAndItsMeanIsTheAverage) {
  ColorTexture t;
  t.colors = {Rgb(0.2), Rgb(0.6)};
  t.scale = {4, 4};
  EXPECT_EQ(texture_reflectance(t, {0.1, 0.1}), Rgb(0.2));
  EXPECT_EQ(texture_reflectance(t, {0.3, 0.1}), Rgb(0.6));
  EXPECT_EQ(texture_reflectance(t, {0.3, 0.3}), Rgb(0.2));
  EXPECT_EQ(texture_mean(t), Rgb(0.4));
  t.kind = ColorTexture::Kind::Image;
  t.image = std::make_shared<Image>(ramp());
  EXPECT_EQ(texture_mean(t), Rgb(1.5, 0.5, 1));
}

}  // namespace
}  // namespace bumprad
