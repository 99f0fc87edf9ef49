// Running the cubeao binary from a test: exit code and stdout, and the JSON object every command
// prints as its last line with --json (DESIGN.md §5); runChild for fault injection (rlimits, extra
// environment, SIGKILL after a delay).
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_paths.h"

namespace cubeao::test {

struct CliRun {
    int code = -1;
    std::string out;
};

// Runs a shell command line; `out` is what it writes to stdout.
inline CliRun runCommand(const std::string& cmd) {
    CliRun r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf{};
    while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// Runs the binary; `out` is its stdout, followed by its stderr when withStderr.
// (Appended piecewise: GCC 12's -Warray-bounds misfires on `std::string(...) + " " + args + (c ? a : b)`.)
inline CliRun runCli(const std::string& args, bool withStderr = false) {
    std::string cmd = cubeaoBinary();
    cmd += ' ';
    cmd += args;
    cmd += withStderr ? " 2>&1" : " 2>/dev/null";
    return runCommand(cmd);
}

inline nlohmann::json lastLine(const std::string& out) {
    std::string s = out;
    while (!s.empty() && s.back() == '\n') s.pop_back();
    return nlohmann::json::parse(s.substr(s.rfind('\n') + 1));
}

// One run of the cubeao binary under injected faults (tests/cli/test_faults.cpp).
struct ChildSpec {
    std::vector<std::string> args;                            // after the binary's name, no shell
    std::vector<std::pair<std::string, std::string>> env;     // set in the child only
    rlim_t fileSizeLimit = RLIM_INFINITY;     // RLIMIT_FSIZE, bytes: SIGXFSZ is ignored, so a write past it
                                              // fails with EFBIG, as on a full disk
    rlim_t addressSpaceLimit = RLIM_INFINITY;  // RLIMIT_AS, bytes: an allocation past it fails
    double killAfterS = 0.0;                  // SIGKILL the child after this many seconds (0: never)
    double timeoutS = 120.0;                  // SIGKILL it after this long anyway (timedOut)
};

struct ChildRun {
    bool exited = false;  // exited normally: `code` is its status
    int code = -1;
    int signal = 0;       // the signal that ended it otherwise
    bool killed = false;  // killAfterS elapsed and SIGKILL was sent
    bool timedOut = false;
    double seconds = 0.0;
    std::string out, err;  // stdout, stderr
    std::string describe() const {
        return exited ? "exit " + std::to_string(code)
                      : "signal " + std::to_string(signal) + (timedOut ? " (timed out)" : "");
    }
};

inline ChildRun runChild(const ChildSpec& spec) {
    using Clock = std::chrono::steady_clock;
    ChildRun r;
    int outPipe[2], errPipe[2];
    if (pipe2(outPipe, O_CLOEXEC) != 0) return r;
    if (pipe2(errPipe, O_CLOEXEC) != 0) {
        close(outPipe[0]), close(outPipe[1]);
        return r;
    }
    // Everything the child needs is built before fork: only async-signal-safe calls after it.
    std::vector<std::string> argStore{cubeaoBinary()};
    argStore.insert(argStore.end(), spec.args.begin(), spec.args.end());
    std::vector<char*> argv;
    for (std::string& a : argStore) argv.push_back(a.data());
    argv.push_back(nullptr);
    // The environment with spec.env applied, for execve: setenv in the child could deadlock on a lock
    // another thread of this process (a GL driver's) held at fork.
    std::vector<std::string> envStore;
    for (char** e = environ; *e != nullptr; ++e) {
        const std::string entry = *e;
        bool replaced = false;
        for (const auto& [k, v] : spec.env) replaced = replaced || entry.compare(0, k.size() + 1, k + "=") == 0;
        if (!replaced) envStore.push_back(entry);
    }
    for (const auto& [k, v] : spec.env) envStore.push_back(k + "=" + v);
    std::vector<char*> envp;
    for (std::string& e : envStore) envp.push_back(e.data());
    envp.push_back(nullptr);
    const auto start = Clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        const rlimit fsize{spec.fileSizeLimit, spec.fileSizeLimit}, as{spec.addressSpaceLimit, spec.addressSpaceLimit};
        if (spec.fileSizeLimit != RLIM_INFINITY) setrlimit(RLIMIT_FSIZE, &fsize);
        if (spec.addressSpaceLimit != RLIM_INFINITY) setrlimit(RLIMIT_AS, &as);
        ::signal(SIGXFSZ, SIG_IGN);  // kept across exec
        dup2(outPipe[1], 1);
        dup2(errPipe[1], 2);
        execve(argv[0], argv.data(), envp.data());
        _exit(127);
    }
    close(outPipe[1]);
    close(errPipe[1]);
    if (pid < 0) {
        close(outPipe[0]), close(errPipe[0]);
        return r;
    }
    pollfd fds[2] = {{outPipe[0], POLLIN, 0}, {errPipe[0], POLLIN, 0}};
    std::string* sinks[2] = {&r.out, &r.err};
    int openPipes = 2;
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    while (openPipes > 0) {
        if (spec.killAfterS > 0.0 && !r.killed && elapsed() >= spec.killAfterS) kill(pid, SIGKILL), r.killed = true;
        if (!r.timedOut && elapsed() >= spec.timeoutS) kill(pid, SIGKILL), r.timedOut = true;
        if (poll(fds, 2, 5) < 0 && errno != EINTR) break;
        for (int i = 0; i < 2; ++i) {
            if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
            std::array<char, 4096> buf{};
            const ssize_t n = read(fds[i].fd, buf.data(), buf.size());
            if (n > 0) {
                sinks[i]->append(buf.data(), std::size_t(n));
            } else if (n == 0 || errno != EINTR) {
                close(fds[i].fd);
                fds[i].fd = -1;
                --openPipes;
            }
        }
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    r.seconds = elapsed();
    r.exited = WIFEXITED(status);
    if (r.exited) r.code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
    return r;
}

}  // namespace cubeao::test
