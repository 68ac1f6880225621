// PNG files: round trips through libpng, RGB for opaque images, nothing left behind on failure.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "fdmsurf/error.hpp"
#include "fdmsurf/render.hpp"

namespace {

namespace fs = std::filesystem;

fdmsurf::Image gradient(std::uint32_t w, std::uint32_t h, bool transparent) {
    fdmsurf::Image im;
    im.width = w;
    im.height = h;
    im.rgba.resize(std::size_t(w) * h * 4);
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            std::uint8_t* p = &im.rgba[(std::size_t(y) * w + x) * 4];
            p[0] = std::uint8_t(x * 7);
            p[1] = std::uint8_t(y * 13);
            p[2] = std::uint8_t((x + y) * 3);
            p[3] = transparent ? std::uint8_t((x * y) % 256) : 255;
        }
    return im;
}

class PngIo : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("fdmsurf_png_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

}  // namespace

TEST_F(PngIo, OpaqueImagesRoundTripAsRgb) {
    const fdmsurf::Image im = gradient(37, 21, false);
    const std::string path = (dir_ / "a.png").string();
    fdmsurf::write_png(im, path);
    // Colour type 2 (RGB) in the IHDR chunk: byte 25 of the file.
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 33u);
    EXPECT_EQ(bytes.substr(1, 3), "PNG");
    EXPECT_EQ(int(bytes[25]), 2);
    const fdmsurf::Image back = fdmsurf::read_png(path);
    EXPECT_EQ(back.width, 37u);
    EXPECT_EQ(back.height, 21u);
    EXPECT_EQ(back.rgba, im.rgba);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(PngIo, TransparentImagesRoundTripAsRgba) {
    const fdmsurf::Image im = gradient(16, 9, true);
    EXPECT_FALSE(im.opaque());
    const std::string path = (dir_ / "t.png").string();
    fdmsurf::write_png(im, path);
    const fdmsurf::Image back = fdmsurf::read_png(path);
    EXPECT_EQ(back.rgba, im.rgba);
}

TEST_F(PngIo, StreamGetsTheFileBytes) {
    const fdmsurf::Image im = gradient(8, 8, false);
    const std::string path = (dir_ / "s.png").string();
    fdmsurf::write_png(im, path);
    std::ostringstream out;
    fdmsurf::write_png(im, out, "a stream");
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(out.str(), bytes);
}

TEST_F(PngIo, FailuresLeaveNothingBehind) {
    const fdmsurf::Image im = gradient(4, 4, false);
    try {
        fdmsurf::write_png(im, (dir_ / "missing" / "a.png").string());
        FAIL() << "expected Error(Io)";
    } catch (const fdmsurf::Error& e) {
        EXPECT_EQ(e.code(), fdmsurf::ErrorCode::Io);
        EXPECT_NE(std::string(e.what()).find("missing/a.png"), std::string::npos) << e.what();
    }
    fdmsurf::Image bad = im;
    bad.rgba.pop_back();
    try {
        fdmsurf::write_png(bad, (dir_ / "bad.png").string());
        FAIL() << "expected Error(InvalidArgument)";
    } catch (const fdmsurf::Error& e) {
        EXPECT_EQ(e.code(), fdmsurf::ErrorCode::InvalidArgument);
    }
    EXPECT_TRUE(fs::is_empty(dir_));
    // A file that is not a PNG.
    std::ofstream(dir_ / "x.png") << "not a png";
    EXPECT_THROW(fdmsurf::read_png((dir_ / "x.png").string()), fdmsurf::Error);
    EXPECT_THROW(fdmsurf::read_png((dir_ / "none.png").string()), fdmsurf::Error);
}
