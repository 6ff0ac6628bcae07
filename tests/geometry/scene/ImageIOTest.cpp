#include <geometry/core/Error.h>
#include <geometry/scene/ImageIO.h>

#include "TestFiles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

namespace {

namespace fs = std::filesystem;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// A fresh directory per test, removed afterwards; nothing generated lands in the source tree.
class ImageIOTest : public testutil::TempDirTest {
protected:
    ImageIOTest() : TempDirTest("imageio") {}
    fs::path file(const std::string& name) const { return mDir / name; }
    void writeBytes(const std::string& name, const std::string& bytes) const {
        std::ofstream(file(name), std::ios::binary) << bytes;
    }
    std::string readBytes(const std::string& name) const {
        std::ifstream in(file(name), std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    std::string expectInputError(const std::string& name) const {
        try {
            geometry::readPfm(file(name));
        } catch (const geometry::InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(name), std::string::npos) << "message should name the file: " << msg;
            return msg;
        }
        ADD_FAILURE() << name << ": expected InputError";
        return {};
    }
};

std::string floatBytes(std::initializer_list<float> values) {
    std::string s;
    for (float f : values)
        s.append(reinterpret_cast<const char*>(&f), sizeof f);
    return s;
}

TEST_F(ImageIOTest, PfmRoundTripOneChannelWithNaN) {
    geometry::FloatImage img;
    img.width = 3;
    img.height = 2;
    img.channels = 1;
    img.data = {0.0f, 0.25f, kNaN, 1.0f, -kInf, 1e-30f};
    geometry::writePfm(file("v.pfm"), img);
    const geometry::FloatImage back = geometry::readPfm(file("v.pfm"));
    EXPECT_EQ(back.width, 3);
    EXPECT_EQ(back.height, 2);
    EXPECT_EQ(back.channels, 1);
    ASSERT_EQ(back.data.size(), img.data.size());
    for (std::size_t i = 0; i < img.data.size(); ++i) {
        if (std::isnan(img.data[i])) {
            EXPECT_TRUE(std::isnan(back.data[i])) << i;
        } else {
            EXPECT_EQ(back.data[i], img.data[i]) << i;
        }
    }
}

TEST_F(ImageIOTest, PfmRoundTripThreeChannels) {
    geometry::FloatImage img;
    img.width = 2;
    img.height = 3;
    img.channels = 3;
    for (int i = 0; i < 18; ++i)
        img.data.push_back(0.5f * float(i) - 3.0f);
    img.data[7] = kNaN;
    geometry::writePfm(file("p.pfm"), img);
    const geometry::FloatImage back = geometry::readPfm(file("p.pfm"));
    EXPECT_EQ(back.channels, 3);
    ASSERT_EQ(back.data.size(), 18u);
    EXPECT_TRUE(std::isnan(back.data[7]));
    for (int i = 0; i < 18; ++i) {
        if (i != 7) {
            EXPECT_EQ(back.data[i], img.data[i]) << i;
        }
    }
    EXPECT_EQ(readBytes("p.pfm").substr(0, 3), "PF\n");
}

TEST_F(ImageIOTest, PfmFileStoresBottomRowFirstLittleEndian) {
    geometry::FloatImage img;
    img.width = 2;
    img.height = 2;
    img.channels = 1;
    img.data = {1.0f, 2.0f,  // top row
                3.0f, 4.0f}; // bottom row
    geometry::writePfm(file("rows.pfm"), img);
    const std::string bytes = readBytes("rows.pfm");
    const std::string header = "Pf\n2 2\n-1.0\n";
    ASSERT_EQ(bytes.size(), header.size() + 16);
    EXPECT_EQ(bytes.substr(0, header.size()), header);
    // Little endian per the negative scale: 3.0f is 00 00 40 40.
    EXPECT_EQ(bytes.substr(header.size(), 4), std::string("\x00\x00\x40\x40", 4));
    float values[4];
    std::memcpy(values, bytes.data() + header.size(), 16);
    const float bottomRowFirst[4] = {3.0f, 4.0f, 1.0f, 2.0f};
    for (int i = 0; i < 4; ++i)
        EXPECT_EQ(values[i], bottomRowFirst[i]) << "value " << i;
}

TEST_F(ImageIOTest, PfmReadsBigEndianAndFlipsRows) {
    // Positive scale: big-endian floats. Rows bottom to top: file row 0 = image row 1.
    std::string data;
    for (float f : {3.0f, 4.0f, 1.0f, 2.0f}) {
        unsigned char b[4];
        std::memcpy(b, &f, 4);
        data += std::string{char(b[3]), char(b[2]), char(b[1]), char(b[0])};
    }
    writeBytes("be.pfm", "Pf\n2 2\n1.0\n" + data);
    const geometry::FloatImage img = geometry::readPfm(file("be.pfm"));
    ASSERT_EQ(img.data.size(), 4u);
    const float topRowFirst[4] = {1.0f, 2.0f, 3.0f, 4.0f};
    for (int i = 0; i < 4; ++i)
        EXPECT_EQ(img.data[i], topRowFirst[i]) << "value " << i;
}

TEST_F(ImageIOTest, MalformedPfmIsInputError) {
    const std::string four = floatBytes({1, 2, 3, 4});
    writeBytes("magic.pfm", "P6\n2 2\n-1.0\n" + four);
    EXPECT_NE(expectInputError("magic.pfm").find("magic"), std::string::npos);
    writeBytes("size.pfm", "Pf\n0 2\n-1.0\n" + four);
    EXPECT_NE(expectInputError("size.pfm").find("width"), std::string::npos);
    writeBytes("size2.pfm", "Pf\n2 x\n-1.0\n" + four);
    EXPECT_NE(expectInputError("size2.pfm").find("height"), std::string::npos);
    writeBytes("neg.pfm", "Pf\n-2 2\n-1.0\n" + four);
    expectInputError("neg.pfm");
    writeBytes("trunc.pfm", "Pf\n2 2\n-1.0\n" + four.substr(0, 13));
    EXPECT_NE(expectInputError("trunc.pfm").find("truncated"), std::string::npos);
    writeBytes("scale.pfm", "Pf\n2 2\n0\n" + four);
    EXPECT_NE(expectInputError("scale.pfm").find("scale"), std::string::npos);
    writeBytes("scale2.pfm", "Pf\n2 2\nabc\n" + four);
    EXPECT_NE(expectInputError("scale2.pfm").find("scale"), std::string::npos);
    writeBytes("extra.pfm", "Pf\n2 2\n-1.0\n" + four + "junk");
    expectInputError("extra.pfm");
    writeBytes("empty.pfm", "");
    expectInputError("empty.pfm");
    // Missing file: the message names the path.
    expectInputError("does-not-exist.pfm");
}

TEST_F(ImageIOTest, WritePfmRejectsInconsistentImage) {
    geometry::FloatImage img;
    img.width = 2;
    img.height = 2;
    img.channels = 1;
    img.data = {1.0f, 2.0f, 3.0f};
    EXPECT_THROW(geometry::writePfm(file("bad.pfm"), img), std::runtime_error);
    img.data.push_back(4.0f);
    img.channels = 2;
    EXPECT_THROW(geometry::writePfm(file("bad.pfm"), img), std::runtime_error);
}

TEST_F(ImageIOTest, PngHasSignature) {
    const int w = 5, h = 3;
    std::vector<std::uint8_t> rgb(w * h * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i)
        rgb[i] = std::uint8_t(i * 7);
    geometry::writePng(file("a.png"), w, h, 3, rgb.data());
    std::vector<std::uint8_t> rgba(w * h * 4, 200);
    geometry::writePng(file("b.png"), w, h, 4, rgba.data());
    const std::string sig("\x89PNG\r\n\x1a\n", 8);
    for (const char* name : {"a.png", "b.png"}) {
        const std::string bytes = readBytes(name);
        ASSERT_GT(bytes.size(), 8u) << name;
        EXPECT_EQ(bytes.substr(0, 8), sig) << name;
        // IHDR follows the signature and carries the size, big endian.
        EXPECT_EQ(bytes.substr(12, 4), "IHDR");
        EXPECT_EQ(std::uint8_t(bytes[19]), w);
        EXPECT_EQ(std::uint8_t(bytes[23]), h);
    }
}

TEST_F(ImageIOTest, PngErrors) {
    std::vector<std::uint8_t> px(12, 0);
    EXPECT_THROW(geometry::writePng(file("c.png"), 2, 2, 5, px.data()), std::runtime_error);
    EXPECT_THROW(geometry::writePng(mDir / "no-such-dir" / "d.png", 2, 2, 3, px.data()),
                 std::runtime_error);
}

TEST_F(ImageIOTest, PngRoundTripsAsRgba) {
    const int w = 7, h = 4;
    std::vector<std::uint8_t> rgb(w * h * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i)
        rgb[i] = std::uint8_t(i * 13 + 1);
    geometry::writePng(file("rgb.png"), w, h, 3, rgb.data());
    const geometry::Rgba8Image img = geometry::readPng(file("rgb.png"));
    ASSERT_EQ(img.width, w);
    ASSERT_EQ(img.height, h);
    ASSERT_EQ(img.rgba.size(), std::size_t(w * h * 4));
    for (int i = 0; i < w * h; ++i) {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(img.rgba[4 * i + c], rgb[3 * i + c]) << i;
        EXPECT_EQ(img.rgba[4 * i + 3], 255);
    }
}

TEST_F(ImageIOTest, UnreadablePngIsInputError) {
    writeBytes("bad.png", "\x89PNG\r\n\x1a\nnot really");
    EXPECT_THROW(geometry::readPng(file("bad.png")), geometry::InputError);
    EXPECT_THROW(geometry::readPng(file("missing.png")), geometry::InputError);
}

} // namespace
