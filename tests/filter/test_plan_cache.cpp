// The on-disk VkFFT plan cache: round trip, and every kind of bad entry is a miss, never a crash.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fdmsurf/fdmsurf.hpp"
#include "filter/plan_cache.hpp"

namespace fs = std::filesystem;
using fdmsurf::detail::PlanCache;

namespace {

fs::path fresh_dir(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / ("fdmsurf-plan-cache-" + name + "-" +
                                                std::to_string(::getpid()));
    fs::remove_all(dir);
    return dir;
}

std::vector<char> bytes_of(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const fs::path& p, const std::vector<char>& b) {
    std::ofstream(p, std::ios::binary | std::ios::trunc).write(b.data(), std::streamsize(b.size()));
}

}  // namespace

TEST(PlanCache, StoresAndLoadsByKey) {
    const fs::path dir = fresh_dir("roundtrip");
    PlanCache cache(dir.string());
    const std::vector<std::uint32_t> words = {0x07230203u, 1u, 2u, 3u, 0xdeadbeefu};
    EXPECT_FALSE(cache.load("a").has_value());
    cache.store("a", words.data(), words.size() * 4);
    auto got = cache.load("a");
    ASSERT_TRUE(got.has_value());
    EXPECT_EQ(*got, words);
    EXPECT_FALSE(cache.load("b").has_value());
    fs::remove_all(dir);
}

TEST(PlanCache, DamagedEntriesAreMisses) {
    const fs::path dir = fresh_dir("damaged");
    PlanCache cache(dir.string());
    const std::vector<std::uint32_t> words(1000, 0x12345678u);
    cache.store("key", words.data(), words.size() * 4);
    const fs::path entry = cache.path_for("key");
    const std::vector<char> good = bytes_of(entry);
    ASSERT_FALSE(good.empty());

    std::vector<char> flipped = good;
    flipped[good.size() / 2] ^= 0x40;  // a payload bit
    write_bytes(entry, flipped);
    EXPECT_FALSE(cache.load("key").has_value());

    write_bytes(entry, std::vector<char>(good.begin(), good.begin() + long(good.size()) / 3));
    EXPECT_FALSE(cache.load("key").has_value());  // truncated

    write_bytes(entry, {});
    EXPECT_FALSE(cache.load("key").has_value());  // empty

    std::vector<char> magic = good;
    magic[0] = 'X';
    write_bytes(entry, magic);
    EXPECT_FALSE(cache.load("key").has_value());

    cache.store("key", words.data(), words.size() * 4);  // rewritten over the bad one
    EXPECT_TRUE(cache.load("key").has_value());
    fs::remove_all(dir);
}

TEST(PlanCache, EmptyDirectoryDisablesIt) {
    PlanCache cache("");
    const std::uint32_t w = 1;
    cache.store("k", &w, 4);
    EXPECT_FALSE(cache.load("k").has_value());
}
