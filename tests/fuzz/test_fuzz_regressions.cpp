// Every input that once broke a fuzz target (tests/fuzz/regressions/fuzz_NAME-WHAT), replayed
// through the same target (fuzz_targets.hpp) in the ordinary suite: it must be read or refused
// with an fdmsurf::Error, and what is read must pass the target's checks (a failed check
// aborts, which fails this test).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz_targets.hpp"

namespace {

namespace fs = std::filesystem;

TEST(FuzzRegressions, EveryInputIsReadOrRefused) {
    const fs::path dir = fs::path(FDMSURF_TEST_DATA_DIR).parent_path() / "fuzz" / "regressions";
    std::vector<fs::path> inputs;
    for (const auto& entry : fs::directory_iterator(dir)) inputs.push_back(entry.path());
    std::sort(inputs.begin(), inputs.end());
    ASSERT_FALSE(inputs.empty()) << dir;
    for (const fs::path& input : inputs) {
        const std::string name = input.filename().string();
        ASSERT_EQ(name.rfind("fuzz_", 0), 0u) << name << ": regression inputs are fuzz_NAME-WHAT";
        const std::string target = name.substr(5, name.find('-') - 5);
        std::ifstream in(input, std::ios::binary);
        const std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
        SCOPED_TRACE(name);
        EXPECT_TRUE(fdmsurf::fuzz::run_target(
            target, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()))
            << "no fuzz target " << target;
    }
}

}  // namespace
