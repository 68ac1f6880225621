// SIGINT/SIGTERM during a run, a write that fails part-way (a file-size limit standing in for a
// full disk), a read-only folder, a lost device and failed allocations (FDMSURF_FAULT), and
// processes writing at once: the CLI stops with its own message
// and exit status, and leaves neither a partial output nor a temporary file behind.
#include <gtest/gtest.h>
#include <grp.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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

// How the child runs: `file_size_limit` > 0: RLIMIT_FSIZE, with SIGXFSZ ignored, so a write
// past it fails with EFBIG as a write to a full disk fails with ENOSPC; `fault`: FDMSURF_FAULT;
// `unprivileged`: as user nobody when the tests run as root (root writes into read-only
// folders); its stdout and stderr go to these files in the test's folder.
struct ChildSetup {
    rlim_t file_size_limit = 0;
    std::string fault;
    bool unprivileged = false;
    std::string stdout_name = "stdout", stderr_name = "stderr";
};

Child start(const fs::path& dir, const std::vector<std::string>& args, const ChildSetup& setup) {
    Child c;
    c.dir = dir;
    c.pid = fork();
    if (c.pid == 0) {
        const std::string out = (dir / setup.stdout_name).string();
        const std::string err = (dir / setup.stderr_name).string();
        if (!freopen(out.c_str(), "w", stdout) || !freopen(err.c_str(), "w", stderr)) _exit(99);
        if (setup.file_size_limit > 0) {
            signal(SIGXFSZ, SIG_IGN);
            rlimit limit{setup.file_size_limit, setup.file_size_limit};
            setrlimit(RLIMIT_FSIZE, &limit);
        }
        if (!setup.fault.empty()) setenv("FDMSURF_FAULT", setup.fault.c_str(), 1);
        if (setup.unprivileged && geteuid() == 0) {
            const gid_t nogroup = 65534;
            if (setgroups(1, &nogroup) != 0 || setgid(65534) != 0 || setuid(65534) != 0) _exit(97);
            setenv("HOME", "/tmp", 1);  // the shader caches of Mesa and fdmsurf go there
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

Child start(const fs::path& dir, const std::vector<std::string>& args, rlim_t file_size_limit = 0) {
    ChildSetup setup;
    setup.file_size_limit = file_size_limit;
    return start(dir, args, setup);
}

// The files in `dir/out` (the output folder of these tests).
std::vector<std::string> outputs(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir / "out")) names.push_back(e.path().filename());
    return names;
}

// The CLI run to its end with FDMSURF_FAULT=`fault`: its exit code (-1, and a failure, when a
// signal ended it) and its stderr.
struct FaultRun {
    int exit_code = -1;
    std::string err;
};

FaultRun run_with_fault(const fs::path& dir, const std::string& fault,
                        const std::vector<std::string>& args) {
    ChildSetup setup;
    setup.fault = fault;
    Child c = start(dir, args, setup);
    const int status = c.wait_status();
    FaultRun r;
    r.err = slurp(dir / "stderr");
    EXPECT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status) << ": " << r.err;
    if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
    return r;
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

// A folder the program may not write into: the output error (exit 3) naming the folder's
// refusal, and nothing in it. As root the child runs as nobody: root writes anywhere.
TEST_F(Interrupts, ReadOnlyFolderGivesTheOutputErrorAndNothing) {
    const fs::path input = dir_ / "two.xyzr";
    std::ofstream(input) << "0 0 0 1.7\n1.5 0 0 1.52\n";
    fs::permissions(input, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    fs::permissions(dir_, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                              fs::perms::others_read | fs::perms::others_exec);
    fs::permissions(dir_ / "out", fs::perms::owner_read | fs::perms::owner_exec |
                                      fs::perms::group_read | fs::perms::group_exec |
                                      fs::perms::others_read | fs::perms::others_exec);
    ChildSetup setup;
    setup.unprivileged = true;
    // The child's stdout and stderr are opened before it drops its privileges.
    Child c = start(dir_, {input.string(), "-o", (dir_ / "out" / "two.ply").string()}, setup);
    const int status = c.wait_status();
    fs::permissions(dir_ / "out", fs::perms::owner_all);
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    const std::string err = slurp(dir_ / "stderr");
    EXPECT_EQ(WEXITSTATUS(status), 3) << err;
    EXPECT_NE(err.find("Permission denied"), std::string::npos) << err;
    EXPECT_NE(err.find((dir_ / "out").string()), std::string::npos) << err;
    EXPECT_TRUE(outputs(dir_).empty());
}

// A lost device (FDMSURF_FAULT=device-lost: the first wait for GPU work reports
// VK_ERROR_DEVICE_LOST): exit 6 with the reason, nothing written, and the remaining inputs not
// tried on a device that is gone. The density on the device: a CPU device would compute the
// whole field on the host, with no GPU work to wait for.
TEST_F(Interrupts, DeviceLostIsExit6AndNothingWritten) {
    const std::string data = FDMSURF_TEST_DATA_DIR;
    const FaultRun r = run_with_fault(dir_, "device-lost",
                                      {data + "/1crn.pdb", data + "/4hhb.pdb.gz", "-o",
                                       (dir_ / "out").string() + "/", "--host-density", "off"});
    EXPECT_EQ(r.exit_code, 6) << r.err;
    EXPECT_NE(r.err.find("VK_ERROR_DEVICE_LOST"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("the Vulkan device was lost"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("the remaining inputs were not processed"), std::string::npos) << r.err;
    EXPECT_TRUE(outputs(dir_).empty());
}

// A later wait fails (the second submission: the device is lost in the middle of the run).
TEST_F(Interrupts, DeviceLostLaterInTheRunIsExit6Too) {
    // The device's marching cubes and vertex atoms: a CPU device would run them on the host,
    // and the density's would be the run's only submission.
    const FaultRun r = run_with_fault(dir_, "device-lost:2",
                                      {std::string(FDMSURF_TEST_DATA_DIR) + "/1crn.pdb", "-o",
                                       (dir_ / "out" / "1crn.ply").string(), "--host-mc", "off",
                                       "--host-atoms", "off"});
    EXPECT_EQ(r.exit_code, 6) << r.err;
    EXPECT_TRUE(outputs(dir_).empty());
}

// An allocation of device memory that fails (FDMSURF_FAULT=out-of-memory:field): exit 7, the
// buffer and its size named with a spacing hint, nothing written. The density on the device,
// whose field buffer it is (a CPU device computes it on the host, with no such buffer).
TEST_F(Interrupts, OutOfDeviceMemoryIsExit7AndNothingWritten) {
    const FaultRun r = run_with_fault(dir_, "out-of-memory:field",
                                      {std::string(FDMSURF_TEST_DATA_DIR) + "/1crn.pdb", "-o",
                                       (dir_ / "out" / "1crn.ply").string(), "--host-density",
                                       "off"});
    EXPECT_EQ(r.exit_code, 7) << r.err;
    EXPECT_NE(r.err.find("out of memory allocating"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("'field'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("coarser --spacing"), std::string::npos) << r.err;
    EXPECT_TRUE(outputs(dir_).empty());
}

// Processes that write at once: two writing distinct files each get their own complete file,
// identical to a run alone; two writing the same file leave one complete file (the rename
// is atomic: whichever finishes last wins, never a mix) and no temporary file.
TEST_F(Interrupts, ConcurrentWritersNeverMixTheirFiles) {
    const std::string data = FDMSURF_TEST_DATA_DIR;
    const std::vector<std::string> common = {data + "/4hhb.pdb.gz", "--spacing", "0.6", "--quiet"};
    auto run = [&](const std::vector<std::pair<std::string, std::string>>& jobs) {
        std::vector<Child> children;
        for (const auto& [output, tag] : jobs) {
            std::vector<std::string> args = common;
            args.insert(args.end(), {"-o", output});
            ChildSetup setup;
            setup.stdout_name = "stdout-" + tag;
            setup.stderr_name = "stderr-" + tag;
            children.push_back(start(dir_, args, setup));
        }
        for (std::size_t i = 0; i < children.size(); ++i) {
            const int status = children[i].wait_status();
            ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
                << slurp(dir_ / ("stderr-" + jobs[i].second));
        }
    };
    const fs::path alone = dir_ / "alone.ply";
    run({{alone.string(), "alone"}});
    const std::string expected = slurp(alone);
    ASSERT_GT(expected.size(), 100000u);

    const fs::path a = dir_ / "out" / "a.ply", b = dir_ / "out" / "b.ply";
    run({{a.string(), "a"}, {b.string(), "b"}});
    EXPECT_TRUE(slurp(a) == expected);
    EXPECT_TRUE(slurp(b) == expected);

    const fs::path same = dir_ / "out" / "same.ply";
    for (int round = 0; round < 2; ++round) {
        run({{same.string(), "s1"}, {same.string(), "s2"}, {same.string(), "s3"}});
        EXPECT_TRUE(slurp(same) == expected) << "round " << round;
    }
    std::vector<std::string> names = outputs(dir_);
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"a.ply", "b.ply", "same.ply"}));
}

#endif

}  // namespace
