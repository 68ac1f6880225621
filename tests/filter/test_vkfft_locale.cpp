// VkFFT writes its kernels' GLSL under the "C" locale; in a process whose locale is not "C" (the
// Python interpreter sets the user's), VkFFT 1.2.26 alone restored the caller's locale from a
// string that glibc had freed (a heap-use-after-free, found by AddressSanitizer in the Python
// module's tests; src/filter/spectral_filter.cpp, CLocaleForVkFFT). The sanitized suite runs this
// test under AddressSanitizer; in any build, the caller's locale must be back, exactly, after a
// plan is made, and the surface must be the one made under "C".
#include <gtest/gtest.h>

#include <clocale>
#include <cstdlib>
#include <memory>
#include <string>

#include "fdmsurf/fdmsurf.hpp"
#include "support/gpu_fixture.hpp"

namespace {

// Puts the locale and FDMSURF_CACHE_DIR back as they were, whatever the test's outcome.
class RestoreLocaleAndCache {
public:
    RestoreLocaleAndCache() : locale_(std::setlocale(LC_ALL, nullptr)) {
        if (const char* v = std::getenv("FDMSURF_CACHE_DIR")) cache_ = v, had_cache_ = true;
    }
    ~RestoreLocaleAndCache() {
        std::setlocale(LC_ALL, locale_.c_str());
        if (had_cache_)
            setenv("FDMSURF_CACHE_DIR", cache_.c_str(), 1);
        else
            unsetenv("FDMSURF_CACHE_DIR");
    }

private:
    std::string locale_, cache_;
    bool had_cache_ = false;
};

}  // namespace

TEST(VkFFTLocale, APlanMadeUnderAnotherLocaleLeavesItAsItWasAndTheSurfaceTheSame) {
    const RestoreLocaleAndCache restore;
    ASSERT_NE(std::setlocale(LC_ALL, "C"), nullptr);
    // No plan cache: a plan read from it skips VkFFT's code generation, where the locale changes.
    ASSERT_EQ(setenv("FDMSURF_CACHE_DIR", "off", 1), 0);
    const fdmsurf::Structure s = fdmsurf::read_structure(FDMSURF_TEST_DATA_DIR "/1crn.pdb");
    fdmsurf::SurfaceOptions options;
    options.spacing = 0.9f;

    const fdmsurf::EngineOptions validating{.validation = true};
    std::string why;
    std::unique_ptr<fdmsurf::Engine> in_c = fdmsurf_test::own_engine(validating, why);
    if (!in_c) GTEST_SKIP() << why;
    ASSERT_STREQ(std::setlocale(LC_ALL, nullptr), "C");
    const fdmsurf::SurfaceResult reference = in_c->make_surface(s.atoms, options);
    EXPECT_STREQ(std::setlocale(LC_ALL, nullptr), "C");
    EXPECT_TRUE(in_c->take_validation_messages().empty());
    in_c.reset();

    // A locale of mixed categories, whose name glibc builds on the heap ("LC_CTYPE=C.UTF-8;...").
    ASSERT_NE(std::setlocale(LC_ALL, "C.UTF-8"), nullptr) << "Debian's libc has C.UTF-8";
    ASSERT_NE(std::setlocale(LC_NUMERIC, "C"), nullptr);
    const std::string before = std::setlocale(LC_ALL, nullptr);
    ASSERT_NE(before, "C");

    std::unique_ptr<fdmsurf::Engine> other = fdmsurf_test::own_engine(validating, why);
    ASSERT_TRUE(other);
    const fdmsurf::SurfaceResult again = other->make_surface(s.atoms, options);
    EXPECT_EQ(std::string(std::setlocale(LC_ALL, nullptr)), before);
    EXPECT_TRUE(other->take_validation_messages().empty());
    other.reset();

    ASSERT_EQ(again.grid.dims, reference.grid.dims);
    EXPECT_EQ(again.mesh.indices, reference.mesh.indices);
    EXPECT_EQ(again.mesh.positions, reference.mesh.positions);
}
