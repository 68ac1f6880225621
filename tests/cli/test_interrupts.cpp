// SIGINT/SIGTERM during a run, and a write that fails part-way (a file-size limit standing in
// for a full disk): the CLI stops with its own message and exit status, and leaves neither the
// output nor a temporary file behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;

#if defined(FDMSURF_CLI_PATH) && defined(FDMSURF_TEST_DATA_DIR)

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The CLI started in the background with stdout and stderr to files in `dir`.
struct Child {
    pid_t pid = -1;
    fs::path dir;
    int wait_status() {
        int status = 0;
        waitpid(pid, &status, 0);
        return status;
    }
};

// `file_size_limit` > 0: RLIMIT_FSIZE in the child, with SIGXFSZ ignored, so a write past it
// fails with EFBIG as a write to a full disk fails with ENOSPC.
Child start(const fs::path& dir, const std::vector<std::string>& args, rlim_t file_size_limit = 0) {
    Child c;
    c.dir = dir;
    c.pid = fork();
    if (c.pid == 0) {
        const std::string out = (dir / "stdout").string(), err = (dir / "stderr").string();
        if (!freopen(out.c_str(), "w", stdout) || !freopen(err.c_str(), "w", stderr)) _exit(99);
        if (file_size_limit > 0) {
            signal(SIGXFSZ, SIG_IGN);
            rlimit limit{file_size_limit, file_size_limit};
            setrlimit(RLIMIT_FSIZE, &limit);
        }
        std::vector<char*> argv;
        std::string program = FDMSURF_CLI_PATH;
        argv.push_back(program.data());
        std::vector<std::string> copy = args;
        for (std::string& a : copy) argv.push_back(a.data());
        argv.push_back(nullptr);
        execv(program.c_str(), argv.data());
        _exit(98);
    }
    return c;
}

// The files in `dir/out` (the output folder of these tests).
std::vector<std::string> outputs(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir / "out")) names.push_back(e.path().filename());
    return names;
}

class Interrupts : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("fdmsurf-interrupts-" + std::to_string(getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "out");
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

const std::string k4yvs = std::string(FDMSURF_TEST_DATA_DIR) + "/4yvs.cif.gz";

// Killed while the mesh is being written (its temporary file is there): exit 143, one line on
// stderr, and nothing left in the output folder.
TEST_F(Interrupts, SigtermWhileWritingLeavesNothing) {
    Child c = start(dir_, {k4yvs, "-o", (dir_ / "out" / "capsid.ply").string()});
    bool seen = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(600);
    while (!seen && std::chrono::steady_clock::now() < deadline) {
        for (const std::string& name : outputs(dir_))
            if (name.find(".tmp.") != std::string::npos) seen = true;
        if (!seen) {
            int status = 0;
            if (waitpid(c.pid, &status, WNOHANG) == c.pid) FAIL() << "the run ended before its write was seen: " << slurp(dir_ / "stderr");
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    }
    ASSERT_TRUE(seen);
    kill(c.pid, SIGTERM);
    const int status = c.wait_status();
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
    const std::string err = slurp(dir_ / "stderr");
    EXPECT_NE(err.find("fdmsurf: error: interrupted by SIGTERM"), std::string::npos) << err;
    EXPECT_TRUE(outputs(dir_).empty()) << outputs(dir_).front();
}

// Ctrl-C early in a long run (before any output exists): exit 130 within a second.
TEST_F(Interrupts, SigintDuringTheSurfaceStopsPromptly) {
    Child c = start(dir_, {k4yvs, "--spacing", "0.25", "-o", (dir_ / "out" / "capsid.ply").string()});
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto t0 = std::chrono::steady_clock::now();
    kill(c.pid, SIGINT);
    const int status = c.wait_status();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT) << slurp(dir_ / "stderr");
    EXPECT_LT(seconds, 1.0);
    EXPECT_NE(slurp(dir_ / "stderr").find("interrupted by SIGINT"), std::string::npos);
    EXPECT_TRUE(outputs(dir_).empty());
}

// A write that fails part-way (file-size limit, as a full disk): the output error (exit 3) with
// the reason, and neither the output nor its temporary file.
TEST_F(Interrupts, WriteFailingPartWayLeavesNothing) {
    Child c = start(dir_, {std::string(FDMSURF_TEST_DATA_DIR) + "/4hhb.pdb.gz", "-o",
                           (dir_ / "out" / "4hhb.ply").string()},
                    1 << 20);
    const int status = c.wait_status();
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 3);
    const std::string err = slurp(dir_ / "stderr");
    EXPECT_NE(err.find("cannot write"), std::string::npos) << err;
    EXPECT_NE(err.find("File too large"), std::string::npos) << err;
    EXPECT_TRUE(outputs(dir_).empty());
}

#endif

}  // namespace
