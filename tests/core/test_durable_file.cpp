// core/durable_file.h: the one writer every file cubeao writes goes through.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cubeao/placement/probe_set.h"
#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using cubeao::DurableFile;
using cubeao::test::TempDir;

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Every name in `dir`, sorted, joined by spaces.
std::string listing(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "" : " ") + n;
    return s;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const cubeao::Error& e) {
        return e.what();
    }
    return "";
}

TEST(DurableFile, CommitReplacesTheTargetAndLeavesNothingElse) {
    const TempDir dir("durable");
    const fs::path target = dir / "a.json";
    dir.write("a.json", "old");
    {
        DurableFile f(target, "probe set");
        EXPECT_EQ(f.temporaryPath().parent_path(), target.parent_path());
        EXPECT_EQ(cubeao::temporaryFileWriter(f.temporaryPath().filename().string(), "a.json"), long(::getpid()));
        f.write(std::string_view("new "));
        f.write(std::string_view("text"));
        EXPECT_EQ(slurp(target), "old");  // nothing visible before the commit
        f.commit();
    }
    EXPECT_EQ(slurp(target), "new text");
    EXPECT_EQ(listing(dir.path()), "a.json");

    // A new file gets the usual permissions: 0666 less the umask, as any program's new file.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    cubeao::writeFileDurably(dir / "b.txt", "b");
    EXPECT_EQ(fs::status(dir / "b.txt").permissions(), fs::perms(0666 & ~mask));
}

TEST(DurableFile, AnUncommittedWriteLeavesTheTargetAsItWas) {
    const TempDir dir("durable");
    const fs::path target = dir / "a.json";
    dir.write("a.json", "old");
    {
        DurableFile f(target);
        f.write(std::string_view("half"));
    }
    EXPECT_EQ(slurp(target), "old");
    EXPECT_EQ(listing(dir.path()), "a.json");
    {
        DurableFile f(target);
        f.write(std::string_view("whole"));
        f.finish();  // synced, but not published
    }
    EXPECT_EQ(slurp(target), "old");
    EXPECT_EQ(listing(dir.path()), "a.json");
}

TEST(DurableFile, FilesPublishedTogetherAppearOnlyWhenPublished) {
    const TempDir dir("durable");
    std::vector<DurableFile> files;
    files.reserve(3);
    for (const char* name : {"x", "y", "manifest"}) {
        DurableFile& f = files.emplace_back(dir / name, "export file");
        f.write(std::string_view(name));
        f.finish();
    }
    for (const char* name : {"x", "y", "manifest"}) EXPECT_FALSE(fs::exists(dir / name)) << name;
    for (DurableFile& f : files) f.publish();
    cubeao::syncDirectoryOf(dir / "manifest");
    EXPECT_EQ(listing(dir.path()), "manifest x y");
    EXPECT_EQ(slurp(dir / "y"), "y");
}

TEST(DurableFile, ErrorsNameTheTargetAndTheStep) {
    const TempDir dir("durable");
    const std::string missing = errorOf([&] { DurableFile f(dir / "no/such/dir/a.json", "probe set"); });
    EXPECT_NE(missing.find((dir / "no/such/dir/a.json").string() + ": cannot write probe set: cannot create a temporary "
                                                                      "file in"),
              std::string::npos)
        << missing;
    EXPECT_NE(missing.find("No such file or directory"), std::string::npos) << missing;

    // A write past RLIMIT_FSIZE fails with EFBIG, as on a full disk: the error names the step, the
    // temporary file is gone, the target untouched.
    dir.write("big.bin", "old");
    rlimit saved{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
    const auto previous = std::signal(SIGXFSZ, SIG_IGN);
    rlimit small = saved;
    small.rlim_cur = 4096;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    const std::string big = errorOf([&] { cubeao::writeFileDurably(dir / "big.bin", std::string(10000, 'x'), "cache"); });
    ::setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, previous);
    EXPECT_NE(big.find((dir / "big.bin").string() + ": cannot write cache: write (.big.bin.tmp-"), std::string::npos)
        << big;
    EXPECT_NE(big.find("File too large"), std::string::npos) << big;
    EXPECT_EQ(slurp(dir / "big.bin"), "old");
    EXPECT_EQ(listing(dir.path()), "big.bin");

    DurableFile f(dir / "c");
    f.finish();
    EXPECT_NE(errorOf([&] { f.write(std::string_view("late")); }).find("write after finish"), std::string::npos);
}

TEST(DurableFile, TemporaryNamesAreRecognisedOnlyForTheirTarget) {
    EXPECT_EQ(cubeao::temporaryFileWriter(".out.cubeao.tmp-1234-99", "out.cubeao"), 1234);
    EXPECT_EQ(cubeao::temporaryFileWriter(".out.cubeao.tmp-1234-99", "other.cubeao"), 0);
    EXPECT_EQ(cubeao::temporaryFileWriter("out.cubeao", "out.cubeao"), 0);
    EXPECT_EQ(cubeao::temporaryFileWriter(".out.cubeao.tmp-x1-2", "out.cubeao"), 0);
    EXPECT_EQ(cubeao::temporaryFileWriter(".out.cubeao.tmp-", "out.cubeao"), 0);
}

// probes.json used a fixed "FILE.tmp": two writers of one file (two `place` runs, a viewer saving
// while a script does) renamed each other's half-written file or failed. Each now has its own.
TEST(DurableFile, ConcurrentWritersOfOneProbeSetEachWriteAWholeFile) {
    const TempDir dir("durable");
    const fs::path file = dir / "probes.json";
    std::vector<std::thread> writers;
    std::atomic<int> failures{0};
    for (int t = 0; t < 4; ++t)
        writers.emplace_back([&, t] {
            std::vector<cubeao::ProbeSpec> probes(std::size_t(50 + 50 * t));
            for (std::size_t i = 0; i < probes.size(); ++i) probes[i].position = glm::vec3(float(i), float(t), 0.0f);
            for (int k = 0; k < 20; ++k) try {
                    cubeao::writeProbeSet(file, probes);
                } catch (const cubeao::Error&) {
                    ++failures;
                }
        });
    for (std::thread& w : writers) w.join();
    EXPECT_EQ(failures.load(), 0);
    const std::vector<cubeao::ProbeSpec> read = cubeao::readProbeSet(file);
    ASSERT_FALSE(read.empty());
    const int t = int(read.front().position.y);
    EXPECT_EQ(read.size(), std::size_t(50 + 50 * t));  // one writer's whole set, not a mixture
    EXPECT_EQ(listing(dir.path()), "probes.json");
}

}  // namespace
