// The renderer against geometry rather than golden images: a ball's silhouette area, mirror
// views, depth order, chain colours, framing and bad options; every render under validation.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "fdmsurf/fdmsurf.hpp"
#include "render/camera.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_atoms.hpp"

namespace {

using fdmsurf::DeviceMesh;
using fdmsurf::Image;
using fdmsurf::RenderOptions;
using fdmsurf::RenderResult;

// Atoms from balls, each with its chain (for colours by chain).
fdmsurf::Atoms chained(std::initializer_list<std::pair<std::array<float, 4>, const char*>> balls) {
    fdmsurf::Atoms a;
    for (const auto& [b, chain] : balls) {
        a.xyz.insert(a.xyz.end(), {b[0], b[1], b[2]});
        a.radius.push_back(b[3]);
        a.element.push_back("C");
        fdmsurf::AtomMeta m;
        m.name = "CA";
        m.residue_name = "GLY";
        m.chain = chain;
        a.meta.push_back(m);
    }
    return a;
}

fdmsurf::SurfaceOptions vdw(float spacing = 0.25f) {
    fdmsurf::SurfaceOptions o;
    o.surface = fdmsurf::SurfaceKind::Vdw;
    o.spacing = spacing;
    return o;
}

// Plain lighting: no occlusion, no depth cue; transparent, so that alpha is the coverage.
RenderOptions plain(std::uint32_t w, std::uint32_t h) {
    RenderOptions r;
    r.width = w;
    r.height = h;
    r.ambient_occlusion = 0.0f;
    r.depth_cue = 0.0f;
    r.background = {0, 0, 0, 0};
    return r;
}

const std::uint8_t* pixel(const Image& im, std::uint32_t x, std::uint32_t y) {
    return &im.rgba[(std::size_t(y) * im.width + x) * 4];
}

// The covered area in pixels: the sum of alpha / 255.
double coverage(const Image& im) {
    double sum = 0.0;
    for (std::size_t i = 3; i < im.rgba.size(); i += 4) sum += im.rgba[i] / 255.0;
    return sum;
}

// The pixel where a point of the structure lands in a front view.
std::array<std::uint32_t, 2> front_pixel(const RenderResult& r, float x, float y) {
    const float px = (x - r.frame.center[0]) / r.pixel_size + 0.5f * float(r.image.width);
    const float py = -(y - r.frame.center[1]) / r.pixel_size + 0.5f * float(r.image.height);
    return {std::uint32_t(px), std::uint32_t(py)};
}

}  // namespace

class Render : public GpuTest {
protected:
    static void TearDownTestSuite() { renderer_.reset(); }

    // One renderer for the suite, released before the shared engine.
    static fdmsurf::Renderer& renderer() {
        if (!renderer_) renderer_ = std::make_unique<fdmsurf::Renderer>(engine());
        return *renderer_;
    }

    static inline std::unique_ptr<fdmsurf::Renderer> renderer_;
};

TEST_F(Render, BallSilhouetteAreaIsPiRSquared) {
    const float r = 5.0f;
    const fdmsurf::DeviceSurfaceResult s =
        engine().make_device_surface(fdmsurf_test::make_atoms({{1.0f, -2.0f, 3.0f, r}}), vdw());
    for (std::uint32_t ss : {1u, 2u}) {
        RenderOptions o = plain(400, 300);
        o.supersample = ss;
        const RenderResult res = renderer().render(s.mesh, o);
        ASSERT_EQ(res.image.width, 400u);
        ASSERT_EQ(res.image.rgba.size(), 400u * 300u * 4u);
        EXPECT_EQ(res.supersample, ss);
        // The framed sphere is the mesh's: centred on the ball, its radius.
        EXPECT_NEAR(res.frame.center[0], 1.0f, 0.05f);
        EXPECT_NEAR(res.frame.center[1], -2.0f, 0.05f);
        EXPECT_NEAR(res.frame.center[2], 3.0f, 0.05f);
        EXPECT_NEAR(res.frame.radius, r, 0.05f);
        // The shorter side spans the diameter plus the margins.
        EXPECT_NEAR(res.pixel_size, 2.0f * res.frame.radius * 1.06f / 300.0f, 1e-4f);
        const double expected = std::numbers::pi * r * r / (res.pixel_size * res.pixel_size);
        EXPECT_NEAR(coverage(res.image) / expected, 1.0, 0.01) << "supersample " << ss;
        // Lit from the front: the centre is bright, and brighter than near the limb.
        const auto c = front_pixel(res, 1.0f, -2.0f);
        const auto limb = front_pixel(res, 1.0f + 0.95f * r, -2.0f);
        EXPECT_EQ(pixel(res.image, c[0], c[1])[3], 255);
        EXPECT_GT(pixel(res.image, c[0], c[1])[1], 150);
        EXPECT_GT(pixel(res.image, c[0], c[1])[1], pixel(res.image, limb[0], limb[1])[1]);
        // Uniform grey when the mesh has no colours.
        const std::uint8_t* p = pixel(res.image, c[0], c[1]);
        EXPECT_NEAR(p[0], p[1], 2);
        EXPECT_NEAR(p[1], p[2], 2);
        // Nothing outside the ball.
        EXPECT_EQ(pixel(res.image, 0, 0)[3], 0);
        EXPECT_EQ(pixel(res.image, 399, 299)[3], 0);
    }
}

TEST_F(Render, FrontAndBackViewsAreMirrorImages) {
    const fdmsurf::Atoms atoms =
        chained({{{-4.0f, 0.0f, 0.0f, 3.0f}, "A"}, {{4.5f, 1.5f, 0.0f, 2.0f}, "B"}});
    fdmsurf::SurfaceOptions so = vdw();
    so.properties.color = fdmsurf::ColorScheme::Chain;
    const fdmsurf::DeviceSurfaceResult s = engine().make_device_surface(atoms, so);
    ASSERT_NE(s.mesh.attribute_buffer(), VK_NULL_HANDLE);
    RenderOptions o = plain(320, 240);
    o.frame = renderer().bounds(s.mesh);
    const RenderResult front = renderer().render(s.mesh, o);
    o.view = fdmsurf::View::Back;
    const RenderResult back = renderer().render(s.mesh, o);
    const Image& a = front.image;
    const Image& b = back.image;
    double diff = 0.0;
    for (std::uint32_t y = 0; y < a.height; ++y)
        for (std::uint32_t x = 0; x < a.width; ++x) {
            const std::uint8_t* p = pixel(a, x, y);
            const std::uint8_t* q = pixel(b, a.width - 1 - x, y);
            diff += std::abs(int(p[3]) - int(q[3])) / 255.0;
        }
    const double covered = coverage(a);
    EXPECT_GT(covered, 1000.0);
    EXPECT_NEAR(coverage(b) / covered, 1.0, 0.005);
    EXPECT_LT(diff / covered, 0.01) << "silhouettes differ by " << diff << " pixels";
    // (The shading is not mirrored: the key light stays above left of the viewer.)
    // Chain A (green) on the left of the front view, on the right of the back view.
    const auto left = front_pixel(front, -4.0f, 0.0f);
    const std::uint8_t* g = pixel(a, left[0], left[1]);
    EXPECT_GT(g[1], 2 * g[2]) << "chain A is green";
    const std::uint8_t* g2 = pixel(b, a.width - 1 - left[0], left[1]);
    EXPECT_GT(g2[1], 2 * g2[2]);
}

TEST_F(Render, NearerBallHidesFartherOne) {
    // A small ball of chain A in front of a large one of chain B, on the same axis.
    const fdmsurf::Atoms atoms =
        chained({{{0.0f, 0.0f, 6.0f, 2.5f}, "A"}, {{0.0f, 0.0f, -6.0f, 5.0f}, "B"}});
    fdmsurf::SurfaceOptions so = vdw(0.3f);
    so.properties.color = fdmsurf::ColorScheme::Chain;
    const fdmsurf::DeviceSurfaceResult s = engine().make_device_surface(atoms, so);
    RenderOptions o = plain(300, 300);
    o.frame = renderer().bounds(s.mesh);
    const RenderResult front = renderer().render(s.mesh, o);
    o.view = fdmsurf::View::Back;
    const RenderResult back = renderer().render(s.mesh, o);
    // Chain colours: A green (0x33FF33), B cyan (0x00FFFF): the blue channel tells them apart.
    const auto centre = front_pixel(front, 0.0f, 0.0f);
    const auto ring = front_pixel(front, 3.8f, 0.0f);  // outside A's silhouette, inside B's
    const std::uint8_t* c = pixel(front.image, centre[0], centre[1]);
    EXPECT_GT(c[1], 2 * c[2]) << "front: the near ball (A, green) hides B at the centre";
    const std::uint8_t* r = pixel(front.image, ring[0], ring[1]);
    EXPECT_EQ(r[3], 255);
    EXPECT_GT(r[2], r[1] / 2) << "front: B (cyan) around A";
    const std::uint8_t* cb = pixel(back.image, centre[0], centre[1]);
    EXPECT_GT(cb[2], cb[1] / 2) << "back: B (cyan) hides A";
    // Front: the silhouette is B's (the larger); A adds nothing.
    const double expected = std::numbers::pi * 25.0 / (front.pixel_size * front.pixel_size);
    EXPECT_NEAR(coverage(front.image) / expected, 1.0, 0.015);
}

TEST_F(Render, ViewsAndTurnsPutTheStructureWhereExpected) {
    // Two balls on the x axis, framed around their midpoint: centred in every view. Framed
    // around the first: the second is right of it from the front, left from the back and
    // from the front turned 180 degrees about y, in line with it turned 90 degrees.
    const fdmsurf::Atoms atoms =
        fdmsurf_test::make_atoms({{0.0f, 0.0f, 0.0f, 1.5f}, {8.0f, 0.0f, 0.0f, 1.5f}});
    const fdmsurf::DeviceSurfaceResult s = engine().make_device_surface(atoms, vdw(0.4f));
    RenderOptions o = plain(200, 200);
    o.frame = {{4.0f, 0.0f, 0.0f}, 6.0f};
    auto covered_x = [&](fdmsurf::View view, std::array<float, 3> turn) {
        o.view = view;
        o.rotate = turn;
        const RenderResult r = renderer().render(s.mesh, o);
        double sum = 0.0, weight = 0.0;
        for (std::uint32_t y = 0; y < r.image.height; ++y)
            for (std::uint32_t x = 0; x < r.image.width; ++x) {
                const double a = pixel(r.image, x, y)[3] / 255.0;
                sum += a * x;
                weight += a;
            }
        return sum / weight - 100.0;  // mean column of the coverage, from the centre
    };
    EXPECT_NEAR(covered_x(fdmsurf::View::Front, {0, 0, 0}), 0.0, 1.0);  // both balls
    EXPECT_NEAR(covered_x(fdmsurf::View::Right, {0, 0, 0}), 0.0, 1.0);
    EXPECT_NEAR(covered_x(fdmsurf::View::Left, {0, 0, 0}), 0.0, 1.0);
    EXPECT_NEAR(covered_x(fdmsurf::View::Top, {0, 0, 0}), 0.0, 1.0);
    // Moving the frame's centre to the first ball: the second one is to the right (front),
    // to the left (back).
    o.frame = {{0.0f, 0.0f, 0.0f}, 10.0f};
    EXPECT_GT(covered_x(fdmsurf::View::Front, {0, 0, 0}), 20.0);
    EXPECT_LT(covered_x(fdmsurf::View::Back, {0, 0, 0}), -20.0);
    EXPECT_LT(covered_x(fdmsurf::View::Front, {0, 180, 0}), -20.0);
    EXPECT_NEAR(covered_x(fdmsurf::View::Front, {0, 90, 0}), 0.0, 1.0);
    EXPECT_NEAR(covered_x(fdmsurf::View::Front, {90, 0, 0}),
                covered_x(fdmsurf::View::Front, {0, 0, 0}), 1.0);
}

TEST_F(Render, OcclusionDepthCueAndOutlineOnlyDarken) {
    const fdmsurf::Structure st = fdmsurf::read_structure(FDMSURF_TEST_DATA_DIR "/1crn.pdb");
    fdmsurf::SurfaceOptions so;
    so.spacing = 0.6f;
    const fdmsurf::DeviceSurfaceResult s = engine().make_device_surface(st.atoms, so);
    RenderOptions o = plain(256, 192);
    o.background = {255, 255, 255, 255};
    const RenderResult bare = renderer().render(s.mesh, o);
    EXPECT_TRUE(bare.image.opaque());
    o.ambient_occlusion = 1.0f;
    o.depth_cue = 0.5f;
    o.outline = true;
    const RenderResult shaded = renderer().render(s.mesh, o);
    double sum_bare = 0.0, sum_shaded = 0.0;
    std::size_t brighter = 0, surface = 0;
    for (std::size_t i = 0; i < bare.image.rgba.size(); i += 4) {
        const int a = bare.image.rgba[i + 1], b = shaded.image.rgba[i + 1];
        if (a == 255 && b == 255) continue;  // background
        ++surface;
        sum_bare += a;
        sum_shaded += b;
        if (b > a + 8) ++brighter;
    }
    EXPECT_GT(surface, 10000u);
    EXPECT_LT(sum_shaded, 0.9 * sum_bare);
    EXPECT_LT(brighter, surface / 100);
    // The white background stays white where nothing was drawn.
    EXPECT_EQ(pixel(shaded.image, 0, 0)[0], 255);
    EXPECT_EQ(pixel(shaded.image, 0, 0)[3], 255);
}

TEST_F(Render, UploadedMeshDrawsLikeTheDeviceSurface) {
    const fdmsurf::Structure st = fdmsurf::read_structure(FDMSURF_TEST_DATA_DIR "/3al1.pdb");
    fdmsurf::SurfaceOptions so;
    so.spacing = 0.6f;
    so.properties.color = fdmsurf::ColorScheme::Chain;
    so.min_cavity_volume = 0.0f;  // the device path keeps every piece
    const fdmsurf::DeviceSurfaceResult dev = engine().make_device_surface(st.atoms, so);
    const fdmsurf::SurfaceResult host = engine().make_surface(st.atoms, so);
    ASSERT_EQ(dev.mesh.vertex_count(), host.mesh.vertex_count());
    const DeviceMesh up = engine().upload_mesh(host.mesh);
    ASSERT_NE(up.attribute_buffer(), VK_NULL_HANDLE);
    RenderOptions o = plain(256, 256);
    const RenderResult a = renderer().render(dev.mesh, o);
    const RenderResult b = renderer().render(up, o);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.image.rgba.size(); ++i)
        if (std::abs(int(a.image.rgba[i]) - int(b.image.rgba[i])) > 2) ++differ;
    EXPECT_LT(differ, a.image.rgba.size() / 1000);
    // Two chains, two colours on screen.
    std::size_t green = 0, cyan = 0;
    for (std::size_t i = 0; i < a.image.rgba.size(); i += 4) {
        const std::uint8_t* p = &a.image.rgba[i];
        if (p[3] != 255 || p[1] < 60) continue;
        if (p[2] < p[1] / 3) ++green;
        if (p[2] > (p[1] * 3) / 4 && p[0] < p[1] / 3) ++cyan;
    }
    EXPECT_GT(green, 1000u);
    EXPECT_GT(cyan, 1000u);
}

TEST_F(Render, BackFacesAreCulledUnlessDoubleSided) {
    // One triangle, counter-clockwise seen from -z: its back faces a front view.
    fdmsurf::Mesh m;
    m.positions = {-5, -5, 0, 5, -5, 0, -5, 5, 0};
    m.indices = {0, 2, 1};
    const DeviceMesh tri = engine().upload_mesh(m);  // normals from the triangle: -z
    RenderOptions o = plain(64, 64);
    o.frame = {{0, 0, 0}, 8.0f};
    const double culled = coverage(renderer().render(tri, o).image);
    o.double_sided = true;
    const RenderResult both = renderer().render(tri, o);
    EXPECT_EQ(culled, 0.0);
    EXPECT_NEAR(coverage(both.image), 50.0 / (both.pixel_size * both.pixel_size), 40.0);
    // Seen from the back, the back side is lit as the side in view.
    const std::uint8_t* p = pixel(both.image, 20, 40);
    EXPECT_EQ(p[3], 255);
    EXPECT_GT(p[1], 120);
    o.double_sided = false;
    o.view = fdmsurf::View::Back;
    EXPECT_NEAR(coverage(renderer().render(tri, o).image) / coverage(both.image), 1.0, 0.04);
}

TEST_F(Render, EmptyMeshGivesTheBackground) {
    RenderOptions o = plain(64, 48);
    o.background = {10, 20, 30, 255};
    const RenderResult r = renderer().render(DeviceMesh{}, o);
    ASSERT_EQ(r.image.rgba.size(), 64u * 48u * 4u);
    for (std::size_t i = 0; i < r.image.rgba.size(); i += 4) {
        ASSERT_EQ(r.image.rgba[i], 10);
        ASSERT_EQ(r.image.rgba[i + 1], 20);
        ASSERT_EQ(r.image.rgba[i + 2], 30);
        ASSERT_EQ(r.image.rgba[i + 3], 255);
    }
}

TEST_F(Render, BadOptionsAreRefused) {
    auto code = [&](RenderOptions o) {
        try {
            renderer().check(o);
        } catch (const fdmsurf::Error& e) {
            return e.code();
        }
        return fdmsurf::ErrorCode::Internal;  // not refused
    };
    RenderOptions o;
    o.width = 0;
    EXPECT_EQ(code(o), fdmsurf::ErrorCode::InvalidArgument);
    o = {};
    o.height = 1u << 20;  // above any device's maxImageDimension2D
    EXPECT_EQ(code(o), fdmsurf::ErrorCode::InvalidArgument);
    o = {};
    o.supersample = 3;
    EXPECT_EQ(code(o), fdmsurf::ErrorCode::InvalidArgument);
    o = {};
    o.ambient_occlusion = 1.5f;
    EXPECT_EQ(code(o), fdmsurf::ErrorCode::InvalidArgument);
    o = {};
    o.rotate[1] = std::nanf("");
    EXPECT_EQ(code(o), fdmsurf::ErrorCode::InvalidArgument);
    EXPECT_EQ(code(RenderOptions{}), fdmsurf::ErrorCode::Internal);
    // make_device_surface refuses what needs the host mesh.
    fdmsurf::SurfaceOptions so = vdw(1.0f);
    so.properties.color = fdmsurf::ColorScheme::Coulombic;
    EXPECT_THROW(engine().make_device_surface(fdmsurf_test::make_atoms({{0, 0, 0, 2}}), so),
                 fdmsurf::Error);
}

TEST(RenderCamera, ViewsAreProperRotations) {
    using fdmsurf::View;
    for (View v : {View::Front, View::Back, View::Left, View::Right, View::Top, View::Bottom}) {
        const auto m = fdmsurf::view_rotation(v, {10.0f, -20.0f, 30.0f});
        // Orthonormal rows, determinant +1.
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const float d =
                    m[3 * i] * m[3 * j] + m[3 * i + 1] * m[3 * j + 1] + m[3 * i + 2] * m[3 * j + 2];
                EXPECT_NEAR(d, i == j ? 1.0f : 0.0f, 1e-5f);
            }
        const float det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                          m[2] * (m[3] * m[7] - m[4] * m[6]);
        EXPECT_NEAR(det, 1.0f, 1e-5f) << fdmsurf::to_string(v);
    }
    // The viewer's axis (third row) of each view: where the camera is.
    auto towards = [](View v) {
        const auto m = fdmsurf::view_rotation(v);
        return std::array<float, 3>{m[6], m[7], m[8]};
    };
    EXPECT_EQ(towards(View::Front), (std::array<float, 3>{0, 0, 1}));
    EXPECT_EQ(towards(View::Back), (std::array<float, 3>{0, 0, -1}));
    EXPECT_EQ(towards(View::Left), (std::array<float, 3>{-1, 0, 0}));
    EXPECT_EQ(towards(View::Right), (std::array<float, 3>{1, 0, 0}));
    EXPECT_EQ(towards(View::Top), (std::array<float, 3>{0, 1, 0}));
    EXPECT_EQ(towards(View::Bottom), (std::array<float, 3>{0, -1, 0}));
    // Turning the front view 90 degrees about the screen's y brings the left side (-x) towards
    // the viewer.
    const auto m = fdmsurf::view_rotation(View::Front, {0.0f, 90.0f, 0.0f});
    EXPECT_NEAR(m[6], -1.0f, 1e-6f);
}

TEST(RenderCamera, FramingFitsTheSphereInTheShorterSide) {
    const fdmsurf::detail::Framing f = fdmsurf::detail::frame_sphere({{1, 2, 3}, 10.0f}, 800, 400);
    EXPECT_NEAR(f.pixel_size, 2.0f * 10.0f * 1.06f / 400.0f, 1e-6f);
    EXPECT_NEAR(f.half_height, 10.0f * 1.06f, 1e-4f);
    EXPECT_NEAR(f.half_width, 2.0f * 10.0f * 1.06f, 1e-4f);
    // An empty mesh (radius 0) still gives a usable camera.
    EXPECT_GT(fdmsurf::detail::frame_sphere({}, 10, 10).pixel_size, 0.0f);
}
