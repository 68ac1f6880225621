// Tests of the program's pictures: -o FILE.png, --image, --image-size, --view(s), --rotate,
// --background, --outline; their parsing, the files, the summary, and the errors (exit 2 for a
// bad size, 3 for an unwritable path, nothing partial left).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_program.hpp"
#include "cli/json_check.hpp"
#include "cli/options.hpp"
#include "cli/parse_check.hpp"
#include "cli/summary.hpp"
#include "fdmsurf/fdmsurf.hpp"

namespace {

namespace fs = std::filesystem;
using fdmsurf::View;
using fdmsurf::cli::CliOptions;
using fdmsurf::cli::parse_args;
using fdmsurf_cli_test::CliProgram;
using fdmsurf_cli_test::CliRun;
using fdmsurf_cli_test::contains;
using fdmsurf_cli_test::kDataDir;
using fdmsurf_cli_test::kTwoAtomsXyzr;
using fdmsurf_cli_test::lines_of;
using fdmsurf_cli_test::parse_error_with;
using fdmsurf_cli_test::parse_json;
using fdmsurf_cli_test::parse_with;

CliOptions parse_png(std::vector<std::string> extra) {
    std::vector<std::string> args{"in.pdb", "-o", "out.png"};
    args.insert(args.end(), extra.begin(), extra.end());
    return parse_args(args);
}

std::string png_error(std::vector<std::string> extra) {
    try {
        parse_png(std::move(extra));
    } catch (const fdmsurf::Error& e) {
        EXPECT_EQ(e.code(), fdmsurf::ErrorCode::InvalidArgument) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error thrown";
    return {};
}

// Distinct colours among the opaque pixels, counted by their hue (the dominant channels).
std::size_t hues(const fdmsurf::Image& im) {
    std::vector<int> seen;
    for (std::size_t i = 0; i < im.rgba.size(); i += 4) {
        const std::uint8_t* p = &im.rgba[i];
        if (p[3] != 255) continue;
        const int top = std::max({p[0], p[1], p[2]});
        if (top < 80) continue;
        const int key =
            (p[0] * 3 > top * 2) * 1 + (p[1] * 3 > top * 2) * 2 + (p[2] * 3 > top * 2) * 4;
        if (std::find(seen.begin(), seen.end(), key) == seen.end()) seen.push_back(key);
    }
    return seen.size();
}

class CliRender : public CliProgram {
protected:
    std::string crambin() const { return (fs::path(kDataDir) / "1crn.pdb").string(); }
};

}  // namespace

TEST(CliRenderOptions, PictureOptionsParse) {
    CliOptions o = parse_png({});
    EXPECT_TRUE(o.image_output);
    EXPECT_EQ(o.render.width, 1024u);
    EXPECT_EQ(o.render.height, 768u);
    EXPECT_EQ(o.views, std::vector<View>{View::Front});
    o = parse_with({"--output-format", "png"});
    EXPECT_TRUE(o.image_output);
    o = parse_args({"in.pdb", "-o", "OUT.PNG"});
    EXPECT_TRUE(o.image_output);
    EXPECT_FALSE(parse_with({}).image_output);

    o = parse_png({"--image-size", "640x480", "--views", "front,Left,top", "--rotate",
                   "10,-20.5,30", "--background", "#102030", "--outline", "--occlusion", "0",
                   "--depth-cue=0.5"});
    EXPECT_EQ(o.render.width, 640u);
    EXPECT_EQ(o.render.height, 480u);
    EXPECT_EQ(o.views, (std::vector<View>{View::Front, View::Left, View::Top}));
    EXPECT_EQ(o.render.rotate, (std::array<float, 3>{10.0f, -20.5f, 30.0f}));
    EXPECT_EQ(o.render.background, (std::array<std::uint8_t, 4>{0x10, 0x20, 0x30, 255}));
    EXPECT_TRUE(o.render.outline);
    EXPECT_EQ(o.render.ambient_occlusion, 0.0f);
    EXPECT_EQ(o.render.depth_cue, 0.5f);
    EXPECT_EQ(parse_png({"--image-size", "1X2"}).render.height, 2u);
    EXPECT_EQ(parse_png({"--background", "transparent"}).render.background[3], 0);
    EXPECT_EQ(parse_png({"--view", "back"}).views, std::vector<View>{View::Back});

    o = parse_with({"--image", "pic.png"});
    EXPECT_FALSE(o.image_output);
    EXPECT_EQ(o.image, "pic.png");
    EXPECT_EQ(fdmsurf::cli::image_for(o, "in.pdb", 1), "pic.png");
}

TEST(CliRenderOptions, BadPictureOptionsAreClearErrors) {
    for (const char* size :
         {"0x10", "10x0", "abc", "640", "640x", "x480", "-1x5", "1.5x2", "99999999999x1"})
        EXPECT_TRUE(contains(png_error({"--image-size", size}), "WIDTHxHEIGHT"))
            << size << ": " << png_error({"--image-size", size});
    EXPECT_TRUE(contains(png_error({"--view", "diagonal"}), "front, back, left, right"));
    EXPECT_TRUE(contains(png_error({"--views", "front,front"}), "listed twice"));
    EXPECT_TRUE(contains(png_error({"--rotate", "10,20"}), "X,Y,Z"));
    EXPECT_TRUE(contains(png_error({"--rotate", "10,a,20"}), "not a number"));
    EXPECT_TRUE(contains(png_error({"--background", "blue"}), "#RRGGBB"));
    EXPECT_TRUE(contains(png_error({"--occlusion", "2"}), "[0, 1]"));
    EXPECT_TRUE(contains(png_error({"--image", "b.png"}), "already writes the picture"));
    // Picture options without a picture are mistakes.
    EXPECT_TRUE(contains(parse_error_with({"--outline"}), "--outline sets up a picture"));
    EXPECT_TRUE(contains(parse_error_with({"--view", "top"}), "-o FILE.png or --image"));
    EXPECT_TRUE(contains(parse_error_with({"--image", "pic.jpg"}), ".png file or a folder"));
    EXPECT_TRUE(contains(parse_error_with({"--image", "-"}), "--output-format png"));
    EXPECT_TRUE(contains(png_error({"-o", "-", "--output-format", "png", "--views", "front,back"}),
                         "one --view"));
    try {
        parse_args({"a.pdb", "b.pdb", "-o", "out/", "--image", "x.png"});
        ADD_FAILURE() << "no error thrown";
    } catch (const fdmsurf::Error& e) {
        EXPECT_TRUE(contains(e.what(), "--image to name a folder")) << e.what();
    }
}

TEST(CliRenderOptions, FileNamesOfViewsAndFolders) {
    using fdmsurf::cli::view_paths;
    EXPECT_EQ(view_paths("out/1crn.png", {View::Front}), std::vector<std::string>{"out/1crn.png"});
    EXPECT_EQ(view_paths("out/1crn.png", {View::Front, View::Top}),
              (std::vector<std::string>{"out/1crn-front.png", "out/1crn-top.png"}));
    const CliOptions o = parse_args({"a.pdb.gz", "b.cif", "-o", "pics/", "--output-format", "png"});
    EXPECT_EQ(fdmsurf::cli::primary_output(o, "a.pdb.gz", 1), "pics/a.png");
    EXPECT_EQ(fdmsurf::cli::primary_output(o, "b.cif", 1), "pics/b.png");
    const CliOptions m = parse_args({"a.pdb", "-o", "meshes/", "--image", "pics/"});
    EXPECT_EQ(fdmsurf::cli::primary_output(m, "a.pdb", 1), "meshes/a.ply");
    EXPECT_EQ(fdmsurf::cli::image_for(m, "a.pdb", 1), "pics/a.png");
    EXPECT_TRUE(fdmsurf::cli::is_png_path("X.PnG"));
    EXPECT_FALSE(fdmsurf::cli::is_png_path("x.png.gz"));
}

TEST(CliRenderSummary, PicturesAndTheDeviceMeshInTextAndJson) {
    fdmsurf::cli::RunReport r;
    r.version = "0.1.0";
    r.input = "in.pdb";
    r.output = "out.png";
    r.output_format = "png";
    r.mesh_on_host = false;
    r.stats.vertices = 1234;
    r.stats.triangles = 2460;
    fdmsurf::cli::ImageReport im;
    im.path = "out.png";
    im.view = "left";
    im.rotate = {0.0f, 30.0f, 0.0f};
    im.width = 640;
    im.height = 480;
    im.pixel_size = 0.125f;
    im.supersample = 2;
    r.images.push_back(im);
    r.times = {{"render-scene", 12.5, true}, {"png", 3.0, false}};
    const std::string text = fdmsurf::cli::text_summary(r);
    EXPECT_TRUE(contains(text, "1,234 vertices, 2,460 triangles, drawn from the device")) << text;
    EXPECT_FALSE(contains(text, "\n  area ")) << text;
    EXPECT_TRUE(contains(text,
                         "image        out.png (640 x 480, left view turned 0,30,0°, "
                         "0.125 Å/pixel)"))
        << text;
    EXPECT_TRUE(contains(text, "render-scene 12.5 (gpu)")) << text;
    const auto json = parse_json(fdmsurf::cli::json_summary(r));
    ASSERT_TRUE(json);
    EXPECT_FALSE(json->find("mesh_on_host")->boolean);
    for (const char* key : {"area", "volume", "pieces", "closed_manifold", "boundary_edges"})
        EXPECT_EQ(json->find(key)->type, fdmsurf_cli_test::JsonValue::Type::Null) << key;
    EXPECT_EQ(json->find("vertices")->number, 1234);
    const auto& images = json->find("images")->array;
    ASSERT_EQ(images.size(), 1u);
    EXPECT_EQ(images[0].find("view")->string, "left");
    EXPECT_EQ(images[0].find("rotate")->array.at(1).number, 30.0);
    EXPECT_EQ(images[0].find("height")->number, 480);
    EXPECT_EQ(images[0].find("pixel_size")->number, 0.125);
    EXPECT_EQ(images[0].find("supersample")->number, 2);
    // A mesh run has no images and its statistics.
    fdmsurf::cli::RunReport m;
    m.stats.area = 12.5;
    const auto mesh = parse_json(fdmsurf::cli::json_summary(m));
    ASSERT_TRUE(mesh);
    EXPECT_TRUE(mesh->find("mesh_on_host")->boolean);
    EXPECT_EQ(mesh->find("area")->number, 12.5);
    EXPECT_TRUE(mesh->find("images")->array.empty());
}

// -o FILE.png: the surface drawn on the device; the PNG, the summary without area, the times.
TEST_F(CliRender, PictureOnlyRunWritesThePngAndReportsIt) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    CliRun r = run({crambin(), "-o", path("1crn.png"), "--image-size", "320x240", "--stats", "json",
                    "--validation"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const fdmsurf::Image im = fdmsurf::read_png(path("1crn.png"));
    EXPECT_EQ(im.width, 320u);
    EXPECT_EQ(im.height, 240u);
    EXPECT_TRUE(im.opaque());
    const auto json = parse_json(lines_of(r.out).at(0));
    ASSERT_TRUE(json) << r.out;
    EXPECT_EQ(json->find("output_format")->string, "png");
    EXPECT_FALSE(json->find("mesh_on_host")->boolean);
    EXPECT_EQ(json->find("area")->type, fdmsurf_cli_test::JsonValue::Type::Null);
    EXPECT_GT(json->find("triangles")->number, 20000);
    const auto* images = json->find("images");
    ASSERT_TRUE(images && images->array.size() == 1);
    EXPECT_EQ(images->array[0].find("path")->string, path("1crn.png"));
    EXPECT_EQ(images->array[0].find("view")->string, "front");
    EXPECT_EQ(images->array[0].find("width")->number, 320);
    EXPECT_GT(images->array[0].find("pixel_size")->number, 0.05);
    const auto* times = json->find("times");
    for (const char* stage : {"render-scene", "render-shade", "render-read", "png", "density"})
        EXPECT_TRUE(times->find(stage)) << stage;
    EXPECT_FALSE(times->find("write"));
    EXPECT_EQ(stray_files(), std::vector<std::string>{"1crn.png"});

    r = run({crambin(), "-o", path("1crn.png"), "--image-size", "64x48"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "drawn from the device (pieces, area and volume are not computed")) << r.out;
    EXPECT_TRUE(contains(r.out, "image        " + path("1crn.png") + " (64 x 48, front view"))
        << r.out;
    EXPECT_TRUE(contains(r.out, "render-scene")) << r.out;
}

// --image beside a mesh, several views, colours by chain on screen.
TEST_F(CliRender, ImageBesideTheMeshWithViews) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = (fs::path(kDataDir) / "3al1.pdb").string();
    CliRun r = run({input, "-o", path("3al1.ply"), "--image", path("3al1.png"), "--views",
                    "front,right", "--image-size", "200x150", "--color", "chain", "--outline",
                    "--background", "transparent", "--stats", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto json = parse_json(lines_of(r.out).at(0));
    ASSERT_TRUE(json) << r.out;
    EXPECT_TRUE(json->find("mesh_on_host")->boolean);
    EXPECT_GT(json->find("area")->number, 1000.0);
    EXPECT_EQ(json->find("images")->array.size(), 2u);
    EXPECT_TRUE(json->find("times")->find("upload-mesh"));
    EXPECT_TRUE(fdmsurf::read_mesh(path("3al1.ply")).triangle_count() > 0);
    for (const char* name : {"3al1-front.png", "3al1-right.png"}) {
        const fdmsurf::Image im = fdmsurf::read_png(path(name));
        EXPECT_EQ(im.width, 200u);
        EXPECT_FALSE(im.opaque()) << name << ": a transparent background";
        EXPECT_GE(hues(im), 2u) << name << ": two chains, two colours";
    }
    // The device path colours the same way.
    r = run({input, "-o", path("dev.png"), "--image-size", "200x150", "--color", "chain"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_GE(hues(fdmsurf::read_png(path("dev.png"))), 2u);
    // With --patch, --simplify or coulombic colours, the mesh is made on the host, then drawn.
    r = run({input, "-o", path("patch.png"), "--patch", "A", "--image-size", "100x100", "--stats",
             "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto patch = parse_json(lines_of(r.out).at(0));
    ASSERT_TRUE(patch) << r.out;
    EXPECT_TRUE(patch->find("mesh_on_host")->boolean);
    EXPECT_FALSE(patch->find("closed_manifold")->boolean);
}

// -o - --output-format png: the PNG on stdout, the summary on stderr.
TEST_F(CliRender, PictureOnStandardOutput) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    const CliRun r = run({input, "-o", "-", "--output-format", "png", "--image-size", "40x30"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.out.starts_with("\x89PNG\r\n\x1a\n"));
    EXPECT_TRUE(contains(r.err, "image        - (40 x 30")) << r.err;
}

// Exit 2 for sizes the device cannot hold or that are not sizes, 3 for an unwritable path;
// nothing written in either case.
TEST_F(CliRender, BadSizesAndPathsFailBeforeAnythingIsWritten) {
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    expect_failure(run({input, "-o", path("a.png"), "--image-size", "0x10"}), 2,
                   {"--image-size", "WIDTHxHEIGHT", "0x10"});
    expect_failure(run({input, "-o", path("a.png"), "--image-size", "640by480"}), 2,
                   {"WIDTHxHEIGHT"});
    expect_failure(run({input, "-o", path("missing") + "/a.png"}), 3,
                   {"missing", "does not exist"});
    expect_failure(run({input, "-o", path("m.ply"), "--image", path("missing") + "/a.png"}), 3,
                   {"missing"});
    FDMSURF_REQUIRE_CLI_DEVICE();
    expect_failure(run({input, "-o", path("a.png"), "--image-size", "100000x10"}), 2,
                   {"100000 x 10", "maxImageDimension2D"});
    expect_failure(
        run({input, "-o", path("m.ply"), "--image", path("a.png"), "--image-size", "10x100000"}), 2,
        {"maxImageDimension2D"});
}

// A picture whose targets do not fit the device's memory is refused before any is allocated
// (16384² took 8 GB of lavapipe's host memory and 48 s, then was written); supersampling is
// dropped first where that alone makes it fit.
TEST_F(CliRender, PicturesLargerThanTheDevicesMemoryAreRefusedFirst) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    std::uint64_t memory = 0;
    for (const fdmsurf::DeviceInfo& d : fdmsurf::list_devices())
        if (d.usable) memory = std::max(memory, d.device_memory);
    if (memory == 0 || memory >= (std::uint64_t(5) << 30))
        GTEST_SKIP() << "a device with 5 GiB or more would draw the picture";
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    const CliRun r = run({input, "-o", path("big.png"), "--image-size", "16384x16384"});
    if (contains(r.err, "maxImageDimension2D")) GTEST_SKIP() << "16384 exceeds the device's";
    expect_failure(r, 4, {"16384 x 16384 picture needs 5.00 GiB of device memory", "--image-size"});
    EXPECT_FALSE(fs::exists(path("big.png")));
    // 6400²: 2 samples per axis would need 2.13 GiB (12 bytes a sample, 8 a pixel); one fits
    // (0.76 GiB).
    const std::uint64_t pixels = 6400ull * 6400ull;
    if (memory < pixels * 20 || memory >= pixels * 56)
        GTEST_SKIP() << "the device's memory is outside 0.76-2.13 GiB";
    const CliRun mid = run({input, "-o", path("mid.png"), "--image-size", "6400x6400", "--stats",
                            "json", "--occlusion", "0"});
    ASSERT_EQ(mid.exit_code, 0) << mid.err;
    const auto json = parse_json(mid.out);
    ASSERT_TRUE(json) << mid.out;
    EXPECT_EQ(json->find("images")->array.at(0).find("supersample")->number, 1);
}
