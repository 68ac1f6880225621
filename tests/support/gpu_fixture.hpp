// Test helper: a GoogleTest fixture that shares one validating Engine across all GPU tests.
//
// The engine is created on first use (SetUpTestSuite of the first GPU suite that runs) and
// destroyed by a global test environment after the last test, so Vulkan is torn down before
// static destruction. With no usable Vulkan device the tests skip with the reason, unless the
// environment variable FDMSURF_REQUIRE_DEVICE=1 asks that they fail instead (CI has lavapipe).
// Every validation-layer message fails the test during which it was reported.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "engine/engine_impl.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/surface.hpp"

namespace fdmsurf_test {

// True when FDMSURF_REQUIRE_DEVICE=1: a missing device is then a failure, not a skip.
inline bool device_required() {
    const char* v = std::getenv("FDMSURF_REQUIRE_DEVICE");
    return v != nullptr && std::strcmp(v, "1") == 0;
}

// An engine of the test's own (fresh plans, other options than the shared one): null, with the
// reason in `why`, when there is no Vulkan device and FDMSURF_REQUIRE_DEVICE is not 1 (the test
// then skips); any other failure, or no device when one is required, throws.
inline std::unique_ptr<fdmsurf::Engine> own_engine(const fdmsurf::EngineOptions& options,
                                                   std::string& why) {
    try {
        return std::make_unique<fdmsurf::Engine>(options);
    } catch (const fdmsurf::Error& e) {
        if (e.code() != fdmsurf::ErrorCode::NoDevice || device_required()) throw;
        why = e.what();
        return nullptr;
    }
}

// Formats validation messages, one per line, for a failure message.
inline std::string join_messages(const std::vector<std::string>& messages) {
    std::string out;
    for (const std::string& m : messages) out += "\n  " + m;
    return out;
}

// The one engine of the test binary, and why there is none when creating it failed.
struct SharedGpu {
    std::unique_ptr<fdmsurf::Engine> engine;
    bool tried = false;
    bool no_device = false;  // creation threw Error(NoDevice): skip (or fail if required)
    std::string reason;      // what creation threw
    std::vector<std::string> creation_messages;  // validation messages seen while creating

    static SharedGpu& get() {
        static SharedGpu shared;
        return shared;
    }

    void create() {
        if (tried) return;
        tried = true;
        try {
            engine = std::make_unique<fdmsurf::Engine>(fdmsurf::EngineOptions{.validation = true});
            creation_messages = engine->take_validation_messages();
        } catch (const fdmsurf::Error& e) {
            no_device = e.code() == fdmsurf::ErrorCode::NoDevice;
            reason = std::string("creating the shared Engine threw Error(") +
                     fdmsurf::to_string(e.code()) + "): " + e.what();
        } catch (const std::exception& e) {
            reason = std::string("creating the shared Engine threw: ") + e.what();
        }
    }
};

// Destroys the shared engine after the last test, before static destruction.
class GpuEnvironment : public ::testing::Environment {
public:
    void TearDown() override { SharedGpu::get().engine.reset(); }
};

inline ::testing::Environment* const gpu_environment =
    ::testing::AddGlobalTestEnvironment(new GpuEnvironment);

}  // namespace fdmsurf_test

// Derive a suite from this (class Density : public GpuTest {}) and use engine() / impl().
class GpuTest : public ::testing::Test {
public:
    static void SetUpTestSuite() { fdmsurf_test::SharedGpu::get().create(); }

protected:
    void SetUp() override {
        auto& shared = fdmsurf_test::SharedGpu::get();
        shared.create();  // in case a suite overrides SetUpTestSuite
        if (!shared.engine) {
            if (shared.no_device && !fdmsurf_test::device_required()) GTEST_SKIP() << shared.reason;
            FAIL() << shared.reason
                   << (shared.no_device ? " (FDMSURF_REQUIRE_DEVICE=1 makes this a failure)" : "");
        }
        // Messages from engine creation are charged to the first test that runs.
        if (!shared.creation_messages.empty()) {
            ADD_FAILURE() << "validation messages while creating the engine:"
                          << fdmsurf_test::join_messages(shared.creation_messages);
            shared.creation_messages.clear();
        }
    }

    void TearDown() override {
        auto& shared = fdmsurf_test::SharedGpu::get();
        if (!shared.engine) return;
        const std::vector<std::string> messages = shared.engine->take_validation_messages();
        EXPECT_TRUE(messages.empty())
            << messages.size()
            << " validation message(s):" << fdmsurf_test::join_messages(messages);
    }

    static fdmsurf::Engine& engine() { return *fdmsurf_test::SharedGpu::get().engine; }
    static fdmsurf::detail::EngineImpl& impl() { return engine().impl(); }
};
