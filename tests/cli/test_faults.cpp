// Fault injection (issue 15): a full disk while a cache is written, a bake killed at random points, a
// missing or broken shader, no GL context, absurd parameters. Each fault runs the real binary in a
// child process (cli_run.h runChild), so the real write path, the real exit status and the real
// message are what is checked. docs/RELIABILITY.md says what each found.
#include <gtest/gtest.h>

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "cubeao/bake/bake_cache.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/gl/context.h"
#include "test_paths.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using cubeao::CacheReader;
using cubeao::test::ChildRun;
using cubeao::test::ChildSpec;
using cubeao::test::contains;
using cubeao::test::TempDir;

std::vector<std::string> words(const std::string& s) {
    std::istringstream in(s);
    return {std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
}

// `cubeao ARGS` (split on blanks: no quoting) under `spec`'s faults.
ChildRun cubeao(const std::string& args, ChildSpec spec = {}) {
    spec.args = words(args);
    return cubeao::test::runChild(spec);
}

std::string bytesOf(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Names in `dir` of writeCache's temporary files (".NAME.tmp-PID-RANDOM") and of bake part files.
std::vector<std::string> filesContaining(const fs::path& dir, const std::string& what) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir))
        if (contains(e.path().filename().string(), what)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}
std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
}

// probes.json with `budget` probes along the builtin scene's camera path.
std::string placeProbes(const TempDir& dir, const std::string& scene, int budget) {
    const fs::path probes = dir / "probes.json";
    const ChildRun r = cubeao("place " + scene + " --method path --budget " + std::to_string(budget) + " --out " +
                              probes.string());
    EXPECT_EQ(r.code, 0) << r.err;
    return probes.string();
}

// The cache holds every index 0..n-1 exactly once and every checksum matches.
void expectCompleteCache(const fs::path& file, std::size_t n) {
    const CacheReader cache(file);
    EXPECT_NO_THROW(cache.verifyAll());
    std::vector<int> seen(n, 0);
    for (std::size_t i = 0; i < cache.probeCount(); ++i) {
        ASSERT_LT(cache.index(i), n);
        ++seen[cache.index(i)];
    }
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(seen[i], 1) << "probe index " << i;
}

// ---- a write error / a full disk while a cache is written ----------------------------------------
// RLIMIT_FSIZE with SIGXFSZ ignored: a write() past the limit fails with EFBIG, which is what the
// cache writer sees of a full disk (ENOSPC) at the same offset, without root or a small file system.

TEST(Faults, FullDiskKeepsThePreviousCache) {
    TempDir dir("faults");
    const std::string probes = placeProbes(dir, "builtin:box-room", 24);
    const std::string bake = "bake builtin:box-room --probes " + probes + " --res 8 --spp 4 --device cpu --out ";
    const fs::path out = dir / "out.cubeao", ref = dir / "ref.cubeao";
    ASSERT_EQ(cubeao(bake + ref.string()).code, 0);
    const std::size_t total = CacheReader(ref).probeCount();
    ASSERT_EQ(total, 24u);
    // The previous cache: the even probes.
    ASSERT_EQ(cubeao(bake + out.string() + " --shard 0/2").code, 0);
    const std::string before = bytesOf(out);
    const cubeao::CacheParams params = CacheReader(out).params();
    const std::string tooLarge = std::strerror(EFBIG);

    // 1. Not even a part fits: the bake fails on its first batch (and the writer's retry on unwinding).
    ChildSpec spec;
    spec.fileSizeLimit = 1024;
    ChildRun r = cubeao(bake + out.string(), spec);
    EXPECT_TRUE(r.exited && r.code == 1) << r.describe() << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, out.string() + ".part-000000: cannot write cache")) << r.err;
    EXPECT_TRUE(contains(r.err, tooLarge)) << r.err;
    EXPECT_EQ(bytesOf(out), before) << "the previous cache changed";
    EXPECT_NO_THROW(CacheReader(out).verifyAll());
    EXPECT_EQ(joined(filesContaining(dir.path(), ".tmp-")), "");
    EXPECT_EQ(joined(filesContaining(dir.path(), ".part-")), "");

    // 2. The part fits, the merged cache does not: finish() fails, the output is as it was and the
    // part stays (a whole, valid cache) for the next run.
    spec.fileSizeLimit = (cubeao::cacheFileSize(params, total / 2) + cubeao::cacheFileSize(params, total)) / 2;
    r = cubeao(bake + out.string(), spec);
    EXPECT_TRUE(r.exited && r.code == 1) << r.describe() << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, out.string() + ": cannot write cache")) << r.err;
    EXPECT_TRUE(contains(r.err, tooLarge)) << r.err;
    EXPECT_EQ(bytesOf(out), before) << "the previous cache changed";
    EXPECT_EQ(joined(filesContaining(dir.path(), ".tmp-")), "");
    const std::vector<std::string> parts = filesContaining(dir.path(), ".part-");
    EXPECT_EQ(parts.size(), 1u) << joined(parts);
    for (const std::string& p : parts) EXPECT_NO_THROW(CacheReader(dir / p).verifyAll()) << p;

    // 3. Room again: the same command merges the part; the file is the one an uninterrupted bake writes.
    r = cubeao(bake + out.string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(bytesOf(out) == bytesOf(ref)) << "resumed cache differs from the uninterrupted bake";
    expectCompleteCache(out, total);
    EXPECT_EQ(joined(filesContaining(dir.path(), ".part-")), "");

    // 4. `merge` onto an existing file that cannot grow: the file is untouched.
    const fs::path even = dir / "even.cubeao", odd = dir / "odd.cubeao", merged = dir / "merged.cubeao";
    ASSERT_EQ(cubeao(bake + even.string() + " --shard 0/2").code, 0);
    ASSERT_EQ(cubeao(bake + odd.string() + " --shard 1/2").code, 0);
    fs::copy_file(even, merged);
    r = cubeao("merge " + merged.string() + " " + even.string() + " " + odd.string(), spec);
    EXPECT_TRUE(r.exited && r.code == 1) << r.describe() << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, merged.string() + ": cannot write cache")) << r.err;
    EXPECT_TRUE(contains(r.err, tooLarge)) << r.err;
    EXPECT_EQ(bytesOf(merged), bytesOf(even));
    EXPECT_EQ(joined(filesContaining(dir.path(), ".tmp-")), "");
    ASSERT_EQ(cubeao("merge " + merged.string() + " " + even.string() + " " + odd.string()).code, 0);
    EXPECT_TRUE(bytesOf(merged) == bytesOf(ref)) << "shards merged differ from the unsharded bake";
}

// ---- the bake killed with SIGKILL at random points --------------------------------------------------

// A pid no process has now: a child that has exited and been reaped.
pid_t deadPid() {
    const pid_t pid = fork();
    if (pid == 0) _exit(0);
    int status = 0;
    waitpid(pid, &status, 0);
    return pid;
}

// One bake killed at random times, several rounds from scratch: in each round the command is killed
// twice (the second kill hits the resumed run) and then run to completion. Every file a kill leaves
// opens and verifies; the finished cache holds every probe index exactly once, every checksum valid,
// and is the very bytes of an uninterrupted bake (the CPU bake is deterministic, checked first). The
// kill times are seeded and printed, and are in the failure message.
TEST(Faults, KilledBakeResumesToTheSameCache) {
    constexpr unsigned kSeed = 15;
    constexpr int kRounds = 3, kKillsPerRound = 2;
    constexpr std::size_t kProbes = 48;  // three batches of 16 (BakeCacheWriter::Options), then the merge
    TempDir dir("faults");
    const std::string probes = placeProbes(dir, "builtin:cloister", int(kProbes));
    const std::string bake = "bake builtin:cloister --probes " + probes + " --res 16 --spp 64 --device cpu --out ";
    const fs::path ref = dir / "ref.cubeao", again = dir / "again.cubeao", out = dir / "out.cubeao";
    const ChildRun first = cubeao(bake + ref.string());
    ASSERT_EQ(first.code, 0) << first.err;
    ASSERT_EQ(cubeao(bake + again.string()).code, 0);
    ASSERT_TRUE(bytesOf(ref) == bytesOf(again)) << "the bake is not deterministic: nothing to compare against";
    expectCompleteCache(ref, kProbes);
    const std::string refBytes = bytesOf(ref);

    // Kill times over the whole run: scene load, baking, part writes, the final merge.
    std::mt19937 rng(kSeed);
    std::uniform_real_distribution<double> when(0.1 * first.seconds, 1.0 * first.seconds);
    std::string log;
    int midRun = 0;
    for (int round = 0; round < kRounds; ++round) {
        for (const std::string& f : filesContaining(dir.path(), "out.cubeao")) fs::remove(dir / f);
        for (int k = 0; k < kKillsPerRound; ++k) {
            ChildSpec spec;
            spec.killAfterS = when(rng);
            const ChildRun r = cubeao(bake + out.string(), spec);
            midRun += r.exited ? 0 : 1;
            // Whatever the run left is whole: the output and every part open and verify. A killed
            // writer's hidden temporary file (".out.cubeao.part-N.tmp-PID-…") is partial by design, never
            // read, and removed by the next run (checked below); its name contains the part's, so skip it.
            std::size_t stored = 0;
            std::vector<fs::path> files = {out};
            for (const std::string& p : filesContaining(dir.path(), "out.cubeao.part-"))
                if (!contains(p, ".tmp-")) files.push_back(dir / p);
            for (const fs::path& f : files) {
                if (!fs::exists(f)) continue;
                try {
                    const CacheReader cache(f);
                    cache.verifyAll();
                    stored += cache.probeCount();
                } catch (const std::exception& e) {
                    ADD_FAILURE() << "round " << round << ", kill " << k << ": " << e.what();
                }
            }
            char line[200];
            std::snprintf(line, sizeof line, "round %d kill %d at %.3f s: %s, %zu probes on disk (output + parts), "
                          "%zu temp files\n", round, k, spec.killAfterS, r.describe().c_str(), stored,
                          filesContaining(dir.path(), ".tmp-").size());
            log += line;
        }
        SCOPED_TRACE("seed " + std::to_string(kSeed) + ", uninterrupted bake " + std::to_string(first.seconds) +
                     " s:\n" + log);
        // A temporary file a killed writer left (its process is gone) is removed by the next run.
        const std::string stale = ".out.cubeao.part-000099.tmp-" + std::to_string(deadPid()) + "-1";
        std::ofstream(dir / stale) << "half a cache";
        const ChildRun last = cubeao(bake + out.string());
        ASSERT_EQ(last.code, 0) << last.err;
        expectCompleteCache(out, kProbes);
        EXPECT_TRUE(bytesOf(out) == refBytes) << "resumed cache differs from the uninterrupted bake";
        EXPECT_EQ(joined(filesContaining(dir.path(), ".tmp-")), "");
        EXPECT_EQ(joined(filesContaining(dir.path(), ".part-")), "");
    }
    std::printf("%s%d of %d kills landed before the run ended\n", log.c_str(), midRun, kRounds * kKillsPerRound);
}

// ---- shaders and the GL context ---------------------------------------------------------------------

bool haveGl(std::string* why) { return cubeao::gl::HeadlessContext::tryCreate(why).has_value(); }

// A copy of the shader directory for one fault.
fs::path copyShaders(const TempDir& dir, const std::string& name) {
    const fs::path copy = dir / name;
    fs::copy(fs::path(cubeao::test::sourceDir()) / "shaders", copy, fs::copy_options::recursive);
    return copy;
}

// Appends a line that is not GLSL to `file`; returns its line number.
int breakShader(const fs::path& file) {
    std::string text = bytesOf(file);
    if (!text.empty() && text.back() != '\n') text += '\n';
    const int line = int(std::count(text.begin(), text.end(), '\n')) + 1;
    std::ofstream(file, std::ios::binary | std::ios::trunc) << text << "this is not glsl;\n";
    return line;
}

TEST(Faults, MissingOrBrokenShaderNamesTheFile) {
    std::string why;
    if (!haveGl(&why)) GTEST_SKIP() << "no OpenGL 4.5 context: " << why;
    TempDir dir("faults");
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]}]})");
    const std::string render = "render builtin:box-room --frames 0:1 --width 32 --height 24 --out " +
                               (dir / "frames").string();
    const std::string bake = "bake builtin:box-room --probes " + probes + " --res 8 --estimator hsplit --out " +
                             (dir / "hsplit.cubeao").string();
    const auto expectFailure = [](const ChildRun& r, const std::string& needle) {
        EXPECT_TRUE(r.exited && r.code == 1) << r.describe() << "\n" << r.err;
        EXPECT_TRUE(contains(r.err, needle)) << "expected \"" << needle << "\" in:\n" << r.err;
        EXPECT_LT(r.seconds, 20.0);
    };
    const auto with = [](const fs::path& shaders) {
        ChildSpec spec;
        spec.env = {{"CUBEAO_SHADER_DIR", shaders.string()}};
        return spec;
    };
    // The copy as it is works (so what follows fails for the fault alone).
    const fs::path good = copyShaders(dir, "good");
    ASSERT_EQ(cubeao(render, with(good)).code, 0);

    const fs::path missing = copyShaders(dir, "missing");
    fs::remove(missing / "ssao/gtao.comp");
    fs::remove(missing / "bake/ao_horizon.comp");
    const std::string noFile = std::strerror(ENOENT);
    expectFailure(cubeao(render, with(missing)), (missing / "ssao/gtao.comp").string() + ": " + noFile);
    expectFailure(cubeao(bake, with(missing)), (missing / "bake/ao_horizon.comp").string() + ": " + noFile);

    // A compile error names the file and the line (the driver's "FILE:LINE(COLUMN)" or "FILE:LINE").
    const fs::path broken = copyShaders(dir, "broken");
    const int gtaoLine = breakShader(broken / "ssao/gtao.comp");
    const int horizonLine = breakShader(broken / "bake/ao_horizon.comp");
    expectFailure(cubeao(render, with(broken)), (broken / "ssao/gtao.comp").string() + ":" + std::to_string(gtaoLine));
    expectFailure(cubeao(bake, with(broken)),
                  (broken / "bake/ao_horizon.comp").string() + ":" + std::to_string(horizonLine));

    // A missing include names the file that includes it, at its line.
    const fs::path noInclude = copyShaders(dir, "noinclude");
    fs::remove(noInclude / "common/gtao.h");
    expectFailure(cubeao(render, with(noInclude)), "cannot find #include \"gtao.h\"");
}

// No GL context: the GPU commands fail at once saying so and why; the CPU path still works.
TEST(Faults, NoGlContextIsReportedAndTheCpuPathWorks) {
    TempDir dir("faults");
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]}]})");
    const std::string render = "render builtin:box-room --frames 0:1 --width 32 --height 24 --out " +
                               (dir / "frames").string();
    const std::string bake = "bake builtin:box-room --probes " + probes + " --res 8 --out ";
    // glvnd finds no EGL vendor library (as on a machine without a GL driver), or the platform
    // variable names none.
    for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
             {"__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent.json"}, {"CUBEAO_EGL_PLATFORM", "bogus"}}) {
        SCOPED_TRACE(key + "=" + value);
        ChildSpec spec;
        spec.env = {{key, value}};
        ChildRun r = cubeao(render, spec);
        EXPECT_TRUE(r.exited && r.code == 1) << r.describe() << "\n" << r.err;
        EXPECT_TRUE(contains(r.err, "no OpenGL 4.5 context (")) << r.err;
        r = cubeao(bake + (dir / "gpu.cubeao").string(), spec);
        EXPECT_TRUE(r.exited && r.code == 1) << r.describe() << "\n" << r.err;
        EXPECT_TRUE(contains(r.err, "--device gpu: no OpenGL 4.5 context (")) << r.err;
        EXPECT_FALSE(fs::exists(dir / "gpu.cubeao"));
        const fs::path cpu = dir / ("cpu-" + key + ".cubeao");
        r = cubeao(bake + cpu.string() + " --device cpu", spec);
        EXPECT_EQ(r.code, 0) << r.err;
        expectCompleteCache(cpu, 1);
    }
}

// The image plugin (metrics/oiio_module.h) missing, or a library that is not it: a command that
// writes images ends with exit 1 naming the path it tried and the variable that overrides it, and
// leaves no frame behind; the plugin of this build, found without the variable, writes them.
TEST(Faults, MissingImagePluginNamesThePath) {
    TempDir dir("faults");
    const auto reference = [&](const std::string& out) {
        return "reference builtin:box-room --frames 0:1 --width 16 --height 12 --spp 4 --out " + (dir / out).string();
    };
    const auto with = [](const std::string& module) {
        ChildSpec spec;
        spec.env = {{"CUBEAO_OIIO_MODULE", module}};
        return spec;
    };
    const std::string absent = (dir / "absent" / "libcubeao_oiio.so").string();
    ChildRun r = cubeao(reference("absent"), with(absent));
    EXPECT_TRUE(r.exited && r.code == 1) << r.describe() << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, "cannot load cubeao's image module")) << r.err;
    EXPECT_TRUE(contains(r.err, absent + ": ")) << r.err;
    EXPECT_TRUE(contains(r.err, "set CUBEAO_OIIO_MODULE")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "absent" / "ao_0000.exr"));

    // A shared library that loads but is not the plugin (libm: always there, no cubeao_oiio_api).
    r = cubeao(reference("other"), with("libm.so.6"));
    EXPECT_TRUE(r.exited && r.code == 1) << r.describe() << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, "libm.so.6: not this build's image module")) << r.err;

    r = cubeao(reference("found"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "found" / "ao_0000.exr"));
}

// A GL error is counted and its text kept, so `cubeao` (main.cpp) ends a command that hit one with exit
// 1 and the error's text, rather than report results computed after it. (No CLI run provokes one
// on purpose, so the count is checked in process: an invalid call on a context of our own.)
TEST(Faults, GlErrorsAreCountedWithTheirText) {
    std::string why;
    auto context = cubeao::gl::HeadlessContext::tryCreate(&why);
    if (!context) GTEST_SKIP() << "no OpenGL 4.5 context: " << why;
    if (!context->debugOutput()) GTEST_SKIP() << "this context has no debug output";
    const std::size_t before = cubeao::gl::debugErrorCount();
    glBindBuffer(GL_ARRAY_BUFFER, 0x7fffffffu);  // a name never generated: GL_INVALID_OPERATION in core
    glFinish();
    EXPECT_EQ(glGetError(), GLenum(GL_INVALID_OPERATION));  // and clears the flag for whoever comes next
    EXPECT_EQ(cubeao::gl::debugErrorCount(), before + 1);
    EXPECT_TRUE(contains(cubeao::gl::firstDebugError(), "GL error #")) << cubeao::gl::firstDebugError();
}

// ---- absurd parameters ---------------------------------------------------------------------------
// Refused as usage errors (exit 2) before any memory is committed: each command line runs under a
// 2 GiB address-space limit (a value that reached an allocation would fail with bad_alloc, exit 1, or
// take its time) and must name the option and its valid range within seconds. 2 GiB, not 1: under
// 1 GiB llvmpipe's context creation hangs (threads that cannot get their stacks), see below.

// AddressSanitizer reserves terabytes of shadow address space: no limit there (the exit code, the
// message and the time are still checked).
constexpr rlim_t kAbsurdAddressSpace = cubeao::test::kAddressSanitizer ? RLIM_INFINITY : rlim_t(2) << 30;
constexpr double kAbsurdSeconds = 5.0;

// {dir} is a fresh directory holding probes.json (one probe in box-room) and cache.cubeao (that
// probe baked at --res 8).
struct AbsurdCase {
    const char* args;
    const char* message;  // what stderr must contain: the option and its range
};

class AbsurdParameters : public ::testing::TestWithParam<AbsurdCase> {
protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir("faults-absurd");
        dir_->write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]}]})");
        const ChildRun r = cubeao("bake builtin:box-room --device cpu --res 8 --spp 4 --probes " +
                                  (*dir_ / "probes.json").string() + " --out " + (*dir_ / "cache.cubeao").string());
        ASSERT_EQ(r.code, 0) << r.err;
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }
    static std::string expand(std::string args) {
        for (std::size_t at; (at = args.find("{dir}")) != std::string::npos;) args.replace(at, 5, dir_->path().string());
        return args;
    }
    static TempDir* dir_;
};
TempDir* AbsurdParameters::dir_ = nullptr;

// The limit leaves room for the real work: the same commands with sane values succeed under it.
TEST_F(AbsurdParameters, SaneValuesRunUnderTheLimit) {
    ChildSpec spec;
    spec.addressSpaceLimit = kAbsurdAddressSpace;
    for (const char* args : {"bake builtin:box-room --device cpu --res 8 --probes {dir}/probes.json --out {dir}/sane.cubeao",
                             "reference builtin:box-room --frames 0:1 --width 16 --height 8 --spp 2 --out {dir}/ref",
                             "place builtin:box-room --method path --budget 4 --out {dir}/placed.json"}) {
        const ChildRun r = cubeao(expand(args), spec);
        EXPECT_EQ(r.code, 0) << args << ": " << r.describe() << "\n" << r.err;
    }
}

TEST_P(AbsurdParameters, RefusedWithTheRangeBeforeAnyWork) {
    ChildSpec spec;
    spec.addressSpaceLimit = kAbsurdAddressSpace;
    spec.timeoutS = 30.0;
    const std::string args = expand(GetParam().args);
    const ChildRun r = cubeao(args, spec);
    EXPECT_TRUE(r.exited && r.code == 2) << args << ": " << r.describe() << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, GetParam().message)) << args << ": expected \"" << GetParam().message << "\" in\n"
                                                     << r.err;
    EXPECT_LT(r.seconds, kAbsurdSeconds) << args;
}

const AbsurdCase kAbsurdCases[] = {
    // bake (0 is each option's default)
    {"bake builtin:box-room --probes {dir}/probes.json --out {dir}/o.cubeao --device cpu --res 65536",
     "--res must be between 0 and 4096"},
    {"bake builtin:box-room --probes {dir}/probes.json --out {dir}/o.cubeao --device cpu --radius inf",
     "--radius must be a finite number >= 0"},
    {"bake builtin:box-room --probes {dir}/probes.json --out {dir}/o.cubeao --device cpu --spp 100000000",
     "--spp must be between 0 and 65536"},
    {"bake builtin:box-room --probes {dir}/probes.json --out {dir}/o.cubeao --device cpu --directions 100000",
     "--directions must be between 0 and 64"},
    {"bake builtin:box-room --probes {dir}/probes.json --out {dir}/o.cubeao --device cpu --depth-res 100000",
     "--depth-res must be between 0 and 4096"},
    {"bake builtin:box-room --probes {dir}/probes.json --out {dir}/o.cubeao --device cpu --verify --verify-spp 1000000000",
     "--verify-spp must be between 0 and 262144"},
    {"bake builtin:box-room --probes {dir}/probes.json --out {dir}/o.cubeao --device cpu --hybrid-threshold nan",
     "--hybrid-threshold must be between 0 and 1"},
    {"bake builtin:box-room --probes {dir}/probes.json --out {dir}/o.cubeao --device cpu --res 10",
     "--res 10: expected a multiple of 4 in 4..4096"},
    // reference
    {"reference builtin:box-room --out {dir}/ref --spp 0", "--spp must be between 1 and 65536 (got 0)"},
    {"reference builtin:box-room --out {dir}/ref --width 100000", "--width must be between 0 and 16384"},
    {"reference builtin:box-room --out {dir}/ref --frames 5:5", "--frames \"5:5\" selects no frames (the path has 24)"},
    // render
    {"render builtin:box-room --out {dir}/frames --width 100000", "--width must be between 0 and 16384"},
    {"render builtin:box-room --out {dir}/frames --height 16384", "image width (--width, or --height times the "
                                                                 "camera's aspect) must be between 1 and 16384"},
    {"render builtin:box-room --out {dir}/frames --steps 100000", "--steps must be between 0 and 64"},
    {"render builtin:box-room --out {dir}/frames --cache {dir}/cache.cubeao --upload-mb 1e9",
     "--upload-mb must lie in [0, 65536]"},
    // place
    {"place builtin:box-room --out {dir}/p.json --samples 2000000000", "--samples must be between 1 and 1000000"},
    {"place builtin:box-room --out {dir}/p.json --rays 100000000", "--rays must be between 1 and 4096"},
    {"place builtin:box-room --out {dir}/p.json --budget -1", "--budget must be between 0 and 1000000"},
    {"place builtin:box-room --out {dir}/p.json --method grid --voxel 1e-9", "--voxel must be at least about"},
    // bench
    {"bench bake --res 65536 --device cpu", "--res must be between 4 and 4096"},
    {"bench cache --probes 100000000", "--probes must be between 1 and 1000000"},
    {"bench cache --probes 1000000 --res 4096", "MiB cache: at most 4096 MiB"},
    {"bench depth --probes 100000000", "--probes must be between 1 and 1024"},
    {"bench depth --frames 10000 --width 4096 --height 4096", "camera points"},
    {"bench render --probes 100000000", "--probes: every count must be between 1 and 100000"},
};
INSTANTIATE_TEST_SUITE_P(Faults, AbsurdParameters, ::testing::ValuesIn(kAbsurdCases));

}  // namespace
